"""Hostile inputs: values outside the range where the laws stay physical, wrong types where YADE would
silently convert, and every failure status a kernel can set each get a clear exception naming what is
wrong, and leave the previous value or scene intact.

The values YADE's example scripts give materials (/usr/share/doc/yade/examples) stay valid: density 0
(fixed walls), young 0 (facets meant not to interact), poisson 0 to 4 (the ks/kn ratio), frictionAngle
0 to radians(60) and 1.2, ViscElMat et = 0 (no shear spring, as in YADE).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import frict_engines, viscel_engines

from granum.core import contacts
from granum.core.contacts import C_ERR_A, C_ERR_B, C_STATUS
from granum.engines import status

NAN, INF = float("nan"), float("inf")


# ---- material parameters ---------------------------------------------------------------------

@pytest.mark.parametrize("cls, name, value, says", [
    ("FrictMat", "young", -1.0, ">= 0"),
    ("FrictMat", "young", NAN, ">= 0"),
    ("FrictMat", "young", INF, ">= 0"),
    ("FrictMat", "poisson", -0.5, "ratio ks/kn"),
    ("FrictMat", "frictionAngle", -0.1, ">= 0"),
    ("FrictMat", "frictionAngle", 2.0, "<= 1.5708"),
    ("FrictMat", "density", -1.0, "negative mass"),
    ("FrictMat", "density", INF, ">= 0"),
    ("ViscElMat", "en", 1.5, "creates energy"),
    ("ViscElMat", "en", -0.1, ">= 0"),
    ("ViscElMat", "et", 2.0, "<= 1"),
    ("ViscElMat", "tc", 0.0, "> 0"),
    ("ViscElMat", "tc", -1e-3, "> 0"),
    ("ViscElMat", "kn", -1.0, ">= 0"),
    ("ViscElMat", "cn", -1.0, ">= 0"),
    ("ViscElMat", "ks", INF, ">= 0"),
    ("ViscElMat", "cs", -1.0, ">= 0"),
    ("ViscElMat", "viscoDyn", -1.0, ">= 0"),
])
def test_material_parameter_out_of_its_range_is_refused(yade, cls, name, value, says):
    """A value where the law stops being physical is a ValueError naming class, attribute, range and value,
    at construction and on assignment; the previous value stays."""
    kind = getattr(yade, cls)
    with pytest.raises(ValueError, match=rf"{cls}\.{name} must be finite.*{says}.*got {value!r}"):
        kind(**{name: value})
    m = kind()
    before = getattr(m, name)
    with pytest.raises(ValueError, match=rf"{cls}\.{name}"):
        setattr(m, name, value)
    assert getattr(m, name) == before or (math.isnan(before) and math.isnan(getattr(m, name)))


@pytest.mark.parametrize("value", [True, "stiff", None, (1, 2)])
def test_material_parameter_of_the_wrong_type_is_a_type_error(yade, value):
    """A flag, a string, None or a tuple where a number is expected is a TypeError naming the attribute
    (YADE takes ``young=True`` as 1 Pa)."""
    m = yade.FrictMat(young=5e6)
    with pytest.raises(TypeError, match=r"FrictMat\.young must be a number"):
        m.young = value
    assert m.young == 5e6


@pytest.mark.parametrize("cls, kw", [
    ("FrictMat", dict(density=0)),                       # walls and fixed bodies (18 example scripts)
    ("FrictMat", dict(young=0)),                         # facets that must not interact (clumps/apply-buoyancy)
    ("FrictMat", dict(poisson=0)),
    ("FrictMat", dict(poisson=4.0)),                     # the ks/kn ratio, not a Poisson's ratio
    ("FrictMat", dict(frictionAngle=0)),
    ("FrictMat", dict(frictionAngle=1.2)),               # concrete/triax.py
    ("FrictMat", dict(frictionAngle=math.pi / 2)),
    ("ViscElMat", dict(en=0.5, et=0.0, young=1e7, poisson=0.5)),   # FluidCouplingVANS1D scripts
    ("ViscElMat", dict(tc=1e-3, en=1.0, et=1.0)),
    ("ViscElMat", dict(en=NAN)),                         # NaN: not given
])
def test_values_of_yade_example_scripts_stay_valid(yade, cls, kw):
    """The material values YADE's example scripts use are accepted unchanged."""
    m = getattr(yade, cls)(**kw)
    for k, v in kw.items():
        assert getattr(m, k) == v or (math.isnan(v) and math.isnan(getattr(m, k)))


def test_zero_tangential_restitution_means_no_shear_spring(yade):
    """ViscElMat et = 0 gives ks = cs = 0 as in YADE 2023.02a (kn, cn from en as usual), not the infinite
    shear stiffness ln(0) would give (values printed by YADE for these bodies: kn 21677109559.480206,
    cn 2903448.1204048023)."""
    m = yade.O.materials.append(yade.ViscElMat(tc=1e-3, en=0.5, et=0.0, density=1000, frictionAngle=0.5))
    yade.O.bodies.append([yade.sphere((0, 0, 0), 1, material=m), yade.sphere((0, 0, 1.9), 1, material=m)])
    yade.O.engines = viscel_engines(yade)
    yade.O.dt = 1e-6
    yade.O.step()
    phys = yade.O.interactions[0, 1].phys
    assert (phys.ks, phys.cs) == (0.0, 0.0)
    assert phys.kn == pytest.approx(21677109559.480206, rel=1e-12)
    assert phys.cn == pytest.approx(2903448.1204048023, rel=1e-12)


# ---- math types and body factories ----------------------------------------------------------

@pytest.mark.parametrize("make, error, says", [
    (lambda y: y.Vector3(1, 2, 3, 4), TypeError, "takes 3 numbers"),
    (lambda y: y.Vector2(1), TypeError, "takes 2 numbers"),
    (lambda y: y.Vector6(1, 2, 3), TypeError, "takes 6 numbers"),
    (lambda y: y.Vector3("a", 2, 3), TypeError, "expected a number"),
    (lambda y: y.Vector3([1, 2]), ValueError, "3-vector, got 2 components"),
])
def test_math_type_of_the_wrong_arity_or_type(yade, make, error, says):
    """Math types refuse a wrong number of components or a non-number, naming the expected form.
    (``Vector3(1, 2)`` is (1, 2, 0), as in YADE, whose Vector3 components default to 0.)"""
    with pytest.raises(error, match=says):
        make(yade)


@pytest.mark.parametrize("call, error, says", [
    (lambda y: y.sphere((0, 0, 0), 1, fixed="no"), TypeError, "sphere: fixed must be True or False, got 'no'"),
    (lambda y: y.sphere((0, 0, 0), 1, dynamic="yes"), TypeError, "sphere: dynamic must be True or False"),
    (lambda y: y.sphere((0, 0, 0), 1, wire=2), TypeError, "sphere: wire must be True or False"),
    (lambda y: y.sphere((0, 0, 0), True), TypeError, "sphere: radius must be a number, got True"),
    (lambda y: y.sphere((0, 0, 0), "1"), TypeError, "sphere: radius must be a number"),
    (lambda y: y.sphere((0, 0, 0), NAN), ValueError, "radius must be positive and finite"),
    (lambda y: y.sphere((0, 0, 0), INF), ValueError, "radius must be positive and finite"),
    (lambda y: y.sphere((0, 0, 0), 1, mask=1.5), TypeError, "sphere: mask must be an integer, got 1.5"),
    (lambda y: y.sphere((1, 2), 1), ValueError, "sphere: center: expected a 3-vector, got 2 components"),
    (lambda y: y.sphere("abc", 1), TypeError, "sphere: center"),
    (lambda y: y.sphere((NAN, 0, 0), 1), ValueError, "pos must be finite"),
    (lambda y: y.box((0, 0, 0), (1, 1, 1), fixed="False"), TypeError, "box: fixed must be True or False"),
    (lambda y: y.facet([(0, 0, 0), (1, 0, 0), (0, 1)]), ValueError, "facet: vertex"),
    (lambda y: y.facet([(0, 0, 0), (1, 0, 0), (0, 1, 0)], highlight="on"), TypeError, "facet: highlight"),
    (lambda y: y.wall((0, 0), axis=1), ValueError, "wall: position"),
])
def test_body_factory_refuses_a_wrong_argument(yade, call, error, says):
    """Body factories name the argument at fault (YADE takes ``fixed='no'`` as fixed and ``radius=True`` as
    1 m, or raises boost's ArgumentError); nothing is added to the scene."""
    with pytest.raises(error, match=says):
        call(yade)
    assert len(yade.O.bodies) == 0


@pytest.mark.parametrize("kw", [dict(fixed=0), dict(fixed=np.bool_(True)), dict(dynamic=0), dict(mask=2.0)])
def test_body_factory_accepts_what_yade_scripts_write(yade, kw):
    """``dynamic=0`` (two example scripts), NumPy bools and integral floats are accepted."""
    yade.sphere((0, 0, 0), 1, **kw)


# ---- failure statuses of a step ---------------------------------------------------------------

FAILURES = {k: v for k, v in vars(contacts).items() if k.startswith("STATUS_") and k != "STATUS_OK"}
#: what each status's message must say
SAYS = {"STATUS_NO_PHYS": "no IPhys functor", "STATUS_NO_LAW": "no Law2 functor",
        "STATUS_NONFINITE": "non-finite or exploding state", "STATUS_NO_GEOM": "no IGeom functor",
        "STATUS_TOO_LARGE": "spans over half of the periodic cell",
        "STATUS_NO_PAIR_VALUE": "has no value for the materials of bodies 0 and 1"}


def test_every_status_has_its_own_message(yade):
    """Each STATUS_* code of core/contacts.py has a message builder, raised as a SimulationError that
    names its cause (and no other status's); the status is cleared and the scene kept."""
    assert set(FAILURES) == set(SAYS), "a new STATUS_* code needs its message and an entry here"
    assert set(FAILURES.values()) <= set(status.MESSAGES)
    yade.O.bodies.append([yade.sphere((0, 0, 0), 1), yade.sphere((0, 0, 1.9), 1)])
    ctr = yade.O._scene.contacts.ctr
    messages = {}
    for name, code in FAILURES.items():
        ctr[C_STATUS], ctr[C_ERR_A], ctr[C_ERR_B] = code, 0, 1
        with pytest.raises(yade.SimulationError) as info:
            yade.O._runner.raise_status()
        messages[name] = str(info.value)
        assert ctr[C_STATUS] == 0
    for name, text in messages.items():
        assert SAYS[name] in text and "body 0" in text or "bodies 0" in text, (name, text)
        assert [other for other, says in SAYS.items() if says in text] == [name], (name, text)
    assert len(set(messages.values())) == len(messages)
    assert len(yade.O.bodies) == 2


def _run_to_failure(yade, match: str):
    with pytest.raises(yade.SimulationError, match=match) as info:
        yade.O.run(5, True)
    assert not yade.O.running
    return str(info.value)


def test_body_wider_than_half_the_periodic_cell(yade):
    """A sphere wider than half the periodic cell that meets a partner of smaller id is named as such (it used
    to be reported as a missing Law2 functor); YADE refuses it too ("Body #1 spans over half of the cell size",
    tests/reference/yade/periodic_span.py)."""
    yade.O.periodic = True
    yade.O.cell.hSize = yade.Matrix3(1, 0, 0, 0, 1, 0, 0, 0, 1)
    yade.O.bodies.append([yade.sphere((0.5, 0.5, 0.5), 0.11), yade.sphere((0.5, 0.5, 0.7), 0.4)])
    yade.O.engines = frict_engines(yade)
    yade.O.dt = 1e-5
    text = _run_to_failure(yade, r"body 1 \(Sphere.*spans over half of the periodic cell along the cell's axis 0"
                                 r".*enlarge O.cell.hSize.*allowBiggerThanPeriod")
    assert "Law2" not in text
    assert yade.O.iter == 0


def test_coincident_centres_are_named_not_the_time_step(yade):
    """Two spheres at the same centre: the undefined contact normal is the cause, not O.dt."""
    yade.O.bodies.append([yade.sphere((0, 0, 0), 1), yade.sphere((0, 0, 0), 1)])
    yade.O.engines = frict_engines(yade)
    yade.O.dt = 1e-5
    text = _run_to_failure(yade, r"bodies 0 and 1 has no defined normal.*centres coincide")
    assert "O.dt" not in text


def test_non_finite_stiffness_is_named_not_the_time_step(yade):
    """A ViscElMat without tc nor kn (YADE's Young's-modulus form, which granum does not compute) gives a
    contact of NaN stiffness: the message names the stiffness and the materials, not O.dt."""
    m = yade.O.materials.append(yade.ViscElMat(en=0.5, et=0.0, young=1e7, density=1000))
    yade.O.bodies.append([yade.sphere((0, 0, 0), 1, material=m), yade.sphere((0, 0, 1.9), 1, material=m)])
    yade.O.engines = viscel_engines(yade)
    yade.O.dt = 1e-6
    text = _run_to_failure(yade, r"non-finite stiffness \(kn=nan.*ViscElMat, ViscElMat")
    assert "O.dt" not in text
