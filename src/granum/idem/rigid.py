"""Rigid bodies made of particles: mass properties, the K matrix, time integration.

Compiled helpers shared by the iDEM kernels. Vectors are ``(x, y, z)`` tuples (see
:mod:`granum.physics.vec`), matrices ``(3, 3)`` float64 arrays; quaternions are
``(w, x, y, z)`` and map the body frame to the world frame.

References: seed article "力積型個別要素法" (summarised in ``shared/reference/idem.md``),
§2 (mass properties), §5 (K matrix), §8 (position and orientation update). [A1]: the article's
"ω" is the angular velocity (its Δω = I^-1 (r x J) says so), stored per body in the world frame.
"""

from __future__ import annotations

import numpy as np

from granum._jit import jit, kernel, prange
from granum.physics.vec import add, cross, dot, load3, matvec, quat_from_rotvec, quat_mul, quat_normalized, scale


def mass_properties(points: np.ndarray, masses: np.ndarray) -> tuple[float, np.ndarray, np.ndarray]:
    """Mass M [kg], centre of mass X (3,) [m] and inertia tensor about X (3, 3) [kg m^2] of point masses.

    M = sum m_i, X = sum m_i x_i / M and I = sum m_i (|r_i|^2 1 - r_i r_i^T) with r_i = x_i - X
    (article §2: the particles are point masses, their own rotational inertia is neglected).
    """
    m = np.asarray(masses, dtype=np.float64)
    mass = float(m.sum())
    com = (m[:, None] * points).sum(axis=0) / mass
    r = points - com
    inertia = np.eye(3) * float((m * (r * r).sum(axis=1)).sum()) - np.einsum("i,ij,ik->jk", m, r, r)
    return mass, com, inertia


@jit
def rotation_matrix(q, out):
    """Write into ``out`` (3, 3) the rotation matrix of the unit quaternion ``q = (w, x, y, z)`` (article §8.6)."""
    w, x, y, z = q[0], q[1], q[2], q[3]
    out[0, 0] = 1.0 - 2.0 * (y * y + z * z)
    out[0, 1] = 2.0 * (x * y - w * z)
    out[0, 2] = 2.0 * (x * z + w * y)
    out[1, 0] = 2.0 * (x * y + w * z)
    out[1, 1] = 1.0 - 2.0 * (x * x + z * z)
    out[1, 2] = 2.0 * (y * z - w * x)
    out[2, 0] = 2.0 * (x * z - w * y)
    out[2, 1] = 2.0 * (y * z + w * x)
    out[2, 2] = 1.0 - 2.0 * (x * x + y * y)


@jit
def rotate_tensor(R, A, out):
    """``out = R A R^T`` for (3, 3) arrays (a body-frame tensor in the world frame)."""
    for i in range(3):
        for j in range(3):
            s = 0.0
            for k in range(3):
                for m in range(3):
                    s += R[i, k] * A[k, m] * R[j, m]
            out[i, j] = s


@jit
def k_apply(inv_ma, inv_ia, ra, inv_mb, inv_ib, rb, v):
    """K_AB v: change of the relative velocity of a particle pair per unit impulse (article §5).

    K_AB = (1/M_A + 1/M_B) 1 - [r_A]x I_A^-1 [r_A]x - [r_B]x I_B^-1 [r_B]x, applied as
    (1/M_A + 1/M_B) v + (I_A^-1 (r_A x v)) x r_A + (I_B^-1 (r_B x v)) x r_B.
    ``inv_ia``/``inv_ib`` are the world-frame inverse inertia tensors (3, 3) [1/(kg m^2)],
    zero for a fixed body; ``ra``/``rb`` the lever arms [m]. Result in [m/s per N s].
    """
    out = scale(v, inv_ma + inv_mb)
    out = add(out, cross(matvec(inv_ia, cross(ra, v)), ra))
    return add(out, cross(matvec(inv_ib, cross(rb, v)), rb))


@jit
def k_matrix(inv_ma, inv_ia, ra, inv_mb, inv_ib, rb):
    """The K_AB matrix (3, 3) as an array (columns K e_k); for tests and diagnostics."""
    K = np.empty((3, 3))
    for k in range(3):
        e = (1.0 if k == 0 else 0.0, 1.0 if k == 1 else 0.0, 1.0 if k == 2 else 0.0)
        col = k_apply(inv_ma, inv_ia, ra, inv_mb, inv_ib, rb, e)
        K[0, k] = col[0]
        K[1, k] = col[1]
        K[2, k] = col[2]
    return K


@jit
def advance_bodies(dt, fixed, pos, vel, ang_vel, ori, inertia0, inv_inertia0, inv_inertia):
    """Positions and orientations after the impulse phase (article §8.4-8.7); updates ``inv_inertia``.

    X <- X + V dt; q <- dq(w dt) * q (Hamilton product, renormalised). The angular momentum
    L = I(q_old) w is kept through the rotation, w <- I(q_new)^-1 L, so a free body conserves
    L exactly (the article keeps w itself; the two agree for rotation about a principal axis).
    ``inv_inertia`` (nb, 3, 3) receives R I0^-1 R^T, the world-frame inverse inertia.
    Shapes: pos/vel/ang_vel (nb, 3) [m, m/s, rad/s], ori (nb, 4), inertia0/inv_inertia0 (nb, 3, 3).
    """
    R = np.empty((3, 3))
    Iw = np.empty((3, 3))
    for b in range(pos.shape[0]):
        if fixed[b]:
            continue
        for k in range(3):
            pos[b, k] += vel[b, k] * dt
        q = (ori[b, 0], ori[b, 1], ori[b, 2], ori[b, 3])
        w = load3(ang_vel, b)
        rotation_matrix(q, R)
        rotate_tensor(R, inertia0[b], Iw)
        L = matvec(Iw, w)
        q = quat_normalized(quat_mul(quat_from_rotvec(scale(w, dt)), q))  # turned by |w| dt about w (§8.5)
        for k in range(4):
            ori[b, k] = q[k]
        rotation_matrix(q, R)
        rotate_tensor(R, inv_inertia0[b], inv_inertia[b])
        w = matvec(inv_inertia[b], L)
        for k in range(3):
            ang_vel[b, k] = w[k]


@jit
def world_inverse_inertia(fixed, ori, inv_inertia0, inv_inertia):
    """``inv_inertia[b] = R_b I0_b^-1 R_b^T`` (zero for fixed bodies), shapes (nb, 4) and (nb, 3, 3)."""
    R = np.empty((3, 3))
    for b in range(ori.shape[0]):
        if fixed[b]:
            inv_inertia[b, :, :] = 0.0
            continue
        rotation_matrix((ori[b, 0], ori[b, 1], ori[b, 2], ori[b, 3]), R)
        rotate_tensor(R, inv_inertia0[b], inv_inertia[b])


def _update_particles(pbody, pos, ori, r0, n0, x, nw):
    """World positions x = X + R r0 and normals n = R n0 of the particles (article §8.7), shapes (np, 3)."""
    for i in prange(pbody.shape[0]):
        b = pbody[i]
        q = (ori[b, 0], ori[b, 1], ori[b, 2], ori[b, 3])
        w, qx, qy, qz = q
        r = load3(r0, i)
        n = load3(n0, i)
        # R v with R from q, written out to stay allocation-free inside prange
        for k in range(3):
            if k == 0:
                row = (1.0 - 2.0 * (qy * qy + qz * qz), 2.0 * (qx * qy - w * qz), 2.0 * (qx * qz + w * qy))
            elif k == 1:
                row = (2.0 * (qx * qy + w * qz), 1.0 - 2.0 * (qx * qx + qz * qz), 2.0 * (qy * qz - w * qx))
            else:
                row = (2.0 * (qx * qz - w * qy), 2.0 * (qy * qz + w * qx), 1.0 - 2.0 * (qx * qx + qy * qy))
            x[i, k] = pos[b, k] + dot(row, r)
            nw[i, k] = dot(row, n)


update_particles, update_particles_par = kernel(_update_particles, over="particles")
