# Benchmark: a Python engine at every step (the cost of leaving compiled code).
#
# The two-body scene of bouncing_sphere.py (the tutorial 01-bouncing-sphere.py) with a
# PyRunner(iterPeriod=BENCH_PERIOD) calling a Python function that counts its calls. YADE's scripts
# check and record their state from PyRunners (checkUnbalanced, addPlotData), every 100 or 1000 steps
# as a rule, some every step; with two bodies the step itself costs almost nothing, so this measures
# what each call costs: in granum, leaving the compiled step loop, the Python engine and the way back.
#
# Runs unmodified with `granum -jN python_engine.py` and `yade -n -x -jN python_engine.py`.
# Environment: BENCH_STEPS (default 20000) steps timed in ONE O.run(n, True), BENCH_PERIOD (default 1)
# the PyRunner's iterPeriod, BENCH_WARMUP (default 1) untimed steps before them.
# Prints one line:  BENCH name=python_engine ... calls=<PyRunner calls during the timed steps>

import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from _bench import env_int, measure  # noqa: E402

t_script = time.perf_counter()
calls = [0]


def count():
    calls[0] += 1


O.bodies.append([
    sphere(center=(0, 0, 0), radius=.5, fixed=True),  # fixed support
    sphere((0, 0, 2), .5),  # free sphere, falls on the support
])
O.engines = [
    ForceResetter(),
    InsertionSortCollider([Bo1_Sphere_Aabb()]),
    InteractionLoop(
        [Ig2_Sphere_Sphere_ScGeom()],
        [Ip2_FrictMat_FrictMat_FrictPhys()],
        [Law2_ScGeom_FrictPhys_CundallStrack()],
    ),
    NewtonIntegrator(gravity=(0, 0, -9.81), damping=0.1),
    PyRunner(command='count()', iterPeriod=env_int('BENCH_PERIOD', 1)),
]
O.dt = .5e-4 * PWaveTimeStep()
warmup = env_int('BENCH_WARMUP', 1)
measure(O, 'python_engine', 2, env_int('BENCH_STEPS', 20000), warmup, t_script,
        extra=lambda: {'calls': calls[0], 'z': f'{O.bodies[1].state.pos[2]:.9g}'})
