# newton_mask: NewtonIntegrator.mask. Three free spheres with masks 1, 0 and 3 under gravity (0, 0, -10),
# dt 0.1, no damping, 3 steps, for mask 0, -1, 2, 1, -2: every sphere's pos and vel.
# Regenerate: cd tests/reference/yade && yade -n -x newton_mask.py
# YADE 2023.02a
import sys; import os; sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from _common import dump

out = {}
for m in (0, -1, 2, 1, -2):
    O.reset()
    O.bodies.append([sphere((0, 0, 0), 1, mask=1), sphere((5, 0, 0), 1, mask=0), sphere((10, 0, 0), 1, mask=3)])
    O.engines = [ForceResetter(), NewtonIntegrator(gravity=(0, 0, -10), damping=0, mask=m)]
    O.dt = 0.1
    O.run(3, True)
    out[str(m)] = [[list(b.state.pos), list(b.state.vel)] for b in O.bodies]
dump('newton_mask', out)
