# Benchmark: a rotating drum.
#
# About BENCH_N spheres (r = 0.01, on a simple cubic lattice of spacing 2r(1 - 1e-3), so that neighbours touch,
# filling the lower half of the drum up to the wall) in a drum read from an STL file by ymport.stl (a closed
# cylinder of radius R, length 0.3 along y, 48 segments; the script writes the file, ASCII, so that granum and YADE
# read the same mesh), turned by a RotationEngine about its axis (1 rad/s, rotateAroundZero).
# FrictMat (E=1e7, nu=0.3, 30 deg, 2600 kg/m^3), Cundall-Strack, NewtonIntegrator(damping=0.2, gravity -z),
# O.dt = 0.5*PWaveTimeStep(). R is chosen so that the half-lattice holds about BENCH_N spheres (at 5,000:
# R = 0.32 m, at 10,000: 0.45 m); they are in contact from the first step and the drum drags them round.
# BENCH_EXTRA=1 also runs the engines of issue #21 that make sense here: the drum's rotation combined with a
# HarmonicMotionEngine shaking it vertically (RotationEngine + HarmonicMotionEngine), and a LinearDragEngine
# (nu=0.05) on the spheres.
#
# Runs unmodified with `granum -jN rotating_drum.py` and `yade -n -x -jN rotating_drum.py`.
# Environment: BENCH_N (default 5000), BENCH_STEPS (default 1000) timed steps, BENCH_WARMUP (default 1),
# BENCH_EXTRA, BENCH_DUMP=path (the spheres' positions and angular velocities after the run, "x y z wx wy wz"
# per sphere, %.17g: bitwise determinism across thread counts).
# Prints one line:  BENCH name=rotating_drum ...

import math
import os
import sys
import tempfile
import time

from yade import ymport

sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from _bench import env_int, measure  # noqa: E402

t_script = time.perf_counter()
n_target = env_int('BENCH_N', 5000)
extra = os.environ.get('BENCH_EXTRA', '') == '1'
dump = os.environ.get('BENCH_DUMP', '')

r, length = 0.01, 0.3
s = 2 * r * (1 - 1e-3)
# a lattice of spacing s fills the lower half of the cylinder of radius R - r and length - 4r with about N spheres
inner = math.sqrt(2 * n_target * s ** 3 / (math.pi * (length - 4 * r)))
R = inner + r
mat = O.materials.append(FrictMat(young=1e7, poisson=0.3, frictionAngle=math.radians(30), density=2600))
m = int(inner / s)
ny = int((length - 4 * r) / s)
spheres = [sphere((i * s, (j - (ny - 1) / 2) * s, k * s), r, material=mat)
           for k in range(-m, 1) for j in range(ny) for i in range(-m, m + 1)
           if math.hypot(i * s, k * s) <= inner]
sphereIds = O.bodies.append(spheres)


def drum_triangles(radius, half_length, segments):
    """The closed cylinder about y: two triangles per side segment and a fan per end, as vertex triples."""
    rim = [(radius * math.cos(2 * math.pi * k / segments), radius * math.sin(2 * math.pi * k / segments))
           for k in range(segments + 1)]
    for (x0, z0), (x1, z1) in zip(rim[:-1], rim[1:], strict=True):
        a, b = (x0, -half_length, z0), (x1, -half_length, z1)
        c, d = (x1, half_length, z1), (x0, half_length, z0)
        yield from ((a, b, c), (a, c, d), ((0, -half_length, 0), b, a), ((0, half_length, 0), d, c))


with tempfile.NamedTemporaryFile('w', suffix='.stl', delete=False) as stl_file:
    stl_file.write('solid drum\n')
    for triangle in drum_triangles(R, length / 2, 48):
        stl_file.write('facet normal 0 0 0\nouter loop\n')
        stl_file.writelines(f'vertex {x!r} {y!r} {z!r}\n' for x, y, z in triangle)
        stl_file.write('endloop\nendfacet\n')
    stl_file.write('endsolid drum\n')
drum = O.bodies.append(ymport.stl(stl_file.name, material=mat))
os.unlink(stl_file.name)

turn = RotationEngine(ids=drum, rotationAxis=(0, 1, 0), angularVelocity=1.0, rotateAroundZero=True,
                      zeroPoint=(0, 0, 0))
engines = [turn + HarmonicMotionEngine(A=(0, 0, 0.002), f=(0, 0, 5))] if extra else [turn]
if extra:
    engines.append(LinearDragEngine(ids=sphereIds, nu=0.05))
O.engines = [
    ForceResetter(),
    InsertionSortCollider([Bo1_Sphere_Aabb(), Bo1_Facet_Aabb()]),
    InteractionLoop(
        [Ig2_Sphere_Sphere_ScGeom(), Ig2_Facet_Sphere_ScGeom()],
        [Ip2_FrictMat_FrictMat_FrictPhys()],
        [Law2_ScGeom_FrictPhys_CundallStrack()],
    ),
] + engines + [NewtonIntegrator(damping=0.2, gravity=(0, 0, -9.81))]
O.dt = 0.5 * PWaveTimeStep()

measure(O, 'rotating_drum', len(sphereIds), env_int('BENCH_STEPS', 1000), env_int('BENCH_WARMUP', 1), t_script)

if dump:
    with open(dump, 'w') as f:
        for i in sphereIds:
            p, w = O.bodies[i].state.pos, O.bodies[i].state.angVel
            f.write(f'{p[0]:.17g} {p[1]:.17g} {p[2]:.17g} {w[0]:.17g} {w[1]:.17g} {w[2]:.17g}\n')
