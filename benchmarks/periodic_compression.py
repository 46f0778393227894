# Benchmark: compression of a periodic cell by its boundary controllers.
#
# BENCH_N spheres (default 4000) from makeCloud((0,0,0), (1,1,1), .02, .3, n, True, seed=1) in a periodic unit
# cell, FrictMat(young=30e9, poisson=.3, friction .1, 1000 kg/m3), Cundall-Strack, NewtonIntegrator(damping=.8),
# O.dt = PWaveTimeStep(). BENCH_CONTROLLER chooses the controller:
#   iso  PeriIsoCompressor(stresses=[-1e8, -1e6], maxUnbalanced=1e-2, globalUpdateInt=20) (randomPeriPack's
#        recipe; the timed steps shrink the cell toward the first stress)
#   p3d  Peri3dController(goal=(-.2, -.2, -.2, 0, 0, .05), stressMask=0, nSteps=2*BENCH_STEPS) (a strain path:
#        compression with shear)
# Timed: BENCH_STEPS steps (default 2000).
#
# Runs unmodified with `granum -jN periodic_compression.py` and `yade -n -x -jN periodic_compression.py`.
# Prints one line:  BENCH name=periodic_iso|periodic_p3d ... volume=... (the cell volume at the end)

import os
import sys
import time

from yade import pack

sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from _bench import env_int, measure  # noqa: E402

t_script = time.perf_counter()
n = env_int('BENCH_N', 4000)
steps = env_int('BENCH_STEPS', 2000)
kind = os.environ.get('BENCH_CONTROLLER', 'iso')
O.periodic = True
O.cell.setBox(1, 1, 1)
sp = pack.SpherePack()
sp.makeCloud((0, 0, 0), (1, 1, 1), .5 * (0.4 / n) ** (1 / 3.), .3, n, True, seed=1)
O.materials.append(FrictMat(young=30e9, poisson=.3, frictionAngle=.1, density=1e3))
for c, r in sp:
    O.bodies.append(sphere(c, r))
if kind == 'iso':
    controller = PeriIsoCompressor(stresses=[-1e8, -1e6], maxUnbalanced=1e-2, globalUpdateInt=20)
else:
    controller = Peri3dController(goal=(-.2, -.2, -.2, 0, 0, .05), stressMask=0, nSteps=2 * steps)
O.engines = [
    ForceResetter(),
    InsertionSortCollider([Bo1_Sphere_Aabb()]),
    InteractionLoop([Ig2_Sphere_Sphere_ScGeom()], [Ip2_FrictMat_FrictMat_FrictPhys()],
                    [Law2_ScGeom_FrictPhys_CundallStrack()]),
    controller,
    NewtonIntegrator(damping=.8),
]
O.dt = PWaveTimeStep()
measure(O, 'periodic_' + kind, len(sp), steps, env_int('BENCH_WARMUP', 1), t_script,
        extra=lambda: {'volume': f'{O.cell.volume:.6g}'})
