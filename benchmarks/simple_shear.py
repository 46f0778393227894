# Benchmark: the simple-shear box of YADE's KinemSimpleShearBox engines.
#
# The six boxes of YADE's SimpleShear preprocessor (length .1, height .02, width .04, thickness .001; lateral boxes
# frictionless) around BENCH_N spheres (default 3000) from makeCloud((0,0,-.02), (.1,.02,.02), rMean=BENCH_R
# (default .0011), rRelFuzz=.15, seed=1): as many as fit. FrictMat (E=4e8, nu=.04, 37 deg, 2600 kg/m3),
# Cundall-Strack, NewtonIntegrator(damping=.2), O.dt = .5 PWaveTimeStep().
# Untimed: BENCH_CONFINE steps (default 3000) of KinemCTDEngine (compSpeed 5 m/s, targetSigma 100 kPa).
# Timed: BENCH_STEPS steps (default 2000) of KinemCNLEngine (shearSpeed .5 m/s) under the normal force reached.
#
# Runs unmodified with `granum -jN simple_shear.py` and `yade -n -x -jN simple_shear.py`.
# Prints one line:  BENCH name=simple_shear ... sigma=... tau=... gamma=... (the normal and shear stress on the top
# box [kPa] and its horizontal displacement [m] at the end)

import glob
import os
import sys
import time

from yade import pack

sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from _bench import env_int, measure  # noqa: E402

t_script = time.perf_counter()
L, H, W, t = 0.1, 0.02, 0.04, 0.001
wall = O.materials.append(FrictMat(young=4e8, poisson=.04, frictionAngle=0, density=1000))
grain = O.materials.append(FrictMat(young=4e8, poisson=.04, frictionAngle=radians(37), density=2600))
O.bodies.append([box(c, e, fixed=True, material=m) for c, e, m in [
    ((-t / 2, H / 2, 0), (t / 2, 2.5 * H + 5 * t, W / 2), wall),
    ((L / 2, -t / 2, 0), (L / 2, t / 2, W / 2), grain),
    ((L + t / 2, H / 2, 0), (t / 2, 2.5 * H + 5 * t, W / 2), wall),
    ((L / 2, H + t / 2, 0), (L / 2, t / 2, W / 2), grain),
    ((L / 2, H / 2, -W / 2 - t / 2), (1.25 * L, H / 2 + t, t / 2), wall),
    ((L / 2, H / 2, W / 2 + t / 2), (1.25 * L, H / 2 + t, t / 2), wall)]])
sp = pack.SpherePack()
sp.makeCloud((0, 0, -W / 2), (L, H, W / 2), rMean=float(os.environ.get('BENCH_R', '.0011')), rRelFuzz=.15,
             num=env_int('BENCH_N', 3000), seed=1)
sphereIds = O.bodies.append([sphere(c, r, material=grain) for c, r in sp])
O.engines = [
    ForceResetter(),
    InsertionSortCollider([Bo1_Sphere_Aabb(), Bo1_Box_Aabb()]),
    InteractionLoop([Ig2_Sphere_Sphere_ScGeom(), Ig2_Box_Sphere_ScGeom()], [Ip2_FrictMat_FrictMat_FrictPhys()],
                    [Law2_ScGeom_FrictPhys_CundallStrack()]),
    NewtonIntegrator(damping=.2),
    KinemCTDEngine(compSpeed=5.0, targetSigma=100.0),
]
O.dt = .5 * PWaveTimeStep()
O.run(env_int('BENCH_CONFINE', 3000), True)
for f in glob.glob('Sigmax_*kPaReached.xml'):  # the save at targetSigma
    os.remove(f)
shear = KinemCNLEngine(shearSpeed=0.5, gammalim=0.01)
O.engines = O.engines[:-1] + [shear]

measure(O, 'simple_shear', len(sphereIds), env_int('BENCH_STEPS', 2000), env_int('BENCH_WARMUP', 1), t_script,
        extra=lambda: {'sigma': f'{O.forces.f(3)[1] / (L * W) / 1000:.6g}',
                       'tau': f'{O.forces.f(3)[0] / (L * W) / 1000:.6g}', 'gamma': f'{shear.gamma:.6g}'})
