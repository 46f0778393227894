# Dense packings and SpherePack statistics (YADE 2023.02a): psd, cellRepeat/cellFill, relDensity, makeCloud in
# a sheared cell, randomPeriPack, randomDensePack (periodic and aperiodic) statistics over seeds.
# Run: yade -n -x pack_dense.py  (writes pack_dense.json)
import math
import os
import sys
sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from _common import catch, dump
from yade import pack
import numpy as np

out = {}
sp = pack.SpherePack([((0, 0, 0), .1), ((1, 0, 0), .2), ((0, 1, 0), .3), ((0, 0, 1), .4), ((1, 1, 1), .25)])
out['psd'] = {'mass5': sp.psd(bins=5), 'count5': sp.psd(bins=5, mass=False), 'mass1': sp.psd(bins=1),
              'default': sp.psd(), 'empty': pack.SpherePack().psd()}
out['relDensity'] = sp.relDensity()
out['cellFill_aperiodic'] = catch(lambda: sp.cellFill((3, 3, 3)))
out['cellRepeat_aperiodic'] = catch(lambda: sp.cellRepeat((2, 2, 2)))
two = [((0.1, 0.2, 0.3), .1), ((0.6, 0.5, 0.4), .2)]
p = pack.SpherePack(two)
p.cellSize = (1, 1, 1)
out['relDensity_periodic'] = p.relDensity()
p.cellRepeat((2, 1, 3))
out['cellRepeat'] = {'list': [(tuple(c), r) for c, r in p], 'cellSize': p.cellSize}
p = pack.SpherePack(two)
p.cellSize = (1, 1, 1)
p.cellFill((2.5, 1, .5))
out['cellFill'] = {'list': [(tuple(c), r) for c, r in p], 'cellSize': p.cellSize}
out['cellRepeat_zero'] = catch(lambda: p.cellRepeat((0, 1, 1)))

# makeCloud in the sheared cell of examples/PeriodicBoundaries/periodic-triax-settingHsize.py
H = Matrix3(1.0, -0.15, -0.10, -0.2, 1.5, 0.3, 0.3, -0.3, 1.0)
Hn = np.array([[H[i, j] for j in range(3)] for i in range(3)])
sheared = []
for seed in range(4):
    s = pack.SpherePack()
    n = s.makeCloud(hSize=H, rMean=-0.01, rRelFuzz=.2, num=500, periodic=True, porosity=0.52, distributeMass=False,
                    seed=seed)
    c = np.array([tuple(x) for x, r in s])
    r = np.array([r for x, r in s])
    f = np.linalg.solve(Hn, c.T).T
    sheared.append({'n': n, 'len': len(s), 'cellSize': s.cellSize, 'isPeriodic': s.isPeriodic,
                    'frac_min': f.min(0).tolist(), 'frac_max': f.max(0).tolist(), 'rmin': r.min(), 'rmax': r.max(),
                    'solid': float((4 / 3 * np.pi * r ** 3).sum() / np.linalg.det(Hn))})
out['makeCloud_sheared'] = sheared


def stats(s, volume):
    r = np.array([r for x, r in s])
    return {'n': len(s), 'rmin': r.min(), 'rmax': r.max(), 'solid': float((4 / 3 * np.pi * r ** 3).sum() / volume),
            'cellSize': s.cellSize, 'isPeriodic': s.isPeriodic}


peri = []
for seed in range(1, 4):
    s = pack.randomPeriPack(radius=.05, initSize=Vector3(1.2, 1.2, 1.2), seed=seed)
    st = stats(s, np.prod(list(s.cellSize)))
    O.switchScene()
    st['iter'] = O.iter
    O.switchScene()
    peri.append(st)
out['randomPeriPack'] = peri
cell = []
for seed in range(1, 4):
    s = pack.randomDensePack(pack.inAlignedBox((0, 0, 0), (1, 1, 1)), radius=.05, spheresInCell=300,
                             returnSpherePack=True, seed=seed)
    st = stats(s, 1.0)
    O.switchScene()
    st['iter'], st['cell'] = O.iter, O.cell.size
    O.switchScene()
    cell.append(st)
out['randomDensePack_cell'] = cell
box = []
for seed in range(1, 3):
    s = pack.randomDensePack(pack.inAlignedBox((0, 0, 0), (1, 1, 1)), radius=.05, returnSpherePack=True, seed=seed)
    box.append(stats(s, 1.0))
out['randomDensePack_box'] = box
# small ones (what the tests run): radius .1
small = {'peri': [], 'cell': [], 'box': []}
for seed in range(1, 4):
    s = pack.randomPeriPack(radius=.1, initSize=Vector3(1.2, 1.2, 1.2), seed=seed)
    small['peri'].append(stats(s, np.prod(list(s.cellSize))))
    s = pack.randomDensePack(pack.inAlignedBox((0, 0, 0), (1, 1, 1)), radius=.1, spheresInCell=100,
                             returnSpherePack=True, seed=seed)
    small['cell'].append(stats(s, 1.0))
    s = pack.randomDensePack(pack.inAlignedBox((0, 0, 0), (1, 1, 1)), radius=.1, rRelFuzz=.2, returnSpherePack=True,
                             seed=seed)
    small['box'].append(stats(s, 1.0))
out['small'] = small
out['infinite'] = catch(lambda: pack.randomDensePack(pack.inSpace(), radius=.1, returnSpherePack=True))
dump('pack_dense', out)
