"""Engines other than the contact pipeline: aspherical rotation, kinematic and force engines, helpers."""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import frict_engines

from granum.mathtypes import as_quat_wxyz


def _rotation_matrix(q):
    w, x, y, z = as_quat_wxyz(q)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def test_free_box_conserves_angular_momentum_and_energy(yade):
    """A torque-free box spinning about a non-principal axis: L exact, energy to O(dt^2), axis precesses."""
    b = yade.box((0, 0, 0), (0.1, 0.2, 0.4))
    yade.O.bodies.append(b)
    yade.O.engines = [yade.ForceResetter(), yade.NewtonIntegrator(damping=0)]
    w0 = np.array([1.0, 2.0, 3.0])
    b.state.angVel = w0
    inertia = np.asarray(b.state.inertia)
    L0 = inertia * w0  # ori is the identity: local = global
    E0 = 0.5 * np.dot(inertia, w0 ** 2)
    dt = 1e-4
    yade.O.dt = dt
    worst_e = worst_w = 0.0
    for _ in range(200):
        yade.O.run(50, True)
        # the angular momentum is the integrated quantity: without torque it must not change at all
        np.testing.assert_array_equal(np.asarray(b.state.angMom), L0)
        R = _rotation_matrix(b.state.ori)
        ll = R.T @ L0
        worst_e = max(worst_e, abs(0.5 * np.dot(ll, ll / inertia) - E0) / E0)
        # the reported angular velocity is the mid-step one, consistent with L to first order
        w = np.asarray(b.state.angVel)
        worst_w = max(worst_w, np.linalg.norm(R @ (ll / inertia) - w) / np.linalg.norm(w))
    wdt = np.linalg.norm(w0) * dt
    assert worst_e < 10 * wdt ** 2  # Fincham's leapfrog is second order
    assert worst_w < 10 * wdt
    assert not np.allclose(np.asarray(b.state.angVel), w0, rtol=1e-2)  # the spin axis really moved


def test_torque_free_rotation_about_a_principal_axis_is_steady(yade):
    """Spin about a principal axis stays constant; the orientation turns by |w| t."""
    b = yade.box((0, 0, 0), (0.1, 0.2, 0.4))
    yade.O.bodies.append(b)
    yade.O.engines = [yade.ForceResetter(), yade.NewtonIntegrator(damping=0)]
    b.state.angVel = (0, 0, 2.0)
    yade.O.dt = 1e-4
    yade.O.run(10000, True)
    np.testing.assert_allclose(np.asarray(b.state.angVel), [0, 0, 2.0], atol=1e-12)
    axis, angle = b.state.ori.toAxisAngle()
    # second-order quaternion update: relative angle error ~ (w dt)^2 w t = 8e-8
    assert angle == pytest.approx(2.0, rel=1e-7)
    np.testing.assert_allclose(np.asarray(axis), [0, 0, 1], atol=1e-9)


def test_translation_engine_moves_bodies_at_constant_velocity(yade):
    """TranslationEngine imposes velocity * (normalised axis); the body moves v t."""
    f = yade.facet([(0, 0, 0), (1, 0, 0), (0, 1, 0)])
    yade.O.bodies.append(f)
    p0 = np.asarray(f.state.pos).copy()
    yade.O.engines = [yade.ForceResetter(), yade.TranslationEngine(ids=[0], velocity=2.0, translationAxis=(0, 0, 3)),
                      yade.NewtonIntegrator()]
    yade.O.dt = 1e-3
    yade.O.run(500, True)
    np.testing.assert_allclose(np.asarray(f.state.pos), p0 + [0, 0, 1.0], rtol=1e-12)
    np.testing.assert_allclose(np.asarray(f.state.vel), [0, 0, 2.0])


def test_rotation_engine_spins_and_orbits(yade):
    """RotationEngine: orientation turns by w t exactly; rotateAroundZero keeps the body on the circle."""
    b = yade.sphere((1, 0, 0), 0.1, fixed=True)
    yade.O.bodies.append(b)
    yade.O.engines = [yade.ForceResetter(),
                      yade.RotationEngine(ids=[0], angularVelocity=math.pi, rotationAxis=(0, 0, 2),
                                          rotateAroundZero=True, zeroPoint=(0, 0, 0)),
                      yade.NewtonIntegrator()]
    dt = 1e-4
    yade.O.dt = dt
    yade.O.run(10000, True)  # t = 1 s: half a turn
    axis, angle = b.state.ori.toAxisAngle()
    assert angle == pytest.approx(math.pi, rel=1e-9)
    # the body moves along the chord of its circle each step (as in YADE), so it stays on the circle
    np.testing.assert_allclose(np.asarray(b.state.pos), [-1, 0, 0], atol=1e-11)


def test_force_engine_gravity_engine_and_dead_engines(yade):
    """ForceEngine adds F, GravityEngine adds m g; a dead engine does nothing."""
    yade.O.bodies.append([yade.sphere((0, 0, 0), 0.1), yade.sphere((5, 0, 0), 0.1)])
    m = yade.O.bodies[0].state.mass
    dead = yade.ForceEngine(ids=[1], force=(0, 100, 0), dead=True)
    yade.O.engines = [yade.ForceResetter(), yade.ForceEngine(ids=[0], force=(3, 0, 0)), dead,
                      yade.GravityEngine(gravity=(0, 0, -10)), yade.NewtonIntegrator(damping=0)]
    yade.O.dt = 1e-3
    yade.O.run(100, True)
    t = 0.1
    np.testing.assert_allclose(np.asarray(yade.O.bodies[0].state.vel), [3 / m * t, 0, -10 * t], rtol=1e-12)
    np.testing.assert_allclose(np.asarray(yade.O.bodies[1].state.vel), [0, 0, -10 * t], rtol=1e-12)
    with pytest.raises(IndexError, match="ids"):
        yade.O.engines = [yade.ForceEngine(ids=[7], force=(1, 0, 0))]
        yade.O.step()


def test_engines_changed_between_steps_act_at_the_next_step(yade):
    """Between two O.step() calls, an engine made dead or alive again, an engine list assigned and a ParallelEngine's
    slave list changed in place (no attribute assigned) each change what the next step runs: the velocity of a free
    body gains F/m dt from each force acting in a step, and nothing else acts (no gravity, no damping)."""
    yade.O.bodies.append(yade.sphere((0, 0, 0), 0.1))
    m = yade.O.bodies[0].state.mass
    dt = 1e-3
    yade.O.dt = dt
    push = yade.ForceEngine(ids=[0], force=(2, 0, 0))
    pe = yade.ParallelEngine([yade.ForceEngine(ids=[0], force=(0, 5, 0))])
    extra = yade.ForceEngine(ids=[0], force=(0, 0, 7))   # made now: making an engine assigns its attributes
    yade.O.engines = [yade.ForceResetter(), push, pe, yade.NewtonIntegrator(damping=0)]
    expected = np.zeros(3)

    def step(*forces):
        yade.O.step()
        for f in forces:
            expected[:] += np.asarray(f) / m * dt
        np.testing.assert_allclose(np.asarray(yade.O.bodies[0].state.vel), expected, rtol=1e-12, atol=0)

    step((2, 0, 0), (0, 5, 0))
    step((2, 0, 0), (0, 5, 0))
    push.dead = True
    step((0, 5, 0))
    push.dead = False
    step((2, 0, 0), (0, 5, 0))
    pe.slaves.append(extra)   # in place: no assignment
    step((2, 0, 0), (0, 5, 0), (0, 0, 7))
    yade.O.engines = [yade.ForceResetter(), yade.NewtonIntegrator(damping=0)]
    step()


def test_create_interaction_makes_distant_bodies_interact(yade):
    """utils.createInteraction makes a real interaction at any distance; Cundall-Strack ends it when apart."""
    yade.O.bodies.append([yade.sphere((0, 0, 0), 0.5), yade.sphere((0, 0, 1.2), 0.5)])
    yade.O.engines = frict_engines(yade)
    i = yade.createInteraction(0, 1)
    assert i.isReal and i.geom.penetrationDepth == pytest.approx(-0.2)
    assert i.phys.kn == pytest.approx(1e7 * 0.5)
    yade.O.step()
    assert not yade.O.interactions.has(0, 1, onlyReal=True)


def test_sum_forces_and_set_contact_friction(yade):
    """sumForces projects the resultant of given bodies; setContactFriction changes contacts and materials."""
    yade.O.bodies.append([yade.sphere((0, 0, 0), 1, fixed=True), yade.sphere((0, 0, 1.99), 1),
                          yade.sphere((0, 1.99, 0), 1)])
    yade.O.engines = frict_engines(yade)
    yade.O.step()
    f = [np.asarray(yade.O.forces.f(i)) for i in range(3)]
    assert yade.sumForces([0, 1], (0, 0, 1)) == pytest.approx(f[0][2] + f[1][2])
    assert yade.sumForces([1, 2], (0, 1, 1)) == pytest.approx(f[1][1] + f[1][2] + f[2][1] + f[2][2])
    yade.setContactFriction(0.1)
    assert yade.O.materials[0].frictionAngle == 0.1
    assert all(i.phys.tangensOfFrictionAngle == pytest.approx(math.tan(0.1)) for i in yade.O.interactions)


def test_sphere_pack_to_simulation_creates_the_bodies(yade):
    """SpherePack.toSimulation appends one sphere per pack entry with the pack's centres and radii."""
    sp = yade.pack.SpherePack()
    n = sp.makeCloud((0, 0, 0), (1, 1, 1), rMean=0.05, rRelFuzz=0.3, seed=3)
    mat = yade.O.materials.append(yade.FrictMat(density=2600, label="grains"))
    ids = sp.toSimulation(material="grains", color=(0, 0, 1))
    assert len(ids) == n == len(yade.O.bodies)
    for (c, r), i in zip(sp, ids, strict=True):
        b = yade.O.bodies[i]
        np.testing.assert_allclose(np.asarray(b.state.pos), np.asarray(c))
        assert b.shape.radius == r and b.material is yade.O.materials[mat]
        assert b.state.mass == pytest.approx(2600 * 4 / 3 * math.pi * r ** 3)
    assert yade.getSpheresVolume() == pytest.approx(sum(4 / 3 * math.pi * r ** 3 for _, r in sp))


def test_regular_hexa_bodies_interact_with_their_neighbours(yade):
    """regularHexa returns a close packing: with a tiny overlap every interior sphere has 12 neighbours."""
    bodies = yade.pack.regularHexa(yade.pack.inSphere((0, 0, 0), 0.3), radius=0.05, gap=-1e-5)
    yade.O.bodies.append(bodies)
    yade.O.engines = frict_engines(yade)
    yade.O.step()
    pos = np.array([b.state.pos for b in yade.O.bodies])
    inner = np.nonzero(np.linalg.norm(pos, axis=1) < 0.15)[0]
    counts = np.bincount([i.id1 for i in yade.O.interactions] + [i.id2 for i in yade.O.interactions],
                         minlength=len(bodies))
    assert len(inner) > 0 and (counts[inner] == 12).all()


def test_tags_hold_an_id_and_user_values(yade):
    """O.tags has YADE's predefined keys and keeps user values."""
    assert {"id", "d.id", "id.d", "isoTime", "author"} <= set(yade.O.tags)
    yade.O.tags["run"] = "a"
    assert dict(yade.O.tags)["run"] == "a"


@pytest.mark.fallback
def test_timing_enabled_times_every_engine(yade, capsys):
    """O.timingEnabled: compiled stages are timed inside the step loop, PyRunners when they run
    (real YADE 2023.02a counts 99 runs of an iterPeriod=100 PyRunner over 10000 steps)."""
    O = yade.O

    def bouncing():
        O.bodies.append([yade.sphere((0, 0, 0), 0.5, fixed=True), yade.sphere((0, 0, 2), 0.5)])
        O.engines = frict_engines(yade, gravity=(0, 0, -9.81), damping=0.1) + [
            yade.PyRunner(command="pass", iterPeriod=100, label="pr")]
        O.dt = 1e-5

    bouncing()
    O.run(1000, True)
    assert all(e.execTime == 0 and e.execCount == 0 for e in O.engines), "not timed unless enabled"
    O.reset()
    bouncing()
    O.timingEnabled = True
    O.run(10000, True)
    compiled, runner = O.engines[:4], O.engines[4]
    assert [e.execCount for e in compiled] == [10000] * 4
    assert runner.execCount == 99
    assert all(e.execTime > 0 for e in O.engines)
    yade.timing.stats()
    out = capsys.readouterr().out.splitlines()
    assert out[0].split() == ["Name", "Count", "Time", "Rel.", "time"]
    assert [line.split()[0] for line in out[2:]] == ["ForceResetter", "InsertionSortCollider", "InteractionLoop",
                                                      "NewtonIntegrator", '"pr"', "TOTAL"]
    assert sum(float(line.split()[-1].rstrip("%")) for line in out[2:-1]) == pytest.approx(100, abs=0.05)


def _two_spheres_sliding(y):
    """A sphere pressed by gravity (along -x) onto a fixed one, sliding on it."""
    y.O.bodies.append([y.sphere((0, 0, 0), 0.5, fixed=True), y.sphere((0.999, 0, 0), 0.5)])
    y.O.bodies[1].state.vel = (0.0, 0.2, 0.05)
    y.O.dt = 0.2 * y.PWaveTimeStep()


def _sphere_loop(y, geoms):
    return [y.ForceResetter(), y.InsertionSortCollider([y.Bo1_Sphere_Aabb(), y.Bo1_Facet_Aabb()]),
            y.InteractionLoop(geoms, [y.Ip2_FrictMat_FrictMat_FrictPhys()], [y.Law2_ScGeom_FrictPhys_CundallStrack()]),
            y.NewtonIntegrator(damping=0.1, gravity=(-10, 0, 0))]


def test_contacts_keep_their_functors_when_the_engine_list_changes(yade):
    """A contact created by a functor that a new engine list no longer lists goes on with that functor (the
    dispatch compiled for the new list includes the functors of the live contacts): the run equals one in
    which the list never changed."""
    y = yade
    _two_spheres_sliding(y)
    y.O.engines = _sphere_loop(y, [y.Ig2_Sphere_Sphere_ScGeom()])
    y.O.run(400, True)
    reference = (tuple(y.O.bodies[1].state.pos), tuple(y.O.interactions[0, 1].phys.shearForce))
    y.O.reset()
    _two_spheres_sliding(y)
    y.O.engines = _sphere_loop(y, [y.Ig2_Sphere_Sphere_ScGeom()])
    y.O.run(200, True)
    y.O.engines = _sphere_loop(y, [y.Ig2_Facet_Sphere_ScGeom()])   # sphere+sphere no longer listed
    y.O.run(200, True)
    assert np.linalg.norm(reference[1]) > 0, "the spheres did not slide"
    assert (tuple(y.O.bodies[1].state.pos), tuple(y.O.interactions[0, 1].phys.shearForce)) == reference


def test_scene_record_follows_added_bodies(yade):
    """The record of the scene's arrays is kept between chunks while its arrays stay the same: bodies added
    within the tables' capacity are seen through it, more bodies make a new one; every body falls."""
    y = yade
    y.O.engines = frict_engines(y, gravity=(0, 0, -10))
    y.O.bodies.append(y.sphere((0, 0, 0), 0.5))
    y.O.dt = 1e-3
    scene = y.O._scene
    first = scene.arrays()
    assert scene.arrays() is first
    y.O.bodies.append(y.sphere((3, 0, 0), 0.5))
    assert scene.arrays() is first          # same storage: the body count is read from the scene's scalars
    y.O.bodies.append([y.sphere((3 * k, 3, 0), 0.5) for k in range(100)])
    assert scene.arrays() is not first      # the tables grew
    y.O.run(10, True)
    assert all(b.state.vel[2] < 0 for b in y.O.bodies)
