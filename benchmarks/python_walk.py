# Benchmark: walking O.interactions and O.bodies from Python, as PyRunners do.
#
# The scene is dense_lattice.py's (BENCH_N, default 46: 97,336 spheres and about 290,000 contacts), run for
# BENCH_STEPS (default 2) steps so that every contact is real. Then, timed:
#   sum(i.phys.normalForce.norm() for i in O.interactions)
# (the walk of the issue: every real interaction, its physics, a vector read and its norm) and, for the
# record, sum(b.state.pos[2] for b in O.bodies) (walk_bodies_s) and the coordination numbers the way YADE's
# scripts count them, sum(len(b.intrs()) for b in O.bodies) (walk_intrs_s).
# "steps" in the BENCH line is the number of interactions walked and "steps_per_s" interactions per second,
# so that benchmarks/run's ratio column compares the walk's speed with YADE's.
#
# Runs unmodified with `granum python_walk.py` and `yade -n -x python_walk.py`.

import os
import sys
import time

os.environ.setdefault('BENCH_N', '46')
os.environ.setdefault('BENCH_STEPS', '2')
here = os.path.dirname(os.path.abspath(sys.argv[0]))
with open(os.path.join(here, 'dense_lattice.py')) as f:
    exec(compile(f.read(), os.path.join(here, 'dense_lattice.py'), 'exec'))

t0 = time.perf_counter()
count, total = 0, 0.0
for i in O.interactions:
    total += i.phys.normalForce.norm()
    count += 1
walk = time.perf_counter() - t0
t0 = time.perf_counter()
z = sum(b.state.pos[2] for b in O.bodies)
walk_bodies = time.perf_counter() - t0
t0 = time.perf_counter()
ends = sum(len(b.intrs()) for b in O.bodies)
walk_intrs = time.perf_counter() - t0
print(f'BENCH name=python_walk spheres={n ** 3} bodies={len(O.bodies)} steps={count} threads={O.numThreads} '
      f'seconds={walk:.6g} steps_per_s={count / walk:.6g} particle_steps_per_s={count / walk:.6g} '
      f'contacts={count} peak_rss_mb=0 walk_bodies_s={walk_bodies:.4g} walk_intrs_s={walk_intrs:.4g} '
      f'sum_fn={total:.10g} sum_z={z:.10g} contact_ends={ends}')
