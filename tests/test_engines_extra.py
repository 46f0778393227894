"""The kinematic, force and field engines of tests/reference/yade/engines_extra.py: YADE 2023.02a's records,
step by step, and closed forms (harmonic motion, terminal velocity under drag, an orbit under central
acceleration), determinism, refused input."""

import math
import sys

import numpy as np
import pytest
from conftest import REFERENCE, granum_reference_run, reference


@pytest.fixture(scope="module")
def granum_runs():
    """The reference script's records, produced by granum."""
    return granum_reference_run("engines_extra.py")


RUNS = sorted(reference("engines_extra"))


@pytest.mark.parametrize("run", RUNS)
def test_as_yade_step_by_step(granum_runs, run):
    """Every body's pos, vel, angVel, ori, force and torque after every step, and the engine's changing
    attributes, equal YADE's to 1e-9 of the largest magnitude the quantity takes in the run. YADE's engines
    hand out their vector attributes by reference (the records all hold the last value), so those are
    compared after the last step only."""
    ref, got = reference("engines_extra")[run], granum_runs[run]
    assert "exception" not in got, got
    assert len(got) == len(ref)
    for key in ref[0]["state"][0]:
        r = np.array([[b[key] for b in rec["state"]] for rec in ref])
        g = np.array([[b[key] for b in rec["state"]] for rec in got])
        if key == "ori":  # q and -q are the same rotation
            g *= np.sign(np.sum(g * r, axis=-1, keepdims=True))
        np.testing.assert_allclose(g, r, rtol=0, atol=1e-9 * max(1.0, np.abs(r).max()), err_msg=f"{run}: {key}")
    for name, value in ref[-1]["attrs"].items():
        if isinstance(value, list):
            np.testing.assert_allclose(np.array(got[-1]["attrs"][name], float), value, rtol=1e-9, atol=1e-12,
                                       err_msg=f"{run}: {name}")
        else:
            r = np.array([rec["attrs"][name] for rec in ref], float)
            g = np.array([rec["attrs"][name] for rec in got], float)
            np.testing.assert_allclose(g, r, rtol=1e-9, atol=1e-12, err_msg=f"{run}: {name}")


def _free_sphere(y, pos=(0, 0, 0), r=0.01, fixed=False):
    return y.O.bodies.append(y.sphere(pos, r, fixed=fixed))


def _run(y, engines, dt, steps, gravity=(0, 0, 0)):
    y.O.engines = [y.ForceResetter()] + engines + [y.NewtonIntegrator(gravity=gravity, damping=0)]
    y.O.dt = dt
    y.O.run(steps, True)


def test_harmonic_motion_closed_form(yade):
    """x(t) = x0 + A (cos(w t + fi) - cos fi) per component: the step sums v(t_k) dt at the start of each step
    (first order), so the error is at most A w^2 t dt / 2 and halves with dt."""
    A, f, fi, t_end = np.array([0.01, 0.0, 0.02]), np.array([3.0, 0.0, 1.0]), np.array([0.3, 1.0, math.pi / 2]), 0.5
    w = 2 * math.pi * f
    errors = []
    for dt in (1e-3, 5e-4):
        yade.O.reset()
        b = _free_sphere(yade, pos=(1, 2, 3), fixed=True)
        _run(yade, [yade.HarmonicMotionEngine(ids=[b], A=tuple(A), f=tuple(f), fi=tuple(fi))], dt, round(t_end / dt))
        exact = np.array([1, 2, 3]) + A * (np.cos(w * t_end + fi) - np.cos(fi))
        err = np.abs(np.asarray(yade.O.bodies[b].state.pos) - exact)
        assert np.all(err <= 0.5 * np.abs(A) * w ** 2 * t_end * dt * (1 + 1e-6) + 1e-15)
        errors.append(err.max())
    assert 1.8 < errors[0] / errors[1] < 2.2


def test_linear_drag_terminal_velocity(yade):
    """Under gravity and Stokes drag (b = 6 pi nu r), the step's update v' = v + dt (g - b v / m) gives exactly
    v_n = v_inf (1 - (1 - b dt/m)^n), v_inf = m g / b: the drag reads the velocity at the start of the step; it
    tends to the closed form v_inf (1 - exp(-b t / m)) to first order in dt."""
    r, g, dt, n = 0.01, -9.81, 1e-4, 400
    b = _free_sphere(yade, r=r)
    m = yade.O.bodies[b].state.mass
    nu = 50 * m / (6 * math.pi * r)  # b/m = 50 1/s
    _run(yade, [yade.LinearDragEngine(ids=[b], nu=nu)], dt, n, gravity=(0, 0, g))
    k, v_inf = 50.0, g / 50.0
    vz = yade.O.bodies[b].state.vel[2]
    assert vz == pytest.approx(v_inf * (1 - (1 - k * dt) ** n), rel=1e-12)
    assert abs(vz - v_inf * (1 - math.exp(-k * n * dt))) <= abs(v_inf) * k ** 2 * n * dt * dt
    yade.O.run(20000, True)  # e^-100: the terminal velocity
    assert yade.O.bodies[b].state.vel[2] == pytest.approx(v_inf, rel=1e-12)


def test_quadratic_drag_terminal_velocity(yade):
    """DragEngine: m g = rho Cd / 2 v^2 pi r^2 at the terminal velocity."""
    r, g, rho, cd = 0.01, -9.81, 1000.0, 0.47
    b = _free_sphere(yade, r=r)
    m = yade.O.bodies[b].state.mass
    _run(yade, [yade.DragEngine(ids=[b], Rho=rho, Cd=cd)], 1e-4, 30000, gravity=(0, 0, g))
    assert yade.O.bodies[b].state.vel[2] == pytest.approx(-math.sqrt(m * -g / (0.5 * rho * cd * math.pi * r * r)),
                                                          rel=1e-9)


def test_central_acceleration_circular_orbit(yade):
    """A constant acceleration a towards a fixed body keeps a body launched at v = sqrt(a r0) on the circle r0:
    over a period the leapfrog's radius error is of second order in dt (a quarter when dt halves)."""
    a, r0 = 2.0, 0.5
    v0 = math.sqrt(a * r0)
    period = 2 * math.pi * r0 / v0
    worst = []
    for dt in (2e-3, 1e-3):
        yade.O.reset()
        c = _free_sphere(yade, fixed=True)
        b = _free_sphere(yade, pos=(r0, 0, 0))
        yade.O.bodies[b].state.vel = (a * dt / 2, v0, 0)  # the leapfrog's velocity half a step before t = 0
        yade.O.engines = [yade.ForceResetter(), yade.CentralConstantAccelerationEngine(centralBody=c, accel=a),
                          yade.NewtonIntegrator(damping=0)]
        yade.O.dt = dt
        radii = []
        for _ in range(round(period / dt)):
            yade.O.step()
            radii.append(np.linalg.norm(np.asarray(yade.O.bodies[b].state.pos)))
        worst.append(np.abs(np.array(radii) - r0).max() / r0)
    assert worst[0] < 1e-4
    assert 3.5 < worst[0] / worst[1] < 4.5


def test_axial_gravity_pulls_towards_the_axis_only(yade):
    """AxialGravityEngine: the force is m a towards the axis, perpendicular to it, whatever the distance."""
    ids = [_free_sphere(yade, pos=p) for p in [(1, 5, 0), (0, -2, 3), (0.1, 0, 0.1)]]
    _run(yade, [yade.AxialGravityEngine(axisPoint=(0, 1, 0), axisDirection=(0, 2, 0), acceleration=4)], 1e-3, 1)
    for i in ids:
        p, f, m = (np.asarray(x) for x in (yade.O.bodies[i].state.pos, yade.O.forces.f(i),
                                           yade.O.bodies[i].state.mass))
        d = p * [1, 0, 1]
        np.testing.assert_allclose(f, -4 * m * d / np.linalg.norm(d), rtol=1e-3)  # p moved by a step


def test_threads_give_the_same_bits(tmp_path):
    """The rotating drum with the new engines (RotationEngine + HarmonicMotionEngine on the drum, LinearDragEngine
    on the spheres): -j1 and -j2 give the same positions and angular velocities, bit for bit."""
    import os
    import subprocess
    from pathlib import Path

    script = Path(__file__).parents[1] / "benchmarks" / "rotating_drum.py"
    states = {}
    for j in ("1", "2"):
        out = tmp_path / f"j{j}.txt"
        subprocess.run([sys.executable, "-m", "granum", "-j", j, str(script)], check=True, timeout=1800,
                       env={**os.environ, "BENCH_N": "1500", "BENCH_STEPS": "300", "BENCH_EXTRA": "1",
                            "BENCH_DUMP": str(out)}, capture_output=True)
        states[j] = out.read_text()
    assert states["1"] == states["2"]
    w = np.loadtxt(tmp_path / "j1.txt")[:, 3:]
    assert np.abs(w).max() > 0, "nothing turned"


def test_save_load_continue_equals_uninterrupted(yade):
    """The engines' state (angle turned, interpolated speeds, the servo's integral and errors) is saved with the
    scene: save, run, load, run again gives the same bits."""
    yade.O.bodies.append([yade.sphere((0, 0, 0), .5, fixed=True), yade.sphere((0, 0, .95), .5, fixed=True)])
    helix = yade.InterpolatingHelixEngine(ids=[0], times=[0, 1e-3], angularVelocities=[1, 3], slope=.5,
                                          rotationAxis=(0, 1, 0), wrap=True)
    servo = yade.ServoPIDController(ids=[1], axis=(0, 0, -1), maxVelocity=.5, target=1e5, kP=1e-6, kI=1e-7, kD=1e-7,
                                    iterPeriod=3)
    yade.O.engines = [yade.ForceResetter(), yade.InsertionSortCollider([yade.Bo1_Sphere_Aabb()]),
                      yade.InteractionLoop([yade.Ig2_Sphere_Sphere_ScGeom()], [yade.Ip2_FrictMat_FrictMat_FrictPhys()],
                                           [yade.Law2_ScGeom_FrictPhys_CundallStrack()]),
                      helix, yade.NewtonIntegrator(damping=0), servo]
    yade.O.dt = 1e-4
    yade.O.run(10, True)
    yade.O.saveTmp()

    def finish():
        yade.O.run(10, True)
        e = yade.O.engines
        return ([tuple(b.state.pos) + tuple(b.state.ori) for b in yade.O.bodies],
                [e[3].angleTurned, e[3].angularVelocity, e[5].iTerm, e[5].errorPrev, e[5].iterPrevStart])

    first = finish()
    yade.O.loadTmp()
    assert finish() == first


@pytest.mark.parametrize("make, bad", [
    (lambda y: y.HarmonicMotionEngine(f=(-1, 0, 0)), "f"),
    (lambda y: y.HarmonicRotationEngine(f=-2), "f"),
    (lambda y: y.DragEngine(Rho=-1), "Rho"),
    (lambda y: y.DragEngine(Cd=float("nan")), "Cd"),
    (lambda y: y.LinearDragEngine(nu=-0.1), "nu"),
    (lambda y: y.ServoPIDController(maxVelocity=-1), "maxVelocity"),
    (lambda y: y.ServoPIDController(iterPeriod=0), "iterPeriod"),
    (lambda y: y.InterpolatingHelixEngine(times=[0, "a"]), "times"),
])
def test_bad_values_refused_naming_them(yade, make, bad):
    with pytest.raises((ValueError, TypeError), match=bad):
        make(yade)


@pytest.mark.parametrize("engine, bad", [
    (lambda y: y.InterpolatingHelixEngine(ids=[0], times=[0, 1], angularVelocities=[1]), "angularVelocities"),
    (lambda y: y.InterpolatingHelixEngine(ids=[0], times=[0, 2, 1], angularVelocities=[1, 2, 3]), "times"),
    (lambda y: y.InterpolatingDirectedForceEngine(ids=[0]), "times"),
    (lambda y: y.InterpolatingDirectedForceEngine(ids=[0], times=[0], magnitudes=[1], direction=(0, 0, 0)),
     "direction"),
    (lambda y: y.ServoPIDController(ids=[0]), "axis"),
    (lambda y: y.BicyclePedalEngine(ids=[0], rotationAxis=(0, 0, 0)), "rotationAxis"),
    (lambda y: y.CentralConstantAccelerationEngine(), "centralBody"),
    (lambda y: y.CentralConstantAccelerationEngine(centralBody=5), "centralBody"),
    (lambda y: y.AxialGravityEngine(axisDirection=(0, 0, 0)), "axisDirection"),
    (lambda y: y.TorqueEngine(ids=[3]), "ids"),
])
def test_bad_setups_refused_before_any_step(yade, engine, bad):
    """Refused when the run starts, naming the attribute; nothing has moved."""
    _free_sphere(yade)
    yade.O.engines = [yade.ForceResetter(), engine(yade), yade.NewtonIntegrator()]
    yade.O.dt = 1e-3
    with pytest.raises((ValueError, IndexError), match=bad):
        yade.O.run(1, True)
    assert yade.O.iter == 0


def test_rotating_drum_as_yade():
    """benchmarks/rotating_drum.py (facetCylinder drum, RotationEngine + HarmonicMotionEngine, LinearDragEngine,
    frictional contacts with the spheres and the moving facets) at 455 spheres over 1001 steps, run by the
    reference script itself: the same contacts, and every sphere's position and angular velocity as YADE's."""
    import granum.yade as y
    from granum.cli import install_yade_alias

    install_yade_alias()  # the benchmark imports yade.geom, as under the launcher

    sys.path.insert(0, str(REFERENCE))
    argv = sys.argv
    try:
        import _common
        out = {}
        saved = _common.dump
        _common.dump = lambda topic, data: out.update(data)
        sys.argv = [str(REFERENCE / "rotating_drum.py")]
        ns: dict = {}
        exec("from granum.yade import *", ns)
        exec(compile((REFERENCE / "rotating_drum.py").read_text(), "rotating_drum.py", "exec"), ns)
    finally:
        _common.dump = saved
        sys.argv = argv
        sys.path.remove(str(REFERENCE))
        y.O.reset()
    ref = reference("rotating_drum")
    assert (out["iter"], out["contacts"]) == (ref["iter"], ref["contacts"])
    np.testing.assert_allclose(np.array(out["facet"][0]), ref["facet"][0], rtol=0, atol=1e-12)
    got, want = np.array(out["spheres"]), np.array(ref["spheres"])
    # rounding differences (the order of the sums) grow through 1000 steps of contacts: measured 1.1e-9 m at most
    np.testing.assert_allclose(got[:, 0], want[:, 0], rtol=0, atol=1e-8)  # positions [m], r = 0.01
    # spins: the drum read from the STL file (two triangles per side panel) gave 2 of 455 spheres up to 2.6e-4 of
    # the largest spin apart (measured), the facetCylinder drum 1e-5
    np.testing.assert_allclose(got[:, 1], want[:, 1], rtol=0, atol=5e-4 * np.abs(want[:, 1]).max())


@pytest.mark.parametrize("mask", [0, -1, 2, 1, -2])
def test_newton_integrator_mask_moves_only_matching_bodies_as_yade(yade, mask):
    """NewtonIntegrator.mask > 0 leaves a body that shares no bit with it alone (velocity and position); <= 0
    moves all (tests/reference/yade/newton_mask.py)."""
    y = yade
    y.O.bodies.append([y.sphere((0, 0, 0), 1, mask=1), y.sphere((5, 0, 0), 1, mask=0), y.sphere((10, 0, 0), 1, mask=3)])
    y.O.engines = [y.ForceResetter(), y.NewtonIntegrator(gravity=(0, 0, -10), damping=0, mask=mask)]
    y.O.dt = 0.1
    y.O.run(3, True)
    got = [[list(b.state.pos), list(b.state.vel)] for b in y.O.bodies]
    np.testing.assert_allclose(got, reference("newton_mask")[str(mask)], rtol=1e-12, atol=1e-15)
