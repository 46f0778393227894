"""Dynamics against closed-form solutions, conservation laws and real YADE's results."""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import frict_engines, reference


@pytest.mark.parametrize("damping", [0.0, 0.3])
def test_free_fall_is_the_exact_leapfrog_solution(yade, damping):
    """A free sphere follows leapfrog exactly: v_n = a n dt, z_n = z0 + a dt^2 n(n+1)/2."""
    O = yade.O
    O.bodies.append(yade.sphere((0, 0, 10), 0.1))
    O.engines = frict_engines(yade, gravity=(0, 0, -9.81), damping=damping)
    O.dt = 1e-4
    n = 5000
    O.run(n, True)
    # YADE's damping acts on the whole acceleration, gravity included: a falling body
    # accelerates at (1 - damping) g
    a = -9.81 * (1 - damping)
    b = O.bodies[0]
    assert O.iter == n
    assert b.state.vel[2] == pytest.approx(a * n * 1e-4, rel=1e-10)
    assert b.state.pos[2] == pytest.approx(10 + a * 1e-8 * n * (n + 1) / 2, rel=1e-10)
    assert b.state.pos[0] == 0 and b.state.vel[1] == 0
    assert O.time == pytest.approx(n * 1e-4, rel=1e-12)


@pytest.mark.parametrize("turn", [1e-7, 0.05, 0.3])
def test_free_spin_turns_by_omega_t(yade, turn):
    """A free sphere spinning at omega turns by |omega| t about omega: the orientation after n steps is
    the closed-form rotation, to n rounding errors (turns per step on both sides of the 0.1 rad where
    the rotation quaternion switches from its series to sine and cosine)."""
    O = yade.O
    O.bodies.append(yade.sphere((0, 0, 0), 0.1))
    axis = np.array([1.0, -2.0, 0.5]) / math.sqrt(5.25)
    O.dt = 1e-3
    O.bodies[0].state.angVel = tuple(axis * turn / O.dt)
    O.engines = frict_engines(yade)
    n = 400
    O.run(n, True)
    x, y, z, w = O.bodies[0].state.ori  # YADE's component order
    angle = (n * turn) % (2 * math.pi)
    expected = np.r_[math.cos(angle / 2), axis * math.sin(angle / 2)]
    got = np.r_[w, x, y, z] * np.sign(np.dot([w, x, y, z], expected))  # q and -q are one rotation
    np.testing.assert_allclose(got, expected, rtol=0, atol=n * 4e-16)


def test_damping_is_yades_sign_rule():
    """NewtonIntegrator's non-viscous damping (3.5,24): a (1 - d) when a and v agree in sign, a (1 + d)
    when they oppose, a unchanged when either is zero."""
    from granum.kernels.newton import damp

    d = 0.3
    for a, v, expected in [(2.0, 1.0, 2.0 * (1 - d)), (-2.0, -1.0, -2.0 * (1 - d)), (2.0, -1.0, 2.0 * (1 + d)),
                           (-2.0, 1.0, -2.0 * (1 + d)), (2.0, 0.0, 2.0), (0.0, 1.0, 0.0)]:
        assert damp(a, v, d) == expected


def test_elastic_collision_conserves_energy_and_momentum(yade):
    """Head-on frictional spheres without damping: momentum exact, energy error bounded by (w dt)."""
    O = yade.O
    r = 0.01
    O.materials.append(yade.FrictMat(young=1e7, poisson=0.3, density=2600, frictionAngle=0.5))
    O.bodies.append([yade.sphere((-r - 1e-4, 0, 0), r), yade.sphere((r + 1e-4, 0.003, 0), r)])
    O.bodies[0].state.vel = (1, 0, 0)
    O.bodies[1].state.vel = (-1, 0, 0)
    O.engines = frict_engines(yade)
    O.dt = 0.1 * yade.PWaveTimeStep()
    O.trackEnergy = True
    m = O.bodies[0].state.mass
    kn = 1e7 * r  # equal spheres: kn = E r
    w_dt = math.sqrt(kn / (m / 2)) * O.dt  # contact frequency x time step
    e0 = m * 1.0  # 2 x m v^2 / 2
    worst = 0.0
    for _ in range(600):
        O.step()
        total = O.energy["kinetic"] + (O.energy["elastPotential"] if "elastPotential" in O.energy else 0.0)
        worst = max(worst, abs(total - e0) / e0)
        p = sum(b.state.mass * np.asarray(b.state.vel) for b in O.bodies)
        assert np.abs(p).max() < 1e-15 * m
    assert O.interactions.countReal() == 0, "the spheres must have separated"
    # kinetic energy is taken at the previous half step, potential energy on the step:
    # the bookkeeping is first order in w dt during contact ...
    assert worst < 2 * w_dt
    # ... and the symplectic integrator returns the energy up to second order afterwards
    v = np.array([b.state.vel for b in O.bodies])
    ke = 0.5 * m * (v ** 2).sum() + sum(0.5 * np.dot(b.state.inertia, np.asarray(b.state.angVel) ** 2)
                                        for b in O.bodies)
    assert abs(ke - e0) / e0 < w_dt ** 2


def _viscel_run(yade, run):
    O = yade.O
    R = run["R"]
    O.engines = [yade.ForceResetter(), yade.InsertionSortCollider([yade.Bo1_Sphere_Aabb()]),
                 yade.InteractionLoop([yade.Ig2_Sphere_Sphere_ScGeom()], [yade.Ip2_ViscElMat_ViscElMat_ViscElPhys()],
                                      [yade.Law2_ScGeom_ViscElPhys_Basic()]),
                 yade.NewtonIntegrator(gravity=(0, 0, 0), damping=0)]
    O.dt = run["dt"]
    mat = O.materials.append(yade.ViscElMat(density=run["density"], **run["material"]))
    a = yade.sphere(run["initial_pos"][0], R, material=mat)
    b = yade.sphere(run["initial_pos"][1], R, material=mat, fixed=run["fixed2"])
    O.bodies.append([a, b])
    a.state.vel = run["before"]["v0"]
    if not run["fixed2"]:
        b.state.vel = run["before"]["v1"]
    first = last = None
    phys = None
    for _ in range(20000):
        O.step()
        if O.interactions.countReal():
            i = O.interactions[0, 1]
            if first is None:
                first = O.iter
                phys = {k: getattr(i.phys, k) for k in ("kn", "cn", "ks", "cs", "tangensOfFrictionAngle")}
            last = O.iter
        elif first is not None and O.iter > last + 100:
            break
    return a, b, phys, first, last


@pytest.mark.parametrize("case", ["headon_en0.3", "headon_en0.7", "headon_kn_cn", "vs_fixed_en0.3"])
def test_viscoelastic_head_on_collision_matches_yade(yade, case):
    """ViscElMat head-on collisions: contact constants, duration and restitution as in real YADE."""
    run = reference("viscel")[case]
    a, b, phys, first, last = _viscel_run(yade, run)
    for k, v in run["phys_at_first_contact"]["dict"].items():
        if k in phys:
            assert phys[k] == pytest.approx(v, rel=1e-12), k
    assert last - first == pytest.approx(run["last_contact_iter"] - run["first_contact_iter"], abs=2)
    ref = run["after"]
    # identical algorithm: the only difference left is floating-point rounding
    assert a.state.vel[0] == pytest.approx(ref["v0"][0], rel=1e-6)
    assert b.state.vel[0] == pytest.approx(ref["v1"][0], abs=1e-9)
    if not run["fixed2"]:
        assert a.state.vel[0] + b.state.vel[0] == pytest.approx(0, abs=1e-15)  # momentum


@pytest.mark.parametrize("case", ["oblique_en0.3_phi0.5", "oblique_en0.3_phi0.05"])
def test_viscoelastic_oblique_collision_matches_yade(yade, case):
    """Oblique ViscElMat impacts (sticking and sliding friction): velocities and spins as in YADE."""
    run = reference("viscel")[case]
    a, b, _, _, _ = _viscel_run(yade, run)
    ref = run["after"]
    np.testing.assert_allclose(np.asarray(a.state.vel), ref["v0"], rtol=1e-5, atol=1e-9)
    np.testing.assert_allclose(np.asarray(b.state.angVel), ref["w1"], rtol=1e-5, atol=1e-7)
    p = a.state.mass * np.asarray(a.state.vel) + b.state.mass * np.asarray(b.state.vel)
    assert np.abs(p).max() < 1e-15


@pytest.mark.parametrize("support", ["sphere", "facet", "wall", "box"])
def test_resting_sphere_carries_exactly_its_weight(yade, support):
    """At rest on a fixed support the contact force is m g and the overlap m g / kn."""
    O = yade.O
    r = 0.1
    O.materials.append(yade.FrictMat(young=1e7, poisson=0.3, density=2000, frictionAngle=0.5))
    # off-centre on flat supports; exactly on top of a sphere (otherwise it rolls off)
    top = yade.sphere((0.0, 0.0, 0.0) if support == "sphere" else (0.01, 0.02, 0.0), r)
    if support == "sphere":
        base = yade.sphere((0, 0, -2 * r), r, fixed=True)
        kn_radii = (r, r)
    elif support == "facet":
        base = yade.facet([(-1, -1, -r), (1, -1, -r), (0, 1, -r)])
        kn_radii = (2 * r, r)  # YADE's facet contacts use 2r for the facet
    elif support == "wall":
        base = yade.wall(-r, axis=2)
        kn_radii = (r, r)
    else:
        base = yade.box((0, 0, -r - 0.5), (1, 1, 0.5), fixed=True)
        kn_radii = (r, r)
    O.bodies.append([base, top])
    O.engines = frict_engines(yade, gravity=(0, 0, -9.81), damping=0.5)
    O.dt = 0.2 * yade.PWaveTimeStep()
    O.run(20000, True)
    m = top.state.mass
    kn = 2 * 1e7 * kn_radii[0] * 1e7 * kn_radii[1] / (1e7 * kn_radii[0] + 1e7 * kn_radii[1])
    i = O.interactions[0, 1]
    fn = np.asarray(i.phys.normalForce)
    assert abs(top.state.vel[2]) < 1e-9
    np.testing.assert_allclose(fn, [0, 0, m * 9.81], rtol=1e-9, atol=1e-9 * m)
    assert i.geom.penetrationDepth == pytest.approx(m * 9.81 / kn, rel=1e-9)
    assert yade.unbalancedForce() < 1e-8


def _incline(yade, slope_deg, friction_deg, ramp, hold):
    """Sphere that cannot roll on a horizontal wall; gravity tilts slowly to the slope angle.

    The tilt grows over ``ramp`` steps (many periods of the tangential spring, so the
    loading is quasi-static and does not overshoot), then stays for ``hold`` steps.
    """
    O = yade.O
    r, rho, young = 0.05, 2000.0, 1e7
    O.materials.append(yade.FrictMat(young=young, poisson=0.3, density=rho, frictionAngle=math.radians(friction_deg)))
    g = 9.81
    s = yade.sphere((0, 0, 0), r)
    m = s.state.mass
    kn = young * r
    s.state.pos = (0, 0, r - m * g / kn)  # start at the normal equilibrium: no bouncing
    s.state.blockedDOFs = "XYZ"
    O.bodies.append([yade.wall(0, axis=2), s])
    O.engines = frict_engines(yade, gravity=(0, 0, -g), damping=0.0)
    newton = O.engines[-1]
    O.dt = 0.2 * yade.PWaveTimeStep()
    xs = []
    for k in range(ramp + hold):
        th = math.radians(slope_deg) * min(1.0, k / ramp)
        newton.gravity = (g * math.sin(th), 0, -g * math.cos(th))
        O.step()
        xs.append((O.time, s.state.pos[0], s.state.vel[0]))
    return np.array(xs), m, kn * 0.3, g, math.radians(slope_deg)


def test_sphere_sticks_below_the_friction_angle(yade):
    """Below the friction angle the sphere stays put: x ~ m g sin(theta)/ks, shear force = m g sin(theta)."""
    xs, m, ks, g, th = _incline(yade, 29.0, 30.0, 3000, 1000)
    assert np.abs(xs[:, 1]).max() <= 1.2 * m * g * math.sin(th) / ks
    fs = yade.O.interactions[0, 1].phys.shearForce
    assert fs[0] == pytest.approx(-m * g * math.sin(th), rel=0.05)


def test_sphere_slides_above_the_friction_angle_with_the_coulomb_acceleration(yade):
    """Above the friction angle it slides with a = g (sin(theta) - tan(phi) cos(theta))."""
    xs, m, ks, g, th = _incline(yade, 31.0, 30.0, 3000, 3000)
    a_exact = g * (math.sin(th) - math.tan(math.radians(30.0)) * math.cos(th))
    late = xs[-2000:]
    a = np.polyfit(late[:, 0], late[:, 2], 1)[0]
    assert a == pytest.approx(a_exact, rel=1e-3)
    assert xs[-1, 1] > 100 * m * g * math.sin(th) / ks  # far beyond any elastic deflection
