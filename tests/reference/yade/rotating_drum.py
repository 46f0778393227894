# rotating_drum: benchmarks/rotating_drum.py at 400 spheres with BENCH_EXTRA=1 (a drum read from an STL file, turned by
# RotationEngine + HarmonicMotionEngine, LinearDragEngine on the spheres, FrictMat contacts), 1000 steps after the
# warm-up step: every sphere's pos and angVel, the drum's first facet's pos and ori, the number of contacts.
# Regenerate: cd tests/reference/yade && yade -n -x rotating_drum.py
import os
import sys

HERE = os.path.dirname(os.path.abspath(sys.argv[0]))
sys.path.insert(0, HERE)
import _common  # noqa: E402

os.environ.update(BENCH_N='400', BENCH_STEPS='1000', BENCH_EXTRA='1', BENCH_WARMUP='1')
script = os.path.join(HERE, '..', '..', '..', 'benchmarks', 'rotating_drum.py')
argv = sys.argv
sys.argv = [script]  # the benchmark finds its helpers next to itself
exec(compile(open(script).read(), script, 'exec'))
sys.argv = argv
_common.dump('rotating_drum', {'iter': O.iter, 'contacts': O.interactions.countReal(),
                       'spheres': [[O.bodies[i].state.pos, O.bodies[i].state.angVel] for i in sphereIds],
                       'facet': [O.bodies[drum[0]].state.pos, O.bodies[drum[0]].state.ori]})
