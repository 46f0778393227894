# mindlin_example: YADE's own example examples/test/mindlin.py (Hertz-Mindlin between a free and a fixed
# sphere pushed together by gravity), run unmodified (exec of its text), then the data it plots
# (plot.data: fn, un, kn, step) and the state of both spheres. granum runs the same file (tests/test_mindlin.py).
# Regenerate: cd tests/reference/yade && xvfb-run -a yade -x mindlin_example.py (the example opens qt views: no -n)
# YADE 2023.02a
import sys; import os; sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from _common import dump

EXAMPLE = '/usr/share/doc/yade/examples/test/mindlin.py'
with open(EXAMPLE) as f:
    exec(compile(f.read(), EXAMPLE, 'exec'))
from yade import plot
dump('mindlin_example', {'data': {k: list(v) for k, v in plot.data.items()}, 'iter': O.iter,
                         'pos': [b.state.pos for b in O.bodies], 'vel': [b.state.vel for b in O.bodies]})
