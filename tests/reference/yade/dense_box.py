# randomDensePack without spheresInCell (YADE 2023.02a): its TriaxialTest in the alternative scene and what it
# returns, for small calls (radius .1 in a unit box: 143 spheres compacted) over seeds, with rRelFuzz, another box,
# cropLayers, a sphere predicate, bodies instead of a SpherePack, and the memoizeDb row; `big` (DENSE_BIG=1) adds
# the 5,000-sphere call of benchmarks/dense_pack.py (radius .0306, seed 1).
# Run: yade -n -x dense_box.py  (writes dense_box.json)
import math
import os
import sqlite3
import sys
import tempfile
sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from _common import dump
from yade import pack, utils


def call(pred, volume, **kw):
    """Statistics of randomDensePack(pred, **kw) and of the compaction it ran (the alternative scene)."""
    s = pack.randomDensePack(pred, returnSpherePack=True, **kw)
    r = [x[1] for x in s]
    out = {'n': len(s), 'rmin': min(r), 'rmax': max(r), 'rmean': sum(r) / len(r),
           'solid': sum(4 / 3 * math.pi * x ** 3 for x in r) / volume, 'center': list(s.center()),
           'isPeriodic': s.isPeriodic}
    O.switchScene()
    rs = [b.shape.radius for b in O.bodies if isinstance(b.shape, Sphere)]
    t = [e for e in O.engines if type(e).__name__ == 'TriaxialCompressionEngine'][0]
    out['compaction'] = {'iter': O.iter, 'spheres': len(rs), 'rmean': sum(rs) / len(rs), 'unbalanced':
                         utils.unbalancedForce(), 'state': t.currentState, 'box0': [t.width0, t.height0, t.depth0],
                         'box': [t.width, t.height, t.depth], 'meanStress': t.meanStress}
    O.switchScene()
    return out


unit = pack.inAlignedBox((0, 0, 0), (1, 1, 1))
out = {}
out['unit'] = [call(unit, 1.0, radius=.1, seed=seed) for seed in range(1, 5)]
out['fuzz'] = [call(unit, 1.0, radius=.1, rRelFuzz=.3, seed=seed) for seed in range(1, 4)]
out['flat'] = call(pack.inAlignedBox((1, 1, 1), (3, 2, 1.5)), 1.0, radius=.08, seed=1)
out['crop'] = call(unit, 1.0, radius=.1, cropLayers=1, seed=1)
out['sphere'] = call(pack.inSphere((0, 0, 0), .6), 4 / 3 * math.pi * .6 ** 3, radius=.1, seed=1)
bodies = pack.randomDensePack(unit, radius=.1, seed=1, returnSpherePack=False, material=FrictMat(young=1e7))
out['bodies'] = {'n': len(bodies), 'types': sorted({type(b.shape).__name__ for b in bodies}),
                 'young': [b.material.young for b in bodies[:2]], 'inScene': len(O.bodies)}
db = os.path.join(tempfile.mkdtemp(), 'memo.sqlite')
pack.randomDensePack(unit, radius=.1, seed=1, returnSpherePack=True, memoizeDb=db)
pack.randomDensePack(unit, radius=.1, seed=1, returnSpherePack=True, memoizeDb=db)
O.switchScene()
out['memo_second_iter'] = O.iter   # YADE 2023.02a compacts again: the stored packing is not reused
O.switchScene()
con = sqlite3.connect(db)
if con.execute("select name from sqlite_master where name = 'packings'").fetchall():   # YADE's table (granum: its own)
    out['memo_rows'] = [list(row) for row in con.execute(
        'select radius, rRelFuzz, dimx, dimy, dimz, N, periodic from packings')]
if os.environ.get('DENSE_BIG'):
    import time
    t0 = time.time()
    out['big'] = call(unit, 1.0, radius=.0306, seed=1)
    out['big']['seconds'] = time.time() - t0
dump('dense_box', out)
