"""Cohesive-frictional contacts with moments: CohFrictMat, CohFrictPhys and YADE's CohesionMoment law.

A contact between two CohFrictMat bodies may be *cohesive*: it then resists tension up to the normal
adhesion a_n and shear up to a_s plus friction, and, with ``momentRotationLaw``, bending and twisting.

**Constants** (Ip2_CohFrictMat_CohFrictMat_CohFrictPhys, with the reference radii r1, r2 of the ScGeom6D):
kn, ks as FrictPhys (:func:`granum.physics.frict.phys_frict`, both from the materials' young and poisson),

.. math::
    k_r = r_1 r_2 k_s \\frac{2 \\alpha_{r1} \\alpha_{r2}}{\\alpha_{r1} + \\alpha_{r2}},\\quad
    k_{tw} = r_1 r_2 k_s \\frac{2 \\alpha_{tw1} \\alpha_{tw2}}{\\alpha_{tw1} + \\alpha_{tw2}}\\ (0 \\text{ if an }
    \\alpha \\text{ is } 0),\\quad
    \\eta_{r} = \\min(\\eta_{r1} r_1, \\eta_{r2} r_2),\\quad \\eta_{tw} = \\min(\\eta_{tw1} r_1, \\eta_{tw2} r_2)

and, when the contact is made cohesive (both materials ``isCohesive``; at creation with
``setCohesionOnNewContacts``, at the step ``setCohesionNow`` acts, or for a contact whose
``initCohesion`` is set), a_n = min(C_n1, C_n2) min(r1, r2)^2, a_s = min(C_s1, C_s2) min(r1, r2)^2,
``fragile`` = fragile1 or fragile2, and the ScGeom6D rotations start from then. The Ip2's MatchMakers
``normalCohesion``, ``shearCohesion`` (no values supplied, as YADE) replace min(C_1, C_2), and ``frictAngle``
(combining the materials' angles) the smaller angle.

**Law** (Law2_ScGeom6D_CohFrictPhys_CohesionMoment), forces on body 2, u_n the penetration depth, u_n^p its
plastic part (``unp``):

.. math::
    F_n = k_n (u_n - u_n^p);\\quad -F_n > a_n:\\ \\text{fragile: the contact ends; else } F_n = -a_n,\\
    u_n^p = u_n + a_n/k_n \\text{ (the contact ends once } -u_n^p > \\text{unpMax} \\ge 0)

    F_s \\leftarrow \\mathrm{rot}(F_s) - k_s \\Delta u_s,\\qquad
    F_s^{max} = \\max(0,\\ a_s + F_n \\tan\\varphi)\\ (a_s \\text{ alone with cohesionDisablesFriction and } a_s > 0)

past F_s^max a fragile cohesive contact loses its cohesion (a_n = a_s = 0, F_s^max = max(0, F_n tan phi)), the
shear force is scaled back to F_s^max, and a tensile normal force is dropped. ``shear_creep``: before the
increment, F_s -= k_s F_s dt / nu (nu = ``creep_viscosity``). Moments, when ``momentRotationLaw`` and the contact is
cohesive (or ``always_use_moment_law``): from the ScGeom6D rotations (total form)

.. math::
    M_t = k_{tw}\\, \\text{twist}\\; n,\\qquad M_b = k_r\\, \\text{bending}

or incrementally (``useIncrementalForm``), with w = omega_2 - omega_1, M_b <- rot(M_b) - k_r (w - (w.n) n) dt,
M_t <- rot(M_t) - k_tw (w.n) n dt; then |M_b| <= eta_r |F_n| if eta_r >= 0 and |M_t| <= eta_tw |F_n| if
eta_tw >= 0 (scaled back). M_t + M_b acts on body 2 and its opposite on body 1 (the contact's ``moment``
columns, :data:`granum.core.contacts.F_MOMENT`); the forces act at the contact point. Energies (O.trackEnergy):
elastic F_n^2/2k_n + |F_s|^2/2k_s + |M_b|^2/2k_r + |M_t|^2/2k_tw, dissipated by shear slip as in Cundall-Strack
(YADE's traceEnergy details, such as the moments' plastic work, are not reproduced).

References:
    YADE class reference: CohFrictMat, CohFrictPhys, Ip2_CohFrictMat_CohFrictMat_CohFrictPhys,
    Law2_ScGeom6D_CohFrictPhys_CohesionMoment; F. Bourrier et al. (2013), *Ecological Engineering* 61:646-657
    (moments); K. Hassan (2010), creep. Checked step by step against YADE 2023.02a:
    tests/reference/yade/cohfrict.py.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from granum._jit import jit
from granum.core.arrays import S_DT, SI_ITER, SI_TRACK_ENERGY
from granum.core.contacts import (
    C_CONTACTS,
    F_E_DISSIP,
    F_E_ELAST,
    F_FN,
    F_FS,
    F_KN,
    F_KS,
    F_MOMENT,
    F_NORMAL,
    F_PEN,
    F_R1,
    F_R2,
    F_TANPHI,
    FLAG_ALIVE,
    FLAG_NEW,
    FLAG_PHYS_AGAIN,
    I_FLAGS,
    I_PHYS,
    register_history,
)
from granum.physics import materials, registry
from granum.physics.frict import FRICT_ANGLE_PARAM, M_FRICTION, pair_friction, series_stiffness
from granum.physics.l3geom import load_row, store_row
from granum.physics.matchmaker import given, pair_value, refuse_pair
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
from granum.physics.scgeom6d import G6_BENDING, G6_TWIST, scgeom6d_init
from granum.physics.vec import add, dot, load3, norm, scale, sub

#: a strength [Pa]: YADE's default -1 gives a negative adhesion, with which a cohesive contact ends as soon
#: as it is not compressed (YADE 2023.02a's behaviour, checked)
_STRENGTH = Range(0.0, also=(-1.0,), why="a strength is a force per area; -1 is YADE's default (no strength)")
registry.register_material(MaterialKind(
    "CohFrictMat", "FrictMat",
    (Param("isCohesive", True, "Whether this body may form cohesive contacts [-]"),
     Param("alphaKr", 2.0, "Dimensionless rolling (bending) stiffness, k_r / (k_s r1 r2) [-]", valid=NON_NEGATIVE),
     Param("alphaKtw", 2.0, "Dimensionless twisting stiffness, k_tw / (k_s r1 r2) [-]", valid=NON_NEGATIVE),
     Param("etaRoll", -1.0, "Dimensionless rolling strength: |M_b| <= etaRoll r |F_n|; negative: elastic [-]",
           valid=Range()),
     Param("etaTwist", -1.0, "Dimensionless twisting strength: |M_t| <= etaTwist r |F_n|; negative: elastic [-]",
           valid=Range()),
     Param("normalCohesion", -1.0, "Tensile strength; the normal adhesion is it times min(r1, r2)^2 [Pa]",
           valid=_STRENGTH),
     Param("shearCohesion", -1.0, "Shear strength; the shear adhesion is it times min(r1, r2)^2 [Pa]",
           valid=_STRENGTH),
     Param("fragile", True, "Cohesion disappears when the strength is exceeded (else perfectly plastic) [-]"),
     Param("momentRotationLaw", False, "Bending and twisting moments at contacts (both bodies must have it) [-]")),
    columns={"isCohesive": "coh_is_cohesive", "alphaKr": "coh_alpha_kr", "alphaKtw": "coh_alpha_ktw",
             "etaRoll": "coh_eta_roll", "etaTwist": "coh_eta_twist", "normalCohesion": "coh_normal",
             "shearCohesion": "coh_shear", "fragile": "coh_fragile", "momentRotationLaw": "coh_moment_law"},
    doc="FrictMat with cohesion and rotational stiffnesses (Law2_ScGeom6D_CohFrictPhys_CohesionMoment)."))

M_COHESIVE = materials.column("coh_is_cohesive")
M_ALPHA_KR = materials.column("coh_alpha_kr")
M_ALPHA_KTW = materials.column("coh_alpha_ktw")
M_ETA_ROLL = materials.column("coh_eta_roll")
M_ETA_TWIST = materials.column("coh_eta_twist")
M_NORMAL_COHESION = materials.column("coh_normal")
M_SHEAR_COHESION = materials.column("coh_shear")
M_FRAGILE = materials.column("coh_fragile")
M_MOMENT_LAW = materials.column("coh_moment_law")

#: rolling (bending) stiffness [N m/rad]
#: (after the energies and the moment, sharing its columns with the other laws' histories, which no cohesive
#: contact uses: see physics.scgeom6d)
CF_KR = register_history("cohfrict", 20, after=("energy", "moment"))
CF_KTW = CF_KR + 1                 # twisting stiffness [N m/rad]
CF_NORMAL_ADHESION = CF_KR + 2     # tensile strength of the contact a_n [N]
CF_SHEAR_ADHESION = CF_KR + 3      # cohesive part of the shear strength a_s [N]
CF_UNP = CF_KR + 4                 # plastic normal displacement u_n^p [m]
CF_UNP_MAX = CF_KR + 5             # largest plastic normal displacement before the contact ends; < 0: none [m]
CF_MAX_ROLL = CF_KR + 6            # rolling strength eta_r [m]; < 0: elastic
CF_MAX_TWIST = CF_KR + 7           # twisting strength eta_tw [m]; < 0: elastic
CF_CREEP_VISCOSITY = CF_KR + 8     # YADE's CohFrictPhys.creep_viscosity (the law uses its own) [Pa s/m]
CF_MOMENT_TWIST = CF_KR + 9        # 9..11 twisting moment on body 2 [N m]
CF_MOMENT_BENDING = CF_KR + 12     # 12..14 bending moment on body 2 [N m]
CF_BROKEN = CF_KR + 15             # 1: no cohesion (never had, or broken) [-]
CF_FRAGILE = CF_KR + 16            # 1: cohesion disappears when the strength is exceeded [-]
CF_MOMENT_LAW = CF_KR + 17         # 1: the contact may carry moments [-]
CF_DISABLES_FRICTION = CF_KR + 18  # 1: the shear strength is a_s alone while cohesive [-]
CF_INIT_COHESION = CF_KR + 19      # 1: make this contact cohesive at the next step [-]
#: the history groups of the cohesive functors (the law writes moments: the force gather adds them)
HISTORY = ("scgeom6d", "cohfrict", "moment")

_BOOL = "bool"
# YADE's parent of CohFrictPhys (and MindlinPhys): declared without fields, the same declaration as other laws
# make; each subtype maps kr and ktw to its own columns
registry.register_phys_type("RotStiffFrictPhys", "FrictPhys")
registry.register_phys_type("CohFrictPhys", "RotStiffFrictPhys", {
    "kr": (CF_KR, 1), "ktw": (CF_KTW, 1),
    "normalAdhesion": (CF_NORMAL_ADHESION, 1), "shearAdhesion": (CF_SHEAR_ADHESION, 1), "unp": (CF_UNP, 1),
    "unpMax": (CF_UNP_MAX, 1), "maxRollPl": (CF_MAX_ROLL, 1), "maxTwistPl": (CF_MAX_TWIST, 1),
    "creep_viscosity": (CF_CREEP_VISCOSITY, 1), "moment_twist": (CF_MOMENT_TWIST, 3),
    "moment_bending": (CF_MOMENT_BENDING, 3), "cohesionBroken": (CF_BROKEN, 1, _BOOL),
    "fragile": (CF_FRAGILE, 1, _BOOL), "momentRotationLaw": (CF_MOMENT_LAW, 1, _BOOL),
    "cohesionDisablesFriction": (CF_DISABLES_FRICTION, 1, _BOOL), "initCohesion": (CF_INIT_COHESION, 1, _BOOL)})


class CohesionNow:
    """Python side of Ip2_CohFrictMat_CohFrictMat_CohFrictPhys (a mixin of its YADE class:
    ``registry.Functor.python``).

    ``setCohesionNow`` acts at one step, as in YADE: the first run after it is set makes cohesive, at its
    first step, the existing contacts of this functor (marked ``FLAG_PHYS_AGAIN``, so that the physics
    functor runs on them again) and the contacts created then; a later run turns it off. The compiled
    parameter ``setCohesionNow`` is that step (-1: none). Contacts whose ``initCohesion`` was set from Python
    are marked the same way.
    """

    _cohesion_iter = -1   # the step at which setCohesionNow acts, -1 while it is not set

    def prepare(self, scene) -> None:
        super().prepare(scene)
        if self._cohesion_iter >= 0 and (not self.setCohesionNow or scene.iter > self._cohesion_iter):
            self.setCohesionNow = False   # it has acted (YADE turns it off at the next step)
            self._cohesion_iter = -1
        if self.setCohesionNow and self._cohesion_iter < 0:
            self._cohesion_iter = scene.iter
        C = scene.contacts
        n = int(C.ctr[C_CONTACTS])
        if n == 0:
            return
        con_i = C.con_i[:n]
        mine = ((con_i[:, I_FLAGS] & FLAG_ALIVE) != 0) & (con_i[:, I_PHYS] == self.code)
        if not self.setCohesionNow:
            if C.con_f.shape[1] <= CF_INIT_COHESION:
                return
            mine &= C.con_f[:n, CF_INIT_COHESION] != 0.0
        con_i[mine, I_FLAGS] |= np.int32(FLAG_PHYS_AGAIN)

    def numeric_params(self) -> list[float]:
        values = super().numeric_params()
        values[IP2_COHESION_NOW] = float(self._cohesion_iter) if self.setCohesionNow else -1.0
        return values


IP2 = Functor(
    "Ip2_CohFrictMat_CohFrictMat_CohFrictPhys", "phys", ("CohFrictMat", "CohFrictMat"), "CohFrictPhys",
    f"{__name__}:phys_cohfrict",
    (Param("setCohesionNow", False, "Make the existing contacts (and those created at the same step) cohesive "
                                    "at the next step; turned off afterwards [-]"),
     Param("setCohesionOnNewContacts", False, "Make every new contact cohesive [-]"),
     Param("normalCohesion", None, "Per-material-pair tensile strength (MatchMaker, supplied no values; None: the "
                                   "min of the materials') [Pa]", valid=_STRENGTH, matchmaker="bare"),
     Param("shearCohesion", None, "Per-material-pair shear strength (MatchMaker, supplied no values; None: the min "
                                  "of the materials') [Pa]", valid=_STRENGTH, matchmaker="bare"),
     FRICT_ANGLE_PARAM),
    "", HISTORY, python=f"{__name__}:CohesionNow")
IP2_COHESION_NOW = IP2.slot("setCohesionNow")
IP2_ON_NEW = IP2.slot("setCohesionOnNewContacts")
IP2_NORMAL_COHESION = IP2.slot("normalCohesion")
IP2_SHEAR_COHESION = IP2.slot("shearCohesion")
IP2_FRICT_ANGLE = IP2.slot("frictAngle")


@jit
def harmonic(a, b):
    """2ab/(a + b), 0 if a or b is 0 (YADE's mean of the materials' alphaKr, alphaKtw)."""
    if a == 0.0 or b == 0.0:
        return 0.0
    return 2.0 * a * b / (a + b)


@jit
def strength(prm, slot, row1, row2, c1, c2):
    """A strength of the contact [Pa]: the Ip2's MatchMaker at ``slot`` when given (NaN: no value for the
    pair), else the smaller of the materials' c1, c2."""
    if given(prm, slot):
        return pair_value(prm, slot, row1, row2, math.nan, math.nan)
    return min(c1, c2)


@jit
def make_cohesive(c, id1, id2, S, C, prm):
    """Cohesion of contact ``c`` from the strengths (module docstring: the Ip2's MatchMakers, else the
    materials'); its rotations start now. Stops the run (``refuse_pair``) when a MatchMaker has no value."""
    f = C.con_f
    row1 = S.material[id1]
    row2 = S.material[id2]
    m1 = S.mat[row1]
    m2 = S.mat[row2]
    normal = strength(prm, IP2_NORMAL_COHESION, row1, row2, m1[M_NORMAL_COHESION], m2[M_NORMAL_COHESION])
    shear = strength(prm, IP2_SHEAR_COHESION, row1, row2, m1[M_SHEAR_COHESION], m2[M_SHEAR_COHESION])
    if normal != normal or shear != shear:
        refuse_pair(C, id1, id2)
    r = min(f[c, F_R1], f[c, F_R2])
    f[c, CF_BROKEN] = 0.0
    f[c, CF_NORMAL_ADHESION] = normal * r * r
    f[c, CF_SHEAR_ADHESION] = shear * r * r
    f[c, CF_FRAGILE] = 1.0 if m1[M_FRAGILE] != 0.0 or m2[M_FRAGILE] != 0.0 else 0.0
    scgeom6d_init(c, id1, id2, S, C)


@jit
def phys_cohfrict(c, id1, id2, S, C, prm):
    """CohFrictPhys of a new contact, or cohesion for an existing one (module docstring)."""
    f = C.con_f
    m1 = S.mat[S.material[id1]]
    m2 = S.mat[S.material[id2]]
    cohesive_now = prm[IP2_COHESION_NOW] == S.iscal[SI_ITER]
    if C.con_i[c, I_FLAGS] & FLAG_NEW:
        r1 = f[c, F_R1]
        r2 = f[c, F_R2]
        e1 = m1[materials.M_YOUNG]
        e2 = m2[materials.M_YOUNG]
        ks = series_stiffness(e1 * m1[materials.M_POISSON], r1, e2 * m2[materials.M_POISSON], r2)
        f[c, F_KN] = series_stiffness(e1, r1, e2, r2)
        f[c, F_KS] = ks
        f[c, F_TANPHI] = math.tan(pair_friction(prm, IP2_FRICT_ANGLE, S.material[id1], S.material[id2],
                                                m1[M_FRICTION], m2[M_FRICTION]))
        f[c, CF_KR] = r1 * r2 * ks * harmonic(m1[M_ALPHA_KR], m2[M_ALPHA_KR])
        f[c, CF_KTW] = r1 * r2 * ks * harmonic(m1[M_ALPHA_KTW], m2[M_ALPHA_KTW])
        f[c, CF_MAX_ROLL] = min(m1[M_ETA_ROLL] * r1, m2[M_ETA_ROLL] * r2)
        f[c, CF_MAX_TWIST] = min(m1[M_ETA_TWIST] * r1, m2[M_ETA_TWIST] * r2)
        f[c, CF_MOMENT_LAW] = 1.0 if m1[M_MOMENT_LAW] != 0.0 and m2[M_MOMENT_LAW] != 0.0 else 0.0
        f[c, CF_BROKEN] = 1.0
        f[c, CF_FRAGILE] = 1.0
        f[c, CF_CREEP_VISCOSITY] = -1.0
        cohesive_now = cohesive_now or prm[IP2_ON_NEW] != 0.0
    both = m1[M_COHESIVE] != 0.0 and m2[M_COHESIVE] != 0.0
    if (cohesive_now and both) or f[c, CF_INIT_COHESION] != 0.0:
        make_cohesive(c, id1, id2, S, C, prm)
        f[c, CF_INIT_COHESION] = 0.0


@jit
def released(c, S, C, keep):
    """A law's contact that would end: False (it ends), unless ``keep`` (neverErase): then it stays with no
    force, moment nor energy, and True."""
    if not keep:
        return False
    f = C.con_f
    for k in range(6):
        f[c, F_FN + k] = 0.0
    for k in range(3):
        f[c, F_MOMENT + k] = 0.0
    if S.iscal[SI_TRACK_ENERGY]:  # the energy columns exist only then (granum.core.contacts)
        f[c, F_E_ELAST] = 0.0
        f[c, F_E_DISSIP] = 0.0
    return True


@jit
def bounded(v, limit):
    """``v`` scaled back to length ``limit`` if longer and ``limit`` >= 0 (< 0: no bound)."""
    length = norm(v)
    if limit >= 0.0 and length > limit:
        return scale(v, limit / length)
    return v


@jit
def law_cohesion_moment(c, id1, id2, S, C, prm):
    """Law2_ScGeom6D_CohFrictPhys_CohesionMoment (module docstring); returns False when the contact ends."""
    f = C.con_f
    dt = S.scal[S_DT]
    pen = f[c, F_PEN]
    kn = f[c, F_KN]
    ks = f[c, F_KS]
    fn = kn * (pen - f[c, CF_UNP])
    adhesion = f[c, CF_NORMAL_ADHESION]
    keep = prm[LAW_NEVER_ERASE] != 0.0
    if -fn > adhesion:
        if f[c, CF_FRAGILE] != 0.0:
            return released(c, S, C, keep)
        fn = -adhesion
        f[c, CF_UNP] = pen + adhesion / kn
        if f[c, CF_UNP_MAX] >= 0.0 and -f[c, CF_UNP] > f[c, CF_UNP_MAX]:
            return released(c, S, C, keep)
    n = load_row(f, c, F_NORMAL)
    normal_force = scale(n, fn)
    rotation = scgeom_shear_rotation(c, id1, id2, S, C)   # the step's, for the force and the moments
    fs = rotate_tangential(load_row(f, c, F_FS), rotation)
    if prm[LAW_SHEAR_CREEP] != 0.0:   # the force of the last step relaxes, then the new increment adds
        fs = sub(fs, scale(fs, ks * dt / prm[LAW_CREEP_VISCOSITY]))
    shift, shift_vel = contact_shift(c, S, C)
    v = scgeom_incident_vel(c, id1, id2, S, C, shift, shift_vel, scgeom_ratchet(c, C))
    fs = sub(fs, scale(tangential(v, n), ks * dt))
    tan_phi = f[c, F_TANPHI]
    max_fs = f[c, CF_SHEAR_ADHESION]
    if f[c, CF_DISABLES_FRICTION] == 0.0 or max_fs == 0.0:
        max_fs += fn * tan_phi
    max_fs = max(0.0, max_fs)
    fs_len = norm(fs)
    dissip = 0.0
    if fs_len > max_fs:
        if f[c, CF_FRAGILE] != 0.0 and f[c, CF_BROKEN] == 0.0:
            f[c, CF_BROKEN] = 1.0
            f[c, CF_NORMAL_ADHESION] = 0.0
            f[c, CF_SHEAR_ADHESION] = 0.0
            max_fs = max(0.0, fn * tan_phi)
        trial = fs
        fs = scale(fs, max_fs / fs_len)
        dissip = dot(scale(sub(trial, fs), 1.0 / ks), fs)
        if fn < 0.0:
            normal_force = (0.0, 0.0, 0.0)
    store_row(f, c, F_FN, normal_force)
    store_row(f, c, F_FS, fs)
    moment = (0.0, 0.0, 0.0)
    mt = load_row(f, c, CF_MOMENT_TWIST)
    mb = load_row(f, c, CF_MOMENT_BENDING)
    if f[c, CF_MOMENT_LAW] != 0.0 and (f[c, CF_BROKEN] == 0.0 or prm[LAW_ALWAYS_MOMENTS] != 0.0):
        if prm[LAW_INCREMENTAL] != 0.0:
            w = sub(load3(S.ang_vel, id2), load3(S.ang_vel, id1))
            wn = dot(w, n)
            mb = sub(rotate_tangential(mb, rotation), scale(sub(w, scale(n, wn)), f[c, CF_KR] * dt))
            mt = sub(rotate_tangential(mt, rotation), scale(n, f[c, CF_KTW] * wn * dt))
        else:
            mt = scale(n, f[c, CF_KTW] * f[c, G6_TWIST])
            mb = scale(load_row(f, c, G6_BENDING), f[c, CF_KR])
        fn_len = norm(normal_force)
        mb = bounded(mb, f[c, CF_MAX_ROLL] * fn_len)
        mt = bounded(mt, f[c, CF_MAX_TWIST] * fn_len)
        store_row(f, c, CF_MOMENT_TWIST, mt)
        store_row(f, c, CF_MOMENT_BENDING, mb)
        moment = add(mt, mb)
    store_row(f, c, F_MOMENT, moment)
    if S.iscal[SI_TRACK_ENERGY]:
        elast = 0.5 * fn * fn / kn if kn > 0.0 else 0.0
        elast += 0.5 * dot(fs, fs) / ks if ks > 0.0 else 0.0
        if moment[0] != 0.0 or moment[1] != 0.0 or moment[2] != 0.0:
            elast += 0.5 * dot(mb, mb) / f[c, CF_KR] if f[c, CF_KR] > 0.0 else 0.0
            elast += 0.5 * dot(mt, mt) / f[c, CF_KTW] if f[c, CF_KTW] > 0.0 else 0.0
        f[c, F_E_ELAST] = elast
        f[c, F_E_DISSIP] = dissip
    return True


LAW = Functor(
    "Law2_ScGeom6D_CohFrictPhys_CohesionMoment", "law", ("ScGeom6D", "CohFrictPhys"), None,
    f"{__name__}:law_cohesion_moment",
    (Param("neverErase", False, "Keep contacts that would end, with no force nor moment [-]"),
     Param("always_use_moment_law", False, "Moments also at non-cohesive contacts (with momentRotationLaw) [-]"),
     Param("shear_creep", False, "Creep of the shear force, dF_s = -k_s F_s dt / creep_viscosity [-]"),
     Param("twist_creep", False, "Creep of the twisting moment (not implemented yet: only False)", supported=False),
     Param("traceEnergy", False, "Accepted for compatibility; energies follow O.trackEnergy [-]"),
     Param("useIncrementalForm", False, "Moments from the relative angular velocity, step by step, instead of "
                                        "the total rotations of the ScGeom6D [-]"),
     Param("creep_viscosity", 1.0, "Viscosity of shear_creep [Pa s/m]",
           valid=Range(0.0, low_open=True, why="the creep rate divides by it"))),
    "", HISTORY)
LAW_NEVER_ERASE = LAW.slot("neverErase")
LAW_ALWAYS_MOMENTS = LAW.slot("always_use_moment_law")
LAW_SHEAR_CREEP = LAW.slot("shear_creep")
LAW_INCREMENTAL = LAW.slot("useIncrementalForm")
LAW_CREEP_VISCOSITY = LAW.slot("creep_viscosity")

registry.register_functor(dataclasses.replace(IP2, doc=__doc__))
registry.register_functor(dataclasses.replace(LAW, doc=__doc__))
