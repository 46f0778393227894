"""Linear elastic-frictional contact: FrictMat, FrictPhys and the Cundall-Strack law.

References:
    P. A. Cundall and O. D. L. Strack (1979), A discrete numerical model for granular
    assemblies, *Geotechnique* 29(1):47-65.
    YADE documentation, sections 3.2 (stiffnesses, (3.2,1)), 3.3.2 (incremental shear)
    and 3.4 (Cundall-Strack law, (3.4,1)-(3.4,2)).
"""

from __future__ import annotations

import math

from granum._jit import jit
from granum.core.arrays import S_DT, SI_TRACK_ENERGY
from granum.core.contacts import (
    F_E_DISSIP,
    F_E_ELAST,
    F_FN,
    F_FS,
    F_KN,
    F_KS,
    F_NORMAL,
    F_PEN,
    F_R1,
    F_R2,
    F_TANPHI,
    FLAG_RADIAL_ARMS,
    I_FLAGS,
)
from granum.physics import materials, registry
from granum.physics.matchmaker import given, pair_value
from granum.physics.registry import Functor, MaterialKind, Param, Range
from granum.physics.scgeom import (
    contact_shift,
    scgeom_incident_vel,
    scgeom_ratchet,
    scgeom_rotate_shear,
    tangential,
)
from granum.physics.vec import dot, norm, scale, sub

registry.register_material(MaterialKind(
    "FrictMat", "ElastMat",
    (Param("frictionAngle", 0.5, "Contact friction angle [rad]",
           valid=Range(0.0, math.pi / 2, why="the Coulomb limit of the shear force is |Fn| tan(frictionAngle), "
                                            "which must not be negative")),),
    columns={"frictionAngle": "friction_angle"},
    doc="Elastic material with Coulomb friction."))
registry.register_phys_type("IPhys")
registry.register_phys_type("NormPhys", "IPhys", {"kn": (F_KN, 1), "normalForce": (F_FN, 3)})
registry.register_phys_type("NormShearPhys", "NormPhys", {"ks": (F_KS, 1), "shearForce": (F_FS, 3)})
registry.register_phys_type("FrictPhys", "NormShearPhys", {"tangensOfFrictionAngle": (F_TANPHI, 1)})

M_FRICTION = materials.column("friction_angle")


@jit
def series_stiffness(e1, l1, e2, l2):
    """Two springs E_i l_i in series: 2 E1 l1 E2 l2 / (E1 l1 + E2 l2); 0 if both vanish."""
    den = e1 * l1 + e2 * l2
    if den == 0.0:
        return 0.0
    return 2.0 * e1 * l1 * e2 * l2 / den


@jit
def pair_friction(prm, slot, row1, row2, phi1, phi2):
    """The friction angle of a contact [rad]: the Ip2's MatchMaker at ``slot`` when given (its algorithm
    combining phi1, phi2), else min(phi1, phi2)."""
    if given(prm, slot):
        return pair_value(prm, slot, row1, row2, phi1, phi2)
    return min(phi1, phi2)


@jit
def phys_frict(c, id1, id2, S, C, prm):
    """FrictPhys constants of a new contact from the materials (YADE (3.2,1) and section 3.2.2).

    .. math::
        k_n = \\frac{2 E_1 r_1 E_2 r_2}{E_1 r_1 + E_2 r_2}, \\quad
        k_s = \\frac{2 E_1 r_1 \\nu_1 E_2 r_2 \\nu_2}{E_1 r_1 \\nu_1 + E_2 r_2 \\nu_2}, \\quad
        \\tan\\varphi = \\tan\\min(\\varphi_1, \\varphi_2)

    r_i are the reference radii of the geometry (a non-positive one is replaced by
    the other: flat bodies borrow the sphere's radius); nu_i is ``poisson``, used
    as the ratio k_s/k_n. ``prm`` is not read: other physics functors (and users' laws) call this.
    """
    f = C.con_f
    r1, r2 = reference_radii(c, C)
    m1 = S.mat[S.material[id1]]
    m2 = S.mat[S.material[id2]]
    e1 = m1[materials.M_YOUNG]
    e2 = m2[materials.M_YOUNG]
    f[c, F_KN] = series_stiffness(e1, r1, e2, r2)
    f[c, F_KS] = series_stiffness(e1 * m1[materials.M_POISSON], r1, e2 * m2[materials.M_POISSON], r2)
    f[c, F_TANPHI] = math.tan(min(m1[M_FRICTION], m2[M_FRICTION]))


@jit
def reference_radii(c, C):
    """The reference radii ``(R1, R2)`` of contact ``c`` [m], a non-positive one (a facet's, a box's) replaced
    by the other."""
    r1 = C.con_f[c, F_R1]
    r2 = C.con_f[c, F_R2]
    if r1 <= 0.0:
        r1 = r2
    if r2 <= 0.0:
        r2 = r1
    return r1, r2


@jit
def phys_frict_ip2(c, id1, id2, S, C, prm):
    """Ip2_FrictMat_FrictMat_FrictPhys: :func:`phys_frict`, then the Ip2's MatchMakers ``kn``, ``ks``,
    ``frictAngle`` when given set the value for the pair of materials instead; their algorithms combine
    E_i r_i, E_i r_i nu_i and phi_i (as YADE)."""
    phys_frict(c, id1, id2, S, C, prm)
    f = C.con_f
    r1, r2 = reference_radii(c, C)
    row1 = S.material[id1]
    row2 = S.material[id2]
    m1 = S.mat[row1]
    m2 = S.mat[row2]
    e1 = m1[materials.M_YOUNG]
    e2 = m2[materials.M_YOUNG]
    if given(prm, IP2_KN):
        f[c, F_KN] = pair_value(prm, IP2_KN, row1, row2, e1 * r1, e2 * r2)
    if given(prm, IP2_KS):
        f[c, F_KS] = pair_value(prm, IP2_KS, row1, row2, e1 * r1 * m1[materials.M_POISSON],
                                e2 * r2 * m2[materials.M_POISSON])
    if given(prm, IP2_FRICT_ANGLE):
        f[c, F_TANPHI] = math.tan(pair_friction(prm, IP2_FRICT_ANGLE, row1, row2, m1[M_FRICTION], m2[M_FRICTION]))


@jit
def law_cundall_strack(c, id1, id2, S, C, prm):
    """Cundall-Strack law on an ScGeom (YADE (3.4,1)-(3.4,2)).

    .. math::
        F_N = k_n \\max(\\delta, 0)\\, n, \\qquad
        F_T \\leftarrow \\mathrm{rot}(F_T) - k_s\\, \\Delta u_T, \\qquad
        |F_T| \\le |F_N| \\tan\\varphi

    F_N and F_T act on body 2 (body 1 gets the opposite). Delta u_T is the tangential
    relative displacement of the step, rot() carries the shear force into the new
    tangent plane. The contact ends when delta < 0 unless ``neverErase`` (prm[NEVER_ERASE]).
    Energies: elastic (|F_N|^2/k_n + |F_T|^2/k_s)/2 and, on slip, the dissipation
    (F_T^trial - F_T)/k_s . F_T.
    """
    f = C.con_f
    pen = f[c, F_PEN]
    if pen < 0.0:
        if prm[NEVER_ERASE] == 0.0:
            return False
        for k in range(6):
            f[c, F_FN + k] = 0.0
        if S.iscal[SI_TRACK_ENERGY]:  # the energy columns exist only then (granum.core.contacts)
            f[c, F_E_ELAST] = 0.0
            f[c, F_E_DISSIP] = 0.0
        return True
    kn = f[c, F_KN]
    ks = f[c, F_KS]
    n = (f[c, F_NORMAL], f[c, F_NORMAL + 1], f[c, F_NORMAL + 2])
    fn = scale(n, kn * pen)
    fs = scgeom_rotate_shear(c, id1, id2, S, C, (f[c, F_FS], f[c, F_FS + 1], f[c, F_FS + 2]))
    shift, shift_vel = contact_shift(c, S, C)
    v = scgeom_incident_vel(c, id1, id2, S, C, shift, shift_vel, scgeom_ratchet(c, C))
    du = scale(tangential(v, n), S.scal[S_DT])
    fs = sub(fs, scale(du, ks))
    max_fs2 = dot(fn, fn) * f[c, F_TANPHI] * f[c, F_TANPHI]
    fs2 = dot(fs, fs)
    dissip = 0.0
    if fs2 > max_fs2:
        trial = fs
        fs = scale(fs, math.sqrt(max_fs2) / math.sqrt(fs2))
        dissip = dot(scale(sub(trial, fs), 1.0 / ks), fs)
    for k in range(3):
        f[c, F_FN + k] = fn[k]
        f[c, F_FS + k] = fs[k]
    if S.iscal[SI_TRACK_ENERGY]:
        elast = 0.5 * dot(fn, fn) / kn if kn > 0.0 else 0.0
        if ks > 0.0:
            elast += 0.5 * norm(fs) ** 2 / ks
        f[c, F_E_ELAST] = elast
        f[c, F_E_DISSIP] = dissip
    # sphericalBodies: YADE's radial lever arms for the torques, flagged once (a store every step would make the
    # row's line dirty: see scgeom_write). The flag is tested first: reading the law's parameter row in every step
    # made the dense lattice's interaction loop 4 % slower (one thread, 1,043 -> 1,002 us a step)
    if not C.con_i[c, I_FLAGS] & FLAG_RADIAL_ARMS and prm[SPHERICAL_BODIES] != 0.0:
        C.con_i[c, I_FLAGS] |= FLAG_RADIAL_ARMS
    return True


#: a per-pair stiffness given by a MatchMaker [N/m]
_STIFFNESS = Range(0.0, why="a negative stiffness pushes along the displacement")
#: a per-pair friction angle given by a MatchMaker [rad]
FRICTION_ANGLE = Range(0.0, math.pi / 2, why="the Coulomb limit |Fn| tan(frictAngle) must not be negative")
#: the Ip2s' ``frictAngle``: a MatchMaker over the two materials' frictionAngle (FrictPhys, CohFrictPhys, MindlinPhys)
FRICT_ANGLE_PARAM = Param("frictAngle", None, "Per-material-pair friction angle (MatchMaker of the materials' "
                          "frictionAngle; None: the min of the two) [rad]", valid=FRICTION_ANGLE, matchmaker="values")
IP2 = Functor(
    "Ip2_FrictMat_FrictMat_FrictPhys", "phys", ("FrictMat", "FrictMat"), "FrictPhys",
    f"{__name__}:phys_frict_ip2",
    (Param("kn", None, "Per-material-pair normal stiffness (MatchMaker of E_i r_i; None: the materials') [N/m]",
           valid=_STIFFNESS, matchmaker="values"),
     Param("ks", None, "Per-material-pair shear stiffness (MatchMaker of E_i r_i nu_i; None: the materials') [N/m]",
           valid=_STIFFNESS, matchmaker="values"),
     FRICT_ANGLE_PARAM),
    phys_frict.py_func.__doc__ + phys_frict_ip2.py_func.__doc__)
registry.register_functor(IP2)
#: places of the Ip2's MatchMakers in its row ``prm``
IP2_KN = IP2.slot("kn")
IP2_KS = IP2.slot("ks")
IP2_FRICT_ANGLE = IP2.slot("frictAngle")
LAW_CS = Functor(
    "Law2_ScGeom_FrictPhys_CundallStrack", "law", ("ScGeom", "FrictPhys"), None,
    f"{__name__}:law_cundall_strack",
    (Param("neverErase", False, "Keep contacts whose penetration became negative [-]"),
     Param("sphericalBodies", True,
           "Torques with lever arms (R_i - delta/2) along the normal (YADE); False: from the contact point [-]"),
     Param("traceEnergy", False, "Accepted for compatibility; energies follow O.trackEnergy [-]")),
    law_cundall_strack.py_func.__doc__)
registry.register_functor(LAW_CS)
#: places of Law2_ScGeom_FrictPhys_CundallStrack's parameters in its row ``prm``
NEVER_ERASE = LAW_CS.slot("neverErase")
SPHERICAL_BODIES = LAW_CS.slot("sphericalBodies")
