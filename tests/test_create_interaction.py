"""utils.createInteraction needs only geometry and physics functors, as in YADE; ScGeom.incidentVel against its
closed form (relative velocity at the contact point, with YADE's anti-ratcheting scaling)."""

from __future__ import annotations

import pytest


def _two_spheres(y, gap: float):
    """Two unit-radius spheres on the x axis, ``gap`` apart (negative: overlapping), the second moving."""
    y.O.bodies.append([y.sphere((0, 0, 0), 1), y.sphere((2 + gap, 0, 0), 1)])
    y.O.bodies[1].state.vel = (-0.5, 0.25, 0)
    y.O.bodies[1].state.angVel = (0, 0, 2.0)
    y.O.dt = 1e-6


def test_create_interaction_without_a_law_then_a_step_names_the_missing_law(yade):
    y = yade
    _two_spheres(y, 0.3)
    y.O.engines = [y.ForceResetter(), y.InsertionSortCollider([y.Bo1_Sphere_Aabb()]),
                   y.InteractionLoop([y.Ig2_Sphere_Sphere_ScGeom()], [y.Ip2_FrictMat_FrictMat_FrictPhys()], []),
                   y.NewtonIntegrator()]
    i = y.utils.createInteraction(0, 1)
    assert i.isReal and i.geom.penetrationDepth == pytest.approx(-0.3) and i.phys.kn > 0
    with pytest.raises(RuntimeError, match="real already"):
        y.utils.createInteraction(0, 1)
    with pytest.raises(y.SimulationError, match="no Law2"):
        y.O.step()


@pytest.mark.parametrize("ratchet", [True, False])
def test_incident_velocity_is_the_relative_velocity_at_the_contact_point(yade, ratchet):
    y = yade
    _two_spheres(y, -0.1)   # penetration 0.1
    y.O.engines = [y.InteractionLoop([y.Ig2_Sphere_Sphere_ScGeom()], [y.Ip2_FrictMat_FrictMat_FrictPhys()], [])]
    i = y.utils.createInteraction(0, 1)
    g = i.geom
    v2, w2 = y.Vector3(-0.5, 0.25, 0), y.Vector3(0, 0, 2.0)
    n = g.normal                      # +x, from body 1 to body 2
    if ratchet:
        # (v2 - v1) (r1 + r2)/(r1 + r2 - delta) + w2 x (-r2 n) - w1 x (r1 n), with r = refR
        expected = v2 * (2.0 / (2.0 - 0.1)) + w2.cross(-1.0 * n)
    else:
        arm2 = g.contactPoint - y.O.bodies[1].state.pos
        expected = v2 + w2.cross(arm2)
    got = g.incidentVel(i, avoidGranularRatcheting=ratchet)
    assert list(got) == pytest.approx(list(expected), rel=1e-14, abs=1e-15)


def test_create_interaction_in_a_periodic_cell_takes_the_nearest_image(yade):
    """Bodies ten cells apart along z: the contact is with body 2's image nearest to body 1 (cellDist), and
    its incident velocity is the relative velocity of that image (as YADE's pbc test checks)."""
    y = yade
    y.O.periodic = True
    y.O.cell.setBox(2.5, 2.5, 3)
    y.O.bodies.append([y.sphere((1, 1, 1), .5), y.sphere((1, 1.9, 1 + 10 * 3), .5)])
    y.O.bodies[1].state.vel = (0, 0, 5)
    y.O.engines = [y.InteractionLoop([y.Ig2_Sphere_Sphere_ScGeom()], [y.Ip2_FrictMat_FrictMat_FrictPhys()], [])]
    i = y.utils.createInteraction(0, 1)
    assert list(i.cellDist) == [0, 0, -10]
    assert i.geom.penetrationDepth == pytest.approx(1 - 0.9, rel=1e-12)
    assert list(i.geom.incidentVel(i, avoidGranularRatcheting=False)) == pytest.approx([0, 0, 5], abs=1e-12)


def test_a_body_has_no_bound_until_the_collider_runs(yade):
    """As in YADE (its core test testErasedAndNewlyCreatedSphere): bound is None on a new body."""
    y = yade
    i = y.O.bodies.append(y.sphere((0, 0, 0), 1))
    assert y.O.bodies[i].bound is None
    y.O.engines = [y.InsertionSortCollider([y.Bo1_Sphere_Aabb()]), y.NewtonIntegrator()]
    y.O.step()
    assert list(y.O.bodies[i].bound.min) == [-1.5, -1.5, -1.5]   # radius + verletDist (0.5 of the radius)


def test_iter_born_is_the_step_an_interaction_became_real(yade):
    """YADE's utilsModule test: an interaction made by createInteraction after one step was born and made real
    at step 1; granum records no step for a potential interaction and says so."""
    y = yade
    _two_spheres(y, -0.01)
    y.O.bodies.append(y.sphere((5, 0, 0), 1))
    y.O.engines = [y.ForceResetter(), y.InsertionSortCollider([y.Bo1_Sphere_Aabb()]),
                   y.InteractionLoop([y.Ig2_Sphere_Sphere_ScGeom()], [y.Ip2_FrictMat_FrictMat_FrictPhys()],
                                     [y.Law2_ScGeom_FrictPhys_CundallStrack()]),
                   y.NewtonIntegrator()]
    y.O.step()
    assert y.O.interactions[0, 1].iterBorn == y.O.interactions[0, 1].iterMadeReal == 0
    i = y.utils.createInteraction(1, 2)
    assert i.iterBorn == i.iterMadeReal == 1
    y.O.interactions.erase(1, 2)
    y.O.bodies[2].state.pos = (4.05, 0, 0)         # 0.06 apart: the bounds (with the Verlet distance) overlap
    y.O.step()
    potential = y.O.interactions[1, 2]
    assert not potential.isReal
    with pytest.raises(NotImplementedError, match="iterBorn: granum records the step of real interactions only"):
        _ = potential.iterBorn
