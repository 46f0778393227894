# Benchmark: a Python engine at every step (the cost of leaving compiled code).
#
# The two-body scene of bouncing_sphere.py (the tutorial 01-bouncing-sphere.py) with a
# PyRunner(iterPeriod=BENCH_PERIOD) calling a Python function that counts its calls. YADE's scripts
# check and record their state from PyRunners (checkUnbalanced, addPlotData), every 100 or 1000 steps
# as a rule, some every step; with two bodies the step itself costs almost nothing, so this measures
# what each call costs: in granum, leaving the compiled step loop, the Python engine and the way back.
#
# With BENCH_DRIVE=step, no PyRunner: the script drives the steps itself, one O.step() call each (YADE's scripts
# and tests loop so: `for i in range(n): O.step()`), which measures what leaving Python costs per call.
#
# Runs unmodified with `granum -jN python_engine.py` and `yade -n -x -jN python_engine.py`.
# Environment: BENCH_STEPS (default 20000) steps timed in ONE O.run(n, True) (or n O.step() calls),
# BENCH_PERIOD (default 1) the PyRunner's iterPeriod, BENCH_WARMUP (default 1) untimed steps before them,
# BENCH_DRIVE (default pyrunner; step: O.step() calls), BENCH_NAME (default python_engine) the name printed.
# Prints one line:  BENCH name=python_engine ... calls=<PyRunner calls during the timed steps>

import os
import sys

here = os.path.dirname(os.path.abspath(sys.argv[0]))
with open(os.path.join(here, 'bouncing_sphere.py')) as f:  # its scene and engines, without its measurement
    exec(compile(f.read().split('\nmeasure(')[0], os.path.join(here, 'bouncing_sphere.py'), 'exec'))
calls = [0]


def count():
    calls[0] += 1


drive = None
if os.environ.get('BENCH_DRIVE', 'pyrunner') == 'step':
    def drive(n):
        for _ in range(n):
            O.step()
else:
    O.engines = O.engines + [PyRunner(command='count()', iterPeriod=env_int('BENCH_PERIOD', 1))]
measure(O, os.environ.get('BENCH_NAME', 'python_engine'), 2, env_int('BENCH_STEPS', 20000),
        env_int('BENCH_WARMUP', 1), t_script, extra=lambda: {'calls': calls[0], 'z': f'{O.bodies[1].state.pos[2]:.9g}'},
        drive=drive)
