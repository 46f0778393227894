"""The Cundall-Strack law written as a user's law (granum.yade.userlaws): the formulas of granum's
Law2_ScGeom_FrictPhys_CundallStrack without its energy terms, for the dense-lattice benchmark with
BENCH_LAW=user (same bits and speed as the built-in law)."""

import math

from granum.physics.scgeom import contact_shift, scgeom_incident_vel, scgeom_ratchet, scgeom_rotate_shear, tangential
from granum.physics.vec import dot, scale, sub
from granum.yade.userlaws import F_FN, F_FS, F_KN, F_KS, F_NORMAL, F_PEN, F_TANPHI, FLAG_RADIAL_ARMS, I_FLAGS, S_DT, law


@law(types=("ScGeom", "FrictPhys"), params={"neverErase": False})
def Law2_ScGeom_FrictPhys_UserCundallStrack(c, id1, id2, S, C, prm):
    """F_N = kn max(delta, 0) n; F_T <- rot(F_T) - ks du_T, |F_T| <= |F_N| tan(phi) (YADE (3.4,1)-(3.4,2))."""
    f = C.con_f
    pen = f[c, F_PEN]
    if pen < 0.0:
        if prm[0] == 0.0:
            return False
        for k in range(6):
            f[c, F_FN + k] = 0.0
        return True
    n = (f[c, F_NORMAL], f[c, F_NORMAL + 1], f[c, F_NORMAL + 2])
    fn = scale(n, f[c, F_KN] * pen)
    fs = scgeom_rotate_shear(c, id1, id2, S, C, (f[c, F_FS], f[c, F_FS + 1], f[c, F_FS + 2]))
    shift, shift_vel = contact_shift(c, S, C)
    v = scgeom_incident_vel(c, id1, id2, S, C, shift, shift_vel, scgeom_ratchet(c, C))
    du = scale(tangential(v, n), S.scal[S_DT])
    fs = sub(fs, scale(du, f[c, F_KS]))
    max_fs2 = dot(fn, fn) * f[c, F_TANPHI] * f[c, F_TANPHI]
    fs2 = dot(fs, fs)
    if fs2 > max_fs2:
        fs = scale(fs, math.sqrt(max_fs2) / math.sqrt(fs2))
    for k in range(3):
        f[c, F_FN + k] = fn[k]
        f[c, F_FS + k] = fs[k]
    C.con_i[c, I_FLAGS] |= FLAG_RADIAL_ARMS   # torques with YADE's radial lever arms (sphericalBodies)
    return True
