"""The runner keeps the parameters of the collider and of the InteractionLoop from chunk to chunk while nothing they
are made of changed (engines.base.Engine.params_key). What must hold: any assignment a script makes between two
chunks (an attribute of the engine, of one of its functors or of a functor's MatchMaker, a new functor list, an
edited material) takes effect at the next chunk, as when the parameters were built anew every time."""

from __future__ import annotations

import math

import pytest

from granum.core.arrays import S_VERLET


def _two_spheres(y, gap=0.2):
    """Two fixed spheres of radius 0.5, ``gap`` [m] apart, with the tutorial's engines (a contact found at a
    distance stays: neverErase)."""
    O = y.O
    O.materials.append(y.FrictMat(young=1e7, frictionAngle=0.5, density=1000))
    O.bodies.append([y.sphere((0, 0, 0), 0.5, fixed=True), y.sphere((0, 0, 1 + gap), 0.5, fixed=True)])
    O.engines = [y.ForceResetter(), y.InsertionSortCollider([y.Bo1_Sphere_Aabb()]),
                 y.InteractionLoop([y.Ig2_Sphere_Sphere_ScGeom()], [y.Ip2_FrictMat_FrictMat_FrictPhys()],
                                   [y.Law2_ScGeom_FrictPhys_CundallStrack(neverErase=True)]),
                 y.NewtonIntegrator()]
    O.dt = 1e-5


@pytest.mark.parametrize("every_step", [False, True])
def test_functor_and_engine_edits_take_effect_at_the_next_chunk(yade, every_step):
    """Detection at a distance switched on between chunks through the geometry functor's
    interactionDetectionFactor (the loop's parameters; the bounds are enlarged from the start), and the collider's
    verletDist changed (its parameters; a mask set makes it run in full): each takes effect at the next chunk, also
    in a run with a Python engine at every step (one chunk a step)."""
    O = yade.O
    _two_spheres(yade)
    O.engines[1].boundDispatcher.functors[0].aabbEnlargeFactor = 1.5
    if every_step:
        O.engines = O.engines + [yade.PyRunner(iterPeriod=1, command="pass")]
    O.run(5, True)
    assert O.interactions.countReal() == 0
    O.engines[2].geomDispatcher.functors[0].interactionDetectionFactor = 1.5
    O.run(2, True)
    assert O.interactions.countReal() == 1
    O.engines[1].verletDist = 0.123
    O.bodies[0].mask = O.bodies[0].mask
    O.run(1, True)
    assert O._scene.scal[S_VERLET] == 0.123


def test_new_functor_list_and_matchmaker_edits_take_effect(yade):
    """A functor list replaced between chunks, a MatchMaker's value edited, and a material edited: each shows in
    the contacts made at the next chunk (the friction angle of the contact's physics)."""
    O = yade.O
    _two_spheres(yade, gap=-0.01)
    O.run(2, True)
    assert O.interactions[0, 1].phys.tangensOfFrictionAngle == pytest.approx(math.tan(0.5))
    ip2 = yade.Ip2_FrictMat_FrictMat_FrictPhys(frictAngle=yade.MatchMaker(algo="val", val=0.2))
    O.engines[2].physDispatcher.functors = [ip2]
    O.interactions.erase(0, 1)
    O.run(2, True)
    assert O.interactions[0, 1].phys.tangensOfFrictionAngle == pytest.approx(math.tan(0.2))
    ip2.frictAngle.val = 0.3
    O.interactions.erase(0, 1)
    O.run(2, True)
    assert O.interactions[0, 1].phys.tangensOfFrictionAngle == pytest.approx(math.tan(0.3))
    O.engines[2].physDispatcher.functors = [yade.Ip2_FrictMat_FrictMat_FrictPhys()]
    O.materials[0].frictionAngle = 0.4
    O.interactions.erase(0, 1)
    O.run(2, True)
    assert O.interactions[0, 1].phys.tangensOfFrictionAngle == pytest.approx(math.tan(0.4))


def test_edits_made_by_a_python_engine_during_a_run_take_effect_at_the_next_step(yade):
    """Within one O.run, a PyRunner at every step switches on detection at a distance at step 5 (an attribute of
    the loop's geometry functor: parameters kept while no attribute anywhere is assigned) and changes the
    integrator's gravity in place at step 8 (a vector's item, no assignment: its parameters are its values): the
    contact exists from step 6 on, and the free sphere's velocity follows the new gravity from step 9 on."""
    O = yade.O
    _two_spheres(yade)
    O.bodies.append(yade.sphere((5, 0, 0), 0.5))
    O.engines[1].boundDispatcher.functors[0].aabbEnlargeFactor = 1.5
    command = ("log.append((O.iter, O.interactions.countReal(), O.bodies[2].state.vel[2]))\n"
               "if O.iter == 5: O.engines[2].geomDispatcher.functors[0].interactionDetectionFactor = 1.5\n"
               "if O.iter == 8: O.engines[3].gravity[2] = -20")
    O.engines = O.engines[:3] + [yade.NewtonIntegrator(damping=0, gravity=(0, 0, -10)),
                                 yade.PyRunner(initRun=True, iterPeriod=1, command=command)]
    log = []
    yade.O._namespace = {"O": O, "log": log}
    O.run(12, True)
    assert [c for _, c, _ in log] == [0] * 6 + [1] * 6
    dv = [b - a for (_, _, a), (_, _, b) in zip(log[:-1], log[1:], strict=True)]
    assert dv[:8] == pytest.approx([-10 * O.dt] * 8) and dv[8:] == pytest.approx([-20 * O.dt] * 3)


def test_a_chunk_whose_parameters_failed_leaves_none_kept_for_later(yade):
    """A chunk whose parameters raise (a PeriTriaxController in a scene made aperiodic) may have built some engines'
    parameters for that scene already: once the scene is periodic again, the collider must pair bodies across the
    cell's boundary, as the parameters of a periodic scene do (the sphere at x = 0.97 touches the one at x = 0.03
    through the boundary only)."""
    O = yade.O
    O.periodic = True
    O.cell.setBox(1, 1, 1)
    O.bodies.append([yade.sphere((0.03, 0.5, 0.5), 0.05), yade.sphere((0.5, 0.5, 0.5), 0.05)])
    O.engines = [yade.ForceResetter(), yade.InsertionSortCollider([yade.Bo1_Sphere_Aabb()]),
                 yade.InteractionLoop([yade.Ig2_Sphere_Sphere_ScGeom()], [yade.Ip2_FrictMat_FrictMat_FrictPhys()],
                                      [yade.Law2_ScGeom_FrictPhys_CundallStrack()]),
                 yade.PeriTriaxController(goal=(0, 0, 0), stressMask=7, maxUnbalanced=0.1),
                 yade.NewtonIntegrator(damping=0)]
    O.dt = 1e-6
    O.step()
    assert O.interactions.countReal() == 0
    O.periodic = False
    with pytest.raises(RuntimeError, match="periodic"):
        O.step()
    O.periodic = True
    O.bodies[1].state.pos = (0.97, 0.5, 0.5)
    O.step()
    assert O.interactions.countReal() == 1
