"""Kinematic engines: HelixEngine, combinations made with ``+`` (CombinedKinematicEngine), ParallelEngine."""

from __future__ import annotations

import json
import math
import shutil
import subprocess
import sys

import numpy as np
import pytest
from conftest import REFERENCE, reference


def test_helix_engine_follows_its_closed_form(yade):
    """A fixed body under HelixEngine lands on the helix every step (YADE moves it along the chord):
    angle w t about the axis through zeroPoint, advance v t along it; angleTurned = w t; the orientation
    turns by w t; rotateAroundZero reads True once the engine has run (as in YADE)."""
    w, v, dt, steps = 0.9, -0.3, 0.05, 40
    axis = np.array([1.0, 2.0, 2.0]) / 3.0
    zero, p0 = np.array([0.5, -1.0, 0.2]), np.array([2.0, 0.5, -1.0])
    yade.O.bodies.append(yade.sphere(tuple(p0), 0.1, fixed=True))
    helix = yade.HelixEngine(ids=[0], angularVelocity=w, rotationAxis=(1, 2, 2), linearVelocity=v,
                             zeroPoint=tuple(zero))
    yade.O.engines = [yade.ForceResetter(), helix, yade.NewtonIntegrator(damping=0)]
    yade.O.dt = dt
    assert not helix.rotateAroundZero
    b = yade.O.bodies[0]
    for n in range(1, steps + 1):
        yade.O.step()
        a, r = w * n * dt, p0 - zero
        rodrigues = r * math.cos(a) + np.cross(axis, r) * math.sin(a) + axis * (axis @ r) * (1 - math.cos(a))
        np.testing.assert_allclose(np.asarray(b.state.pos), zero + rodrigues + v * n * dt * axis, rtol=0,
                                   atol=1e-13)
        assert helix.angleTurned == pytest.approx(a, rel=1e-13)
    got_axis, angle = b.state.ori.toAxisAngle()
    assert angle == pytest.approx(w * steps * dt, rel=1e-12)
    np.testing.assert_allclose(np.asarray(got_axis), axis, atol=1e-12)
    np.testing.assert_allclose(np.asarray(b.state.angVel), w * axis, rtol=1e-15)
    assert helix.rotateAroundZero


def test_yade_reference_script_gives_yade_numbers(tmp_path):
    """tests/reference/yade/kinematic.py run unmodified by granum: translation + rotation (+ helix)
    combinations, a lone HelixEngine, a dead part, a ParallelEngine give real YADE's states after every
    step, and the same combination bookkeeping (ids, comb, ``c + d`` is c, TypeError for other sums)."""
    for name in ("kinematic.py", "_common.py"):
        shutil.copy(REFERENCE / name, tmp_path / name)
    r = subprocess.run([sys.executable, "-m", "granum", str(tmp_path / "kinematic.py")], capture_output=True,
                       text=True, timeout=600)
    assert r.returncode == 0, r.stdout + r.stderr
    ours, yade = json.loads((tmp_path / "kinematic.json").read_text()), reference("kinematic")
    assert ours.keys() == yade.keys()
    for scene in ("comb_tr", "comb_rth", "helix", "dead_part", "parallel"):
        assert len(ours[scene]["steps"]) == len(yade[scene]["steps"])
        for got, want in zip(ours[scene]["steps"], yade[scene]["steps"], strict=True):
            assert got.keys() == want.keys()
            for i, body in want["bodies"].items():
                for field, value in body.items():
                    np.testing.assert_allclose(got["bodies"][i][field], value, rtol=1e-12, atol=1e-14,
                                               err_msg=f"{scene} step {want['iter']} body {i} {field}")
            for key in set(want) - {"bodies"}:
                assert got[key] == pytest.approx(want[key], rel=1e-14), (scene, key)
    for key in ("same_object", "ids", "comb"):
        assert ours["comb_rth"][key] == yade["comb_rth"][key]
    assert ours["sums"] == yade["sums"]


def test_combination_bookkeeping(yade):
    """``a + b`` acts on a copy of a.ids; ``c + d`` appends to c; comb holds kinematic engines only; labels of
    combined engines become global names (YADE's testLabels)."""
    t = yade.TranslationEngine(ids=[3, 4], label="kt")
    r = yade.RotationEngine(label="kr")
    c = t + r
    assert isinstance(c, yade.CombinedKinematicEngine) and c.comb == [t, r] and c.ids == [3, 4]
    t.ids = [1]
    assert c.ids == [3, 4]
    h = yade.HelixEngine()
    assert (c + h) is c and c.comb == [t, r, h]
    with pytest.raises(TypeError):
        c.comb = [t, yade.ForceResetter()]
    with pytest.raises(TypeError):
        t + yade.ForceEngine()
    c.label = "kc"
    yade.O.engines = [c]
    ns = yade.O.namespace()
    assert ns["kt"] is t and ns["kr"] is r and ns["kc"] is c


def test_bare_kinematic_engine_is_refused(yade):
    """KinematicEngine imposes no motion (YADE logs an error every step); granum refuses to run it."""
    yade.O.bodies.append(yade.sphere((0, 0, 0), 0.1))
    yade.O.engines = [yade.KinematicEngine(ids=[0])]
    with pytest.raises(NotImplementedError, match="KinematicEngine"):
        yade.O.step()


def _scene(yade, engines):
    yade.O.reset()
    yade.O.bodies.append([yade.sphere((x, 0.3 * x, 0), 0.4) for x in range(6)])
    yade.O.bodies[5].state.vel = (1, 0, 0)
    yade.O.engines = engines
    yade.O.dt = 1e-3
    yade.O.run(200, True)
    return [(tuple(b.state.pos), tuple(b.state.vel), tuple(b.state.angVel), tuple(b.state.ori)) for b in yade.O.bodies]


def test_parallel_engine_runs_its_slaves_in_order(yade):
    """ParallelEngine([a, [b, c]]) gives the same bits as a, b, c listed in order; dead slaves are skipped;
    reassigning slaves changes what runs; a dispatcher is accepted as in YADE but cannot run on its own."""
    from conftest import frict_engines

    def engines(parallel):
        reset, collider, loop, newton = frict_engines(yade, gravity=(0, 0, -9.81))
        trans = yade.TranslationEngine(ids=[0], velocity=0.5, translationAxis=(0, 0, 1))
        rot = yade.RotationEngine(ids=[1, 2], angularVelocity=3, rotationAxis=(1, 1, 0), rotateAroundZero=True)
        dead = yade.ForceEngine(ids=[3], force=(0, 0, 50), dead=True)
        force = yade.ForceEngine(ids=[4], force=(0, 7, 0))
        if parallel:
            return [reset, collider, loop, yade.ParallelEngine([trans, [rot, dead, force]]), newton]
        return [reset, collider, loop, trans, rot, force, newton]

    assert _scene(yade, engines(True)) == _scene(yade, engines(False))
    pe = yade.ParallelEngine([yade.InsertionSortCollider(), [yade.BoundDispatcher(), yade.ForceResetter()]])
    assert len(pe.slaves) == 2 and len(pe.slaves[1]) == 2
    yade.O.engines = [pe]
    with pytest.raises(TypeError, match="BoundDispatcher"):
        yade.O.step()
    with pytest.raises(TypeError, match="slaves"):
        pe.slaves = [[yade.ForceResetter()], 3]
    pe.slaves = []
    assert pe.slaves == []
    moved = _scene(yade, [yade.ForceResetter(), pe, yade.NewtonIntegrator(damping=0)])
    assert moved[0][0] == (0.0, 0.0, 0.0)  # no slave: nothing moves body 0
    pe.slaves = [yade.TranslationEngine(ids=[0], velocity=1, translationAxis=(1, 0, 0))]
    yade.O.run(10, True)
    assert yade.O.bodies[0].state.pos[0] == pytest.approx(0.01)
