# Benchmark: the dense lattice with cohesive contacts and moments (Law2_ScGeom6D_CohFrictPhys_CohesionMoment).
#
# The scene of dense_lattice.py (n^3 spheres of radius r = 0.01 on a simple cubic lattice with spacing
# 2r(1 - 1e-3), in a closed geom.facetBox overlapping the outer spheres by r*1e-3), with
# CohFrictMat(young=1e8, poisson=0.3, frictionAngle=30 deg, density=2600, normalCohesion=shearCohesion=1e6,
# momentRotationLaw=True, etaRoll=etaTwist=0.1) for spheres and facets, Ig2_Sphere_Sphere_ScGeom6D and
# Ig2_Facet_Sphere_ScGeom6D, Ip2_CohFrictMat_CohFrictMat_CohFrictPhys(setCohesionNow=True: every contact of
# the first step is cohesive), Law2_ScGeom6D_CohFrictPhys_CohesionMoment(useIncrementalForm=True: bending and
# twisting moments bounded by the rolling/twisting strengths), NewtonIntegrator(damping=0.2, gravity -z),
# O.dt = 0.5*PWaveTimeStep(). At n = 20: 8,000 spheres and about 25,000 cohesive contacts with moments.
#
# Runs unmodified with `granum -jN cohesive_lattice.py` and `yade -n -x -jN cohesive_lattice.py`.
# Environment: BENCH_N (default 20), BENCH_STEPS (default 500), BENCH_WARMUP (default 1), BENCH_DUMP=path:
# after the run, write the sphere positions and angular velocities to path (one line "x y z wx wy wz" per
# sphere, %.17g), to check bitwise determinism across thread counts and runs.
# Prints one line:  BENCH name=cohesive_lattice ...

import os
import sys
import time

from yade import geom

sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from _bench import env_int, measure  # noqa: E402

t_script = time.perf_counter()
n = env_int('BENCH_N', 20)
dump = os.environ.get('BENCH_DUMP', '')

r = 0.01
overlap = 1e-3
s = 2 * r * (1 - overlap)  # lattice spacing
mat = O.materials.append(CohFrictMat(young=1e8, poisson=0.3, frictionAngle=radians(30), density=2600,
                                     normalCohesion=1e6, shearCohesion=1e6, momentRotationLaw=True, etaRoll=0.1,
                                     etaTwist=0.1))

# centres x = r + i*s (i = 0..n-1) on each axis, x fastest, z slowest
sphereIds = O.bodies.append(
    [sphere((r + i * s, r + j * s, r + k * s), r, material=mat) for k in range(n) for j in range(n) for i in range(n)])

half = 0.5 * (n - 1) * s + r * (1 - overlap)
c = r + 0.5 * (n - 1) * s
O.bodies.append(geom.facetBox((c, c, c), (half, half, half), material=mat))

O.engines = [
    ForceResetter(),
    InsertionSortCollider([Bo1_Sphere_Aabb(), Bo1_Facet_Aabb()]),
    InteractionLoop(
        [Ig2_Sphere_Sphere_ScGeom6D(), Ig2_Facet_Sphere_ScGeom6D()],
        [Ip2_CohFrictMat_CohFrictMat_CohFrictPhys(setCohesionNow=True)],
        [Law2_ScGeom6D_CohFrictPhys_CohesionMoment(useIncrementalForm=True)],
    ),
    NewtonIntegrator(damping=0.2, gravity=(0, 0, -9.81)),
]
O.dt = 0.5 * PWaveTimeStep()

measure(O, 'cohesive_lattice', len(sphereIds), env_int('BENCH_STEPS', 500), env_int('BENCH_WARMUP', 1), t_script)

if dump:
    with open(dump, 'w') as f:
        for i in sphereIds:
            p, w = O.bodies[i].state.pos, O.bodies[i].state.angVel
            f.write(f'{p[0]:.17g} {p[1]:.17g} {p[2]:.17g} {w[0]:.17g} {w[1]:.17g} {w[2]:.17g}\n')
