# Benchmark: dense lattice (also the scaling benchmark, via BENCH_N).
#
# n^3 spheres of radius r = 0.01 on a simple cubic lattice with spacing 2r(1 - 1e-3),
# so that every sphere overlaps its 6 neighbours slightly, confined by a closed
# geom.facetBox whose walls overlap the outer spheres by the same amount (r*1e-3).
# FrictMat(young=1e8, poisson=0.3, frictionAngle=30 deg, density=2600), Cundall-Strack
# chain (BENCH_LAW=mindlin: Hertz-Mindlin, Ip2_FrictMat_FrictMat_MindlinPhys and
# Law2_ScGeom_MindlinPhys_Mindlin with their defaults; BENCH_LAW=cohesive: cohesive contacts with
# moments, CohFrictMat with the same moduli and normalCohesion=shearCohesion=1e6,
# momentRotationLaw=True, etaRoll=etaTwist=0.1, Ig2_*_ScGeom6D,
# Ip2_CohFrictMat_CohFrictMat_CohFrictPhys(setCohesionNow=True: every contact of the first step is
# cohesive), Law2_ScGeom6D_CohFrictPhys_CohesionMoment(useIncrementalForm=True)),
# BENCH_LAW=cpm: the concrete particle model, CpmMat(young=1e8, poisson=0.3, frictionAngle=30 deg,
# density=2600, sigmaT=3e4, epsCrackOnset=1e-4, relDuctility=30) for the spheres, FrictMat for the box,
# Ip2_CpmMat_CpmMat_CpmPhys (the contacts of the first steps are cohesive), Ip2_FrictMat_CpmMat_FrictPhys,
# Law2_ScGeom_CpmPhys_Cpm and Cundall-Strack for the box);
# BENCH_LAW=viscel_rolling: the visco-elastic law with rolling resistance, ViscElMat with the same density and
# friction, tc=1e-3, en=.5, et=.5, mR=.05, mRtype=2, Ip2_ViscElMat_ViscElMat_ViscElPhys and
# Law2_ScGeom_ViscElPhys_Basic);
# BENCH_LAW=cdm: the extended Hertz-Mindlin law (conical damage, pressure-dependent friction), FrictMatCDM with the
# same moduli, density and friction, sigmaMax=1e6 (below the lattice's Hertzian peak pressure, about 1.6e6 Pa: the
# contacts are crushed from the first step), alpha=1.2, c1=0.1, c2=1e-6, for spheres and facets,
# Ip2_FrictMatCDM_FrictMatCDM_MindlinPhysCDM and Law2_ScGeom_MindlinPhysCDM_HertzMindlinCDM),
# NewtonIntegrator(damping=0.2, gravity -z), O.dt = 0.5*PWaveTimeStep().
# At n = 20: 8,000 spheres and about 25,000 contacts (3 n^2 (n-1) sphere-sphere + walls).
#
# Runs unmodified with `granum -jN dense_lattice.py` and `yade -n -x -jN dense_lattice.py`.
# Environment: BENCH_N (default 20) lattice size, BENCH_STEPS (default 500) timed steps,
# BENCH_WARMUP (default 1) untimed steps before them, BENCH_DUMP=path: after the run,
# write the sphere positions and angular velocities to path (one line "x y z wx wy wz" per
# sphere, %.17g) to check bitwise determinism across thread counts and runs. BENCH_NAME overrides
# the name printed (benchmarks/run uses scaling_N, dense_lattice_mindlin, cohesive_lattice).
# BENCH_LAW: the contact law (mindlin, cohesive, cpm, viscel_rolling, cdm; user: Cundall-Strack as a user's law,
# granum only).
# Prints one line:  BENCH name=dense_lattice ...

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
LAW = os.environ.get('BENCH_LAW', '')
if LAW == 'cohesive':
    mat = O.materials.append(CohFrictMat(young=1e8, poisson=0.3, frictionAngle=radians(30), density=2600,
                                         normalCohesion=1e6, shearCohesion=1e6, momentRotationLaw=True,
                                         etaRoll=0.1, etaTwist=0.1))
elif LAW == 'viscel_rolling':
    mat = O.materials.append(ViscElMat(young=1e8, poisson=0.3, frictionAngle=radians(30), density=2600, tc=1e-3,
                                       en=0.5, et=0.5, mR=0.05, mRtype=2))
elif LAW == 'cdm':
    mat = O.materials.append(FrictMatCDM(young=1e8, poisson=0.3, frictionAngle=radians(30), density=2600,
                                         sigmaMax=1e6, alpha=1.2, c1=0.1, c2=1e-6))
else:
    mat = O.materials.append(FrictMat(young=1e8, poisson=0.3, frictionAngle=radians(30), density=2600))
wallMat = mat
if LAW == 'cpm':
    mat = O.materials.append(CpmMat(young=1e8, poisson=0.3, frictionAngle=radians(30), density=2600, sigmaT=3e4,
                                    epsCrackOnset=1e-4, relDuctility=30))

# centres x = r + i*s (i = 0..n-1) on each axis, x fastest, z slowest
sphereIds = O.bodies.append(
    [sphere((r + i * s, r + j * s, r + k * s), r, material=mat) for k in range(n) for j in range(n) for i in range(n)])

# walls through the outer spheres, overlapping them by r*overlap like the neighbours do
half = 0.5 * (n - 1) * s + r * (1 - overlap)
c = r + 0.5 * (n - 1) * s
O.bodies.append(geom.facetBox((c, c, c), (half, half, half), material=wallMat))

geoms = [Ig2_Sphere_Sphere_ScGeom(), Ig2_Facet_Sphere_ScGeom()]
ip2, law = Ip2_FrictMat_FrictMat_FrictPhys(), Law2_ScGeom_FrictPhys_CundallStrack()
if LAW == 'user':  # granum only: the same law written as a user's law
    from user_cundall_strack import Law2_ScGeom_FrictPhys_UserCundallStrack
    law = Law2_ScGeom_FrictPhys_UserCundallStrack()
elif LAW == 'mindlin':  # Hertz-Mindlin (granum and YADE)
    ip2, law = Ip2_FrictMat_FrictMat_MindlinPhys(), Law2_ScGeom_MindlinPhys_Mindlin()
elif LAW == 'cpm':  # the concrete particle model (granum and YADE)
    ip2 = [Ip2_CpmMat_CpmMat_CpmPhys(), Ip2_FrictMat_CpmMat_FrictPhys()]
    law = [Law2_ScGeom_CpmPhys_Cpm(), law]
elif LAW == 'cohesive':  # cohesion with bending and twisting moments (granum and YADE)
    geoms = [Ig2_Sphere_Sphere_ScGeom6D(), Ig2_Facet_Sphere_ScGeom6D()]
    ip2 = Ip2_CohFrictMat_CohFrictMat_CohFrictPhys(setCohesionNow=True)
    law = Law2_ScGeom6D_CohFrictPhys_CohesionMoment(useIncrementalForm=True)
elif LAW == 'viscel_rolling':  # visco-elastic with rolling resistance (granum and YADE)
    ip2, law = Ip2_ViscElMat_ViscElMat_ViscElPhys(), Law2_ScGeom_ViscElPhys_Basic()
elif LAW == 'cdm':  # the extended Hertz-Mindlin law (granum and YADE)
    ip2, law = Ip2_FrictMatCDM_FrictMatCDM_MindlinPhysCDM(), Law2_ScGeom_MindlinPhysCDM_HertzMindlinCDM()

O.engines = [
    ForceResetter(),
    InsertionSortCollider([Bo1_Sphere_Aabb(), Bo1_Facet_Aabb()]),
    InteractionLoop(
        geoms,
        ip2 if isinstance(ip2, list) else [ip2],
        law if isinstance(law, list) else [law],
    ),
    NewtonIntegrator(damping=0.2, gravity=(0, 0, -9.81)),
]
O.dt = 0.5 * PWaveTimeStep()

measure(O, os.environ.get('BENCH_NAME', 'dense_lattice'), len(sphereIds), env_int('BENCH_STEPS', 500),
        env_int('BENCH_WARMUP', 1), t_script)

if dump:
    with open(dump, 'w') as f:
        for i in sphereIds:
            p, w = O.bodies[i].state.pos, O.bodies[i].state.angVel
            f.write(f'{p[0]:.17g} {p[1]:.17g} {p[2]:.17g} {w[0]:.17g} {w[1]:.17g} {w[2]:.17g}\n')
