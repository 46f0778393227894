# Benchmark: building a scene from Python, as YADE scripts do.
#
# BENCH_N^3 spheres (default 40: 64,000) of dense_lattice.py's lattice, made one by one with utils.sphere() in a
# list comprehension and appended with one O.bodies.append(list). Timed: the two together (`seconds`), and each
# apart (`sphere_s`, `append_s`). "steps" in the BENCH line is the number of spheres built and "steps_per_s"
# spheres per second, so that benchmarks/run's ratio column compares the building speed with YADE's.
# With BENCH_APPEND=each, each sphere is appended as it is made, O.bodies.append(sphere(...)) in the loops, as
# many YADE scripts do (`sphere_s` then holds the whole and `append_s` 0). BENCH_NAME: the name printed.
#
# Runs unmodified with `granum python_build.py` and `yade -n -x python_build.py`.

import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from _bench import env_int  # noqa: E402

n = env_int('BENCH_N', 40)
r = 0.01
s = 2 * r * (1 - 1e-3)
mat = O.materials.append(FrictMat(young=1e8, poisson=0.3, frictionAngle=radians(30), density=2600))
t0 = time.perf_counter()
if os.environ.get('BENCH_APPEND', 'list') == 'each':
    ids = [O.bodies.append(sphere((r + i * s, r + j * s, r + k * s), r, material=mat))
           for k in range(n) for j in range(n) for i in range(n)]
    t1 = time.perf_counter()
else:
    spheres = [sphere((r + i * s, r + j * s, r + k * s), r, material=mat)
               for k in range(n) for j in range(n) for i in range(n)]
    t1 = time.perf_counter()
    ids = O.bodies.append(spheres)
t2 = time.perf_counter()
count = len(ids)
name = os.environ.get('BENCH_NAME', 'python_build')
print(f'BENCH name={name} spheres={count} bodies={len(O.bodies)} steps={count} threads={O.numThreads} '
      f'seconds={t2 - t0:.6g} steps_per_s={count / (t2 - t0):.6g} particle_steps_per_s={count / (t2 - t0):.6g} '
      f'contacts=0 peak_rss_mb=0 sphere_s={t1 - t0:.4g} append_s={t2 - t1:.4g}')
