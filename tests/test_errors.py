"""Bad input gets a clear Python exception and leaves the scene usable."""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import frict_engines, viscel_engines


def test_missing_body_id_is_an_index_error(yade):
    """O.bodies[id] out of range raises IndexError naming the id; negative ids count from the end."""
    yade.O.bodies.append([yade.sphere((0, 0, 0), 1), yade.sphere((3, 0, 0), 1)])
    with pytest.raises(IndexError, match="1000"):
        yade.O.bodies[1000]
    assert yade.O.bodies[-1].id == 1
    with pytest.raises(IndexError):
        yade.O.forces.f(5)
    with pytest.raises(IndexError):
        yade.O.interactions[0, 7]


def test_missing_interaction_is_a_value_error(yade):
    """O.interactions[i, j] for bodies that do not interact raises ValueError (as in YADE)."""
    yade.O.bodies.append([yade.sphere((0, 0, 0), 1), yade.sphere((30, 0, 0), 1)])
    yade.O.engines = frict_engines(yade)
    yade.O.step()
    with pytest.raises(ValueError, match="No such interaction"):
        yade.O.interactions[0, 1]
    assert not yade.O.interactions.has(0, 1)


def test_appending_a_body_twice_is_refused(yade):
    """The second append of the same Body raises and adds nothing."""
    b = yade.sphere((0, 0, 0), 1)
    assert yade.O.bodies.append(b) == 0
    with pytest.raises(ValueError, match="already"):
        yade.O.bodies.append(b)
    assert len(yade.O.bodies) == 1


@pytest.mark.parametrize("radius", [0, -1, math.nan, math.inf])
def test_non_positive_or_non_finite_radius_is_refused(yade, radius):
    """utils.sphere and Sphere.radius refuse radii that are not positive and finite."""
    with pytest.raises(ValueError, match="radius"):
        yade.sphere((0, 0, 0), radius)
    s = yade.sphere((0, 0, 0), 1)
    yade.O.bodies.append(s)
    with pytest.raises(ValueError, match="radius"):
        s.shape.radius = radius
    assert s.shape.radius == 1


@pytest.mark.parametrize("dt", [-1e-3, math.nan, math.inf])
def test_negative_or_non_finite_dt_is_refused(yade, dt):
    """O.dt must be finite and not negative (0 is allowed, as YADE's pbc tests use it); the previous value is
    kept."""
    yade.O.dt = 1e-4
    with pytest.raises(ValueError, match="dt"):
        yade.O.dt = dt
    assert yade.O.dt == 1e-4


def test_negative_mass_and_massless_free_body_are_refused(yade):
    """A negative mass raises at once; a free body without mass stops the run before the first step."""
    s = yade.sphere((0, 0, 0), 1)
    with pytest.raises(ValueError, match="mass"):
        s.state.mass = -1
    s.state.mass = 0
    yade.O.bodies.append(s)
    yade.O.engines = frict_engines(yade)
    with pytest.raises(yade.SimulationError, match="body 0 has mass 0"):
        yade.O.step()
    assert yade.O.iter == 0
    s.state.blockedDOFs = "xyz"  # a massless body is fine once it cannot translate
    yade.O.step()
    assert yade.O.iter == 1


@pytest.mark.parametrize("period", [1, 3])
def test_a_mass_taken_away_during_a_run_stops_it_before_compiled_code_divides_by_it(yade, period):
    """A PyRunner zeroes a free sphere's mass at step 3: the run stops with the error before the next step's
    compiled engines run (the clock stands after step 3), whether the runner goes step by step or in chunks."""
    yade.O.bodies.append([yade.sphere((0, 0, 0), 1), yade.sphere((5, 0, 0), 1)])
    yade.O.engines = frict_engines(yade, gravity=(0, 0, -10)) + [yade.PyRunner(
        iterPeriod=period, initRun=True, command="if O.iter == 3: O.bodies[1].state.mass = 0")]
    yade.O.dt = 1e-3
    with pytest.raises(yade.SimulationError, match="body 1 has mass 0"):
        yade.O.run(10, True)
    assert yade.O.iter == 4
    assert np.isfinite(np.asarray(yade.O.bodies[1].state.vel)).all()


@pytest.mark.parametrize("where", ["center", "pos", "vel", "angVel", "color"])
def test_nan_coordinates_are_refused(yade, where):
    """NaN in positions, velocities or colours raises ValueError naming the attribute; nothing changes."""
    bad = (0.0, math.nan, 0.0)
    if where == "center":
        with pytest.raises(ValueError):
            yade.sphere(bad, 1)
        return
    b = yade.sphere((1, 2, 3), 1)
    yade.O.bodies.append(b)
    obj = b.shape if where == "color" else b.state
    before = np.array(getattr(obj, where))
    with pytest.raises(ValueError, match=where.replace("angVel", "ang")):
        setattr(obj, where, bad)
    np.testing.assert_array_equal(np.array(getattr(obj, where)), before)


@pytest.mark.parametrize("make", [
    lambda y: y.NewtonIntegrator(dampin=0.1),
    lambda y: y.InsertionSortCollider([], verletDst=0.1),
    lambda y: y.FrictMat(yung=1e7),
    lambda y: y.PyRunner(comand="pass"),
    lambda y: y.Ig2_Sphere_Sphere_ScGeom(interactionDetectionFactr=1.2),
])
def test_unknown_keyword_is_an_error_with_a_suggestion(yade, make):
    """A misspelled constructor keyword raises TypeError suggesting the right name."""
    with pytest.raises(TypeError, match="did you mean"):
        make(yade)


def test_unknown_attribute_names_are_errors(yade):
    """Assigning a misspelled attribute raises AttributeError instead of creating it silently."""
    b = yade.sphere((0, 0, 0), 1)
    yade.O.bodies.append(b)
    newton = yade.NewtonIntegrator()
    targets = [(newton, "dampin"), (b, "dynamc"), (b.state, "velocity"), (b.shape, "radiu"),
               (yade.O, "dtt"), (yade.FrictMat(), "frictionangle"), (yade.O.bodies, "foo")]
    for obj, name in targets:
        with pytest.raises(AttributeError, match=name):
            setattr(obj, name, 1)
    yade.O.engines = frict_engines(yade)
    yade.O.bodies.append(yade.sphere((0, 0, 1.9), 1))
    yade.O.step()
    with pytest.raises(AttributeError, match="kn_"):
        yade.O.interactions[0, 1].phys.kn_ = 3


def test_missing_physics_functor_names_both_materials(yade):
    """A contact between materials without an Ip2 functor stops at the first step, naming both types."""
    m1 = yade.O.materials.append(yade.ViscElMat(tc=1e-3, en=0.5, et=0.5))
    m2 = yade.O.materials.append(yade.FrictMat())
    yade.O.bodies.append([yade.sphere((0, 0, 0), 1, material=m1), yade.sphere((0, 0, 1.99), 1, material=m2)])
    yade.O.engines = viscel_engines(yade)
    yade.O.dt = 1e-6
    with pytest.raises(yade.SimulationError, match="ViscElMat\\+FrictMat"):
        yade.O.step()
    assert yade.O.iter == 0
    assert yade.O.interactions.countReal() == 0
    # adding the missing functor lets the same scene run (FrictMat covers ViscElMat too)
    yade.O.engines[2].physDispatcher.functors = [yade.Ip2_FrictMat_FrictMat_FrictPhys()]
    yade.O.engines[2].lawDispatcher.functors = [yade.Law2_ScGeom_FrictPhys_CundallStrack()]
    yade.O.step()
    assert yade.O.interactions.countReal() == 1


def test_missing_law_functor_is_an_error(yade):
    """A contact without a matching Law2 functor stops at the first step."""
    yade.O.bodies.append([yade.sphere((0, 0, 0), 1), yade.sphere((0, 0, 1.99), 1)])
    yade.O.engines = [yade.ForceResetter(), yade.InsertionSortCollider([yade.Bo1_Sphere_Aabb()]),
                      yade.InteractionLoop([yade.Ig2_Sphere_Sphere_ScGeom()], [yade.Ip2_FrictMat_FrictMat_FrictPhys()],
                                           [yade.Law2_ScGeom_ViscElPhys_Basic()]),
                      yade.NewtonIntegrator()]
    with pytest.raises(yade.SimulationError, match="Law2"):
        yade.O.step()


def test_missing_geometry_functor_names_both_shapes(yade):
    """Bodies whose bounds overlap with no listed Ig2 functor for their shapes stop the run."""
    yade.O.bodies.append([yade.box((0, 0, 0), (1, 1, 1), fixed=True), yade.sphere((0, 0, 1.9), 1)])
    yade.O.engines = frict_engines(yade, geoms=[yade.Ig2_Sphere_Sphere_ScGeom()])
    with pytest.raises(yade.SimulationError, match="Box.*Sphere.*Ig2_"):
        yade.O.step()


def test_functor_of_the_wrong_role_is_refused(yade):
    """Passing a law where geometry functors are expected is a TypeError."""
    with pytest.raises(TypeError, match="IGeom"):
        yade.InteractionLoop([yade.Law2_ScGeom_FrictPhys_CundallStrack()], [], [])


@pytest.mark.fallback
@pytest.mark.parametrize("cause", ["exploding", "nan"])
def test_diverging_run_stops_with_body_and_step(yade, cause):
    """A run whose velocities explode or become NaN stops naming the body and step; the scene stays usable."""
    yade.O.bodies.append([yade.sphere((0, 0, 0), 0.1, fixed=True), yade.sphere((0, 0, 0.5), 0.1)])
    if cause == "exploding":  # a force no granular material produces: the speed passes 1e8 m/s
        extra = [yade.ForceEngine(ids=[1], force=(0, 0, 1e12))]
    else:
        extra = [yade.PyRunner(command="O.forces.addF(1, (float('nan'), 0, 0))", iterPeriod=7)]
    yade.O.engines = frict_engines(yade)[:3] + extra + frict_engines(yade)[3:]
    yade.O.dt = 1e-3
    with pytest.raises(yade.SimulationError, match=r"step \d+: body 1 has a non-finite or exploding state"):
        yade.O.run(1000, True)
    assert 0 <= yade.O.iter < 1000
    assert not yade.O.running
    assert yade.O.bodies[0].state.pos[2] == 0  # the scene is still there to inspect
    yade.O.engines = frict_engines(yade)    # removing the cause lets the user go on
    yade.O.bodies[1].state.vel = (0, 0, 0)
    yade.O.bodies[1].state.pos = (0, 0, 0.5)
    yade.O.step()


def test_error_in_pyrunner_stops_the_run_and_reaches_the_caller(yade):
    """An exception in a PyRunner command propagates from O.run(n, True) and from O.wait(), as YADE's
    RuntimeError naming the command (YADE's own tests check the message: tools/yade_tests.py core)."""
    yade.O.bodies.append(yade.sphere((0, 0, 0), 1))
    yade.O.engines = frict_engines(yade) + [yade.PyRunner(command="1/0", iterPeriod=5)]
    with pytest.raises(RuntimeError, match="PyRunner error.\n\nCOMMAND: '1/0'") as info:
        yade.O.run(100, True)
    assert isinstance(info.value.__cause__, ZeroDivisionError)
    assert str(info.value).endswith("ZeroDivisionError: division by zero\n")
    assert yade.O.iter == 5
    yade.O.run(100)
    with pytest.raises(RuntimeError, match="PyRunner error") as info:
        yade.O.wait()
    assert isinstance(info.value.__cause__, ZeroDivisionError)
    assert not yade.O.running


def test_functor_registered_late_or_outside_granum_is_refused():
    """A functor the compiled dispatch would never call (registered after the kernels were generated) or
    whose code the kernel cache does not track (outside granum.physics) is refused with a message."""
    import granum.kernels.dispatch  # noqa: F401  (generates the dispatch)
    from granum.physics import registry
    from granum.physics.registry import Functor

    late = Functor("Law2_Test_Late", "law", ("ScGeom", "FrictPhys"), None,
                   "granum.physics.frict:law_cundall_strack", (), "")
    with pytest.raises(RuntimeError, match="after the kernels were compiled"):
        registry.register_functor(late)
    outside = Functor("Law2_Test_Outside", "law", ("ScGeom", "FrictPhys"), None, "mylaws:law_mine", (), "")
    with pytest.raises(ValueError, match="must be in a module of granum.physics"):
        registry.register_functor(outside)
    assert "Law2_Test_Late" not in registry.FUNCTORS and "Law2_Test_Outside" not in registry.FUNCTORS
