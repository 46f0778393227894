"""Clumps: mass properties from the members, rigid motion, conservation laws."""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import frict_engines

from granum.mathtypes import as_quat_wxyz


def _rotation(q):
    w, x, y, z = as_quat_wxyz(q)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


MEMBERS = [((0, 0, 0), 0.1), ((0.25, 0, 0), 0.08), ((0, 0.3, 0.1), 0.12), ((-0.1, -0.2, 0.3), 0.05)]


def test_clump_mass_and_inertia_follow_the_parallel_axis_theorem(yade):
    """Non-overlapping spheres: M = sum m, c = sum m x / M, I = sum (2/5 m r^2 1 + m (|d|^2 1 - d d^T))."""
    cid, ids = yade.O.bodies.appendClumped([yade.sphere(c, r) for c, r in MEMBERS])
    m = np.array([1000 * 4 / 3 * math.pi * r ** 3 for _, r in MEMBERS])
    x = np.array([c for c, _ in MEMBERS], float)
    M = m.sum()
    c = (m[:, None] * x).sum(axis=0) / M
    inertia = sum(0.4 * mi * r ** 2 * np.eye(3) + mi * ((xi - c) @ (xi - c) * np.eye(3) - np.outer(xi - c, xi - c))
                  for mi, xi, (_, r) in zip(m, x, MEMBERS, strict=True))
    clump = yade.O.bodies[cid]
    assert clump.isClump and all(yade.O.bodies[i].isClumpMember and yade.O.bodies[i].clumpId == cid for i in ids)
    assert clump.state.mass == pytest.approx(M, rel=1e-14)
    np.testing.assert_allclose(np.asarray(clump.state.pos), c, atol=1e-15)
    # principal inertia in the clump frame: R diag(I) R^T is the tensor about the centre
    R = _rotation(clump.state.ori)
    np.testing.assert_allclose(R @ np.diag(np.asarray(clump.state.inertia)) @ R.T, inertia, rtol=1e-12, atol=1e-16)
    assert sorted(clump.shape.members) == ids


def test_overlapping_members_are_integrated_on_a_grid(yade):
    """With discretization, two overlapping spheres count their common volume once."""
    r, d = 0.1, 0.1  # centres one radius apart: lens volume pi (4r + d)(2r - d)^2 / 12
    cid, _ = yade.O.bodies.appendClumped([yade.sphere((0, 0, 0), r), yade.sphere((d, 0, 0), r)],
                                         discretization=40)
    vol = 2 * 4 / 3 * math.pi * r ** 3 - math.pi * (4 * r + d) * (2 * r - d) ** 2 / 12
    assert yade.O.bodies[cid].state.mass == pytest.approx(1000 * vol, rel=2e-3)
    np.testing.assert_allclose(np.asarray(yade.O.bodies[cid].state.pos), [d / 2, 0, 0], atol=1e-4)


def test_free_clump_conserves_angular_momentum_and_stays_rigid(yade):
    """A spinning free clump: angular momentum exact, member distances fixed, energy to O(dt^2)."""
    cid, ids = yade.O.bodies.appendClumped([yade.sphere(c, r) for c, r in MEMBERS])
    clump = yade.O.bodies[cid]
    clump.state.angVel = (3, -2, 5)
    clump.state.vel = (0.5, 0, 0)
    yade.O.engines = [yade.ForceResetter(), yade.NewtonIntegrator(damping=0)]
    yade.O.dt = 1e-4
    L0 = np.asarray(clump.state.angMom).copy()
    x = np.array([yade.O.bodies[i].state.pos for i in ids])
    d0 = np.linalg.norm(x[:, None] - x[None, :], axis=2)
    inertia = np.asarray(clump.state.inertia)
    e0 = 0.5 * np.sum((_rotation(clump.state.ori).T @ L0) ** 2 / inertia)
    worst = 0.0
    for _ in range(50):
        yade.O.run(40, True)
        np.testing.assert_array_equal(np.asarray(clump.state.angMom), L0)
        x = np.array([yade.O.bodies[i].state.pos for i in ids])
        np.testing.assert_allclose(np.linalg.norm(x[:, None] - x[None, :], axis=2), d0, atol=1e-12)
        ll = _rotation(clump.state.ori).T @ L0
        worst = max(worst, abs(0.5 * np.sum(ll ** 2 / inertia) - e0) / e0)
    assert worst < 10 * (np.linalg.norm([3, -2, 5]) * 1e-4) ** 2  # second-order rotation
    # members move with the clump: v_m = v_c + w x (x_m - x_c)
    for i in ids:
        b = yade.O.bodies[i]
        arm = np.asarray(b.state.pos) - np.asarray(clump.state.pos)
        np.testing.assert_allclose(np.asarray(b.state.vel),
                                   np.asarray(clump.state.vel) + np.cross(np.asarray(clump.state.angVel), arm),
                                   atol=1e-12)
    # the centre of mass moves uniformly
    assert clump.state.pos[0] == pytest.approx(clump.state.refPos[0] + 0.5 * yade.O.time, rel=1e-12)


def test_clump_falls_and_rests_on_a_wall_as_one_body(yade):
    """A clump dropped on a wall settles with its members' contacts carrying its whole weight."""
    yade.O.bodies.append(yade.wall(0, axis=2))
    cid, ids = yade.O.bodies.appendClumped([yade.sphere((0, 0, 0.3), 0.1), yade.sphere((0.15, 0, 0.3), 0.1),
                                            yade.sphere((0, 0.15, 0.35), 0.07)])
    yade.O.engines = frict_engines(yade, gravity=(0, 0, -9.81), damping=0.4)
    yade.O.dt = 0.2 * yade.PWaveTimeStep()
    yade.O.run(30000, True)
    M = yade.O.bodies[cid].state.mass
    fz = sum(i.phys.normalForce[2] for i in yade.O.interactions)
    assert fz == pytest.approx(M * 9.81, rel=1e-6)
    assert yade.unbalancedForce() < 1e-6
    assert all(i.id1 == 0 and i.id2 in ids for i in yade.O.interactions)  # only member-wall contacts
    assert np.linalg.norm(yade.O.bodies[cid].state.vel) < 1e-9


def test_clump_errors(yade):
    """Clumping a body twice, an unknown id or no id at all is a clear error."""
    yade.O.bodies.append([yade.sphere((0, 0, 0), 0.1), yade.sphere((1, 0, 0), 0.1)])
    yade.O.bodies.clump([0, 1])
    with pytest.raises(ValueError, match="already belongs"):
        yade.O.bodies.clump([0])
    with pytest.raises(IndexError):
        yade.O.bodies.clump([7])
    with pytest.raises(ValueError):
        yade.O.bodies.clump([])


def test_a_clump_made_during_a_run_is_integrated_as_one_body(yade):
    """A run of spheres only, whose integrator is compiled without the clumps' paths (``NewtonParams.aspherical``),
    meets a clump that a PyRunner between ForceResetter and NewtonIntegrator makes: within that very step the
    integrator moves the members with the clump (v_m = v_c + w x (x_m - x_c)), and from then on the angular momentum
    is conserved exactly (no torque, no damping) while the angular velocity precesses at constant kinetic energy."""
    O = yade.O
    O.bodies.append([yade.sphere((0, 0, 0), 0.1), yade.sphere((0.15, 0, 0.05), 0.08)])
    O.bodies[0].state.vel = (1, 0, 0)
    O.bodies[1].state.vel = (0, 2, 0)   # not a rigid motion: the clump takes the members' momenta
    O.bodies[0].state.angVel = (0, 0, 20)   # and a spin off the clump's axis: it will not turn about a principal axis
    O.engines = [yade.ForceResetter(),
                 yade.PyRunner(iterPeriod=1, command="O.bodies.clump([0, 1]) if O.iter == 5 else None"),
                 yade.NewtonIntegrator(damping=0)]
    O.dt = 1e-4
    O.run(5, True)
    assert len(O.bodies) == 2
    O.run(1, True)
    clump = O.bodies[2]
    assert clump.isClump

    def members_rigid():
        xc, vc, wc = (np.asarray(v) for v in (clump.state.pos, clump.state.vel, clump.state.angVel))
        for i in (0, 1):
            b = O.bodies[i]
            np.testing.assert_allclose(np.asarray(b.state.vel), vc + np.cross(wc, np.asarray(b.state.pos) - xc),
                                       atol=1e-12)

    assert np.linalg.norm(np.asarray(clump.state.angVel)) > 1   # the clump spins: its members' velocities differ
    members_rigid()
    L0 = np.asarray(clump.state.angMom).copy()
    w0 = np.asarray(clump.state.angVel).copy()
    O.run(200, True)
    members_rigid()
    np.testing.assert_array_equal(np.asarray(clump.state.angMom), L0)
    # Euler's equations: the angular velocity of a body turning off its principal axes precesses about L, its
    # kinetic energy w.L/2 kept to second order in w dt
    w = np.asarray(clump.state.angVel)
    assert np.linalg.norm(w - w0) > 0.01 * np.linalg.norm(w0)
    assert w @ L0 == pytest.approx(w0 @ L0, rel=10 * (np.linalg.norm(w0) * O.dt) ** 2)


def test_newton_compiles_the_aspherical_paths_only_for_scenes_that_need_them(yade):
    """NewtonIntegrator's parameters ask for the paths of clumps and aspherical bodies
    (``NewtonParams.aspherical``) once the scene holds a body made aspherical, a clump or a box, and keep asking
    after the clump is erased (compiled for nothing, never left out); a scene of spheres and walls does not. Its
    ``exactAsphericalRot=False`` (YADE's aspherical bodies turned as spheres) is refused by name."""
    O = yade.O
    newton = yade.NewtonIntegrator()

    def paths():
        return newton.params(O._scene, [newton]).aspherical.value

    O.bodies.append([yade.sphere((0, 0, 0), 0.1), yade.sphere((0.15, 0, 0), 0.1), yade.wall(-1, axis=2)])
    assert paths() == ("aspherical", False)
    O.bodies[1].aspherical = True
    assert paths() == ("aspherical", True)
    O.bodies[1].aspherical = False
    assert paths() == ("aspherical", False)
    cid = O.bodies.clump([0, 1])
    assert paths() == ("aspherical", True)
    O.bodies.erase(cid)
    assert paths() == ("aspherical", True)
    O.reset()
    O.bodies.append(yade.sphere((0, 0, 0), 0.1))
    assert paths() == ("aspherical", False)
    O.bodies.append(yade.box((1, 0, 0), (0.1, 0.2, 0.3)))
    assert paths() == ("aspherical", True)
    with pytest.raises(NotImplementedError, match="exactAsphericalRot"):
        yade.NewtonIntegrator(exactAsphericalRot=False)
