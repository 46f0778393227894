"""The concrete particle model (CPM): CpmMat, CpmPhys, its Ip2 functors and Law2_ScGeom_CpmPhys_Cpm.

A CPM contact is a cohesive link formulated in strains and stresses over an equivalent cross-section.
It softens by damage in tension and is plastic in shear (Mohr-Coulomb, with the cohesion damaged) and,
optionally, in compression.

**Constants** (Ip2_CpmMat_CpmMat_CpmPhys, at creation; the materials' parameters are averaged
arithmetically, a copy for one shared material). With the ScGeom's radii r1, r2, its penetration depth
delta_0 and the distance of the centres d_0 then:

.. math::
    E = \\bar E,\\quad G = \\bar E\\,\\bar\\nu,\\quad \\tan\\varphi = \\tan\\bar\\varphi,\\quad
    c_T = \\bar\\sigma_T,\\quad \\varepsilon_0 = \\bar\\varepsilon_{crack},\\quad
    \\varepsilon_f = \\overline{\\text{relDuctility}}\\ \\varepsilon_0

    A = \\pi \\min(r_1, r_2)^2,\\quad l_0 = d_0,\\quad k_n = A E / l_0,\\quad k_s = A G / l_0

``neverDamage`` if either material has it; the contact is cohesive when ``cohesiveThresholdIter`` < 0 or
the step is before it.

**Law** (Law2_ScGeom_CpmPhys_Cpm), at every step, with the isotropic prestress p (``isoPrestress``):

.. math::
    \\varepsilon_N = -\\frac{\\delta - \\delta_0}{l_0} + \\frac{p}{E},\\qquad
    \\boldsymbol\\varepsilon_T \\leftarrow \\mathrm{rot}(\\boldsymbol\\varepsilon_T) + \\frac{\\Delta\\mathbf u_T}{l_0}

(Delta u_T: the step's tangential displacement of body 2 relative to body 1; the plastic shear strain is not
carried into the new tangent plane, as in YADE). Compression plasticity (``epsSoft`` < 0): where
epsilon_N - epsilon_N^pl < epsSoft, the normal stress is at most
E (epsSoft + relKnSoft (epsilon_N - epsilon_N^pl - epsSoft)) in magnitude, the excess going to
epsilon_N^pl. Damage: kappa_D is the largest equivalent strain so far,

.. math::
    \\tilde\\varepsilon = \\sqrt{\\langle\\varepsilon_N\\rangle^2 + (\\xi |\\boldsymbol\\varepsilon_T|)^2},\\qquad
    \\omega = g(\\kappa_D) = \\begin{cases}
        1 - \\frac{\\varepsilon_0}{\\kappa_D} e^{-(\\kappa_D - \\varepsilon_0)/\\varepsilon_f} & \\text{damLaw 1} \\\\
        \\min\\big(1, \\frac{\\varepsilon_f}{\\kappa_D} \\frac{\\kappa_D - \\varepsilon_0}{\\varepsilon_f -
        \\varepsilon_0}\\big) & \\text{damLaw 0 (linear softening)}
    \\end{cases}\\quad (\\kappa_D > \\varepsilon_0;\\ 0 \\text{ below})

(xi: ``equivStrainShearContrib``; omega = 0 with ``neverDamage``, 1 for a non-cohesive contact). Stresses:

.. math::
    \\sigma_N = (1 - \\omega [\\varepsilon_N > 0]) E (\\varepsilon_N - \\varepsilon_N^{pl}),\\qquad
    \\boldsymbol\\sigma_T = G (\\boldsymbol\\varepsilon_T - \\boldsymbol\\varepsilon_T^{pl}),\\qquad
    |\\boldsymbol\\sigma_T| \\le \\max(0,\\ c_T (1 - \\omega) - \\sigma_N \\tan\\varphi)

(returned by the ratio r = yield / |sigma_T^trial|; epsilon_T^pl grows by (1 - r) sigma_T / G of the returned stress,
YADE's increment), then sigma_N -= p. The forces on body 2 are
-A sigma_N n and -A sigma_T (``Fn`` = A sigma_N, ``Fs`` = A sigma_T; tension positive). The relative
residual strength is (1 - omega) kappa_D / epsilon_0 past the crack onset, 1 before it, 0 for a non-cohesive
contact. The contact ends when epsilon_N > 0 and it is not cohesive or omega > ``omegaThreshold``; both
bodies' ``CpmState.numBrokenCohesive`` count it (YADE counts every contact the law ends). As in YADE, the law adds
nothing to ``O.energy`` (its elastic energy: ``Law2_ScGeom_CpmPhys_Cpm.elasticEnergy()``).

YADE 2023.02a's build has the public model only: the yield surfaces other than Mohr-Coulomb
(``yieldSurfType``, ``yieldLogSpeed``, ``yieldEllipseShift``) and the rate dependence (``dmgTau``,
``dmgRateExp``, ``plTau``, ``plRateExp``) change nothing there (checked: ``rate_equals_tension`` in the
reference data); granum refuses values other than their defaults instead of ignoring them.

References:
    V. Šmilauer (2010), *Cohesive particle model using the discrete element method on the Yade platform*,
    PhD thesis, CTU Prague and Université Grenoble I; YADE documentation (3.2.1.1 and (3.3,3): the
    equivalent cross-section), class reference of CpmMat, CpmPhys, Ip2_CpmMat_CpmMat_CpmPhys,
    Law2_ScGeom_CpmPhys_Cpm, CpmStateUpdater. The details (averaging, prestress, equivalent strain, the
    counts, the residual strength) were checked step by step against YADE 2023.02a:
    tests/reference/yade/cpm.py.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from granum._jit import jit
from granum.core.arrays import S_DT, SI_ITER
from granum.core.atomic import fetch_add
from granum.core.bodies import CPM_IS_STATE
from granum.core.contacts import (
    F_FN,
    F_FS,
    F_KN,
    F_KS,
    F_NORMAL,
    F_PEN,
    F_R1,
    F_R2,
    F_TANPHI,
    register_history,
)
from granum.physics import materials, registry
from granum.physics.frict import M_FRICTION, phys_frict
from granum.physics.l3geom import load_row, store_row
from granum.physics.materials import NON_NEGATIVE
from granum.physics.registry import Functor, MaterialKind, Param, Range
from granum.physics.scgeom import (
    contact_shift,
    rotate_tangential,
    scgeom_incident_vel,
    scgeom_ratchet,
    scgeom_shear_rotation,
    tangential,
)
from granum.physics.vec import add, dot, load3, norm, scale, sub

_NAN = float("nan")
#: YADE's public build ignores these (see the module docstring): only their defaults are accepted
_PUBLIC_ONLY = " (YADE 2023.02a's public CPM ignores it; granum accepts only the default)"

registry.register_material(MaterialKind(
    "CpmMat", "FrictMat",
    (Param("density", 4800.0, "Density [kg/m^3]; 4800 gives about 2800 on a packing of density 0.58",
           valid=Range(0.0, why="a negative density gives a negative mass")),
     Param("sigmaT", _NAN, "Initial cohesion (tensile strength) [Pa]; NaN: not given", valid=NON_NEGATIVE),
     Param("neverDamage", False, "No damage ever (for testing) [-]"),
     Param("epsCrackOnset", _NAN, "Limit elastic strain, where damage starts [-]; NaN: not given",
           valid=NON_NEGATIVE),
     Param("relDuctility", _NAN, "Relative ductility: the fracture strain is it times epsCrackOnset [-]",
           valid=NON_NEGATIVE),
     Param("equivStrainShearContrib", 0.0, "Weight of the shear strain in the equivalent strain [-]",
           valid=NON_NEGATIVE),
     Param("damLaw", 1, "Damage evolution in tension: 0 linear softening, 1 exponential [-]",
           valid=Range(0.0, 1.0, why="0 (linear softening) and 1 (exponential) are the damage laws")),
     Param("dmgTau", -1.0, "Characteristic time of damage viscosity [s]" + _PUBLIC_ONLY, supported=False),
     Param("dmgRateExp", 0.0, "Exponent of damage viscosity [-]" + _PUBLIC_ONLY, supported=False),
     Param("plTau", -1.0, "Characteristic time of visco-plasticity [s]" + _PUBLIC_ONLY, supported=False),
     Param("plRateExp", 0.0, "Exponent of visco-plasticity [-]" + _PUBLIC_ONLY, supported=False),
     Param("isoPrestress", 0.0, "Isotropic prestress of the whole specimen (negative: compression) [Pa]",
           valid=Range())),
    columns={"sigmaT": "cpm_sigma_t", "neverDamage": "cpm_never_damage", "epsCrackOnset": "cpm_eps_crack",
             "relDuctility": "cpm_rel_ductility", "equivStrainShearContrib": "cpm_shear_contrib",
             "damLaw": "cpm_dam_law", "dmgTau": "cpm_dmg_tau", "dmgRateExp": "cpm_dmg_rate_exp",
             "plTau": "cpm_pl_tau", "plRateExp": "cpm_pl_rate_exp", "isoPrestress": "cpm_iso_prestress"},
    doc="Concrete material of the concrete particle model (CPM); its bodies get a CpmState.\n\n" + __doc__))

M_SIGMA_T = materials.column("cpm_sigma_t")
M_NEVER_DAMAGE = materials.column("cpm_never_damage")
M_EPS_CRACK = materials.column("cpm_eps_crack")
M_REL_DUCTILITY = materials.column("cpm_rel_ductility")
M_SHEAR_CONTRIB = materials.column("cpm_shear_contrib")
M_DAM_LAW = materials.column("cpm_dam_law")
M_DMG_TAU = materials.column("cpm_dmg_tau")
M_DMG_RATE_EXP = materials.column("cpm_dmg_rate_exp")
M_PL_TAU = materials.column("cpm_pl_tau")
M_PL_RATE_EXP = materials.column("cpm_pl_rate_exp")
M_ISO_PRESTRESS = materials.column("cpm_iso_prestress")

#: the CpmPhys columns (after the energies: the law writes no moment; they share their columns with the
#: other laws' histories, which no CPM contact uses)
CPM_WIDTH = 39                     # columns of the group
CPM_E = register_history("cpm", CPM_WIDTH, after=("energy",))   # normal modulus [Pa]
CPM_G = CPM_E + 1                  # shear modulus [Pa]
CPM_CROSS_SECTION = CPM_E + 2      # equivalent cross-section A [m^2]
CPM_REF_LENGTH = CPM_E + 3         # distance of the centres at creation l_0 [m]
CPM_REF_PD = CPM_E + 4             # penetration depth at creation delta_0 [m]
CPM_EPS_FRACTURE = CPM_E + 5       # epsilon_f [-]
CPM_COHESION = CPM_E + 6           # undamaged cohesion c_T [Pa]
CPM_EPS_CRACK = CPM_E + 7          # epsilon_0 [-]
CPM_REL_DUCTILITY = CPM_E + 8      # [-]
CPM_ISO_PRESTRESS = CPM_E + 9      # p [Pa]
CPM_SHEAR_CONTRIB = CPM_E + 10     # xi [-]
CPM_DAM_LAW = CPM_E + 11           # 0 linear, 1 exponential [-]
CPM_NEVER_DAMAGE = CPM_E + 12      # 1: omega stays 0 [-]
CPM_IS_COHESIVE = CPM_E + 13       # 1: cohesive [-]
CPM_DMG_TAU = CPM_E + 14           # YADE's CpmPhys.dmgTau (the public model does not use it) [s]
CPM_DMG_RATE_EXP = CPM_E + 15      # dmgRateExp (unused) [-]
CPM_PL_TAU = CPM_E + 16            # plTau (unused) [s]
CPM_PL_RATE_EXP = CPM_E + 17       # plRateExp (unused) [-]
CPM_DMG_STRAIN = CPM_E + 18        # dmgStrain (the rate-dependent model's; 0 here) [-]
CPM_DMG_OVERSTRESS = CPM_E + 19    # dmgOverstress (0 here) [Pa]
CPM_OMEGA = CPM_E + 20             # damage omega [-]
CPM_FN = CPM_E + 21                # Fn = A sigma_N (tension positive) [N]
CPM_FS = CPM_E + 22                # 22..24 Fs = A sigma_T [N]
CPM_EPS_N = CPM_E + 25             # epsilon_N [-]
CPM_EPS_T = CPM_E + 26             # 26..28 epsilon_T [-]
CPM_SIGMA_N = CPM_E + 29           # sigma_N [Pa]
CPM_SIGMA_T = CPM_E + 30           # 30..32 sigma_T [Pa]
CPM_KAPPA_D = CPM_E + 33           # kappa_D, the largest equivalent strain so far [-]
CPM_EPS_N_PL = CPM_E + 34          # epsilon_N^pl [-]
CPM_EPS_T_PL = CPM_E + 35          # 35..37 epsilon_T^pl [-]
CPM_REL_RESIDUAL = CPM_E + 38      # relative residual strength [-]
HISTORY = ("cpm",)

_BOOL = "bool"
registry.register_phys_type("CpmPhys", "NormShearPhys", {
    "E": (CPM_E, 1), "G": (CPM_G, 1), "tanFrictionAngle": (F_TANPHI, 1), "undamagedCohesion": (CPM_COHESION, 1),
    "crossSection": (CPM_CROSS_SECTION, 1), "refLength": (CPM_REF_LENGTH, 1), "refPD": (CPM_REF_PD, 1),
    "epsCrackOnset": (CPM_EPS_CRACK, 1), "relDuctility": (CPM_REL_DUCTILITY, 1),
    "epsFracture": (CPM_EPS_FRACTURE, 1), "equivStrainShearContrib": (CPM_SHEAR_CONTRIB, 1),
    "dmgTau": (CPM_DMG_TAU, 1), "dmgRateExp": (CPM_DMG_RATE_EXP, 1), "dmgStrain": (CPM_DMG_STRAIN, 1),
    "dmgOverstress": (CPM_DMG_OVERSTRESS, 1), "plTau": (CPM_PL_TAU, 1), "plRateExp": (CPM_PL_RATE_EXP, 1),
    "isoPrestress": (CPM_ISO_PRESTRESS, 1), "neverDamage": (CPM_NEVER_DAMAGE, 1, _BOOL),
    "damLaw": (CPM_DAM_LAW, 1, "int"), "isCohesive": (CPM_IS_COHESIVE, 1, _BOOL), "omega": (CPM_OMEGA, 1),
    "Fn": (CPM_FN, 1), "Fs": (CPM_FS, 3), "epsN": (CPM_EPS_N, 1), "epsT": (CPM_EPS_T, 3),
    "sigmaN": (CPM_SIGMA_N, 1), "sigmaT": (CPM_SIGMA_T, 3), "kappaD": (CPM_KAPPA_D, 1),
    "epsNPl": (CPM_EPS_N_PL, 1), "epsTPl": (CPM_EPS_T_PL, 3), "relResidualStrength": (CPM_REL_RESIDUAL, 1)})


@jit
def mean(a, b):
    """Arithmetic mean of two materials' parameters (a copy when they are equal, as for a shared material)."""
    return a if a == b else 0.5 * (a + b)


@jit
def phys_cpm(c, id1, id2, S, C, prm):
    """CpmPhys of a new contact (module docstring: the constants)."""
    f = C.con_f
    m1 = S.mat[S.material[id1]]
    m2 = S.mat[S.material[id2]]
    young = mean(m1[materials.M_YOUNG], m2[materials.M_YOUNG])
    shear = young * mean(m1[materials.M_POISSON], m2[materials.M_POISSON])
    eps_crack = mean(m1[M_EPS_CRACK], m2[M_EPS_CRACK])
    ductility = mean(m1[M_REL_DUCTILITY], m2[M_REL_DUCTILITY])
    r = min(f[c, F_R1], f[c, F_R2])
    area = math.pi * r * r
    shift, _ = contact_shift(c, S, C)
    length = norm(sub(add(load3(S.pos, id2), shift), load3(S.pos, id1)))
    f[c, CPM_E] = young
    f[c, CPM_G] = shear
    f[c, F_TANPHI] = math.tan(mean(m1[M_FRICTION], m2[M_FRICTION]))
    f[c, CPM_COHESION] = mean(m1[M_SIGMA_T], m2[M_SIGMA_T])
    f[c, CPM_EPS_CRACK] = eps_crack
    f[c, CPM_REL_DUCTILITY] = ductility
    f[c, CPM_EPS_FRACTURE] = ductility * eps_crack
    f[c, CPM_ISO_PRESTRESS] = mean(m1[M_ISO_PRESTRESS], m2[M_ISO_PRESTRESS])
    f[c, CPM_SHEAR_CONTRIB] = mean(m1[M_SHEAR_CONTRIB], m2[M_SHEAR_CONTRIB])
    f[c, CPM_DAM_LAW] = m1[M_DAM_LAW]   # the materials' agree (CpmIp2.prepare)
    f[c, CPM_NEVER_DAMAGE] = 1.0 if m1[M_NEVER_DAMAGE] != 0.0 or m2[M_NEVER_DAMAGE] != 0.0 else 0.0
    f[c, CPM_DMG_TAU] = mean(m1[M_DMG_TAU], m2[M_DMG_TAU])
    f[c, CPM_DMG_RATE_EXP] = mean(m1[M_DMG_RATE_EXP], m2[M_DMG_RATE_EXP])
    f[c, CPM_PL_TAU] = mean(m1[M_PL_TAU], m2[M_PL_TAU])
    f[c, CPM_PL_RATE_EXP] = mean(m1[M_PL_RATE_EXP], m2[M_PL_RATE_EXP])
    threshold = prm[IP2_COHESIVE_THRESHOLD]
    f[c, CPM_IS_COHESIVE] = 1.0 if threshold < 0.0 or S.iscal[SI_ITER] < threshold else 0.0
    f[c, CPM_CROSS_SECTION] = area
    f[c, CPM_REF_LENGTH] = length
    f[c, CPM_REF_PD] = f[c, F_PEN]
    f[c, F_KN] = area * young / length
    f[c, F_KS] = area * shear / length
    f[c, CPM_REL_RESIDUAL] = 1.0 if f[c, CPM_IS_COHESIVE] != 0.0 else 0.0


@jit
def damage(kappa, eps_crack, eps_fracture, never_damage, linear):
    """Damage omega = g(kappa_D) of the module docstring (YADE's CpmPhys.funcG) [-]."""
    if kappa <= eps_crack or never_damage:
        return 0.0
    if linear:   # not bounded by 1 past eps_fracture, as YADE's (the contact then ends, omega > omegaThreshold)
        return eps_fracture / kappa * (kappa - eps_crack) / (eps_fracture - eps_crack)
    return 1.0 - eps_crack / kappa * math.exp(-(kappa - eps_crack) / eps_fracture)


@jit
def damage_inverse(omega, eps_crack, eps_fracture, never_damage=False, dam_law=1):
    """kappa_D whose damage is ``omega`` (YADE's CpmPhys.funcGInv): 0 for omega <= 0 or with ``never_damage``;
    the linear law in closed form, the exponential one by Newton's method from the crack onset (g is increasing
    and concave there) [-]."""
    if omega <= 0.0 or never_damage:
        return 0.0
    if dam_law == 0:
        return eps_fracture * eps_crack / (eps_fracture - omega * (eps_fracture - eps_crack))
    kappa = eps_crack
    for _ in range(100):
        g = damage(kappa, eps_crack, eps_fracture, False, False) if kappa > eps_crack else 0.0
        slope = eps_crack / kappa * math.exp(-(kappa - eps_crack) / eps_fracture) * (1.0 / kappa + 1.0 / eps_fracture)
        step = (omega - g) / slope
        kappa += step
        if abs(step) <= 1e-15 * kappa:
            break
    return kappa


@jit
def count_broken(S, id1, id2):
    """Count the ended contact on both bodies' CpmState.numBrokenCohesive (atomically: the law runs in
    parallel over contacts, and integer counts do not depend on the order). Bodies whose count column is
    not allocated (no CpmState in the scene) are skipped."""
    broken = S.cpm_broken
    if id1 < broken.shape[0]:
        fetch_add(broken, id1, 1)
    if id2 < broken.shape[0]:
        fetch_add(broken, id2, 1)


@jit
def law_cpm(c, id1, id2, S, C, prm):
    """Law2_ScGeom_CpmPhys_Cpm (module docstring); returns False when the contact ends."""
    f = C.con_f
    young = f[c, CPM_E]
    shear = f[c, CPM_G]
    length = f[c, CPM_REF_LENGTH]
    iso = f[c, CPM_ISO_PRESTRESS]
    cohesive = f[c, CPM_IS_COHESIVE] != 0.0
    eps_crack = f[c, CPM_EPS_CRACK]
    n = load_row(f, c, F_NORMAL)
    eps_n = -(f[c, F_PEN] - f[c, CPM_REF_PD]) / length + iso / young
    rotation = scgeom_shear_rotation(c, id1, id2, S, C)
    shift, shift_vel = contact_shift(c, S, C)
    v = scgeom_incident_vel(c, id1, id2, S, C, shift, shift_vel, scgeom_ratchet(c, C))
    eps_t = add(rotate_tangential(load_row(f, c, CPM_EPS_T), rotation),
                scale(tangential(v, n), S.scal[S_DT] / length))
    eps_t_pl = load_row(f, c, CPM_EPS_T_PL)
    eps_n_pl = f[c, CPM_EPS_N_PL]
    xi = f[c, CPM_SHEAR_CONTRIB]
    eps_pos = max(eps_n - eps_n_pl, 0.0)
    kappa = max(f[c, CPM_KAPPA_D], math.sqrt(eps_pos * eps_pos + xi * xi * dot(eps_t, eps_t)))
    omega = 1.0
    if cohesive:
        omega = damage(kappa, eps_crack, f[c, CPM_EPS_FRACTURE], f[c, CPM_NEVER_DAMAGE] != 0.0,
                       f[c, CPM_DAM_LAW] == 0.0)
    if eps_n > 0.0 and (not cohesive or omega > prm[LAW_OMEGA_THRESHOLD]):
        count_broken(S, id1, id2)
        return False
    elastic_n = eps_n - eps_n_pl
    sigma_n = (1.0 - (omega if elastic_n > 0.0 else 0.0)) * young * elastic_n
    eps_soft = prm[LAW_EPS_SOFT]
    if eps_soft < 0.0 and elastic_n < eps_soft:   # plastic compression, the softer branch
        soft = young * (eps_soft + prm[LAW_REL_KN_SOFT] * (elastic_n - eps_soft))
        if sigma_n < soft:
            eps_n_pl += (sigma_n - soft) / young
            sigma_n = soft
    sigma_t = scale(sub(eps_t, eps_t_pl), shear)
    cohesion = f[c, CPM_COHESION] * (1.0 - omega) - sigma_n * f[c, F_TANPHI]
    yield_t = cohesion if cohesion > 0.0 else 0.0   # a NaN cohesion (sigmaT not given) gives 0, as in YADE
    sigma_t_len = norm(sigma_t)
    if sigma_t_len > yield_t:
        ratio = yield_t / sigma_t_len
        sigma_t = scale(sigma_t, ratio)
        # YADE's plastic increment: (1 - ratio) sigma_T / G with the returned sigma_T, i.e. the stress taken off
        # times the ratio, over G (none when the yield stress is 0)
        slip = scale(sigma_t, (1.0 - ratio) / shear)
        eps_t_pl = add(eps_t_pl, slip)
    sigma_n -= iso
    area = f[c, CPM_CROSS_SECTION]
    fn = sigma_n * area
    fs = scale(sigma_t, area)
    f[c, CPM_EPS_N] = eps_n
    f[c, CPM_EPS_N_PL] = eps_n_pl
    f[c, CPM_KAPPA_D] = kappa
    f[c, CPM_OMEGA] = omega
    f[c, CPM_SIGMA_N] = sigma_n
    f[c, CPM_FN] = fn
    store_row(f, c, CPM_EPS_T, eps_t)
    store_row(f, c, CPM_EPS_T_PL, eps_t_pl)
    store_row(f, c, CPM_SIGMA_T, sigma_t)
    store_row(f, c, CPM_FS, fs)
    store_row(f, c, F_FN, scale(n, -fn))
    store_row(f, c, F_FS, scale(fs, -1.0))
    residual = 0.0
    if cohesive:
        residual = (1.0 - omega) * kappa / eps_crack if kappa > eps_crack else 1.0
    f[c, CPM_REL_RESIDUAL] = residual
    return True


class CpmIp2:
    """Python side of Ip2_CpmMat_CpmMat_CpmPhys (a mixin of its YADE class: ``registry.Functor.python``):
    before a run it refuses CpmMats of the scene's bodies whose damLaw differ (a contact between them would
    take the law of whichever body the dispatch puts first) and allocates the bodies' CpmState counts the
    law writes."""

    def prepare(self, scene) -> None:
        b = scene.bodies
        used = sorted({int(m) for m in b.material[:b.count][b.alive[:b.count]]})
        laws = {}
        for k in used:
            mat = scene.materials[k]
            if "CpmMat" in registry.material_ancestry(type(mat).kind):
                laws.setdefault(int(mat.damLaw), k)
        if len(laws) > 1:
            (law_a, mat_a), (law_b, mat_b) = sorted(laws.items())[:2]
            raise ValueError(f"{type(self).__name__}: CpmMat {mat_a} has damLaw={law_a} and CpmMat {mat_b} "
                             f"damLaw={law_b}; a contact between them has no damage law of its own: use one damLaw")
        if laws:
            b.allocate("cpm_broken")


IP2 = Functor(
    "Ip2_CpmMat_CpmMat_CpmPhys", "phys", ("CpmMat", "CpmMat"), "CpmPhys", f"{__name__}:phys_cpm",
    (Param("cohesiveThresholdIter", 10, "Contacts created before this step are cohesive, later ones not; 0: "
                                        "never, negative: always [-]"),
     Param("E", None, "Per-material-pair normal modulus (MatchMaker; not implemented: only None, the average)",
           supported=False)),
    "", HISTORY, python=f"{__name__}:CpmIp2")
IP2_COHESIVE_THRESHOLD = IP2.slot("cohesiveThresholdIter")


class CpmLaw:
    """Python side of Law2_ScGeom_CpmPhys_Cpm (a mixin of its YADE class): checks its parameters before a
    run; ``yieldSigmaTMagnitude`` fails as in YADE's public build."""

    def prepare(self, scene) -> None:
        name = type(self).__name__
        for p in self.spec.compiled_params():
            if p.valid is not None:
                p.check(name, float(getattr(self, p.name)))

    def yieldSigmaTMagnitude(self, sigmaN, omega, undamagedCohesion, tanFrictionAngle):
        """YADE's full model's yield surface, which its public build (2023.02a) does not have either."""
        raise RuntimeError("Full CPM model not available in this build")


_ANY = Range()
LAW = Functor(
    "Law2_ScGeom_CpmPhys_Cpm", "law", ("ScGeom", "CpmPhys"), None, f"{__name__}:law_cpm",
    (Param("epsSoft", 1.0, "Strain where softening in compression starts; non-negative: none [-]", valid=_ANY),
     Param("relKnSoft", 0.3, "Relative stiffness of the softening branch in compression (0: perfectly plastic, "
                             "< 0 softening, > 0 hardening) [-]", valid=_ANY),
     Param("omegaThreshold", 1.0, "Damage past which a contact in tension ends (>= 1: never) [-]", valid=_ANY),
     Param("yieldSurfType", 2, "Yield function of the full model" + _PUBLIC_ONLY, supported=False),
     Param("yieldLogSpeed", 0.1, "Scaling of the logarithmic yield surface" + _PUBLIC_ONLY, supported=False),
     Param("yieldEllipseShift", _NAN, "Shift of the elliptic yield surface" + _PUBLIC_ONLY, supported=False)),
    "", HISTORY, python=f"{__name__}:CpmLaw")
LAW_EPS_SOFT = LAW.slot("epsSoft")
LAW_REL_KN_SOFT = LAW.slot("relKnSoft")
LAW_OMEGA_THRESHOLD = LAW.slot("omegaThreshold")

registry.register_functor(dataclasses.replace(IP2, doc=__doc__))
registry.register_functor(dataclasses.replace(LAW, doc=__doc__))
registry.register_functor(Functor(
    "Ip2_FrictMat_CpmMat_FrictPhys", "phys", ("FrictMat", "CpmMat"), "FrictPhys",
    "granum.physics.frict:phys_frict",
    (Param("frictAngle", None, "Per-material-pair friction angle (MatchMaker; not implemented: only None, the min "
                               "of the two)", supported=False),),
    "FrictPhys between a FrictMat and a CpmMat, as Ip2_FrictMat_FrictMat_FrictPhys makes it (checked against "
    "YADE 2023.02a: the same kn, ks and friction).\n\n" + phys_frict.py_func.__doc__))


def body_without_state(bodies, materials) -> int:
    """The first live body whose material is a CpmMat but whose state is not a CpmState (the law's and
    CpmStateUpdater's per-body values need one: YADE refuses such a body at the next step), or -1.

    ``bodies``: the body table (:mod:`granum.core.bodies`); ``materials``: the material objects its
    ``material`` column indexes."""
    cpm = [k for k, m in enumerate(materials) if "CpmMat" in registry.material_ancestry(m.kind)]
    if not cpm:
        return -1
    n = bodies.count
    uses = bodies.alive[:n] & np.isin(bodies.material[:n], cpm)
    has = bodies.stored("cpm_state")
    flag = has[:n, CPM_IS_STATE] != 0.0 if has.shape[0] else np.zeros(n, bool)
    bad = np.nonzero(uses & ~flag)[0]
    return int(bad[0]) if bad.size else -1
