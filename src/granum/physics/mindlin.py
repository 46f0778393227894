"""Hertz-Mindlin contacts: MindlinPhys, its Ip2 from two FrictMats and the laws on an ScGeom.

Constants of a contact (``Ip2_FrictMat_FrictMat_MindlinPhys``), from the two materials'
Young's moduli E_i, Poisson's ratios nu_i and the geometry's reference radii R_i:

.. math::
    G_i = \\frac{E_i}{2 (1 + \\nu_i)},\\quad
    E^* = \\frac{E_1 E_2}{(1 - \\nu_1^2) E_2 + (1 - \\nu_2^2) E_1},\\quad
    G^* = \\Big(\\frac{2 - \\nu_1}{G_1} + \\frac{2 - \\nu_2}{G_2}\\Big)^{-1},\\quad
    R^* = \\frac{R_1 R_2}{R_1 + R_2}

    k_{no} = \\tfrac43 E^* \\sqrt{R^*},\\qquad k_{so} = 8 G^* \\sqrt{R^*},\\qquad
    F_{adh} = 4 \\pi R^* \\gamma\\ \\text{(DMT)}

(a non-positive reference radius, a facet's or a box's, is replaced by the other one). The law
(``Law2_ScGeom_MindlinPhys_Mindlin``) with the overlap delta:

.. math::
    F_n = k_{no} \\delta^{3/2} - F_{adh}\\,[\\text{includeAdhesion}],\\quad
    k_n = \\tfrac32 k_{no} \\sqrt\\delta,\\quad k_s = k_{so} \\sqrt\\delta,\\quad
    F_s^{el} \\leftarrow \\mathrm{rot}(F_s^{el}) - k_s\\, v_s\\, \\Delta t

with viscous damping c_n = 2 beta_n sqrt(m k_n), c_s = 2 beta_s sqrt(m k_s) (m: the reduced mass,
or the mass of the only dynamic body), F_N = F_n n - c_n v_n, F_S = F_s^el - c_s v_s, and the Coulomb
limit |F_s^el| <= |F_N| tan(phi) (|F_N| + F_adh with adhesion); a sliding contact has no shear
damping. Without adhesion the normal force never pulls: a negative total is set to zero (the viscous
part then equals the elastic one). beta_n, beta_s are given, or follow from restitution coefficients
e through Thornton et al.'s fit (B6), see :func:`damping_ratio`.

References:
    R. D. Mindlin, H. Deresiewicz (1953), Elastic spheres in contact under varying oblique forces,
    *J. Appl. Mech.* 20:327-344. K. L. Johnson (1985), *Contact Mechanics*, Cambridge (Hertz, DMT).
    C. Thornton, S. J. Cummins, P. W. Cleary (2013), An investigation of the comparative behaviour
    of alternative contact force models during inelastic collisions, *Powder Technol.* 233:30-46,
    appendix B, (B6). YADE class reference: MindlinPhys, Ip2_FrictMat_FrictMat_MindlinPhys,
    Law2_ScGeom_MindlinPhys_Mindlin, Law2_ScGeom_MindlinPhys_HertzWithLinearShear; the details
    (which parameters win, the zero-force clamp, the energies) were checked against YADE 2023.02a
    (tests/reference/yade/mindlin.py).
"""

from __future__ import annotations

import math
from dataclasses import replace

from granum._jit import jit
from granum.core.arrays import S_DT, SI_TRACK_ENERGY
from granum.core.bodies import DOF_ALL
from granum.core.contacts import (
    F_E_DISSIP,
    F_E_ELAST,
    F_FN,
    F_FS,
    F_KN,
    F_KS,
    F_MOMENT,
    F_NORMAL,
    F_PEN,
    F_TANPHI,
    register_history,
    register_totals,
)
from granum.physics import materials, registry
from granum.physics.frict import FRICT_ANGLE_PARAM, M_FRICTION, pair_friction, reference_radii
from granum.physics.l3geom import load_row, store_row
from granum.physics.matchmaker import given, pair_value, refuse_pair
from granum.physics.materials import NON_NEGATIVE
from granum.physics.registry import Functor, Param, Range
from granum.physics.scgeom import (
    contact_shift,
    rotate_tangential,
    scgeom_incident_vel,
    scgeom_ratchet,
    scgeom_rotate_shear,
    scgeom_shear_rotation,
)
from granum.physics.vec import add, dot, load3, scale, sub

#: per-contact columns of MindlinPhys (the group "mindlin"), offsets from F_MINDLIN
F_MINDLIN = register_history("mindlin", 36, after=("energy", "moment"))
F_KNO = F_MINDLIN           # kno: k_no = 4/3 E* sqrt(R*) [N/m^1.5]
F_KSO = F_MINDLIN + 1       # kso: k_so = 8 G* sqrt(R*) [N/m^1.5]
F_ADH = F_MINDLIN + 2       # adhesionForce: DMT pull-off force 4 pi R* gamma [N]
F_BETAN = F_MINDLIN + 3     # betan: normal damping ratio [-]
F_BETAS = F_MINDLIN + 4     # betas: shear damping ratio [-]
F_SHEAR_EL = F_MINDLIN + 5  # 5..7 shearElastic: elastic part of the shear force on body 2 [N]
F_SLIDING = F_MINDLIN + 8   # isSliding: 1 when the Coulomb limit holds the shear force [-]
F_ADHESIVE = F_MINDLIN + 9  # isAdhesive: 1 when the normal force pulls (includeAdhesion) [-]
F_NVISC = F_MINDLIN + 10    # 10..12 normalViscous: viscous part taken off the normal force [N]
F_SVISC = F_MINDLIN + 13    # 13..15 shearViscous: viscous part taken off the shear force [N]
F_US_EL = F_MINDLIN + 16    # 16..18 usElastic: elastic shear displacement [m]
F_US_TOT = F_MINDLIN + 19   # 19..21 usTotal: elastic + plastic shear displacement [m]
F_RADIUS = F_MINDLIN + 22   # radius: contact radius sqrt(delta R*) (only with calcEnergy; else NaN) [m]
#: this contact's share of the law's energy accumulators (calcEnergy), cumulative [J]
F_FRICT_DISSIP = F_MINDLIN + 23
F_SHEAR_ENERGY = F_MINDLIN + 24
F_NDAMP_DISSIP = F_MINDLIN + 25
F_SDAMP_DISSIP = F_MINDLIN + 26
F_KR = F_MINDLIN + 27           # kr: bending (rolling) stiffness of the moment law [N m/rad]
F_KTW = F_MINDLIN + 28          # ktw: twisting stiffness [N m/rad]
F_MAX_BEND = F_MINDLIN + 29     # maxBendPl: eta (R1 + R2)/2, the plastic bending moment per unit normal force [m]
F_MOMENT_BEND = F_MINDLIN + 30  # 30..32 momentBend: bending moment on body 2 [N m]
F_MOMENT_TWIST = F_MINDLIN + 33  # 33..35 momentTwist: twisting moment on body 2 [N m]
F_MINDLIN_END = F_MINDLIN + 36
#: the law's accumulators keep the shares of ended contacts (YADE 2023.02a's, checked)
register_totals("mindlin", F_FRICT_DISSIP, 4)
#: the Mindlin columns, and the contact moment the force gather adds (includeMoment)
HISTORY = ("mindlin", "moment")

registry.register_phys_type("RotStiffFrictPhys", "FrictPhys")
registry.register_phys_type("MindlinPhys", "RotStiffFrictPhys", {
    "kno": (F_KNO, 1), "kso": (F_KSO, 1), "adhesionForce": (F_ADH, 1), "betan": (F_BETAN, 1),
    "betas": (F_BETAS, 1), "shearElastic": (F_SHEAR_EL, 3), "isSliding": (F_SLIDING, 1, "bool"),
    "isAdhesive": (F_ADHESIVE, 1, "bool"), "normalViscous": (F_NVISC, 3), "shearViscous": (F_SVISC, 3),
    "usElastic": (F_US_EL, 3), "usTotal": (F_US_TOT, 3), "radius": (F_RADIUS, 1), "kr": (F_KR, 1),
    "ktw": (F_KTW, 1), "maxBendPl": (F_MAX_BEND, 1), "momentBend": (F_MOMENT_BEND, 3),
    "momentTwist": (F_MOMENT_TWIST, 3)})

#: a restitution coefficient of Hertz-Mindlin damping: 0 would need an infinite damping
_RESTITUTION = Range(0.0, 1.0, low_open=True, why="a restitution coefficient must lie in (0, 1]: 0 needs an "
                                                  "infinite damping and above 1 a collision creates energy")
_RATIO = Range(0.0, why="a negative damping ratio feeds energy into the contact")
#: Poisson's ratios for which E* and G* stay positive (FrictMat itself refuses nu < 0); YADE's examples
#: use nu = 0.6 with Hertz-Mindlin (examples/test/mindlin.py), above the thermodynamic 0.5
HERTZ_POISSON = Range(0.0, 1.0, high_open=True, why="Hertz-Mindlin's E* = 1/((1 - nu1^2)/E1 + (1 - nu2^2)/E2) "
                                                   "needs 1 - nu^2 > 0")


class MindlinIp2:
    """Python side of Ip2_FrictMat_FrictMat_MindlinPhys (a mixin of its YADE class:
    ``registry.Functor.python``): before a run it refuses, naming the value, what the formulas do not hold
    for: its parameters outside their ranges, restitution coefficients given with damping ratios, and a
    material of the scene's bodies whose Poisson's ratio is outside [0, 1)."""

    def prepare(self, scene) -> None:
        super().prepare(scene)   # the MatchMakers' ranges and tables
        name = type(self).__name__
        for p in self.spec.compiled_params():
            if p.valid is not None and not p.matchmaker:
                p.check(name, float(getattr(self, p.name)))
        check_damping(name, self.en, self.es, self.betan, self.betas)
        check_poisson(name, scene)


def scene_material_rows(scene) -> list[int]:
    """The rows of ``scene.materials`` that its live bodies use, in increasing order."""
    b = scene.bodies
    return sorted({int(m) for m in b.material[:b.count][b.alive[:b.count]]})


def material_name(scene, k: int) -> str:
    """How an error names material row ``k``: its row, label and class."""
    mat = scene.materials[k]
    label = f" {mat.label!r}" if getattr(mat, "label", "") else ""
    return f"material {k}{label} ({type(mat).__name__})"


def check_poisson(owner: str, scene) -> None:
    """Raise ValueError, naming ``owner``, the material and the value, when a material of the scene's bodies
    has a Poisson's ratio outside [0, 1) (:data:`HERTZ_POISSON`)."""
    for k in scene_material_rows(scene):
        nu = getattr(scene.materials[k], "poisson", None)
        if nu is not None and not HERTZ_POISSON.holds(float(nu)):
            raise ValueError(f"{owner}: {material_name(scene, k)} has poisson={nu!r}; Hertz-Mindlin needs a "
                             f"Poisson's ratio that {HERTZ_POISSON.says()} ({HERTZ_POISSON.why})")


IP2 = Functor(
    "Ip2_FrictMat_FrictMat_MindlinPhys", "phys", ("FrictMat", "FrictMat"), "MindlinPhys",
    f"{__name__}:phys_mindlin",
    (Param("gamma", 0.0, "Surface energy of DMT adhesion [J/m^2]", valid=NON_NEGATIVE),
     Param("eta", 0.0, "Plastic bending moment coefficient (rolling resistance, includeMoment) [-]",
           valid=NON_NEGATIVE),
     Param("krot", 0.0, "Rotational stiffness of the moment law (includeMoment) [N m/rad]", valid=NON_NEGATIVE),
     Param("ktwist", 0.0, "Twisting stiffness of the moment law (includeMoment) [N m/rad]", valid=NON_NEGATIVE),
     Param("en", None, "Normal restitution coefficient (MatchMaker, supplied no values; None: not given) [-]",
           valid=_RESTITUTION, matchmaker="bare"),
     Param("es", None, "Shear restitution coefficient (MatchMaker, supplied no values; None: not given, then en) "
                       "[-]", valid=_RESTITUTION, matchmaker="bare"),
     Param("betan", None, "Normal viscous damping ratio c_n / c_n,crit (MatchMaker, supplied no values; None: not "
                          "given, 0) [-]", valid=_RATIO, matchmaker="bare"),
     Param("betas", None, "Shear viscous damping ratio (MatchMaker, supplied no values; None: not given, then "
                          "betan) [-]", valid=_RATIO, matchmaker="bare"),
     FRICT_ANGLE_PARAM),
    "", HISTORY, python=f"{__name__}:MindlinIp2")
GAMMA = IP2.slot("gamma")
ETA = IP2.slot("eta")
KROT = IP2.slot("krot")
KTWIST = IP2.slot("ktwist")
EN = IP2.slot("en")
ES = IP2.slot("es")
BETAN = IP2.slot("betan")
BETAS = IP2.slot("betas")
FRICT_ANGLE = IP2.slot("frictAngle")

#: Thornton et al. (2013) (B6): the coefficients h_1..h_10 of their fit of the damping ratio of a
#: Hertzian contact as a function of the restitution coefficient
_THORNTON_H = (-6.918798, -16.41105, 146.8049, -796.4559, 2928.711, -7206.864, 11494.29, -11342.18, 6276.757,
               -1489.915)


@jit
def damping_ratio(e):
    """Damping ratio beta of a Hertz-Mindlin contact whose restitution coefficient is ``e`` (0 < e <= 1),
    Thornton et al. (2013) (B6):

    .. math::
        \\alpha = \\sum_{k=1}^{10} h_k e^k,\\qquad \\beta = \\sqrt{\\frac{1}{1 - (1 + e)^2 e^{\\alpha}} - 1}

    and beta = 0 for e = 1 (no damping, as YADE)."""
    if e >= 1.0:
        return 0.0
    a = 0.0
    for k in range(len(_THORNTON_H) - 1, -1, -1):
        a = e * (_THORNTON_H[k] + a)
    return math.sqrt(1.0 / (1.0 - (1.0 + e) ** 2 * math.exp(a)) - 1.0)


@jit
def damping_ratios(en, es, betan, betas):
    """``(beta_n, beta_s)`` from the Ip2's parameters (NaN: not given), YADE's rules: restitution
    coefficients win (one given serves both directions); otherwise beta_n (0 if not given) and beta_s
    (beta_n if not given). Mixing the two kinds is refused before a run (:func:`check_damping`)."""
    if en == en or es == es:
        return damping_ratio(en if en == en else es), damping_ratio(es if es == es else en)
    bn = betan if betan == betan else 0.0
    return bn, (betas if betas == betas else bn)


def check_damping(owner: str, en, es, betan, betas) -> None:
    """Raise ValueError when restitution coefficients and damping ratios are both given (not None): YADE
    refuses en with betan (es with betas) and silently ignores a ratio given with a restitution coefficient."""
    names = [n for n, v in (("en", en), ("es", es), ("betan", betan), ("betas", betas)) if v is not None]
    if any(n.startswith("e") for n in names) and any(n.startswith("b") for n in names):
        raise ValueError(f"{owner}: give the damping either as restitution coefficients (en, es) or as damping "
                         f"ratios (betan, betas), not both (given: {', '.join(names)})")


@jit
def damping_value(prm, slot, row1, row2):
    """The Ip2's damping MatchMaker at ``slot`` for the material rows; NaN when it is not given or has no
    value for them (:func:`phys_mindlin` tells the two apart)."""
    if given(prm, slot):
        return pair_value(prm, slot, row1, row2, math.nan, math.nan)
    return math.nan


@jit
def reduced_mass(id1, id2, S):
    """Mass of the contact's oscillator [kg]: the dynamic body's when the other is fixed (all degrees of
    freedom blocked), else m1 m2 / (m1 + m2)."""
    m1 = S.mass[id1]
    m2 = S.mass[id2]
    fixed1 = S.blocked[id1] == DOF_ALL
    fixed2 = S.blocked[id2] == DOF_ALL
    if fixed1 and not fixed2:
        return m2
    if fixed2 and not fixed1:
        return m1
    return m1 * m2 / (m1 + m2)


@jit
def effective_radius(c, C):
    """R* = R1 R2 / (R1 + R2) of contact ``c`` [m] (:func:`reference_radii`)."""
    r1, r2 = reference_radii(c, C)
    return r1 * r2 / (r1 + r2)


@jit
def hertz_moduli(m1, m2):
    """``(E*, G*)`` [Pa] of two materials' rows of the material table (see the module docstring):
    E* = E1 E2 / ((1 - nu1^2) E2 + (1 - nu2^2) E1), G* = 1 / ((2 - nu1)/G1 + (2 - nu2)/G2)."""
    e1 = m1[materials.M_YOUNG]
    e2 = m2[materials.M_YOUNG]
    v1 = m1[materials.M_POISSON]
    v2 = m2[materials.M_POISSON]
    g1 = e1 / (2.0 * (1.0 + v1))
    g2 = e2 / (2.0 * (1.0 + v2))
    return e1 * e2 / ((1.0 - v1 * v1) * e2 + (1.0 - v2 * v2) * e1), 1.0 / ((2.0 - v1) / g1 + (2.0 - v2) / g2)


@jit
def phys_mindlin(c, id1, id2, S, C, prm):
    """MindlinPhys constants of a new contact (see the module docstring): kno, kso, the DMT adhesion
    force, the damping ratios, tan(phi) = tan(min(phi_1, phi_2)); kn and ks start at 0 (the law sets
    them from the overlap), the radius at NaN."""
    f = C.con_f
    m1 = S.mat[S.material[id1]]
    m2 = S.mat[S.material[id2]]
    e_star, g_star = hertz_moduli(m1, m2)
    r1, r2 = reference_radii(c, C)
    r = r1 * r2 / (r1 + r2)
    f[c, F_KNO] = 4.0 / 3.0 * e_star * math.sqrt(r)
    f[c, F_KSO] = 8.0 * g_star * math.sqrt(r)
    f[c, F_ADH] = 4.0 * math.pi * r * prm[GAMMA]
    row1 = S.material[id1]
    row2 = S.material[id2]
    en = damping_value(prm, EN, row1, row2)
    es = damping_value(prm, ES, row1, row2)
    betan = damping_value(prm, BETAN, row1, row2)
    betas = damping_value(prm, BETAS, row1, row2)
    if (given(prm, EN) and en != en) or (given(prm, ES) and es != es) or (given(prm, BETAN) and betan != betan) \
            or (given(prm, BETAS) and betas != betas):
        refuse_pair(C, id1, id2)
    bn, bs = damping_ratios(en, es, betan, betas)
    f[c, F_BETAN] = bn
    f[c, F_BETAS] = bs
    f[c, F_KN] = 0.0
    f[c, F_KS] = 0.0
    f[c, F_TANPHI] = math.tan(pair_friction(prm, FRICT_ANGLE, row1, row2, m1[M_FRICTION], m2[M_FRICTION]))
    for k in range(F_SHEAR_EL, F_MINDLIN_END):
        f[c, k] = 0.0
    for k in range(3):
        f[c, F_MOMENT + k] = 0.0
    f[c, F_RADIUS] = math.nan
    f[c, F_KR] = prm[KROT]
    f[c, F_KTW] = prm[KTWIST]
    f[c, F_MAX_BEND] = prm[ETA] * 0.5 * (r1 + r2)


registry.register_functor(replace(IP2, doc=phys_mindlin.py_func.__doc__))

LAW = Functor(
    "Law2_ScGeom_MindlinPhys_Mindlin", "law", ("ScGeom", "MindlinPhys"), None,
    f"{__name__}:law_mindlin",
    (Param("includeAdhesion", False, "DMT adhesion: the normal force less adhesionForce, which may pull [-]"),
     Param("calcEnergy", False, "Accumulate the law's energies (frictionDissipation, shearEnergy, "
                                "normDampDissip, shearDampDissip) and the contact radius [-]"),
     Param("includeMoment", False, "Bending (rolling) and twisting moments with the Ip2's krot, ktwist and the "
                                   "plastic limit eta (R1 + R2)/2 |F_N| (none when eta = 0) [-]"),
     Param("neverErase", False, "Keep contacts whose overlap became negative, with no force [-]"),
     Param("nothing", False, "YADE's placeholder for the deprecated preventGranularRatcheting (no effect) [-]")),
    "", HISTORY)
INCLUDE_ADHESION = LAW.slot("includeAdhesion")
INCLUDE_MOMENT = LAW.slot("includeMoment")
CALC_ENERGY = LAW.slot("calcEnergy")
NEVER_ERASE = LAW.slot("neverErase")


@jit
def separated(c, S, C, never_erase):
    """A contact whose overlap became negative: False (the contact ends), or with ``never_erase`` no force,
    no stiffness, True."""
    if never_erase == 0.0:
        return False
    f = C.con_f
    for k in range(6):
        f[c, F_FN + k] = 0.0
    f[c, F_KN] = 0.0
    f[c, F_KS] = 0.0
    if S.iscal[SI_TRACK_ENERGY]:  # the energy columns exist only then (granum.core.contacts)
        f[c, F_E_ELAST] = 0.0
        f[c, F_E_DISSIP] = 0.0
    return True


@jit
def contact_moments(c, id1, id2, S, C, n, rotation, fn_norm, dt):
    """Bending and twisting moments of contact ``c`` (includeMoment), on body 2 (body 1 gets the opposite),
    from the relative rotation of the step, split along the normal n:

    .. math::
        M_b \\leftarrow \\mathrm{rot}(M_b) - k_r (\\omega_{rel} - (\\omega_{rel}\\cdot n) n) \\Delta t,\\quad
        M_t \\leftarrow \\mathrm{rot}(M_t) - k_{tw} (\\omega_{rel}\\cdot n) n \\Delta t,\\quad
        |M_b| \\le \\mathrm{maxBendPl} |F_N|\\ (\\text{when maxBendPl} > 0)

    with omega_rel = omega_2 - omega_1; rot() is the shear force's rotation. Written to the contact moment
    (:data:`granum.core.contacts.F_MOMENT`) that the force gather adds."""
    f = C.con_f
    w = sub(load3(S.ang_vel, id2), load3(S.ang_vel, id1))
    wn = dot(w, n)
    mb = sub(rotate_tangential(load_row(f, c, F_MOMENT_BEND), rotation), scale(sub(w, scale(n, wn)), f[c, F_KR] * dt))
    mt = sub(rotate_tangential(load_row(f, c, F_MOMENT_TWIST), rotation), scale(n, f[c, F_KTW] * wn * dt))
    max_mb = f[c, F_MAX_BEND] * fn_norm
    mb_norm = math.sqrt(dot(mb, mb))
    if max_mb > 0.0 and mb_norm > max_mb:
        mb = scale(mb, max_mb / mb_norm)
    store_row(f, c, F_MOMENT_BEND, mb)
    store_row(f, c, F_MOMENT_TWIST, mt)
    store_row(f, c, F_MOMENT, add(mb, mt))


@jit
def law_mindlin(c, id1, id2, S, C, prm):
    """Hertz-Mindlin law on an ScGeom (see the module docstring), forces on body 2.

    Besides the forces it keeps YADE's MindlinPhys state: the elastic shear force, the viscous parts,
    the elastic and total shear displacements (u_s -= v_s dt, the elastic one scaled with the force on
    slip), isSliding, isAdhesive. With ``calcEnergy``, this contact's share of the law's accumulators:
    friction dissipation (u_tot - u_tot^prev) . F_s^el on slip, shear elastic energy
    (u_el - u_el^prev) . (F_s^el + F_s^el,prev)/2, normal and shear damping dissipation
    F_visc . v dt, and the contact radius sqrt(delta R*). O.energy gets no term (as in YADE).
    """
    f = C.con_f
    pen = f[c, F_PEN]
    if pen < 0.0:
        return separated(c, S, C, prm[NEVER_ERASE])
    dt = S.scal[S_DT]
    adhesion = prm[INCLUDE_ADHESION] != 0.0
    kno = f[c, F_KNO]
    sqrt_pen = math.sqrt(pen)
    fn_el = kno * pen * sqrt_pen
    if adhesion:
        fn_el -= f[c, F_ADH]
        f[c, F_ADHESIVE] = 1.0 if fn_el < 0.0 else 0.0
    kn = 1.5 * kno * sqrt_pen
    ks = f[c, F_KSO] * sqrt_pen
    f[c, F_KN] = kn
    f[c, F_KS] = ks
    n = load_row(f, c, F_NORMAL)
    rotation = scgeom_shear_rotation(c, id1, id2, S, C)
    fs_el = rotate_tangential(load_row(f, c, F_SHEAR_EL), rotation)
    fs_prev = fs_el
    shift, shift_vel = contact_shift(c, S, C)
    v = scgeom_incident_vel(c, id1, id2, S, C, shift, shift_vel, scgeom_ratchet(c, C))
    vn = scale(n, dot(v, n))
    vs = sub(v, vn)
    du = scale(vs, -dt)
    fs_el = add(fs_el, scale(du, ks))
    # viscous damping
    bn = f[c, F_BETAN]
    bs = f[c, F_BETAS]
    cn = 0.0
    cs = 0.0
    if bn != 0.0 or bs != 0.0:
        m = reduced_mass(id1, id2, S)
        cn = 2.0 * bn * math.sqrt(m * kn)
        cs = 2.0 * bs * math.sqrt(m * ks)
        # the normal dashpot sees the true approach speed (no anti-ratcheting scaling), as in YADE
        vn = scale(n, dot(scgeom_incident_vel(c, id1, id2, S, C, shift, shift_vel, False), n))
    nvisc = scale(vn, cn)
    fn = sub(scale(n, fn_el), nvisc)
    if not adhesion and dot(fn, n) < 0.0:   # no attraction: the viscous part at most cancels the elastic one
        fn = (0.0, 0.0, 0.0)
        nvisc = scale(n, fn_el)
    us_el = rotate_tangential(load_row(f, c, F_US_EL), rotation)
    us_el_prev = us_el
    us_el = add(us_el, du)
    us_tot = rotate_tangential(load_row(f, c, F_US_TOT), rotation)
    us_tot_prev = us_tot
    us_tot = add(us_tot, du)
    # Coulomb
    fn_norm = math.sqrt(dot(fn, fn))
    max_fs = (fn_norm + f[c, F_ADH] if adhesion else fn_norm) * f[c, F_TANPHI]
    svisc = (0.0, 0.0, 0.0)
    sliding = dot(fs_el, fs_el) > max_fs * max_fs
    energy = prm[CALC_ENERGY] != 0.0
    if sliding:
        ratio = max_fs / math.sqrt(dot(fs_el, fs_el))
        fs_el = scale(fs_el, ratio)
        us_el = scale(us_el, ratio)
        fs = fs_el
        if energy:
            f[c, F_FRICT_DISSIP] += dot(sub(us_tot, us_tot_prev), fs_el)
    else:
        svisc = scale(vs, cs)
        fs = sub(fs_el, svisc)
    f[c, F_SLIDING] = 1.0 if sliding else 0.0
    store_row(f, c, F_FN, fn)
    store_row(f, c, F_FS, fs)
    store_row(f, c, F_SHEAR_EL, fs_el)
    if bn != 0.0 or bs != 0.0:   # undamped, the viscous parts stay 0 (the clamp needs a viscous part)
        store_row(f, c, F_NVISC, nvisc)
        store_row(f, c, F_SVISC, svisc)
    store_row(f, c, F_US_EL, us_el)
    store_row(f, c, F_US_TOT, us_tot)
    if energy:
        f[c, F_SHEAR_ENERGY] += 0.5 * dot(sub(us_el, us_el_prev), add(fs_el, fs_prev))
        f[c, F_NDAMP_DISSIP] += dot(nvisc, scale(vn, dt))
        if not sliding:
            f[c, F_SDAMP_DISSIP] += dot(svisc, scale(vs, dt))
        r = effective_radius(c, C)
        f[c, F_RADIUS] = ((fn_el + (f[c, F_ADH] if adhesion else 0.0)) * r ** 1.5 / kno) ** (1.0 / 3.0)
    if prm[INCLUDE_MOMENT] != 0.0:
        contact_moments(c, id1, id2, S, C, n, rotation, math.sqrt(dot(fn, fn)), dt)
    if S.iscal[SI_TRACK_ENERGY]:  # YADE's Mindlin adds nothing to O.energy
        f[c, F_E_ELAST] = 0.0
        f[c, F_E_DISSIP] = 0.0
    return True


registry.register_functor(replace(LAW, doc=law_mindlin.py_func.__doc__))

HWLS = Functor(
    "Law2_ScGeom_MindlinPhys_HertzWithLinearShear", "law", ("ScGeom", "MindlinPhys"), None,
    f"{__name__}:law_hertz_linear_shear",
    (Param("neverErase", False, "Keep contacts whose overlap became negative, with no force [-]"),
     Param("nonLin", 0, "Shear nonlinearity: 0 linear (k = kso), > 0: k = kso sqrt(delta) (YADE 2023.02a gives "
                        "1, 2 and 3 the same forces) [-]")),
    "", HISTORY)
HWLS_NEVER_ERASE = HWLS.slot("neverErase")
NON_LIN = HWLS.slot("nonLin")


@jit
def law_hertz_linear_shear(c, id1, id2, S, C, prm):
    """Hertz normal force with a linear shear spring on an ScGeom (YADE's HertzWithLinearShear):

    .. math::
        F_N = k_{no} \\delta^{3/2} n,\\qquad F_S \\leftarrow \\mathrm{rot}(F_S) - k\\, v_s \\Delta t,\\qquad
        |F_S| \\le |F_N| \\tan\\varphi

    with k = kso (nonLin 0) or kso sqrt(delta) (nonLin > 0); no damping. The phys's kn and ks are left
    as the Ip2 set them (0), as in YADE.
    """
    f = C.con_f
    pen = f[c, F_PEN]
    if pen < 0.0:
        return separated(c, S, C, prm[HWLS_NEVER_ERASE])
    n = load_row(f, c, F_NORMAL)
    sqrt_pen = math.sqrt(pen)
    fn = scale(n, f[c, F_KNO] * pen * sqrt_pen)
    k = f[c, F_KSO] if prm[NON_LIN] == 0.0 else f[c, F_KSO] * sqrt_pen
    fs = scgeom_rotate_shear(c, id1, id2, S, C, load_row(f, c, F_FS))
    shift, shift_vel = contact_shift(c, S, C)
    v = scgeom_incident_vel(c, id1, id2, S, C, shift, shift_vel, scgeom_ratchet(c, C))
    vs = sub(v, scale(n, dot(v, n)))
    fs = sub(fs, scale(vs, k * S.scal[S_DT]))
    max_fs = math.sqrt(dot(fn, fn)) * f[c, F_TANPHI]
    if dot(fs, fs) > max_fs * max_fs:
        fs = scale(fs, max_fs / math.sqrt(dot(fs, fs)))
    store_row(f, c, F_FN, fn)
    store_row(f, c, F_FS, fs)
    if S.iscal[SI_TRACK_ENERGY]:
        f[c, F_E_ELAST] = 0.0
        f[c, F_E_DISSIP] = 0.0
    return True


registry.register_functor(replace(HWLS, doc=law_hertz_linear_shear.py_func.__doc__))
