# Benchmark: triaxial compression in a box of six walls (the scene of YADE's triax tutorial, session 1).
#
# BENCH_N spheres (default 1000) from makeCloud((0,0,0), (1,1,1), -1, .3333, n, False, .95, seed=1) between
# the six boxes of aabbWalls, FrictMat(young=5e6, poisson=.5, 30 deg, 2600 kg/m3), frictionless walls,
# Cundall-Strack, GlobalStiffnessTimeStepper(timeStepUpdateInterval=100, timestepSafetyCoefficient=.8),
# TriaxialStressController and NewtonIntegrator(damping=.2).
# Untimed: BENCH_CONFINE steps (default 4000) of isotropic confinement to 10 kPa by growing the spheres
# (internalCompaction). Timed: BENCH_STEPS steps (default 2000) of triaxial compression, lateral stresses
# held at 10 kPa by the walls and the y walls moving at the strain rate -0.02 /s (damping .1).
#
# Runs unmodified with `granum -jN triaxial.py` and `yade -n -x -jN triaxial.py`.
# Prints one line:  BENCH name=triaxial ... porosity=... q=... (q: deviator s22 - s11 at the end [Pa],
# compression positive; the set-up time includes the confinement)

import os
import sys
import time

from yade import pack

sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from _bench import env_int, measure  # noqa: E402

t_script = time.perf_counter()
n = env_int('BENCH_N', 1000)
young = 5e6
O.materials.append(FrictMat(young=young, poisson=0.5, frictionAngle=radians(30), density=2600, label='spheres'))
O.materials.append(FrictMat(young=young, poisson=0.5, frictionAngle=0, density=0, label='walls'))
O.bodies.append(aabbWalls([Vector3(0, 0, 0), Vector3(1, 1, 1)], thickness=0, material='walls'))
sp = pack.SpherePack()
sp.makeCloud(Vector3(0, 0, 0), Vector3(1, 1, 1), -1, 0.3333, n, False, 0.95, seed=1)
sphereIds = O.bodies.append([sphere(c, r, material='spheres') for c, r in sp])

triax = TriaxialStressController(maxMultiplier=1. + 2e4 / young, finalMaxMultiplier=1. + 2e3 / young, thickness=0,
                                 stressMask=7, internalCompaction=True, goal1=-1e4, goal2=-1e4, goal3=-1e4)
newton = NewtonIntegrator(damping=0.2)
O.engines = [
    ForceResetter(),
    InsertionSortCollider([Bo1_Sphere_Aabb(), Bo1_Box_Aabb()]),
    InteractionLoop([Ig2_Sphere_Sphere_ScGeom(), Ig2_Box_Sphere_ScGeom()], [Ip2_FrictMat_FrictMat_FrictPhys()],
                    [Law2_ScGeom_FrictPhys_CundallStrack()]),
    GlobalStiffnessTimeStepper(active=1, timeStepUpdateInterval=100, timestepSafetyCoefficient=0.8),
    triax,
    newton,
]
O.run(env_int('BENCH_CONFINE', 4000), True)
triax.internalCompaction = False
triax.stressMask = 5
triax.goal2 = -0.02
newton.damping = 0.1

measure(O, 'triaxial', len(sphereIds), env_int('BENCH_STEPS', 2000), env_int('BENCH_WARMUP', 1), t_script,
        extra=lambda: {'porosity': f'{triax.porosity:.6g}',
                       'q': f'{triax.stress(triax.wall_right_id)[0] - triax.stress(triax.wall_top_id)[1]:.6g}'})
