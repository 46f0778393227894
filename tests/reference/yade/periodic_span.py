# periodic_span: which bodies YADE 2023.02a's periodic InsertionSortCollider refuses as wider than half the
# cell ("Body #N spans over half of the cell size"), measured with spheres (verletDist 0 unless said).
# Each case: a periodic cell hSize (rows), spheres (centre, radius) in id order, allowBiggerThanPeriod; five
# O.step() calls: whether a step raised and its message, O.iter, the interactions (ids, cellDist, isReal), and
# each sphere's bound (YADE's bound of a sheared cell is in the cell's unsheared frame).
# Found: only a body that meets a partner of smaller id is checked (a lone body, or the smaller id of a pair,
# may be wider: up to .99 of the cell, where YADE aborts on an assertion, not run here); the span is measured
# along the axes of the unsheared frame, where YADE widens a sphere's box by 1 + g^2/2 for a shear g.
# Regenerate: cd tests/reference/yade && yade -n -x periodic_span.py
import sys; import os; sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from _common import dump, tojson

UNIT = ((1, 0, 0), (0, 1, 0), (0, 0, 1))
SHEAR = ((1, 1, 0), (0, 1, 0), (0, 0, 1))        # hSize[0,1] = 1: 45 degrees, cellFlipping's flip point
SHEAR_Z = ((1, 0, .5), (0, 1, 0), (0, 0, 1))     # hSize[0,2] = .5


def case(name, hsize, spheres, allow=False, verlet=0.0):
    O.reset()
    O.periodic = True
    O.cell.hSize = Matrix3(*[x for row in hsize for x in row])
    O.bodies.append([sphere(c, r) for c, r in spheres])
    O.engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb()], verletDist=verlet,
                                                        allowBiggerThanPeriod=allow),
                 InteractionLoop([Ig2_Sphere_Sphere_ScGeom()], [Ip2_FrictMat_FrictMat_FrictPhys()],
                                 [Law2_ScGeom_FrictPhys_CundallStrack()]),
                 NewtonIntegrator(gravity=(0, 0, 0))]
    O.dt = 1e-6
    out = {'name': name, 'hSize': hsize, 'spheres': spheres, 'allowBiggerThanPeriod': allow,
           'verletDist': verlet, 'raised': False}
    try:
        for _ in range(5):
            O.step()
    except Exception as e:
        out.update(raised=True, message=str(e))
    out.update(iter=O.iter, interactions=[[i.id1, i.id2, tuple(i.cellDist), i.isReal] for i in O.interactions],
               bounds=[[b.bound.min, b.bound.max] if b.bound else None for b in O.bodies])
    return tojson(out)


C = (.5, .5, .5)
data = {'cases': [
    case('lone_wide', UNIT, [(C, .4)]),
    case('wide_first', UNIT, [(C, .4), ((.5, .5, .7), .11)]),
    case('wide_second', UNIT, [(C, .11), ((.5, .5, .7), .4)]),
    case('wide_second_apart', UNIT, [(C, .11), ((.9, .9, .9), .4)]),
    case('both_over_half', UNIT, [(C, .26), ((.5, .5, .7), .26)]),
    case('both_under_half', UNIT, [(C, .24), ((.5, .5, .7), .24)]),
    case('wide_second_allowed', UNIT, [(C, .11), ((.5, .5, .7), .4)], allow=True),
    case('both_over_half_allowed', UNIT, [(C, .26), ((.5, .5, .7), .26)], allow=True),
    case('sheared_narrow', SHEAR, [((.3, .4, .5), .13), ((.55, .45, .5), .13)]),
    case('sheared_narrow_verlet', SHEAR, [((.3, .4, .5), .12), ((.55, .45, .5), .12)], verlet=.01),
    case('sheared_wide', SHEAR, [((.3, .4, .5), .19), ((.6, .45, .5), .19)]),
    case('sheared_z_narrow', SHEAR_Z, [((.3, .4, .5), .2), ((.55, .4, .7), .2)]),
    case('sheared_z_wide', SHEAR_Z, [((.3, .4, .5), .25), ((.55, .4, .7), .25)]),
]}
dump('periodic_span', data)
