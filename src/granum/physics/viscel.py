"""Linear visco-elastic contact: ViscElMat, ViscElPhys and its basic law, with rolling resistance.

A spring-dashpot pair acts along the normal and in the tangent plane, with Coulomb
friction. Parameters come either from a contact time ``tc`` and restitution coefficients
``en`` (normal), ``et`` (tangential), or directly (``kn``, ``cn``, ``ks``, ``cs``). In the first
form the contact's tc, en, et are the Ip2's MatchMakers when given, else the means of the two
materials' values, and with the reduced mass m = m1 m2 / (m1 + m2) (a massless body, a facet,
counts with the other body's mass: tests/reference/yade/viscel_facet.py):

.. math::
    k_n = m\\,\\frac{\\pi^2 + \\ln^2 e_n}{t_c^2},\\quad c_n = -\\frac{2 m \\ln e_n}{t_c},\\quad
    k_s = \\frac{2}{7}\\,m\\,\\frac{\\pi^2 + \\ln^2 e_t}{t_c^2},\\quad c_s = -\\frac{2}{7}\\,\\frac{2 m \\ln e_t}{t_c}

(e = 0: no spring nor dashpot). This is the damped oscillator of mass m with duration tc and restitution
en; because the force may not pull the bodies together, the measured restitution is somewhat higher than
``en`` (as in YADE). In the second form each of kn, cn, ks, cs is the two materials' in series
(x1 x2 / (x1 + x2)). The friction angle is the Ip2's ``frictAngle`` MatchMaker, else the smaller one.

**Rolling resistance** (Zhou et al. 1999; ``mR``, ``mRtype`` of the materials): the contact's
mR = 2 / (1/mR_1 + 1/mR_2) over the materials with mR != 0 (0 if neither has one); both materials must
have the same mRtype. A moment acts on body 2 (its opposite on body 1):

.. math::
    M = -m_R\\,|F_N|\\,s\\,(\\omega_2 - \\omega_1),\\qquad
    s = 1\\ (\\text{mRtype } 1),\\quad s = |c_1 \\times \\omega_1 - c_2 \\times \\omega_2|\\ (\\text{mRtype } 2)

with |F_N| the normal force (dashpot included) and c_i the vectors from the body centres to the contact
point. As in YADE 2023.02a (measured, tests/reference/yade/viscel_pairs.py), the relative angular velocity
is not normalised, although Zhou's equations (3), (4) use its direction.

References:
    L. Pournin, Th. M. Liebling, A. Mocellin (2001), Molecular-dynamics force models
    for better control of energy dissipation in numerical simulations of dense granular
    media, *Phys. Rev. E* 65, 011302.
    Y. C. Zhou, B. D. Wright, R. Y. Yang, B. H. Xu, A. B. Yu (1999), Rolling friction in the dynamic
    simulation of sandpile formation, *Physica A* 269:536-553.
    YADE class reference: ViscElMat, Ip2_ViscElMat_ViscElMat_ViscElPhys,
    Law2_ScGeom_ViscElPhys_Basic; checked against YADE 2023.02a (tests/reference/yade/viscel.py,
    viscel_pairs.py).
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
    F_MOMENT,
    F_NORMAL,
    F_PEN,
    F_POINT,
    F_TANPHI,
    register_history,
)
from granum.physics import materials, registry
from granum.physics.frict import FRICTION_ANGLE, M_FRICTION, pair_friction
from granum.physics.l3geom import load_row, store_row
from granum.physics.matchmaker import given, pair_value, refuse_pair
from granum.physics.materials import NON_NEGATIVE
from granum.physics.registry import Functor, MaterialKind, Param, Range
from granum.physics.scgeom import contact_shift, scgeom_incident_vel, scgeom_rotate_shear, tangential
from granum.physics.vec import add, cross, dot, load3, norm, scale, sub

_NAN = float("nan")
#: a restitution coefficient: above 1 a collision creates energy
_RESTITUTION = Range(0.0, 1.0, why="a restitution coefficient above 1 creates energy")
registry.register_material(MaterialKind(
    "ViscElMat", "FrictMat",
    (Param("tc", _NAN, "Contact time [s]", valid=Range(0.0, low_open=True, why="a contact lasts some time")),
     Param("en", _NAN, "Normal restitution coefficient [-] (0: no normal spring nor dashpot, as in YADE)",
           valid=_RESTITUTION),
     Param("et", _NAN, "Tangential restitution coefficient [-] (0: no shear spring nor dashpot, as in YADE)",
           valid=_RESTITUTION),
     Param("kn", _NAN, "Normal stiffness [N/m] (used when tc, en, et are not given)", valid=NON_NEGATIVE),
     Param("cn", _NAN, "Normal damping [N s/m]", valid=NON_NEGATIVE),
     Param("ks", _NAN, "Shear stiffness [N/m]", valid=NON_NEGATIVE),
     Param("cs", _NAN, "Shear damping [N s/m]", valid=NON_NEGATIVE),
     Param("mR", 0.0, "Rolling resistance coefficient (Zhou et al. 1999); 0: none [-]", valid=NON_NEGATIVE),
     Param("mRtype", 1, "Rolling resistance model, 1 or 2 (Zhou et al. 1999, equations (3) and (4)); both "
                        "materials of a contact must have the same [-]"),
     Param("lubrication", False, "Lubrication (not implemented yet: only False)", supported=False),
     Param("viscoDyn", 0.001, "Fluid viscosity for lubrication [Pa s] (no effect without lubrication)",
           valid=NON_NEGATIVE),
     Param("roughnessScale", 0.001, "Roughness for lubrication [m] (no effect without lubrication)",
           valid=NON_NEGATIVE)),
    columns={"tc": "visc_tc", "en": "visc_en", "et": "visc_et", "kn": "visc_kn", "cn": "visc_cn",
             "ks": "visc_ks", "cs": "visc_cs", "mR": "visc_mr", "mRtype": "visc_mr_type"},
    doc="Material of the linear visco-elastic contact (spring-dashpot with Coulomb friction)."))
#: normal and shear damping coefficients of the contact (ViscElPhys cn, cs) [N s/m]; the law writes the rolling
#: moment, so the group starts after the energies and the moment
F_CN = register_history("viscel_damping", 2, after=("energy", "moment"))
F_CS = F_CN + 1
#: the contact's rolling resistance mR [-] and model mRtype (1 or 2)
F_MR = register_history("viscel_rolling", 2, after=("viscel_damping",))
F_MR_TYPE = F_MR + 1
registry.register_phys_type("ViscElPhys", "FrictPhys", {"cn": (F_CN, 1), "cs": (F_CS, 1), "mR": (F_MR, 1),
                                                        "mRtype": (F_MR_TYPE, 1, "int")})

#: elastic part of the shear force (the spring's state; F_FS also holds the dashpot part) [N]
F_SHEAR_EL = register_history("viscel_shear_elastic", 3, after=("viscel_rolling",))
#: the history groups both viscoelastic functors use (the law writes the contact moment)
HISTORY = ("viscel_damping", "viscel_rolling", "viscel_shear_elastic", "moment")

M_TC = materials.column("visc_tc")
M_EN = materials.column("visc_en")
M_ET = materials.column("visc_et")
M_KN = materials.column("visc_kn")
M_CN = materials.column("visc_cn")
M_KS = materials.column("visc_ks")
M_CS = materials.column("visc_cs")
M_MR = materials.column("visc_mr")
M_MR_TYPE = materials.column("visc_mr_type")


@jit
def spring_dashpot(m, tc, e):
    """``(k, c)`` of the damped oscillator of mass ``m`` [kg] lasting ``tc`` [s] with restitution ``e``:
    ``k = m (pi^2 + ln^2 e) / tc^2`` [N/m], ``c = -2 m ln(e) / tc`` [N s/m]; ``e = 0`` means no spring nor
    dashpot at all (``(0, 0)``, as in YADE), not the infinite ones the formula would give."""
    if e == 0.0:
        return 0.0, 0.0
    ln_e = math.log(e)
    return m * (math.pi ** 2 + ln_e ** 2) / tc ** 2, -2.0 * m * ln_e / tc


@jit
def series(x1, x2):
    """Two springs (or dashpots) in series: x1 x2 / (x1 + x2); 0 if both vanish."""
    den = x1 + x2
    return x1 * x2 / den if den != 0.0 else 0.0


@jit
def pair_or_mean(prm, slot, row1, row2, x1, x2):
    """The Ip2's MatchMaker at ``slot`` for the material rows when given (NaN: it has no value), else the
    mean of the materials' x1, x2 (NaN when they have none)."""
    if given(prm, slot):
        return pair_value(prm, slot, row1, row2, math.nan, math.nan)
    return 0.5 * (x1 + x2)


@jit
def rolling_coefficient(mr1, mr2):
    """The contact's mR from the materials': 2 / sum of 1/mR_i over the nonzero ones; 0 if both are 0."""
    inv = (1.0 / mr1 if mr1 != 0.0 else 0.0) + (1.0 / mr2 if mr2 != 0.0 else 0.0)
    return 2.0 / inv if inv != 0.0 else 0.0


@jit
def phys_viscel(c, id1, id2, S, C, prm):
    """ViscElPhys constants of a new contact (see the module docstring); stops the run (``refuse_pair``) when
    a MatchMaker has no value for the pair or the materials' mRtype differ."""
    row1 = S.material[id1]
    row2 = S.material[id2]
    m1 = S.mat[row1]
    m2 = S.mat[row2]
    f = C.con_f
    tc = pair_or_mean(prm, IP2_TC, row1, row2, m1[M_TC], m2[M_TC])
    en = pair_or_mean(prm, IP2_EN, row1, row2, m1[M_EN], m2[M_EN])
    et = pair_or_mean(prm, IP2_ET, row1, row2, m1[M_ET], m2[M_ET])
    phi = pair_friction(prm, IP2_FRICT_ANGLE, row1, row2, math.nan, math.nan) if given(prm, IP2_FRICT_ANGLE) \
        else min(m1[M_FRICTION], m2[M_FRICTION])
    missing = (given(prm, IP2_TC) and tc != tc) or (given(prm, IP2_EN) and en != en) or \
        (given(prm, IP2_ET) and et != et) or phi != phi or m1[M_MR_TYPE] != m2[M_MR_TYPE]
    if missing:
        refuse_pair(C, id1, id2)
    if tc == tc and en == en and et == et:
        mass1 = S.mass[id1]
        mass2 = S.mass[id2]
        # a massless body (facet, wall) counts with the other's mass (YADE 2023.02a, measured)
        mass = series(mass1 if mass1 > 0.0 else mass2, mass2 if mass2 > 0.0 else mass1)
        kn, cn = spring_dashpot(mass, tc, en)
        ks, cs = spring_dashpot(mass, tc, et)
        f[c, F_KN] = kn
        f[c, F_CN] = cn
        f[c, F_KS] = 2.0 / 7.0 * ks
        f[c, F_CS] = 2.0 / 7.0 * cs
    else:
        f[c, F_KN] = series(m1[M_KN], m2[M_KN])
        f[c, F_CN] = series(m1[M_CN], m2[M_CN])
        f[c, F_KS] = series(m1[M_KS], m2[M_KS])
        f[c, F_CS] = series(m1[M_CS], m2[M_CS])
    f[c, F_TANPHI] = math.tan(phi)
    f[c, F_MR] = rolling_coefficient(m1[M_MR], m2[M_MR])
    f[c, F_MR_TYPE] = m1[M_MR_TYPE]


@jit
def rolling_moment(c, id1, id2, S, C, shift, fn_mag):
    """The rolling resistance moment on body 2 of contact ``c`` (module docstring) [N m]; ``fn_mag``: |F_N|."""
    f = C.con_f
    w1 = load3(S.ang_vel, id1)
    w2 = load3(S.ang_vel, id2)
    k = f[c, F_MR] * fn_mag
    if f[c, F_MR_TYPE] == 2.0:
        point = load_row(f, c, F_POINT)
        c1 = sub(point, load3(S.pos, id1))
        c2 = sub(point, add(load3(S.pos, id2), shift))
        k *= norm(sub(cross(c1, w1), cross(c2, w2)))
    return scale(sub(w2, w1), -k)


@jit
def law_viscel(c, id1, id2, S, C, prm):
    """Spring-dashpot law with Coulomb friction on an ScGeom.

    .. math::
        F_N = (k_n \\delta + c_n \\dot\\delta)\\, n,\\qquad
        F_T^{el} \\leftarrow \\mathrm{rot}(F_T^{el}) - k_s \\Delta u_T,\\qquad
        F_T = F_T^{el} - c_s v_T

    acting on body 2, with v_T the tangential relative velocity. When
    |F_T^el| exceeds |F_N| tan(phi) the elastic part is scaled to the cone and the
    shear dashpot is off (sliding). The force never pulls the bodies together: when
    kn delta + cn ddelta/dt < 0 both forces are zero (and the shear spring is reset).
    The rolling moment (:func:`rolling_moment`) goes to the contact moment ``F_MOMENT`` when mR > 0.
    The contact ends when delta < 0.
    """
    f = C.con_f
    pen = f[c, F_PEN]
    if pen < 0.0:
        return False
    n = (f[c, F_NORMAL], f[c, F_NORMAL + 1], f[c, F_NORMAL + 2])
    shift, shift_vel = contact_shift(c, S, C)
    # the velocity at the contact point with the true lever arms (no anti-ratcheting scaling)
    v = scgeom_incident_vel(c, id1, id2, S, C, shift, shift_vel, False)
    closing = -dot(v, n)   # d(delta)/dt
    fn_mag = f[c, F_KN] * pen + f[c, F_CN] * closing
    if fn_mag < 0.0:
        for k in range(6):
            f[c, F_FN + k] = 0.0
        for k in range(3):
            f[c, F_SHEAR_EL + k] = 0.0
            f[c, F_MOMENT + k] = 0.0
        if S.iscal[SI_TRACK_ENERGY]:  # the energy columns are written only then (granum.core.contacts)
            f[c, F_E_ELAST] = 0.0
            f[c, F_E_DISSIP] = 0.0
        return True
    fn = scale(n, fn_mag)
    vt = tangential(v, n)
    fs = scgeom_rotate_shear(c, id1, id2, S, C, (f[c, F_SHEAR_EL], f[c, F_SHEAR_EL + 1], f[c, F_SHEAR_EL + 2]))
    fs = sub(fs, scale(vt, f[c, F_KS] * S.scal[S_DT]))
    max_fs = fn_mag * f[c, F_TANPHI]
    fs_norm = math.sqrt(dot(fs, fs))
    total = fs
    if fs_norm > max_fs:
        fs = scale(fs, max_fs / fs_norm)
        total = fs
    else:
        total = sub(fs, scale(vt, f[c, F_CS]))
    for k in range(3):
        f[c, F_FN + k] = fn[k]
        f[c, F_FS + k] = total[k]
        f[c, F_SHEAR_EL + k] = fs[k]
    store_row(f, c, F_MOMENT, rolling_moment(c, id1, id2, S, C, shift, fn_mag) if f[c, F_MR] > 0.0
              else (0.0, 0.0, 0.0))
    if S.iscal[SI_TRACK_ENERGY]:
        f[c, F_E_ELAST] = 0.5 * f[c, F_KN] * pen * pen + (0.5 * dot(fs, fs) / f[c, F_KS] if f[c, F_KS] > 0 else 0.0)
        f[c, F_E_DISSIP] = 0.0
    return True


class RollingTypes:
    """Python side of Ip2_ViscElMat_ViscElMat_ViscElPhys (a mixin of its YADE class:
    ``registry.Functor.python``): says why a contact was refused when the materials' mRtype differ."""

    def explain_pair(self, scene, id1: int, id2: int) -> str | None:
        mats = [scene.materials[scene.bodies.material[i]] for i in (id1, id2)]
        types = [getattr(m, "mRtype", 1) for m in mats]
        if types[0] != types[1]:
            return (f"{type(self).__name__}: bodies {id1} and {id2} touch, and their materials have different "
                    f"rolling resistance models (mRtype={types[0]} and mRtype={types[1]}); both must have the "
                    f"same (YADE stops there too)")
        return super().explain_pair(scene, id1, id2)


IP2 = Functor(
    "Ip2_ViscElMat_ViscElMat_ViscElPhys", "phys", ("ViscElMat", "ViscElMat"), "ViscElPhys",
    f"{__name__}:phys_viscel",
    (Param("tc", None, "Per-material-pair contact time (MatchMaker, supplied no values; None: the mean of the "
                       "materials') [s]", valid=Range(0.0, low_open=True, why="a contact lasts some time"),
           matchmaker="bare"),
     Param("en", None, "Per-material-pair normal restitution (MatchMaker, supplied no values; None: the mean of "
                       "the materials') [-]", valid=_RESTITUTION, matchmaker="bare"),
     Param("et", None, "Per-material-pair tangential restitution (MatchMaker, supplied no values; None: the mean "
                       "of the materials') [-]", valid=_RESTITUTION, matchmaker="bare"),
     Param("frictAngle", None, "Per-material-pair friction angle (MatchMaker, supplied no values; None: the min "
                               "of the materials') [rad]", valid=FRICTION_ANGLE, matchmaker="bare")),
    phys_viscel.py_func.__doc__, HISTORY, python=f"{__name__}:RollingTypes")
registry.register_functor(IP2)
#: places of the Ip2's MatchMakers in its row ``prm``
IP2_TC = IP2.slot("tc")
IP2_EN = IP2.slot("en")
IP2_ET = IP2.slot("et")
IP2_FRICT_ANGLE = IP2.slot("frictAngle")
registry.register_functor(Functor(
    "Law2_ScGeom_ViscElPhys_Basic", "law", ("ScGeom", "ViscElPhys"), None,
    f"{__name__}:law_viscel", (), law_viscel.py_func.__doc__, HISTORY))
