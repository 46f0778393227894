"""GlobalStiffnessTimeStepper with clumps against real YADE (tests/reference/yade/timestepper_clump.py): a clump
sums its members' contact stiffnesses (member radii as lever arms) and uses its own mass and inertia; a contact
without normal force adds no stiffness."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import reference

REF = reference("timestepper_clump")
FIXED = {"touch_x": [(.34, 0, 0)], "touch_z": [(0, 0, 1.14)], "touch_xz": [(.34, 0, 0), (0, 0, 1.14)]}


def _scene(y, gravity=(0, 0, 0)):
    y.O.materials.append(y.FrictMat(young=6e6, poisson=.8, frictionAngle=.1, density=2600))
    ts = y.GlobalStiffnessTimeStepper(timestepSafetyCoefficient=.6, timeStepUpdateInterval=1)
    y.O.engines = [y.ForceResetter(), y.InsertionSortCollider([y.Bo1_Sphere_Aabb()]),
                   y.InteractionLoop([y.Ig2_Sphere_Sphere_ScGeom()], [y.Ip2_FrictMat_FrictMat_FrictPhys()],
                                     [y.Law2_ScGeom_FrictPhys_CundallStrack()]),
                   ts, y.NewtonIntegrator(damping=.4, gravity=gravity)]
    y.O.dt = 1e-3
    return ts


@pytest.mark.parametrize("case", sorted(FIXED))
def test_touched_clump_step_as_yade(yade, case):
    """A 3-sphere clump touched along x (translation governs), z (rotation about the clump's axis governs) or
    both: O.dt after one step, and the clump's mass and inertia, as YADE's. The member's own mass would give a
    step √3 smaller (touch_x)."""
    ref = REF[case]
    _scene(yade)
    cid, members = yade.O.bodies.appendClumped([yade.sphere((0, 0, z), .2) for z in (0, .4, .8)])
    yade.O.bodies.append([yade.sphere(c, .15, fixed=True) for c in FIXED[case]])
    yade.O.step()
    clump = yade.O.bodies[cid].state
    assert clump.mass == pytest.approx(ref["clump_mass"], rel=1e-12)
    assert list(clump.inertia) == pytest.approx(ref["clump_inertia"], rel=1e-9)
    assert yade.O.bodies[members[0]].state.mass == pytest.approx(ref["member_mass"], rel=1e-12)
    assert yade.O.interactions.countReal() == len(ref["contacts"])
    assert yade.O.dt == pytest.approx(ref["dt"], rel=1e-9)


def test_two_clumps_step_as_yade(yade):
    """Two clumps touching each other, no fixed body: the lighter clump's mass sets the step."""
    _scene(yade)
    yade.O.bodies.appendClumped([yade.sphere((0, 0, 0), .2), yade.sphere((0, .3, 0), .2)])
    yade.O.bodies.appendClumped([yade.sphere((.34, 0, 0), .15), yade.sphere((.34, 0, .25), .15)])
    yade.O.step()
    assert yade.O.dt == pytest.approx(REF["two_clumps"]["dt"], rel=1e-9)


def test_falling_clumps_steps_as_yade(yade):
    """Four clumps falling on a row of fixed spheres: every step's O.dt and previousDt over 60 steps (contacts
    made and lost, the x1.05 growth cap) as YADE's. Tolerances: granum's angular velocity of an aspherical clump
    differs from YADE's by ~2e-5 (relative) from the first step (measured; a separate rotation-update
    difference), so the trajectories part by up to 7e-5 m after 60 steps and the steps by up to 3e-6."""
    ts = _scene(yade, gravity=(0, 0, -9.81))
    y = yade
    y.O.bodies.append([y.sphere((x * .4, 0, 0), .2, fixed=True) for x in range(-3, 4)])
    y.O.bodies.appendClumped([y.sphere((-1, 0, .45), .2), y.sphere((-.75, .1, .6), .15)])
    y.O.bodies.appendClumped([y.sphere((-.3, 0, .5), .18), y.sphere((-.1, .05, .62), .12),
                              y.sphere((.05, -.1, .7), .1)])
    y.O.bodies.appendClumped([y.sphere((.45, 0, .38), .2), y.sphere((.55, .2, .55), .17)])
    y.O.bodies.appendClumped([y.sphere((1.1, .05, .45), .16), y.sphere((1.2, -.1, .7), .2),
                              y.sphere((1.0, 0, .8), .1)])
    for k, s in enumerate(REF["drop"]["steps"]):
        y.O.step()
        assert y.O.dt == pytest.approx(s["dt"], rel=1e-5), f"step {k + 1}"
        assert ts.previousDt == pytest.approx(s["previousDt"], rel=1e-5), f"step {k + 1}"
    pos = np.array([list(b.state.pos) for b in y.O.bodies])
    np.testing.assert_allclose(pos, REF["drop"]["final_pos"], rtol=0, atol=1e-4)


def test_unloaded_contact_adds_no_stiffness(yade):
    """A sphere resting on a box at exactly zero penetration (no normal force) and overlapping a fixed sphere:
    only the loaded contact counts, as in YADE (counting both would give a step 1.41 times smaller)."""
    ref = REF["zero_force"]
    y = yade
    y.O.materials.append(y.FrictMat(young=6e6, poisson=.4, frictionAngle=.1, density=2600))
    y.O.bodies.append([y.sphere((0, 0, 0), .5), y.box((0, 0, -1), (.5, .5, .5), fixed=True),
                       y.sphere((.9, 0, 0), .5, fixed=True)])
    y.O.engines = [y.ForceResetter(), y.InsertionSortCollider([y.Bo1_Sphere_Aabb(), y.Bo1_Box_Aabb()]),
                   y.InteractionLoop([y.Ig2_Sphere_Sphere_ScGeom(), y.Ig2_Box_Sphere_ScGeom()],
                                     [y.Ip2_FrictMat_FrictMat_FrictPhys()], [y.Law2_ScGeom_FrictPhys_CundallStrack()]),
                   y.GlobalStiffnessTimeStepper(timestepSafetyCoefficient=.6, timeStepUpdateInterval=1),
                   y.NewtonIntegrator(damping=.4, gravity=(0, 0, 0))]
    y.O.dt = 1e-3
    y.O.step()
    forces = sorted(abs(i.phys.normalForce[0]) + abs(i.phys.normalForce[2]) for i in y.O.interactions)
    assert forces[0] == 0.0 and forces[1] == pytest.approx(3e5, rel=1e-12)
    assert y.O.bodies[0].state.mass == pytest.approx(ref["mass"], rel=1e-12)
    assert y.O.dt == pytest.approx(ref["dt"], rel=1e-12)
