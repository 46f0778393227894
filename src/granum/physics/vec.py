"""Small-vector algebra on tuples, for use inside compiled kernels.

Vectors are ``(x, y, z)`` tuples of floats and quaternions ``(w, x, y, z)`` tuples.
Tuples live in registers: unlike small NumPy arrays they never touch the heap, which
keeps per-contact functions allocation-free (and portable to a GPU backend).
Quaternions are unit quaternions mapping the body (local) frame to the global frame.
"""

from __future__ import annotations

import math

import numpy as np

from granum._jit import jit

#: squared rotation angle [rad^2] below which :func:`quat_from_rotvec` uses its series (|r| < 0.1 rad)
ROTVEC_SERIES_MAX2 = 0.01
#: reciprocals of the ratios of successive Taylor coefficients of cos(h) and sin(h)/h in h^2
_COS_STEPS = (1.0 / 2.0, 1.0 / 12.0, 1.0 / 30.0, 1.0 / 56.0)
_SINC_STEPS = (1.0 / 6.0, 1.0 / 20.0, 1.0 / 42.0, 1.0 / 72.0)


@jit
def load3(a, i):
    """Row ``i`` of an (n, 3) array as a tuple."""
    return (a[i, 0], a[i, 1], a[i, 2])


@jit
def store3(a, i, v):
    """Write tuple ``v`` into row ``i`` of an (n, 3) array."""
    a[i, 0] = v[0]
    a[i, 1] = v[1]
    a[i, 2] = v[2]


@jit
def load4(a, i):
    """Row ``i`` of an (n, 4) array as a tuple."""
    return (a[i, 0], a[i, 1], a[i, 2], a[i, 3])


@jit
def add(a, b):
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


@jit
def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


@jit
def scale(a, s):
    return (a[0] * s, a[1] * s, a[2] * s)


@jit
def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


@jit
def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


@jit
def norm(a):
    return math.sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2])


@jit
def quat_rotate(q, v):
    """Rotate vector ``v`` by unit quaternion ``q = (w, x, y, z)``: q v q*."""
    w = q[0]
    u = (q[1], q[2], q[3])
    t = scale(cross(u, v), 2.0)
    return add(add(v, scale(t, w)), cross(u, t))


@jit
def quat_rotate_inv(q, v):
    """Rotate vector ``v`` by the conjugate of ``q``: global to local frame."""
    return quat_rotate((q[0], -q[1], -q[2], -q[3]), v)


@jit(inline="always")  # also inlined where a loop must vectorize (a call stops LLVM's loop vectorizer)
def quat_mul_inlined(a, b):
    """Hamilton product ``a * b`` of quaternions (w, x, y, z), inlined where it is called."""
    return (a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
            a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
            a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
            a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0])


@jit
def quat_mul(a, b):
    """Hamilton product ``a * b`` of quaternions (w, x, y, z)."""
    return quat_mul_inlined(a, b)


@jit
def quat_normalized(q):
    n = math.sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3])
    return (q[0] / n, q[1] / n, q[2] / n, q[3] / n)


#: |q|^2 - 1 below which :func:`quat_renormalized` takes its series
RENORM_SERIES_MAX = 1e-6


@jit
def quat_renormalized(q):
    """``q / |q|`` for a quaternion that is unit to rounding (the product of unit quaternions): with
    |q|^2 = 1 + e, 1/|q| = 1 - e/2 + 3e^2/8 - ..., so q (1 - e/2) is within 3e^2/8 < 4e-13 relative of it for
    |e| < 1e-6 and exact to rounding for |e| ~ 1e-16, without square root or division (with them, the
    renormalization took 56 of NewtonIntegrator's 470 us a step on the 10,000-sphere drum, one thread).
    Farther from unit: :func:`quat_normalized`."""
    e = norm_excess(q)
    if abs(e) < RENORM_SERIES_MAX:
        return renormalized_series(q, e)
    return quat_normalized(q)


@jit(inline="always")
def norm_excess(q):
    """|q|^2 - 1 of a quaternion (w, x, y, z)."""
    return q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3] - 1.0


@jit(inline="always")
def renormalized_series(q, e):
    """:func:`quat_renormalized`'s series, q (1 - e/2), for ``e`` = :func:`norm_excess` of q below
    RENORM_SERIES_MAX in magnitude."""
    f = 1.0 - 0.5 * e
    return (q[0] * f, q[1] * f, q[2] * f, q[3] * f)


@jit
def quat_from_rotvec(r):
    """Unit quaternion of the rotation by angle |r| about r/|r| (identity for r = 0):
    (cos(|r|/2), r sin(|r|/2)/|r|).

    A body turns by |r| = |omega| dt per step, far below 0.1 rad: there both factors come from
    their Taylor series in h^2 = |r|^2/4 up to h^8 (truncation error below h^10/10! < 3e-20),
    without square root, sine, cosine or division (those took a tenth of NewtonIntegrator's time
    at 1e5 spheres); larger angles take the library functions.
    """
    a2 = r[0] * r[0] + r[1] * r[1] + r[2] * r[2]
    if a2 < ROTVEC_SERIES_MAX2:
        c, s = rotvec_series(a2)
    else:
        angle = math.sqrt(a2)
        c = math.cos(0.5 * angle)
        s = math.sin(0.5 * angle) / angle
    return (c, r[0] * s, r[1] * s, r[2] * s)


@jit(inline="always")
def rotvec_series(a2):
    """The factors (c, s) of :func:`quat_from_rotvec`, (c, r s), from their series, for a squared angle
    a2 = |r|^2 below ROTVEC_SERIES_MAX2 [rad^2]."""
    h2 = 0.25 * a2
    k, j = _COS_STEPS, _SINC_STEPS  # nested (Horner) form: 1 - h^2/2 (1 - h^2/12 (1 - ...)), ...
    c = 1.0 - h2 * k[0] * (1.0 - h2 * k[1] * (1.0 - h2 * k[2] * (1.0 - h2 * k[3])))
    s = 0.5 * (1.0 - h2 * j[0] * (1.0 - h2 * j[1] * (1.0 - h2 * j[2] * (1.0 - h2 * j[3]))))
    return c, s


@jit
def quat_angle(q):
    """Rotation angle of a unit quaternion, in [0, pi] [rad]."""
    w = min(1.0, abs(q[0]))
    return 2.0 * math.acos(w)


@jit
def matvec(m, v):
    """Product of a (3, 3) array and a 3-tuple."""
    return (m[0, 0] * v[0] + m[0, 1] * v[1] + m[0, 2] * v[2],
            m[1, 0] * v[0] + m[1, 1] * v[1] + m[1, 2] * v[2],
            m[2, 0] * v[0] + m[2, 1] * v[1] + m[2, 2] * v[2])


@jit
def det3(m):
    """Determinant of a (3, 3) array by cofactors along the first row (exact for diagonal matrices, unlike LU).

    Written out rather than ``np.linalg.det``: compiled code with NumPy's linear algebra needs SciPy's
    LAPACK, which granum does not depend on."""
    return (m[0, 0] * (m[1, 1] * m[2, 2] - m[1, 2] * m[2, 1]) - m[0, 1] * (m[1, 0] * m[2, 2] - m[1, 2] * m[2, 0])
            + m[0, 2] * (m[1, 0] * m[2, 1] - m[1, 1] * m[2, 0]))


@jit
def inv3(m):
    """Inverse of a (3, 3) array as its adjugate over :func:`det3`, a new (3, 3) array.

    A singular matrix gives inf/NaN entries (IEEE division), as Eigen's ``inverse()`` in YADE."""
    r = 1.0 / det3(m)
    out = np.empty((3, 3))
    for i in range(3):
        i1, i2 = (i + 1) % 3, (i + 2) % 3
        for j in range(3):
            j1, j2 = (j + 1) % 3, (j + 2) % 3
            # cofactor C[j, i] (cyclic indices carry the sign); out = C^T / det
            out[i, j] = (m[j1, i1] * m[j2, i2] - m[j1, i2] * m[j2, i1]) * r
    return out


@jit
def quat_from_rows(r0, r1, r2):
    """Quaternion (w, x, y, z) of the rotation matrix with rows ``r0``, ``r1``, ``r2`` (Shepperd's method).

    From the largest of the trace and the diagonal entries, as Eigen's ``Quaternion(Matrix3)``; not
    normalised, so a matrix that drifted from orthonormal gives a quaternion of norm near 1.
    """
    m = (r0, r1, r2)
    trace = r0[0] + r1[1] + r2[2]
    if trace > 0.0:
        t = math.sqrt(trace + 1.0)
        s = 0.5 / t
        return (0.5 * t, (r2[1] - r1[2]) * s, (r0[2] - r2[0]) * s, (r1[0] - r0[1]) * s)
    i = 0
    if r1[1] > r0[0]:
        i = 1
    if r2[2] > m[i][i]:
        i = 2
    j = (i + 1) % 3
    k = (j + 1) % 3
    t = math.sqrt(m[i][i] - m[j][j] - m[k][k] + 1.0)
    s = 0.5 / t
    w = (m[k][j] - m[j][k]) * s
    qi = 0.5 * t
    qj = (m[j][i] + m[i][j]) * s
    qk = (m[k][i] + m[i][k]) * s
    if i == 0:
        return (w, qi, qj, qk)
    if i == 1:
        return (w, qk, qi, qj)
    return (w, qj, qk, qi)


@jit
def quat_to_rows(q):
    """Rows of the rotation matrix of the quaternion ``q`` (w, x, y, z), taken as a unit one."""
    w, x, y, z = q
    return ((1.0 - 2.0 * (y * y + z * z), 2.0 * (x * y - w * z), 2.0 * (x * z + w * y)),
            (2.0 * (x * y + w * z), 1.0 - 2.0 * (x * x + z * z), 2.0 * (y * z - w * x)),
            (2.0 * (x * z - w * y), 2.0 * (y * z + w * x), 1.0 - 2.0 * (x * x + y * y)))


@jit
def quat_slerp(a, b, t):
    """Spherical linear interpolation from ``a`` (t = 0) to ``b`` (t = 1) along the shorter arc.

    a sin((1 - t) theta)/sin(theta) + b sin(t theta)/sin(theta), cos(theta) = |a . b|, with b's sign
    flipped when a . b < 0; linear weights (1 - t, t) when theta is below 1e-15 (as Eigen).
    """
    d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3]
    abs_d = abs(d)
    if abs_d >= 1.0 - 1e-15:
        wa = 1.0 - t
        wb = t
    else:
        theta = math.acos(abs_d)
        sin_theta = math.sin(theta)
        wa = math.sin((1.0 - t) * theta) / sin_theta
        wb = math.sin(t * theta) / sin_theta
    if d < 0.0:
        wb = -wb
    return (wa * a[0] + wb * b[0], wa * a[1] + wb * b[1], wa * a[2] + wb * b[2], wa * a[3] + wb * b[3])
