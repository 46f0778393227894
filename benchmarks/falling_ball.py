# Benchmark: falling ball (the scene of YADE's --quickperformance check).
#
# A ball of ~4,400 spheres on a hexagonal close-packed lattice (pack.regularHexa)
# falls under gravity (-y) inside a closed facet box and hits the bottom.
# ViscElMat (tc=0.001, en=et=0.003), O.dt = 1e-4, NewtonIntegrator(damping=0);
# ball radius / sphere radius = 23.658, the box is the packing's bounding box
# enlarged by 5 %, as in `yade --quickperformance`.
#
# Runs unmodified with `granum -jN falling_ball.py` and `yade -n -x -jN falling_ball.py`.
# Environment: BENCH_STEPS (default 2000) timed steps, BENCH_WARMUP (default 1)
# untimed steps before them, BENCH_RAD (default 23.658) ball radius / sphere radius.
# Prints one line:  BENCH name=falling_ball ...

import os
import sys
import time

from yade import geom, pack

sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from _bench import env_int, measure  # noqa: E402

t_script = time.perf_counter()
radRAD = float(os.environ.get('BENCH_RAD', '23.658'))

tc = 0.001
mat = O.materials.append(ViscElMat(density=2300, frictionAngle=radians(35), tc=tc, en=0.003, et=0.003))
O.dt = 0.1 * tc

rad = 0.5  # radius of the ball
sphereIds = O.bodies.append(
    pack.regularHexa(pack.inSphere((0, 0, 0), rad), radius=rad / radRAD, gap=0.5 * rad / radRAD, material=mat))

# bounding box of the packing, enlarged by 5 %
lo = [min(O.bodies[i].state.pos[k] - O.bodies[i].shape.radius for i in sphereIds) for k in range(3)]
hi = [max(O.bodies[i].state.pos[k] + O.bodies[i].shape.radius for i in sphereIds) for k in range(3)]
center = tuple(0.5 * (lo[k] + hi[k]) for k in range(3))
halfSize = tuple(0.5 * (hi[k] - lo[k]) * 1.05 for k in range(3))
O.bodies.append(geom.facetBox(center, halfSize, material=mat))

O.engines = [
    ForceResetter(),
    InsertionSortCollider([Bo1_Sphere_Aabb(), Bo1_Facet_Aabb()]),
    InteractionLoop(
        [Ig2_Sphere_Sphere_ScGeom(), Ig2_Facet_Sphere_ScGeom()],
        [Ip2_ViscElMat_ViscElMat_ViscElPhys()],
        [Law2_ScGeom_ViscElPhys_Basic()],
    ),
    NewtonIntegrator(damping=0, gravity=(0, -9.81, 0)),
]

measure(O, 'falling_ball', len(sphereIds), env_int('BENCH_STEPS', 2000), env_int('BENCH_WARMUP', 1), t_script)
