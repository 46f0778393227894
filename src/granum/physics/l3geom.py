"""L3Geom: contact geometry in local axes, and its elastic-perfectly plastic law.

The contact carries a local frame T (rows: the normal n from body 1 to body 2, then two tangents t1,
t2), the contact point c and the local displacement u = (u_n, u_t1, u_t2) [m]; u0 [m] is its shifted
origin (the equilibrium distance, the plastic slip), so the elastic displacement is u - u0. The tangent
axes follow the rigid motion of the pair, and the shear components of u grow incrementally with the
relative velocity seen in the frame; u_n is recomputed from the positions at every step.

References:
    YADE class reference: L3Geom, Ig2_Sphere_Sphere_L3Geom, Law2_L3Geom_FrictPhys_ElPerfPl
    (documentation of YADE 2023.02a; behaviour checked against it: tests/reference/yade/l3geom.py).
"""

from __future__ import annotations

import math

from granum._jit import jit
from granum.core.arrays import S_DT, SI_ITER, SI_TRACK_ENERGY
from granum.core.contacts import (
    F_E_DISSIP,
    F_E_ELAST,
    F_FN,
    F_FS,
    F_KN,
    F_KS,
    F_NORMAL,
    F_PEN,
    F_POINT,
    F_R1,
    F_R2,
    F_TANPHI,
    FLAG_NEW,
    FLAG_RADIAL_ARMS,
    I_FLAGS,
    register_history,
)
from granum.core.shapes import ShapeKind
from granum.physics import registry
from granum.physics.registry import Functor, Param
from granum.physics.scgeom import contact_shift
from granum.physics.sphere import sphere_pair
from granum.physics.vec import (
    add,
    cross,
    dot,
    load3,
    norm,
    quat_from_rows,
    quat_slerp,
    quat_to_rows,
    scale,
    sub,
)

#: local displacement u (normal, tangent 1, tangent 2) [m]
L3_U = register_history("l3geom", 18, after=("energy",))  # no law with moments uses L3Geom
#: origin of the displacement u0 (equilibrium normal distance, plastic slip) [m]
L3_U0 = L3_U + 3
#: local frame T, row by row (normal, tangent 1, tangent 2) [-]
L3_TRSF = L3_U + 6
#: force on body 1 in local coordinates, F = T f [N] (YADE's debugging field)
L3_F = L3_U + 15
#: the history group of every L3Geom functor
HISTORY = ("l3geom",)

registry.register_geom_type("L3Geom", "GenericSpheresContact",
                            {"u": (L3_U, 3), "u0": (L3_U0, 3), "trsf": (L3_TRSF, 9), "F": (L3_F, 3)})

#: approxMask bits of Ig2_Sphere_Sphere_L3Geom
APPROX_PREV_TRSF = 1     # transform the velocity with the previous frame instead of the mid-step slerp
APPROX_PREV_NORMAL = 2   # take the previous normal instead of the mid-step one
APPROX_NO_RENORM = 4     # do not renormalise the mid-step normal


@jit
def load_row(f, c, col):
    """Columns ``col``..``col + 2`` of row ``c`` of ``f`` as a tuple."""
    return (f[c, col], f[c, col + 1], f[c, col + 2])


@jit
def store_row(f, c, col, v):
    """Write the 3-tuple ``v`` into columns ``col``..``col + 2`` of row ``c`` of ``f``."""
    f[c, col] = v[0]
    f[c, col + 1] = v[1]
    f[c, col + 2] = v[2]


@jit
def orthonormal_tangents(n, t1):
    """Tangents of a frame that drifted from orthonormal, the normal ``n`` kept (Gram-Schmidt): t1 made
    orthogonal to n and normalised, t2 = n x t1."""
    t1 = sub(t1, scale(n, dot(t1, n)))
    t1 = scale(t1, 1.0 / norm(t1))
    return t1, cross(n, t1)


@jit
def initial_frame(n):
    """Tangents of a new contact with normal ``n``: t1 = normalised n x e, e = e_y if |n_y| < |n_z| else e_z
    (t1 lies in the xz or the xy plane), t2 = n x t1."""
    e = (0.0, 1.0, 0.0) if abs(n[1]) < abs(n[2]) else (0.0, 0.0, 1.0)
    return orthonormal_tangents(n, cross(n, e))


@jit
def l3geom_spheres_like(c, id1, id2, shift, S, C, prm, n, point, un, r1, r2):
    """Create or update the L3Geom of contact ``c`` (normal ``n``, contact point ``point`` [m], normal
    displacement ``un`` = distance - (r1 + r2) [m], reference radii ``r1``, ``r2`` [m]).

    A new contact gets the frame of :func:`initial_frame`, u = (u_n, 0, 0) and u0 = (u_n, 0, 0) if
    ``distFactor`` (prm[DIST_FACTOR]) < 0 (the initial distance is the equilibrium one), else 0. An existing
    one, with the previous normal n0 and frame T0 (``approxMask`` = prm[APPROX_MASK] bits in brackets):

    .. math::
        n_m = \\frac{n_0 + n}{|n_0 + n|}\\ [n_m = n_0 \\text{ if } 2;\\ \\text{not normalised if } 4],\\quad
        o_r = n_0 \\times n,\\quad o_t = n_m \\left(n_m \\cdot \\frac{\\omega_1 + \\omega_2}{2}\\right) \\Delta t

        v_r = (v_2 + \\omega_2 \\times b_2) - (v_1 + \\omega_1 \\times b_1),\\quad
        v_r \\leftarrow v_r - (n_m \\cdot v_r)\\, n_m

        T_{i} \\leftarrow T_{0,i} - T_{0,i} \\times o_r - T_{0,i} \\times o_t\\ (i = 1, 2),\\quad T_0 \\leftarrow n

        T_m = \\mathrm{slerp}(q(T_0), q(T), 1/2)\\ [q(T_0) \\text{ if } 1],\\quad
        u \\leftarrow (u_n,\\ u_1 + (T_m v_r)_1 \\Delta t,\\ u_2 + (T_m v_r)_2 \\Delta t)

    with branch vectors b1 = c - x1 and b2 = -r2 n (``noRatch``, prm[NO_RATCH]) or c - x2 (YADE 2023.02a's
    arms: its documentation gives r1 n for b1 with ``noRatch``, its results c - x1); v_2 includes the
    periodic image's velocity; q(T) is the quaternion of T (:func:`quat_from_rows`, not normalised, as the
    rotation matrix T_m is taken from). Every ``trsfRenorm`` (prm[TRSF_RENORM] > 0) steps, when the step counter is a
    multiple of it, the tangents are made orthonormal again (:func:`orthonormal_tangents`). Lever arms of the
    torques are (r_i + u_n/2) n, as YADE's L3Geom.
    """
    f = C.con_f
    flags = C.con_i[c, I_FLAGS]
    store_row(f, c, F_NORMAL, n)
    store_row(f, c, F_POINT, point)
    f[c, F_PEN] = -un   # for the lever arms of the force gather (FLAG_RADIAL_ARMS)
    f[c, F_R1] = r1
    f[c, F_R2] = r2
    approx = int(prm[APPROX_MASK])
    if flags & FLAG_NEW:
        t1, t2 = initial_frame(n)
        store_row(f, c, L3_TRSF, n)
        store_row(f, c, L3_TRSF + 3, t1)
        store_row(f, c, L3_TRSF + 6, t2)
        store_row(f, c, L3_U, (un, 0.0, 0.0))
        store_row(f, c, L3_U0, (un if prm[DIST_FACTOR] < 0.0 else 0.0, 0.0, 0.0))
        if not flags & FLAG_RADIAL_ARMS:
            C.con_i[c, I_FLAGS] = flags | FLAG_RADIAL_ARMS
        return
    dt = S.scal[S_DT]
    n0 = load_row(f, c, L3_TRSF)
    prev1 = load_row(f, c, L3_TRSF + 3)
    prev2 = load_row(f, c, L3_TRSF + 6)
    if approx & APPROX_PREV_NORMAL:
        mid_n = n0
    else:
        mid_n = scale(add(n0, n), 0.5)
        if not approx & APPROX_NO_RENORM:
            mid_n = scale(mid_n, 1.0 / norm(mid_n))
    w1 = load3(S.ang_vel, id1)
    w2 = load3(S.ang_vel, id2)
    rot = cross(n0, n)
    twist = scale(mid_n, dot(mid_n, scale(add(w1, w2), 0.5)) * dt)
    _, shift_vel = contact_shift(c, S, C)
    b1 = sub(point, load3(S.pos, id1))
    b2 = scale(n, -r2) if prm[NO_RATCH] != 0.0 else sub(point, add(load3(S.pos, id2), shift))
    v2 = add(add(load3(S.vel, id2), shift_vel), cross(w2, b2))
    vr = sub(v2, add(load3(S.vel, id1), cross(w1, b1)))
    vr = sub(vr, scale(mid_n, dot(mid_n, vr)))
    t1 = sub(prev1, add(cross(prev1, rot), cross(prev1, twist)))
    t2 = sub(prev2, add(cross(prev2, rot), cross(prev2, twist)))
    renorm = int(prm[TRSF_RENORM])
    if renorm > 0 and S.iscal[SI_ITER] % renorm == 0:
        t1, t2 = orthonormal_tangents(n, t1)
    mid_q = quat_from_rows(n0, prev1, prev2)
    if not approx & APPROX_PREV_TRSF:
        mid_q = quat_slerp(mid_q, quat_from_rows(n, t1, t2), 0.5)
    _, mid1, mid2 = quat_to_rows(mid_q)
    store_row(f, c, L3_TRSF, n)
    store_row(f, c, L3_TRSF + 3, t1)
    store_row(f, c, L3_TRSF + 6, t2)
    f[c, L3_U] = un
    f[c, L3_U + 1] += dot(mid1, vr) * dt
    f[c, L3_U + 2] += dot(mid2, vr) * dt


@jit
def geom_sphere_sphere_l3(c, id1, id2, shift, S, C, prm):
    """Sphere-sphere L3Geom (see :func:`l3geom_spheres_like`).

    .. math::
        u_n = |x_2 - x_1| - (r_1 + r_2),\\quad n = \\frac{x_2 - x_1}{|x_2 - x_1|},\\quad
        c = x_1 + (r_1 + u_n/2)\\, n

    A potential pair becomes real when |x2 - x1| <= |f_d| (r1 + r2), f_d being ``distFactor``
    (prm[DIST_FACTOR]);
    detection (``c`` < 0) returns the separation |x2 - x1| - |f_d| (r1 + r2) [m].
    """
    r1, r2, p1, d, dist = sphere_pair(id1, id2, shift, S)
    if c < 0:
        return dist - abs(prm[DIST_FACTOR]) * (r1 + r2)
    un = dist - (r1 + r2)
    n = scale(d, 1.0 / dist)
    l3geom_spheres_like(c, id1, id2, shift, S, C, prm, n, add(p1, scale(n, r1 + 0.5 * un)), un, r1, r2)
    return 0.0


@jit
def law_l3geom_elperfpl(c, id1, id2, S, C, prm):
    """Elastic-perfectly plastic law on an L3Geom (YADE's Law2_L3Geom_FrictPhys_ElPerfPl).

    .. math::
        F = (k_n (u - u_0)_n,\\ k_s (u - u_0)_{t1},\\ k_s (u - u_0)_{t2}),\\qquad
        |F_t| \\le \\max(0, -F_n) \\tan\\varphi

    F [N] is the force on body 1 in the local frame T (F_n < 0 pushes the bodies apart); body 2 gets
    -T^T F. The contact ends when (u - u0)_n > 0 unless ``noBreak`` (prm[NO_BREAK]). Past the Coulomb limit
    (unless ``noSlip``, prm[NO_SLIP]) the shear is scaled back onto it by r = F_max/|F_t| and the excess
    (1 - r)(u - u0)_t is added to u0 (plastic slip). Energies: elastic (F_n^2/k_n + |F_t|^2/k_s)/2,
    dissipated F_t . Delta u0_t per slip.
    """
    f = C.con_f
    u = load_row(f, c, L3_U)
    u0 = load_row(f, c, L3_U0)
    rel = sub(u, u0)
    if rel[0] > 0.0 and prm[NO_BREAK] == 0.0:
        return False
    kn = f[c, F_KN]
    ks = f[c, F_KS]
    fn = kn * rel[0]
    ft1 = ks * rel[1]
    ft2 = ks * rel[2]
    dissip = 0.0
    if prm[NO_SLIP] == 0.0:
        max_ft = max(0.0, -fn) * f[c, F_TANPHI]
        ft2_sum = ft1 * ft1 + ft2 * ft2
        if ft2_sum > max_ft * max_ft:
            ratio = max_ft / math.sqrt(ft2_sum)
            slip1 = (1.0 - ratio) * rel[1]
            slip2 = (1.0 - ratio) * rel[2]
            f[c, L3_U0 + 1] += slip1
            f[c, L3_U0 + 2] += slip2
            ft1 *= ratio
            ft2 *= ratio
            dissip = ft1 * slip1 + ft2 * slip2
    store_row(f, c, L3_F, (fn, ft1, ft2))
    n = load_row(f, c, L3_TRSF)
    on_first = add(add(scale(n, fn), scale(load_row(f, c, L3_TRSF + 3), ft1)), scale(load_row(f, c, L3_TRSF + 6), ft2))
    normal = load_row(f, c, F_NORMAL)
    normal_part = scale(normal, -dot(on_first, normal))
    store_row(f, c, F_FN, normal_part)
    store_row(f, c, F_FS, sub(scale(on_first, -1.0), normal_part))
    if S.iscal[SI_TRACK_ENERGY]:   # the energy columns exist only then (granum.core.contacts)
        elast = 0.5 * fn * fn / kn if kn > 0.0 else 0.0
        if ks > 0.0:
            elast += 0.5 * (ft1 * ft1 + ft2 * ft2) / ks
        f[c, F_E_ELAST] = elast
        f[c, F_E_DISSIP] = dissip
    return True


_GEOM_PARAMS = (
    Param("noRatch", True, "Branch vectors r1 n and -r2 n in the relative velocity, instead of from the centres "
                           "to the contact point (see Ig2_Sphere_Sphere_ScGeom.avoidGranularRatcheting) [-]"),
    Param("distFactor", 1.0, "Make the contact real when the distance is below |distFactor| (r1 + r2); if "
                             "negative, the initial distance is the equilibrium one (u0) [-]"),
    Param("trsfRenorm", 100, "Make the local frame orthonormal again every this many steps; <= 0: never [-]"),
    Param("approxMask", 0, "Approximations, added bits: 1 previous frame instead of the mid-step slerp, 2 previous "
                           "normal instead of the mid-step one, 4 mid-step normal not renormalised [-]"),
)

IG2_L3 = Functor(
    "Ig2_Sphere_Sphere_L3Geom", "geom", (ShapeKind.SPHERE, ShapeKind.SPHERE), "L3Geom",
    f"{__name__}:geom_sphere_sphere_l3", _GEOM_PARAMS,
    geom_sphere_sphere_l3.py_func.__doc__ + l3geom_spheres_like.py_func.__doc__, HISTORY)
registry.register_functor(IG2_L3)
LAW_L3 = Functor(
    "Law2_L3Geom_FrictPhys_ElPerfPl", "law", ("L3Geom", "FrictPhys"), None,
    f"{__name__}:law_l3geom_elperfpl",
    (Param("noBreak", False, "Keep the contact when the particles separate (it then pulls) [-]"),
     Param("noSlip", False, "No plastic slip: the shear force is not limited [-]")),
    law_l3geom_elperfpl.py_func.__doc__, HISTORY)
registry.register_functor(LAW_L3)
#: places of the functors' parameters in their rows ``prm`` (the geometry's: ``_GEOM_PARAMS``)
NO_RATCH = IG2_L3.slot("noRatch")
DIST_FACTOR = IG2_L3.slot("distFactor")
TRSF_RENORM = IG2_L3.slot("trsfRenorm")
APPROX_MASK = IG2_L3.slot("approxMask")
NO_BREAK = LAW_L3.slot("noBreak")
NO_SLIP = LAW_L3.slot("noSlip")
