# Benchmark: spheres made by a BoxFactory while they fall into a facet box.
#
# A BoxFactory (half sizes 0.15 x 0.15 x 0.1 m, 0.4 m above the floor) makes spheres of radius 0.004-0.006 m
# at BENCH_RATE spheres per step on average (massFlowRate from the mean sphere mass), thrown down at 2 m/s,
# until BENCH_N spheres; they fall under gravity (-z) into a closed facet box (0.6 x 0.6 x 1 m). FrictMat
# (E=1e7, nu=0.3, 30 deg, 2600 kg/m^3), Cundall-Strack, NewtonIntegrator(damping=0.2), O.dt = 5e-5.
# It measures the factory's cost per step (metering every step, placing the spheres due, growing the arrays,
# the collider's full run after each insertion) on top of a growing granular flow.
#
# Runs unmodified with `granum -jN sphere_factory.py` and `yade -n -x -jN sphere_factory.py`.
# Environment: BENCH_N (default 5000) spheres, BENCH_RATE (default 5) spheres per step, BENCH_STEPS (default
# 1000) timed steps, BENCH_WARMUP (default 1) untimed steps before them.
# Prints one line:  BENCH name=sphere_factory ...

import math
import os
import sys
import time

from yade import geom

sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from _bench import env_int, measure  # noqa: E402

t_script = time.perf_counter()
n = env_int('BENCH_N', 5000)
rate = env_int('BENCH_RATE', 5)

mat = O.materials.append(FrictMat(young=1e7, poisson=0.3, frictionAngle=math.radians(30), density=2600))
O.bodies.append(geom.facetBox((0, 0, 0.5), (0.3, 0.3, 0.5), material=mat))
O.dt = 5e-5
mean_mass = 2600 * 4 / 3 * math.pi * (0.25 * (0.004 + 0.006) * (0.004 ** 2 + 0.006 ** 2))  # mean of r^3 on [a, b]
factory = BoxFactory(center=(0, 0, 0.8), extents=(0.15, 0.15, 0.1), rMin=0.004, rMax=0.006, vMin=2, vMax=2,
                     normal=(0, 0, -1), massFlowRate=rate * mean_mass / O.dt, maxParticles=n, materialId=mat,
                     label='factory')
O.engines = [
    ForceResetter(),
    InsertionSortCollider([Bo1_Sphere_Aabb(), Bo1_Facet_Aabb()]),
    InteractionLoop(
        [Ig2_Sphere_Sphere_ScGeom(), Ig2_Facet_Sphere_ScGeom()],
        [Ip2_FrictMat_FrictMat_FrictPhys()],
        [Law2_ScGeom_FrictPhys_CundallStrack()],
    ),
    NewtonIntegrator(damping=0.2, gravity=(0, 0, -9.81)),
    factory,
]

measure(O, 'sphere_factory', n, env_int('BENCH_STEPS', 1000), env_int('BENCH_WARMUP', 1), t_script,
        extra=lambda: {'made': factory.numParticles, 'mass': f'{factory.totalMass:.6g}'})
