"""Ctrl-C and concurrent edits never corrupt a scene.

* Ctrl-C at random moments of ``O.run(n, True)`` (SIGINT from a seeded timer): after each interrupt the
  scene runs on, saves and loads, and the run continued after the load equals bitwise the run continued
  without it. ``GRANUM_STRESS_INTERRUPTS`` sets how many interrupts (CI: a few; the issue's full run: 100).
* Appends and erases of bodies from the main thread while ``O.run()`` goes on in the background: no
  crash, and the final scene is consistent. ``GRANUM_STRESS_SECONDS`` and ``GRANUM_STRESS_ROUNDS`` set
  how long and how often (CI: 1 s once; the issue's full run: 10 s, 5 times).
"""

from __future__ import annotations

import os
import random
import signal
import subprocess
import sys
import threading

import numpy as np
import pytest

from granum.engines import interrupts

INTERRUPTS = int(os.environ.get("GRANUM_STRESS_INTERRUPTS", "4"))
SECONDS = float(os.environ.get("GRANUM_STRESS_SECONDS", "1"))
ROUNDS = int(os.environ.get("GRANUM_STRESS_ROUNDS", "1"))

#: run in a process of its own: SIGINT goes to its main thread, with Python's default handler during each
#: O.run (granum's own takes over inside: granum.engines.interrupts) and a no-op one between the checks.
_CTRL_C = r"""
import os, random, signal, sys, threading
import numpy as np
from granum.yade import *

signal.signal(signal.SIGINT, lambda s, f: None)
O.bodies.append(geom.facetBox((.5, .5, .5), (.5, .5, .5), wallMask=31))
sp = pack.SpherePack()
sp.makeCloud((0, 0, 0), (1, 1, 1), rMean=.03, rRelFuzz=.2, num=2000, seed=1)
sp.toSimulation()
O.engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb(), Bo1_Facet_Aabb()]),
             InteractionLoop([Ig2_Sphere_Sphere_ScGeom(), Ig2_Facet_Sphere_ScGeom()],
                             [Ip2_FrictMat_FrictMat_FrictPhys()], [Law2_ScGeom_FrictPhys_CundallStrack()]),
             NewtonIntegrator(gravity=(0, 0, -9.81), damping=.3)]
O.dt = .5 * PWaveTimeStep()

def state():
    b = O._scene.bodies
    n = b.count
    return [b.pos[:n].copy(), b.vel[:n].copy(), b.ang_vel[:n].copy(), b.ori[:n].copy()]

rng = random.Random(int(sys.argv[1]))
path = sys.argv[2]
interrupted = 0
for k in range(int(sys.argv[3])):
    timer = threading.Timer(rng.uniform(0.0, 0.4), os.kill, (os.getpid(), signal.SIGINT))
    signal.signal(signal.SIGINT, signal.default_int_handler)   # as in an ordinary program
    try:
        timer.start()
        O.run(10**9, True)
    except KeyboardInterrupt:
        interrupted += 1
    finally:
        signal.signal(signal.SIGINT, lambda s, f: None)
    timer.cancel()
    timer.join()
    assert not O.running
    O.save(path)                    # the file O.load accepts
    O.saveTmp("here")
    O.run(7, True)
    straight = state()
    O.load(path)
    O.run(7, True)
    assert all(np.array_equal(a, b) for a, b in zip(straight, state())), f"interrupt {k}: load differs"
    O.loadTmp("here")
    O.run(7, True)
    assert all(np.array_equal(a, b) for a, b in zip(straight, state())), f"interrupt {k}: loadTmp differs"
print("INTERRUPTED", interrupted, "ITER", O.iter, "CONTACTS", O.interactions.countReal())
"""


def test_ctrl_c_at_random_moments_leaves_a_scene_that_runs_saves_loads_and_resumes_bitwise(tmp_path):
    r = subprocess.run([sys.executable, "-c", _CTRL_C, "12345", str(tmp_path / "scene.yade"), str(INTERRUPTS)],
                       capture_output=True, text=True, timeout=600 + 20 * INTERRUPTS)
    assert r.returncode == 0, r.stdout[-2000:] + r.stderr[-4000:]
    words = next(ln for ln in r.stdout.splitlines() if ln.startswith("INTERRUPTED")).split()
    assert int(words[1]) == INTERRUPTS   # every interrupt landed in a run and was raised there
    assert int(words[5]) > 0


def _consistent(y) -> None:
    """The scene's arrays agree with each other (and a checkpoint of it loads, which validates them)."""
    s = y.O._scene
    b, C = s.bodies, s.contacts
    from granum.core.contacts import C_CONTACTS, C_PAIRS, FLAG_ALIVE, I_FLAGS, I_ID1, I_ID2

    n, nc, npairs = b.count, int(C.ctr[C_CONTACTS]), int(C.ctr[C_PAIRS])
    assert nc <= C.con_i.shape[0] and nc <= C.con_f.shape[0] and npairs <= C.pair_ids.shape[0]
    live = (C.con_i[:nc, I_FLAGS] & FLAG_ALIVE) != 0
    ids = C.con_i[:nc][live][:, [I_ID1, I_ID2]]
    assert ((ids >= 0) & (ids < n)).all() and b.alive[:n][ids].all()
    pairs = C.pair_ids[:npairs]
    assert ((pairs >= 0) & (pairs < n)).all()
    assert np.isfinite(b.pos[:n][b.alive[:n]]).all()
    y.O.saveTmp("check")
    y.O.loadTmp("check")


def test_appends_and_erases_during_a_background_run_keep_the_scene_consistent(yade):
    y = yade
    y.O.bodies.append(y.geom.facetBox((.5, .5, .5), (.5, .5, .5), wallMask=31))
    sp = y.pack.SpherePack()
    sp.makeCloud((0, 0, 0), (1, 1, 1), rMean=.04, rRelFuzz=.2, num=400, seed=3)
    sp.toSimulation()
    y.O.engines = [y.ForceResetter(), y.InsertionSortCollider([y.Bo1_Sphere_Aabb(), y.Bo1_Facet_Aabb()]),
                   y.InteractionLoop([y.Ig2_Sphere_Sphere_ScGeom(), y.Ig2_Facet_Sphere_ScGeom()],
                                     [y.Ip2_FrictMat_FrictMat_FrictPhys()], [y.Law2_ScGeom_FrictPhys_CundallStrack()]),
                   y.NewtonIntegrator(gravity=(0, 0, -9.81), damping=.3)]
    y.O.dt = .5 * y.PWaveTimeStep()
    rng = random.Random(7)
    for _ in range(ROUNDS):
        y.O.run()
        deadline = threading.Event()
        threading.Timer(SECONDS, deadline.set).start()
        edits = 0
        while not deadline.is_set():
            alive = [b.id for b in y.O.bodies if isinstance(b.shape, y.Sphere)]
            if rng.random() < 0.5 and len(alive) > 50:
                y.O.bodies.erase(rng.choice(alive))
            else:
                y.O.bodies.append(y.sphere((rng.uniform(.1, .9), rng.uniform(.1, .9), rng.uniform(.5, .9)), .03))
            edits += 1
        assert y.O.running   # the edits paused the run and resumed it each time
        y.O.pause()
        y.O.wait()
        assert edits > 0
        _consistent(y)
        y.O.run(20, True)
        _consistent(y)


def _sigint_now():
    """Deliver SIGINT to this process and let Python run its handler (at the next bytecode)."""
    signal.raise_signal(signal.SIGINT)


def test_the_guards_defer_ctrl_c_to_a_step_boundary_and_put_the_handler_back():
    """The handler protocol of granum.engines.interrupts, in the main thread: a shielded exchange raises
    KeyboardInterrupt only once it is over, a deferred run only where it asks (raise_pending), a second Ctrl-C
    inside an engine's Python code at once; an exception leaves as itself; the handler before comes back."""
    assert threading.current_thread() is threading.main_thread()
    before = signal.getsignal(signal.SIGINT)
    mine = lambda s, f: None   # noqa: E731  (the handler a user's program had)
    signal.signal(signal.SIGINT, mine)
    try:
        steps = []
        with pytest.raises(KeyboardInterrupt):
            with interrupts.shielded():
                _sigint_now()
                steps.append("exchange finished")
        assert steps == ["exchange finished"] and signal.getsignal(signal.SIGINT) is mine

        with pytest.raises(ZeroDivisionError):   # not replaced by the Ctrl-C pending when it left
            with interrupts.shielded():
                _sigint_now()
                raise ZeroDivisionError("the exchange failed")
        assert signal.getsignal(signal.SIGINT) is mine

        with interrupts.deferred():
            _sigint_now()
            steps.append("step finished")
            with pytest.raises(KeyboardInterrupt):
                interrupts.raise_pending()
            interrupts.raise_pending()   # asked once: nothing pending any more
            with interrupts.shielded():   # inside a run the run's guard already defers
                _sigint_now()
            with interrupts.user_code():
                with pytest.raises(KeyboardInterrupt):   # the second Ctrl-C, in a PyRunner's command
                    _sigint_now()
                    steps.append("never")
            _sigint_now()   # outside the command again: deferred
            steps.append("next step finished")
        assert steps[1:] == ["step finished", "next step finished"]
        assert signal.getsignal(signal.SIGINT) is mine

        with interrupts.user_code():   # outside a run: Python's handler decides (here: mine, which ignores it)
            _sigint_now()
    finally:
        signal.signal(signal.SIGINT, before)
