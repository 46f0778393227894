# Benchmark: pack.randomDensePack of about 5,000 spheres in a box (issue #19), the whole call.
#
# randomDensePack(inAlignedBox((0,0,0),(1,1,1)), radius=BENCH_RADIUS (default .0306), seed=1,
# returnSpherePack=True): YADE's aperiodic packing, a TriaxialTest of int(0.6/(4/3 pi r^3)) spheres (4,999 at the
# default radius) in the alternative scene, radii grown to -40 kPa, walls unloaded to -500 Pa, run by 500 steps
# until the unbalanced force is at most .005, then cut to the box (about 1,240 spheres of 1.44 r are returned).
# BENCH_WARMUP=1 (default) first makes an untimed packing of 143 spheres (radius .1): granum's kernels are
# compiled or loaded from its cache there, not in the timed call.
# The row counts one call as one "step": seconds is the call's wall time and steps_per_s its inverse, so the
# table's ratio granum/YADE is YADE's time over granum's. Also prints the spheres returned (`returned`), their
# mean radius, the porosity in the box (1 - their volume over the box's), the compaction's steps (`iter`) and
# the process's CPU time of the call (`cpu_s`, all threads).
# Runs unmodified with `granum -jN dense_pack.py` and `yade -n -x -jN dense_pack.py`.

import math
import os
import resource
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from _bench import env_int  # noqa: E402
from yade import pack  # noqa: E402

t_script = time.perf_counter()
radius = float(os.environ.get('BENCH_RADIUS', '.0306'))
box = pack.inAlignedBox((0, 0, 0), (1, 1, 1))
if env_int('BENCH_WARMUP', 1) > 0:
    pack.randomDensePack(box, radius=.1, seed=1, returnSpherePack=True)
t_setup = time.perf_counter() - t_script
t0, c0 = time.perf_counter(), time.process_time()
sp = pack.randomDensePack(box, radius=radius, seed=1, returnSpherePack=True)
seconds, cpu = time.perf_counter() - t0, time.process_time() - c0
radii = [r for _, r in sp]
O.switchScene()
iters, compacted = O.iter, sum(1 for b in O.bodies if isinstance(b.shape, Sphere))
O.switchScene()
rss_mb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
fields = {'name': 'dense_pack', 'spheres': compacted, 'bodies': compacted + 6, 'steps': 1, 'threads': O.numThreads,
          'seconds': f'{seconds:.6g}', 'steps_per_s': f'{1 / seconds:.6g}',
          'particle_steps_per_s': f'{compacted * iters / seconds:.6g}', 'peak_rss_mb': f'{rss_mb:.1f}',
          'setup_s': f'{t_setup:.3g}', 'total_s': f'{time.perf_counter() - t_script:.6g}', 'cpu_s': f'{cpu:.4g}',
          'iter': iters, 'returned': len(radii), 'rmean': f'{sum(radii) / len(radii):.6g}',
          'porosity': f'{1 - sum(4 / 3 * math.pi * r ** 3 for r in radii):.6g}'}
print('BENCH ' + ' '.join(f'{k}={v}' for k, v in fields.items()))
