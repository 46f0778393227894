# Benchmark: bouncing sphere (the fixed cost of a step).
#
# The two-body scene of the tutorial script 01-bouncing-sphere.py: a fixed sphere and
# a free sphere 2 m above it (default material), Cundall-Strack chain,
# NewtonIntegrator(gravity -z, damping=0.1), O.dt = 0.5e-4*PWaveTimeStep().
# With two bodies, the time per step is almost all per-step overhead (engine
# dispatch, collider bookkeeping, Python/compiled-code boundaries), not physics.
#
# Runs unmodified with `granum -jN bouncing_sphere.py` and `yade -n -x -jN bouncing_sphere.py`.
# Environment: BENCH_STEPS (default 2000000) steps timed in ONE O.run(n, True),
# BENCH_WARMUP (default 1) untimed steps before them.
# Prints one line:  BENCH name=bouncing_sphere ... z=<final height of the free sphere>

import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from _bench import env_int, measure  # noqa: E402

t_script = time.perf_counter()

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
]
O.dt = .5e-4 * PWaveTimeStep()

measure(O, 'bouncing_sphere', 2, env_int('BENCH_STEPS', 2000000), env_int('BENCH_WARMUP', 1), t_script,
        extra=lambda: {'z': f'{O.bodies[1].state.pos[2]:.9g}'})
