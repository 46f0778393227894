"""Linear visco-elastic contact: ViscElMat, ViscElPhys and its basic law.

A spring-dashpot pair acts along the normal and in the tangent plane, with Coulomb
friction. Parameters come either directly (``kn``, ``cn``, ``ks``, ``cs``) or from a
contact time ``tc`` and restitution coefficients ``en`` (normal), ``et`` (tangential),
per body of mass m:

.. math::
    k_n = m\\,\\frac{\\pi^2 + \\ln^2 e_n}{t_c^2},\\quad c_n = -\\frac{2 m \\ln e_n}{t_c},\\quad
    k_s = \\frac{2}{7}\\,m\\,\\frac{\\pi^2 + \\ln^2 e_t}{t_c^2},\\quad c_s = -\\frac{2}{7}\\,\\frac{2 m \\ln e_t}{t_c}

and the two bodies' values combine in series (x = x1 x2 / (x1 + x2)); a massless
body (facet, wall) counts with the other body's mass, as in YADE 2023.02a (measured:
tests/reference/yade/viscel_facet.py): a sphere on a facet gets the constants of
reduced mass m/2, as if the facet were a sphere of equal mass. For two equal free
spheres this is the damped oscillator of reduced mass m/2 with duration tc and
restitution en; because the force may not pull the bodies together, the measured
restitution is somewhat higher than ``en`` (as in YADE).

References:
    L. Pournin, Th. M. Liebling, A. Mocellin (2001), Molecular-dynamics force models
    for better control of energy dissipation in numerical simulations of dense granular
    media, *Phys. Rev. E* 65, 011302.
    YADE class reference: ViscElMat, Ip2_ViscElMat_ViscElMat_ViscElPhys,
    Law2_ScGeom_ViscElPhys_Basic.
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
    F_TANPHI,
    register_history,
)
from granum.physics import materials, registry
from granum.physics.frict import M_FRICTION
from granum.physics.materials import NON_NEGATIVE
from granum.physics.registry import Functor, MaterialKind, Param, Range
from granum.physics.scgeom import contact_shift, scgeom_incident_vel, scgeom_rotate_shear, tangential
from granum.physics.vec import dot, scale, sub

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
     Param("mR", 0.0, "Rolling resistance coefficient [-] (rolling resistance is not implemented yet: only 0)",
           supported=False),
     Param("mRtype", 1, "Rolling resistance model, 1 or 2 [-] (no effect while mR is 0)"),
     Param("lubrication", False, "Lubrication (not implemented yet: only False)", supported=False),
     Param("viscoDyn", 0.001, "Fluid viscosity for lubrication [Pa s] (no effect without lubrication)",
           valid=NON_NEGATIVE),
     Param("roughnessScale", 0.001, "Roughness for lubrication [m] (no effect without lubrication)",
           valid=NON_NEGATIVE)),
    columns={"tc": "visc_tc", "en": "visc_en", "et": "visc_et", "kn": "visc_kn", "cn": "visc_cn",
             "ks": "visc_ks", "cs": "visc_cs"},
    doc="Material of the linear visco-elastic contact (spring-dashpot with Coulomb friction)."))
#: normal and shear damping coefficients of the contact (ViscElPhys cn, cs) [N s/m]
F_CN = register_history("viscel_damping", 2, after=("energy",))  # ViscEl writes no moment (yet)
F_CS = F_CN + 1
registry.register_phys_type("ViscElPhys", "FrictPhys", {"cn": (F_CN, 1), "cs": (F_CS, 1)})

#: elastic part of the shear force (the spring's state; F_FS also holds the dashpot part) [N]
F_SHEAR_EL = register_history("viscel_shear_elastic", 3, after=("viscel_damping",))
#: the history groups both viscoelastic functors use
HISTORY = ("viscel_damping", "viscel_shear_elastic")

M_TC = materials.column("visc_tc")
M_EN = materials.column("visc_en")
M_ET = materials.column("visc_et")
M_KN = materials.column("visc_kn")
M_CN = materials.column("visc_cn")
M_KS = materials.column("visc_ks")
M_CS = materials.column("visc_cs")


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
def body_constants(m, mat):
    """``(kn, cn, ks, cs)`` of one body of mass ``m`` with ViscElMat parameters ``mat``."""
    tc = mat[M_TC]
    en = mat[M_EN]
    et = mat[M_ET]
    if tc == tc and en == en and et == et:
        kn, cn = spring_dashpot(m, tc, en)
        ks, cs = spring_dashpot(m, tc, et)
        return kn, cn, 2.0 / 7.0 * ks, 2.0 / 7.0 * cs
    return (mat[M_KN], mat[M_CN], mat[M_KS], mat[M_CS])


@jit
def series(x1, x2):
    """Two springs (or dashpots) in series."""
    den = x1 + x2
    return x1 * x2 / den if den != 0.0 else 0.0


@jit
def phys_viscel(c, id1, id2, S, C, prm):
    """ViscElPhys constants of a new contact (see the module docstring)."""
    m1 = S.mat[S.material[id1]]
    m2 = S.mat[S.material[id2]]
    # a massless body (facet, wall) takes the other body's mass (YADE's rule)
    mass1 = S.mass[id1] if S.mass[id1] > 0.0 else S.mass[id2]
    mass2 = S.mass[id2] if S.mass[id2] > 0.0 else S.mass[id1]
    a = body_constants(mass1, m1)
    b = body_constants(mass2, m2)
    f = C.con_f
    f[c, F_KN] = series(a[0], b[0])
    f[c, F_CN] = series(a[1], b[1])
    f[c, F_KS] = series(a[2], b[2])
    f[c, F_CS] = series(a[3], b[3])
    f[c, F_TANPHI] = math.tan(min(m1[M_FRICTION], m2[M_FRICTION]))


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
    if S.iscal[SI_TRACK_ENERGY]:
        f[c, F_E_ELAST] = 0.5 * f[c, F_KN] * pen * pen + (0.5 * dot(fs, fs) / f[c, F_KS] if f[c, F_KS] > 0 else 0.0)
        f[c, F_E_DISSIP] = 0.0
    return True


registry.register_functor(Functor(
    "Ip2_ViscElMat_ViscElMat_ViscElPhys", "phys", ("ViscElMat", "ViscElMat"), "ViscElPhys",
    f"{__name__}:phys_viscel",
    (Param("tc", None, "Per-material-pair contact time (MatchMaker; not implemented: only None, from the materials)",
           supported=False),
     Param("en", None, "Per-material-pair normal restitution (MatchMaker; not implemented: only None)",
           supported=False),
     Param("et", None, "Per-material-pair tangential restitution (MatchMaker; not implemented: only None)",
           supported=False),
     Param("frictAngle", None, "Per-material-pair friction angle (MatchMaker; not implemented: only None)",
           supported=False)),
    phys_viscel.py_func.__doc__, HISTORY))
registry.register_functor(Functor(
    "Law2_ScGeom_ViscElPhys_Basic", "law", ("ScGeom", "ViscElPhys"), None,
    f"{__name__}:law_viscel", (), law_viscel.py_func.__doc__, HISTORY))
