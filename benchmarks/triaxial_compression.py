# Benchmark: YADE's TriaxialTest preprocessor driven by TriaxialCompressionEngine (its state machine).
#
# TriaxialTest(numberOfGrains=BENCH_N (default 1000), noFiles=True).load(): a makeCloud of n spheres (cloud
# porosity .8, radii +-30 %) in the unit box between six boxes, FrictMat (E=15 MPa, ks/kn=.5, 18 deg), walls at
# 10 m/s at most, GlobalStiffnessTimeStepper (interval 50), TriaxialCompressionEngine (compaction to 50 kPa by
# the walls, then loading along y at 0.1 /s under 50 kPa once the unbalanced force is below 0.01),
# NewtonIntegrator(damping=.2). Timed: BENCH_STEPS steps (default 3000) from the start, through the compaction
# and, with the defaults, into the loading: the wall servo, the state machine's checks every 20 steps
# (unbalanced force), the time stepper on a packing that densifies.
#
# BENCH_DUMP=path: after the run, write the sphere positions and velocities (%.17g, one line "x y z vx vy vz"
# per sphere) to check bitwise determinism across thread counts.
# Runs unmodified with `granum -jN triaxial_compression.py` and `yade -n -x -jN triaxial_compression.py`.
# Prints one line:  BENCH name=triaxial_compression ... state=... porosity=... q=... (q: s22 - s11 [Pa] from the
# stresses of the right and top walls (stress(1), stress(3): the controller's wall order), compression positive)

import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from _bench import env_int, measure  # noqa: E402

t_script = time.perf_counter()
n = env_int('BENCH_N', 1000)
TriaxialTest(numberOfGrains=n, noFiles=True).load()
triax = O.engines[4]

measure(O, 'triaxial_compression', n, env_int('BENCH_STEPS', 3000), env_int('BENCH_WARMUP', 1), t_script,
        extra=lambda: {'state': triax.currentState, 'porosity': f'{triax.porosity:.6g}',
                       'q': f'{triax.stress(1)[0] - triax.stress(3)[1]:.6g}'})
dump = os.environ.get('BENCH_DUMP', '')
if dump:
    with open(dump, 'w') as f:
        for b in O.bodies:
            if isinstance(b.shape, Sphere):
                f.write(' '.join(f'{v:.17g}' for v in list(b.state.pos) + list(b.state.vel)) + '\n')
