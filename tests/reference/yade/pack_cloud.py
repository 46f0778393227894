# pack_cloud: SpherePack.makeCloud with a seed, sphere by sphere (centre, radius) and the return value,
# for each way of giving the sizes: rMean and rRelFuzz with and without num, a periodic box, a 2D box,
# too many spheres for the box (YADE stops and warns), porosity with num (the triax tutorial's call, and
# one where YADE retries with a higher porosity), a psd by number and by mass, with and without num.
# Regenerate: cd tests/reference/yade && yade -n -x pack_cloud.py
# YADE 2023.02a
import sys; import os; sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from _common import catch, dump
from yade import pack

CASES = {
    'fuzz_num4': dict(minCorner=(0, 0, 0), maxCorner=(1, 1, 1), rMean=.1, rRelFuzz=.5, num=4, seed=1),
    'fuzz_no_num': dict(minCorner=(0, 0, 0), maxCorner=(1, 1, 1), rMean=.1, rRelFuzz=.5, seed=1),
    'mono_num20_seed3': dict(minCorner=(0, 0, 0), maxCorner=(1, 1, 1), rMean=.1, rRelFuzz=0, num=20, seed=3),
    'periodic': dict(minCorner=(0, 0, 0), maxCorner=(1, 1, 1), rMean=.1, rRelFuzz=.2, num=10, periodic=True, seed=1),
    'flat_2d': dict(minCorner=(0, 0, 0), maxCorner=(1, 1, 0), rMean=.05, rRelFuzz=.2, num=30, seed=5),
    'offset_box': dict(minCorner=(-1, 2, -.5), maxCorner=(0, 2.5, .5), rMean=.04, rRelFuzz=.1, num=40, seed=7),
    'too_many': dict(minCorner=(0, 0, 0), maxCorner=(1, 1, 1), rMean=.15, rRelFuzz=0, num=50, seed=1),
    'porosity_tutorial': dict(minCorner=(0, 0, 0), maxCorner=(1, 1, 1), rMean=-1, rRelFuzz=.3333, num=1000,
                              periodic=False, porosity=.95, seed=1),
    'porosity_retries': dict(minCorner=(0, 0, 0), maxCorner=(1, 1, 1), rMean=-1, rRelFuzz=.2, num=200,
                             porosity=.5, seed=1),
    'psd_num': dict(minCorner=(0, 0, 0), maxCorner=(1, 1, 1), psdSizes=[.05, .1, .2], psdCumm=[0, .5, 1], num=30,
                    seed=1),
    'psd_no_num': dict(minCorner=(0, 0, 0), maxCorner=(1, 1, 1), psdSizes=[.05, .1, .2], psdCumm=[0, .5, 1], seed=1),
    'psd_mass_num': dict(minCorner=(0, 0, 0), maxCorner=(1, 1, 1), psdSizes=[.05, .1, .2], psdCumm=[0, .5, 1],
                         num=30, distributeMass=True, seed=2),
}


def cloud(kw):
    sp = pack.SpherePack()
    returned = sp.makeCloud(**kw)
    return {'kwargs': kw, 'returned': returned, 'spheres': [[list(c), r] for c, r in sp],
            'appliedPsdScaling': sp.appliedPsdScaling}


dump('pack_cloud', {name: catch(lambda kw=kw: cloud(kw)) for name, kw in CASES.items()})
