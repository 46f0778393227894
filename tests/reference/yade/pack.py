# pack: counts, extents and first centres produced by pack.regularOrtho /
# pack.regularHexa with inAlignedBox / inSphere / inCylinder predicates, and
# SpherePack.makeCloud (counts over seeds, rMean=-1 with num, container protocol).
# Regenerate: cd tests/reference/yade && yade -n -x pack.py
# YADE 2023.02a
import sys; import os; sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from _common import catch, dump
from yade import pack


def summarize_bodies(bodies):
    c = [b.state.pos for b in bodies]
    r = [b.shape.radius for b in bodies]
    return {'count': len(bodies),
            'min_corner': [min(p[k] - ri for p, ri in zip(c, r)) for k in range(3)],
            'max_corner': [max(p[k] + ri for p, ri in zip(c, r)) for k in range(3)],
            'centre_min': [min(p[k] for p in c) for k in range(3)],
            'centre_max': [max(p[k] for p in c) for k in range(3)],
            'centre_sum': [sum(p[k] for p in c) for k in range(3)],
            'radii_min_max': [min(r), max(r)] if r else None,
            'first5_centres': c[:5], 'first5_radii': r[:5],
            'distinct_x_count': len(set(round(p[0], 9) for p in c)),
            'body_class_dynamic_mask': [type(bodies[0].shape).__name__, bodies[0].dynamic, bodies[0].mask] if bodies else None}

out = {}
R = .5 / 23.658
cases = {
    'regularOrtho(inAlignedBox((0,0,0),(1,1,1)),radius=.05,gap=0)':
        lambda: pack.regularOrtho(pack.inAlignedBox((0, 0, 0), (1, 1, 1)), radius=.05, gap=0),
    'regularHexa(inSphere((0,0,0),.5),radius=.5/23.658,gap=.5*.5/23.658)':
        lambda: pack.regularHexa(pack.inSphere((0, 0, 0), .5), radius=R, gap=.5 * R),
    'regularHexa(inCylinder((0,0,0),(0,0,1),.5),radius=.05,gap=0)':
        lambda: pack.regularHexa(pack.inCylinder((0, 0, 0), (0, 0, 1), .5), radius=.05, gap=0),
    'regularHexa(inAlignedBox((0,0,0),(1,1,1)),radius=.05,gap=0)':
        lambda: pack.regularHexa(pack.inAlignedBox((0, 0, 0), (1, 1, 1)), radius=.05, gap=0),
}
for name, f in cases.items():
    out[name] = catch(lambda: summarize_bodies(f()))

def cloud(**kw):
    sp = pack.SpherePack()
    n = sp.makeCloud((0, 0, 0), (1, 1, 1), **kw)
    rs = [r for c, r in sp]
    return sp, {'returned': n, 'len': len(sp), 'rmin': min(rs), 'rmax': max(rs), 'rmean': sum(rs) / len(rs),
                'spheres_volume': sum(4 / 3. * 3.141592653589793 * r ** 3 for r in rs), 'first3': sp.toList()[:3]}

out['makeCloud(rMean=.05,rRelFuzz=.5,seed=s)'] = {s: catch(lambda: cloud(rMean=.05, rRelFuzz=.5, seed=s)[1])
                                                   for s in range(1, 6)}
out['makeCloud(rMean=.05,rRelFuzz=.5) default seed, two calls'] = [
    catch(lambda: cloud(rMean=.05, rRelFuzz=.5)[1]) for _ in range(2)]
out['makeCloud(rMean=-1,num=100,seed=1)'] = catch(lambda: cloud(rMean=-1, num=100, seed=1)[1])
out['makeCloud(rMean=-1,num=100,rRelFuzz=.3,seed=1)'] = catch(lambda: cloud(rMean=-1, num=100, rRelFuzz=.3, seed=1)[1])
out['makeCloud(rMean=-1,num=100,porosity=.5,seed=1)'] = catch(lambda: cloud(rMean=-1, num=100, porosity=.5, seed=1)[1])
out['makeCloud(rMean=.1,num=20,rRelFuzz=.3,seed=1)'] = catch(lambda: cloud(rMean=.1, num=20, rRelFuzz=.3, seed=1)[1])
out['makeCloud(rMean=.2,num=1000,seed=1) (cannot fit)'] = catch(lambda: cloud(rMean=.2, num=1000, seed=1)[1])

sp, _ = cloud(rMean=.1, num=20, rRelFuzz=.3, seed=1)
it = iter(sp)
first = next(it)
out['SpherePack protocol'] = {
    'len(sp)': len(sp),
    'type(sp.toList())': type(sp.toList()).__name__,
    'sp.toList()[0]': sp.toList()[0],
    'type(sp.toList()[0])': type(sp.toList()[0]).__name__,
    'types inside toList()[0]': [type(x).__name__ for x in sp.toList()[0]],
    'next(iter(sp))': first, 'type(next(iter(sp)))': type(first).__name__,
    'sp[0]': catch(lambda: sp[0]),
    'sp.aabb()': catch(lambda: sp.aabb()),
    'sp.dim()': catch(lambda: sp.dim()),
    'sp.center()': catch(lambda: sp.center()),
    'sp.relDensity()': catch(lambda: sp.relDensity()),
    'sp.psd()': catch(lambda: sp.psd()),
    'sp.isPeriodic': catch(lambda: sp.isPeriodic),
    'sp.cellSize': catch(lambda: sp.cellSize),
}
ids = sp.toSimulation()
out['SpherePack protocol']['toSimulation() ids'] = ids
out['SpherePack protocol']['body0 after toSimulation'] = {
    'pos': O.bodies[0].state.pos, 'radius': O.bodies[0].shape.radius, 'mass': O.bodies[0].state.mass,
    'material': type(O.bodies[0].material).__name__, 'material_dict': O.bodies[0].material.dict()}
dump('pack', out)
