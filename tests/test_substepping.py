"""YADE's sub-stepping (O.subStepping, O.subStep): a step run one engine at a time gives the same bits as the
whole step, O.subStep counts through the engines, and an engine list assigned meanwhile takes over at the next
step."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import frict_engines


def _scene(y):
    y.O.bodies.append([y.sphere((0, 0, 0), .5, fixed=True), y.sphere((0, 0, .95), .5), y.sphere((.3, 0, 1.9), .5)])
    y.O.engines = frict_engines(y, gravity=(0, 0, -9.81), damping=.2) + [y.PyRunner(command="pass", iterPeriod=1)]
    y.O.dt = 1e-4


def _state(y):
    b = y.O._scene.bodies
    n = b.count
    return b.pos[:n].copy(), b.vel[:n].copy(), b.ang_vel[:n].copy()


@pytest.mark.fallback
def test_sub_steps_give_the_bits_of_whole_steps(yade):
    y = yade
    _scene(y)
    y.O.run(50, True)
    y.O.saveTmp("start")
    y.O.run(20, True)
    whole = _state(y)
    y.O.loadTmp("start")
    y.O.subStepping = True
    seen = []
    for _ in range(20 * (len(y.O.engines) + 2)):   # beginning, each engine, end
        y.O.step()
        seen.append(y.O.subStep)
    assert y.O.iter == 70
    assert seen[:len(y.O.engines) + 2] == list(range(len(y.O.engines) + 1)) + [-1]
    for a, b in zip(whole, _state(y), strict=True):
        assert np.array_equal(a, b)


def test_turning_sub_stepping_off_finishes_the_step_and_o_substep_reads_the_running_engine(yade):
    y = yade
    _scene(y)
    seen = []
    y.O.engines = y.O.engines[:-1] + [y.PyRunner(command="seen.append(O.subStep)", iterPeriod=1, initRun=True)]
    y.O._namespace = {"seen": seen, "O": y.O}
    y.O.subStepping = True
    y.O.step()
    y.O.step()
    assert (y.O.subStep, y.O.iter) == (1, 0)
    y.O.subStepping = False
    y.O.step()
    assert (y.O.subStep, y.O.iter) == (-1, 1)
    assert seen == [len(y.O.engines) - 1]        # the PyRunner, last engine, ran once
    y.O.step()                                   # a whole step: the PyRunner reads its own index
    assert seen == [len(y.O.engines) - 1] * 2 and y.O.subStep == -1


def test_engines_assigned_during_a_sub_stepped_step_take_over_at_the_next(yade):
    y = yade
    y.O.engines = [y.PyRunner(initRun=True, iterPeriod=1,
                              command="O.engines = [ForceResetter(), GravityEngine(), NewtonIntegrator()]"),
                   y.ForceResetter()]
    y.O._namespace = y.namespace()
    y.O.subStepping = True
    y.O.step()
    y.O.step()
    assert y.O.subStep == 1 and len(y.O.engines) == 3
    assert len(y.O._nextEngines) == 3 and len(y.O._currEngines) == 2
    y.O.step()
    y.O.step()
    assert y.O.subStep == -1
    y.O.step()
    assert y.O.subStep == 0 and len(y.O._nextEngines) == 0 and len(y.O._currEngines) == 3


def test_a_body_moved_between_the_collider_and_the_interaction_loop_touches_in_that_step(yade):
    """Sub-stepping: a sphere moved from Python after the collider's sub-step, onto another of its potential
    pairs, is in contact with it after the interaction loop's sub-step, as in YADE (the loop evaluates the pair
    where the bodies are then): the motions the collider's check left for the loop do not outlive the sub-step
    (granum.core.scene.Scene.take_contacts)."""
    y = yade
    y.O.bodies.append([y.sphere((0, 0, 0), 1.0), y.sphere((2.4, 0, 0), 1.0)])   # bounds overlap: 1.5 + 1.5 > 2.4
    y.O.engines = frict_engines(y)
    y.O.dt = 1e-6
    y.O.step()
    assert not y.O.interactions[0, 1].isReal
    y.O.subStepping = True
    y.O.step()   # the step's beginning
    y.O.step()   # ForceResetter
    y.O.step()   # the collider: nothing moved, no run
    assert y.O.subStep == 2 and y.O.engines[1].numAction == 1
    y.O.bodies[1].state.pos = (1.95, 0, 0)   # 0.45 from its bound's position: within the Verlet distance, 0.5
    y.O.step()   # the interaction loop
    assert y.O.interactions[0, 1].isReal
