"""The extended Hertz-Mindlin law: the conical damage model (CDM) in the normal direction and a
pressure-dependent friction coefficient in the tangential one (YADE's FrictMatCDM, MindlinPhysCDM,
Ip2_FrictMatCDM_FrictMatCDM_MindlinPhysCDM, Ip2_FrictMat_FrictMatCDM_MindlinPhysCDM,
Law2_ScGeom_MindlinPhysCDM_HertzMindlinCDM).

Contact constants (the Ip2s): E* and G* as Hertz-Mindlin's (:func:`granum.physics.mindlin.hertz_moduli`),
R_0 = R1 R2 / (R1 + R2) from the geometry's reference radii, and from the materials (two FrictMatCDMs: the
smaller value of each; a FrictMat with a FrictMatCDM: the FrictMatCDM's sigma_max and alpha, c1 = c2 = 0):

.. math::
    \\sigma_{max} = \\min(\\sigma_{max,1}, \\sigma_{max,2}),\\quad
    a_f = \\frac{1 - \\sin\\alpha}{\\sin\\alpha},\\quad \\alpha = \\min(\\alpha_1, \\alpha_2),\\quad
    \\mu_0 = \\tan\\min(\\varphi_1, \\varphi_2)

Normal direction, the conical damage model (Harkness et al. 2016): each particle's surface is a cone of
half-angle alpha capped by a sphere; when the Hertzian peak pressure p_0 exceeds the material strength
sigma_max, the tip is crushed: the curvature radius R of the contact grows from R_0 and the crushed
height is a plastic overlap. With the overlap delta:

.. math::
    \\delta_{el} = \\delta - (R - R_0)\\, a_f,\\qquad p_0 = \\frac{2 E^*}{\\pi}\\sqrt{\\frac{\\delta_{el}}{R}}

and when p_0 > sigma_max (the contact yields), R grows to the radius at which p_0 = sigma_max:

.. math::
    R = \\frac{\\delta + R_0 a_f}{(\\pi \\sigma_{max} / (2 E^*))^2 + a_f}

R never shrinks: on unloading the damage stays and the contact is elastic with the damaged R. Then

.. math::
    F_n = \\tfrac43 E^* \\sqrt{R}\\, \\delta_{el}^{3/2},\\quad k_n = F_n / \\delta_{el},\\quad
    k_s = 8 G^* \\sqrt{R \\delta_{el}}

and no force (k_n = k_s = 0) while delta_el <= 0 (the overlap is all plastic).

Tangential direction: an incremental shear force F_s <- rot(F_s) - k_s v_s dt (v_s the relative shear
velocity of the geometry), limited by the pressure-dependent friction coefficient of Suhr & Six (2016),
with the mean contact pressure sigma = F_n / (pi R delta_el) (= F_n / (pi a^2), a the contact radius):

.. math::
    \\mu = \\mu_0 + \\frac{c_1}{1 + c_2\\, \\sigma},\\qquad |F_s| \\le \\mu F_n

(c1 = 0: constant mu_0; c2 = 0: mu_0 + c1). This law has no damping, adhesion, moments or energies
(as YADE's). The formulas were measured on YADE 2023.02a (tests/reference/yade/cdm.py: granum agrees to
1e-10), with what YADE refuses, which it does by aborting: sigma_max >= E* of the pair (also YADE's default
1e99, which its documentation says switches the model off), sigma_max <= 0 and alpha outside (0, pi/2).

References (as YADE's class documentation cites them; the papers were not at hand, the formulas above are
YADE 2023.02a's, measured):
    J. Harkness, A. Zervos, L. Le Pen, S. Aingaran, W. Powrie (2016), Discrete element simulation of railway
    ballast: modelling cell pressure effects in triaxial tests, *Granular Matter* 18:65 (the conical damage
    model). B. Suhr, K. Six (2016), On the effect of stress dependent interparticle friction in direct shear
    tests, *Powder Technol.* 294:211-220. B. Suhr, K. Six (2017), Parametrisation of a DEM model for railway
    ballast under different load cases, *Granular Matter* 19:64. YADE class reference: FrictMatCDM,
    MindlinPhysCDM, Law2_ScGeom_MindlinPhysCDM_HertzMindlinCDM.
"""

from __future__ import annotations

import math
from dataclasses import replace

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
    F_TANPHI,
    register_history,
)
from granum.physics import materials, registry
from granum.physics.frict import FRICT_ANGLE_PARAM, M_FRICTION, pair_friction, reference_radii
from granum.physics.l3geom import load_row, store_row
from granum.physics.materials import NON_NEGATIVE
from granum.physics.mindlin import (
    F_ADH,
    F_KNO,
    F_KSO,
    F_MINDLIN_END,
    F_RADIUS,
    F_SHEAR_EL,
    F_SLIDING,
    check_poisson,
    hertz_moduli,
    material_name,
    scene_material_rows,
    separated,
)
from granum.physics.registry import Functor, MaterialKind, Param, Range
from granum.physics.scgeom import (
    contact_shift,
    rotate_tangential,
    scgeom_incident_vel,
    scgeom_ratchet,
    scgeom_shear_rotation,
)
from granum.physics.vec import add, dot, scale, sub

registry.register_material(MaterialKind(
    "FrictMatCDM", "FrictMat",
    (Param("sigmaMax", 1e99, "Compressive strength of the material [Pa]; it must stay below the E* of each "
                             "contact (YADE 2023.02a refuses larger values, its default 1e99 included)",
           valid=Range(0.0, low_open=True, why="the conical damage model crushes the contact where the pressure "
                                                "exceeds sigmaMax")),
     Param("alpha", 1e-6, "Half-angle of the conical asperities [rad], in (0, pi/2)",
           valid=Range(0.0, math.pi / 2, low_open=True, high_open=True,
                       why="the crushed height (R - R0)(1 - sin alpha)/sin alpha needs 0 < sin alpha < 1")),
     Param("c1", 0.0, "Pressure-dependent friction mu = mu0 + c1/(1 + c2 sigma): c1 [-] (0: constant mu0)",
           valid=NON_NEGATIVE),
     Param("c2", 0.0, "Pressure-dependent friction mu = mu0 + c1/(1 + c2 sigma): c2 [1/Pa] (0: mu0 + c1)",
           valid=NON_NEGATIVE)),
    columns={"sigmaMax": "cdm_sigma_max", "alpha": "cdm_alpha", "c1": "cdm_c1", "c2": "cdm_c2"},
    doc="Material of the extended Hertz-Mindlin law: the conical damage model (sigmaMax, alpha) and the "
        "pressure-dependent friction (c1, c2)."))
M_SIGMA_MAX = materials.column("cdm_sigma_max")
M_ALPHA = materials.column("cdm_alpha")
M_C1 = materials.column("cdm_c1")
M_C2 = materials.column("cdm_c2")

#: per-contact columns of MindlinPhysCDM (the group "cdm"), after the Mindlin columns it extends. ScGeom6D's
#: columns start after Mindlin's too (not after these, which would widen every cohesive pool): the interaction
#: loop refuses this law on an ScGeom6D, naming the shared groups (InteractionLoop.check_contact_columns)
F_CDM = register_history("cdm", 9, after=("mindlin",))
F_CDM_E = F_CDM                # E: E* [Pa]
F_CDM_G = F_CDM + 1            # G: G* [Pa]
F_SIGMA_MAX = F_CDM + 2        # sigmaMax: the contact's strength [Pa]
F_ALPHA_FAC = F_CDM + 3        # alphaFac: (1 - sin alpha)/sin alpha [-]
F_CDM_R = F_CDM + 4            # R: curvature radius of the (damaged) contact [m]; R0 is MindlinPhys.radius
F_YIELDING = F_CDM + 5         # isYielding: 1 while the contact is being crushed [-]
F_MU0 = F_CDM + 6              # mu0: tan of the contact's friction angle [-]
F_C1 = F_CDM + 7               # c1 [-]
F_C2 = F_CDM + 8               # c2 [1/Pa]
#: the Mindlin columns (kno, kso, radius, shearElastic, isSliding...) and the CDM ones
HISTORY = ("mindlin", "cdm")

registry.register_phys_type("MindlinPhysCDM", "MindlinPhys", {
    "E": (F_CDM_E, 1), "G": (F_CDM_G, 1), "sigmaMax": (F_SIGMA_MAX, 1), "alphaFac": (F_ALPHA_FAC, 1),
    "R": (F_CDM_R, 1), "isYielding": (F_YIELDING, 1, "bool"), "mu0": (F_MU0, 1), "c1": (F_C1, 1),
    "c2": (F_C2, 1)})


class CdmIp2:
    """Python side of the two CDM Ip2s (a mixin of their YADE classes: ``registry.Functor.python``): before a
    run it refuses, naming the materials and the value, a Poisson's ratio outside [0, 1) and a pair of the
    scene's materials that this Ip2 handles whose sigmaMax is not below their E* (YADE aborts on such a
    contact; p_0 can never reach E*, so a larger strength cannot switch the model off either)."""

    def prepare(self, scene) -> None:
        super().prepare(scene)
        name = type(self).__name__
        check_poisson(name, scene)
        rows = scene_material_rows(scene)
        for i, k1 in enumerate(rows):
            for k2 in rows[i:]:
                self._check_strength(name, scene, k1, k2)

    def _check_strength(self, name: str, scene, k1: int, k2: int) -> None:
        """Refuse the pair of material rows ``k1``, ``k2`` if this Ip2 may handle it with a sigmaMax not
        below their E*: the smaller one of two FrictMatCDMs (CdmPairIp2), body 2's (FrictCdmIp2, which also
        takes two FrictMatCDMs when it is the only CDM Ip2 listed: either may be body 2)."""
        m1, m2 = scene.materials[k1], scene.materials[k2]
        if any("FrictMat" not in registry.material_ancestry(m.kind) for m in (m1, m2)):
            return
        cdm = [float(m.sigmaMax) for m in (m1, m2) if "FrictMatCDM" in registry.material_ancestry(m.kind)]
        if len(cdm) < self._cdm_count:
            return
        sigma_max = min(cdm) if self._cdm_count == 2 else max(cdm)
        e_star = 1.0 / ((1.0 - m1.poisson ** 2) / m1.young + (1.0 - m2.poisson ** 2) / m2.young)
        if not sigma_max < e_star:
            raise ValueError(f"{name}: {material_name(scene, k1)} with {material_name(scene, k2)}: sigmaMax="
                             f"{sigma_max!r} is not below their E* = {e_star!r} Pa; the conical damage model "
                             f"needs sigmaMax < E* (YADE 2023.02a aborts such a contact, its default 1e99 "
                             f"included; a strength the Hertzian pressure never reaches, just below E*, leaves "
                             f"the contacts elastic)")


class CdmPairIp2(CdmIp2):
    """:class:`CdmIp2` of Ip2_FrictMatCDM_FrictMatCDM_MindlinPhysCDM: pairs of two FrictMatCDMs."""

    _cdm_count = 2


class FrictCdmIp2(CdmIp2):
    """:class:`CdmIp2` of Ip2_FrictMat_FrictMatCDM_MindlinPhysCDM: a FrictMatCDM with a FrictMat that is not one."""

    _cdm_count = 1


@jit
def init_cdm(c, id1, id2, S, C, prm, sigma_max, alpha, c1, c2):
    """MindlinPhysCDM constants of a new contact (see the module docstring) from the pair's strength sigma_max
    [Pa], cone angle alpha [rad] and friction parameters c1 [-], c2 [1/Pa]: E*, G*, kno = 4/3 E* sqrt(R0),
    kso = 8 G* sqrt(R0), radius = R = R0, alphaFac, mu0 = tan(phi) (the Ip2's frictAngle MatchMaker when
    given, else the smaller angle); the Mindlin state (shear force, isSliding...) starts at 0."""
    f = C.con_f
    row1 = S.material[id1]
    row2 = S.material[id2]
    m1 = S.mat[row1]
    m2 = S.mat[row2]
    e_star, g_star = hertz_moduli(m1, m2)
    r1, r2 = reference_radii(c, C)
    r0 = r1 * r2 / (r1 + r2)
    mu0 = math.tan(pair_friction(prm, FRICT_ANGLE, row1, row2, m1[M_FRICTION], m2[M_FRICTION]))
    for k in range(F_ADH, F_MINDLIN_END):
        f[c, k] = 0.0
    f[c, F_KNO] = 4.0 / 3.0 * e_star * math.sqrt(r0)
    f[c, F_KSO] = 8.0 * g_star * math.sqrt(r0)
    f[c, F_RADIUS] = r0
    f[c, F_KN] = 0.0
    f[c, F_KS] = 0.0
    f[c, F_TANPHI] = mu0
    f[c, F_CDM_E] = e_star
    f[c, F_CDM_G] = g_star
    f[c, F_SIGMA_MAX] = sigma_max
    sin_alpha = math.sin(alpha)
    f[c, F_ALPHA_FAC] = (1.0 - sin_alpha) / sin_alpha
    f[c, F_CDM_R] = r0
    f[c, F_YIELDING] = 0.0
    f[c, F_MU0] = mu0
    f[c, F_C1] = c1
    f[c, F_C2] = c2


@jit
def phys_cdm_cdm(c, id1, id2, S, C, prm):
    """Ip2_FrictMatCDM_FrictMatCDM_MindlinPhysCDM: :func:`init_cdm` with the smaller sigmaMax, alpha, c1 and
    c2 of the two materials (as YADE 2023.02a)."""
    m1 = S.mat[S.material[id1]]
    m2 = S.mat[S.material[id2]]
    init_cdm(c, id1, id2, S, C, prm, min(m1[M_SIGMA_MAX], m2[M_SIGMA_MAX]), min(m1[M_ALPHA], m2[M_ALPHA]),
             min(m1[M_C1], m2[M_C1]), min(m1[M_C2], m2[M_C2]))


@jit
def phys_frict_cdm(c, id1, id2, S, C, prm):
    """Ip2_FrictMat_FrictMatCDM_MindlinPhysCDM (body 1 the FrictMat, body 2 the FrictMatCDM): :func:`init_cdm`
    with the FrictMatCDM's sigmaMax and alpha and a constant friction coefficient (c1 = c2 = 0), as YADE
    2023.02a. (YADE aborts when the FrictMatCDM body is the interaction's id1; granum takes the materials in
    the functor's order.)"""
    m2 = S.mat[S.material[id2]]
    init_cdm(c, id1, id2, S, C, prm, m2[M_SIGMA_MAX], m2[M_ALPHA], 0.0, 0.0)


IP2_CDM = Functor(
    "Ip2_FrictMatCDM_FrictMatCDM_MindlinPhysCDM", "phys", ("FrictMatCDM", "FrictMatCDM"), "MindlinPhysCDM",
    f"{__name__}:phys_cdm_cdm", (FRICT_ANGLE_PARAM,), "", HISTORY, python=f"{__name__}:CdmPairIp2")
FRICT_ANGLE = IP2_CDM.slot("frictAngle")
registry.register_functor(replace(IP2_CDM, doc=phys_cdm_cdm.py_func.__doc__ + "\n\n" + init_cdm.py_func.__doc__))
IP2_FRICT_CDM = Functor(
    "Ip2_FrictMat_FrictMatCDM_MindlinPhysCDM", "phys", ("FrictMat", "FrictMatCDM"), "MindlinPhysCDM",
    f"{__name__}:phys_frict_cdm", (FRICT_ANGLE_PARAM,), "", HISTORY, python=f"{__name__}:FrictCdmIp2")
if IP2_FRICT_CDM.slot("frictAngle") != FRICT_ANGLE:   # init_cdm reads both Ip2s' rows through one slot
    raise AssertionError("the two CDM Ip2s must keep frictAngle at the same slot")
registry.register_functor(replace(IP2_FRICT_CDM,
                                  doc=phys_frict_cdm.py_func.__doc__ + "\n\n" + init_cdm.py_func.__doc__))

LAW = Functor(
    "Law2_ScGeom_MindlinPhysCDM_HertzMindlinCDM", "law", ("ScGeom", "MindlinPhysCDM"), None,
    f"{__name__}:law_cdm",
    (Param("neverErase", False, "Keep contacts whose overlap became negative, with no force [-]"),),
    "", HISTORY)
NEVER_ERASE = LAW.slot("neverErase")


@jit
def crush(pen, r, r0, alpha_fac, e_star, sigma_max):
    """Conical damage of a contact of overlap ``pen`` [m] and curvature radius ``r`` [m] (initially ``r0``):
    ``(R, delta_el, yielding)``, R grown to the radius at which the Hertzian peak pressure equals
    ``sigma_max`` [Pa] when it exceeds it at ``r`` (see the module docstring)."""
    d_el = pen - (r - r0) * alpha_fac
    if d_el > 0.0 and 2.0 * e_star / math.pi * math.sqrt(d_el / r) > sigma_max:
        k = math.pi * sigma_max / (2.0 * e_star)
        r = (pen + r0 * alpha_fac) / (k * k + alpha_fac)
        return r, pen - (r - r0) * alpha_fac, True
    return r, d_el, False


@jit
def law_cdm(c, id1, id2, S, C, prm):
    """The extended Hertz-Mindlin law on an ScGeom (see the module docstring), forces on body 2; keeps R,
    isYielding, the friction coefficient (tangensOfFrictionAngle), the shear force (also as shearElastic) and
    isSliding, which a contact with no elastic overlap leaves as they were (its forces and stiffnesses are zero;
    the next elastic step starts from the kept shearElastic)."""
    f = C.con_f
    pen = f[c, F_PEN]
    if pen < 0.0:
        return separated(c, S, C, prm[NEVER_ERASE])
    if S.iscal[SI_TRACK_ENERGY]:  # the law reports no energy (as YADE's)
        f[c, F_E_ELAST] = 0.0
        f[c, F_E_DISSIP] = 0.0
    r, d_el, yielding = crush(pen, f[c, F_CDM_R], f[c, F_RADIUS], f[c, F_ALPHA_FAC], f[c, F_CDM_E],
                              f[c, F_SIGMA_MAX])
    f[c, F_CDM_R] = r
    f[c, F_YIELDING] = 1.0 if yielding else 0.0
    if d_el <= 0.0:
        for k in range(6):   # shearElastic keeps its last value (as YADE's)
            f[c, F_FN + k] = 0.0
        f[c, F_KN] = 0.0
        f[c, F_KS] = 0.0
        return True
    sqrt_r = math.sqrt(r)
    sqrt_d = math.sqrt(d_el)
    kn = 4.0 / 3.0 * f[c, F_CDM_E] * sqrt_r * sqrt_d   # F_n / delta_el
    fn = kn * d_el
    ks = 8.0 * f[c, F_CDM_G] * sqrt_r * sqrt_d
    f[c, F_KN] = kn
    f[c, F_KS] = ks
    n = load_row(f, c, F_NORMAL)
    rotation = scgeom_shear_rotation(c, id1, id2, S, C)
    fs = rotate_tangential(load_row(f, c, F_SHEAR_EL), rotation)
    shift, shift_vel = contact_shift(c, S, C)
    v = scgeom_incident_vel(c, id1, id2, S, C, shift, shift_vel, scgeom_ratchet(c, C))
    vs = sub(v, scale(n, dot(v, n)))
    fs = add(fs, scale(vs, -ks * S.scal[S_DT]))
    sigma = kn / (math.pi * r)   # the mean pressure F_n / (pi a^2), a^2 = R delta_el
    mu = f[c, F_MU0] + f[c, F_C1] / (1.0 + f[c, F_C2] * sigma)
    f[c, F_TANPHI] = mu
    max_fs = fn * mu
    sliding = dot(fs, fs) > max_fs * max_fs
    if sliding:
        fs = scale(fs, max_fs / math.sqrt(dot(fs, fs)))
    f[c, F_SLIDING] = 1.0 if sliding else 0.0
    store_row(f, c, F_FN, scale(n, fn))
    store_row(f, c, F_FS, fs)
    store_row(f, c, F_SHEAR_EL, fs)
    return True


registry.register_functor(replace(LAW, doc=law_cdm.py_func.__doc__))
