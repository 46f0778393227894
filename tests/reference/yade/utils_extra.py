# Reference values for granum's tests/test_utils_extra.py: yade.utils measures and edits missing before,
# yade.bodiesHandling, yade.linterpolation and yade.post2d (AxisFlatten; YADE 2023.02a's Cylinder/HelixFlatten
# fail with NameError). Run: yade -n -x utils_extra.py
import math
from yade import utils, post2d, linterpolation as L, bodiesHandling as BH
import sys; import os; sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from _common import catch, dump

out = {}
O.materials.append(FrictMat(young=1e7, poisson=.3, density=2000, frictionAngle=.5))
O.bodies.append([sphere((0, 0, 0), .5), sphere((0.95, 0, 0), .5), sphere((0, 0.9, 0.1), .4), sphere((3, 0, 0), .3, fixed=True),
                 facet([(-1, -1.3, -0.45), (2, -1, -0.35), (0, 2, -0.4)]),
                 box((5, 5, 5), (.1, .2, .3), orientation=Quaternion((1, 1, 0), .3))])
vels = {0: (1, 2, 3), 1: (-1, 0, .5), 3: (7, 0, 0), 5: (0, 1, 0)}
for i, v in vels.items():
    O.bodies[i].state.vel = v
O.bodies[0].state.angVel = (.1, .2, .3)
O.bodies[2].state.angVel = (0, 0, 1)
O.bodies[5].state.angMom = (1, 2, 3)
O.bodies[1].mask = 3
out['scene_before'] = {'momentum': catch(utils.momentum), 'angularMomentum': catch(utils.angularMomentum),
                       'angularMomentum_123': catch(lambda: utils.angularMomentum((1, 2, 3)))}
O.engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb(), Bo1_Facet_Aabb(), Bo1_Box_Aabb()]),
             InteractionLoop([Ig2_Sphere_Sphere_ScGeom(), Ig2_Facet_Sphere_ScGeom()], [Ip2_FrictMat_FrictMat_FrictPhys()],
                             [Law2_ScGeom_FrictPhys_CundallStrack()]),
             NewtonIntegrator(gravity=(0, 0, -10), damping=0)]
O.dt = 1e-4
O.step()
out['interactions'] = [[i.id1, i.id2] for i in O.interactions]
out['forces'] = {b.id: [O.forces.f(b.id), O.forces.t(b.id)] for b in O.bodies}
out['after_step'] = {
    'momentum': catch(utils.momentum), 'angularMomentum': catch(utils.angularMomentum),
    'angularMomentum_123': catch(lambda: utils.angularMomentum((1, 2, 3))),
    'aabbDim': catch(utils.aabbDim), 'aabbDim_cut_centers': catch(lambda: utils.aabbDim(.1, True)),
    'fractionalBox': catch(utils.fractionalBox), 'fractionalBox_half': catch(lambda: utils.fractionalBox(.5)),
    'fractionalBox_given': catch(lambda: utils.fractionalBox(.5, ((0, 0, 0), (1, 2, 3)))),
    'perpendicularArea': [catch(lambda: utils.perpendicularArea(a)) for a in range(3)],
    'sumFacetNormalForces': {str(a): catch(lambda: utils.sumFacetNormalForces([4], a)) for a in (-1, 0, 1, 2)},
    'forcesOnPlane_x': catch(lambda: utils.forcesOnPlane((0.5, 0, 0), (1, 0, 0))),
    'forcesOnPlane_minus2x': catch(lambda: utils.forcesOnPlane((0.5, 0, 0), (-2, 0, 0))),
    'forcesOnPlane_z': catch(lambda: utils.forcesOnPlane((0, 0, -0.3), (0, 0, 1))),
    'forcesOnCoordPlane_x': catch(lambda: utils.forcesOnCoordPlane(0.5, 0)),
    'forcesOnCoordPlane_y': catch(lambda: utils.forcesOnCoordPlane(0.5, 1)),
    'maxOverlapRatio': catch(utils.maxOverlapRatio),
    'psd': catch(utils.psd), 'psd_count3': catch(lambda: utils.psd(bins=3, mass=False)),
    'psd_mask2': catch(lambda: utils.psd(mask=2)),
    'sumTorques': catch(lambda: utils.sumTorques([0, 1], (0, 2, 0), (1, 0, 0))),
    'numIntrsOfEachBody': catch(utils.numIntrsOfEachBody),
    'negPosExtremeIds_x': catch(lambda: utils.negPosExtremeIds(0, 1.0)),
    'getSpheresVolume2D': catch(utils.getSpheresVolume2D),
    'spheresPackDimensions_01': catch(lambda: BH.spheresPackDimensions([0, 1])),
    'spheresPackDimensions_mask2': catch(lambda: BH.spheresPackDimensions([0, 1, 2, 3], mask=2)),
    'spheresPackDimensions_23': catch(lambda: BH.spheresPackDimensions([O.bodies[2], O.bodies[3]])),
    'spheresPackDimensions_04': catch(lambda: BH.spheresPackDimensions([0, 4])),
    'spheresPackDimensions_empty': catch(lambda: BH.spheresPackDimensions([])),
    'facetsDimensions_4': catch(lambda: BH.facetsDimensions([4])),
}
raw = lambda: post2d.data(lambda b: b.state.vel[0], post2d.AxisFlatten(False, 2))
out['post2d'] = {
    'raw_scalar': catch(raw),
    'raw_all': catch(lambda: post2d.data(lambda b: b.state.vel[0], post2d.AxisFlatten(False, 1), onlyDynamic=False)),
    'raw_vector_ref': catch(lambda: post2d.data(lambda b: b.state.vel, post2d.AxisFlatten(True, 0))),
}
for name, kw in (('smooth', {}), ('smooth_margin', {'margin': (.5, .2)}), ('smooth_thresh1', {'relThreshold': 1.}),
                 ('smooth_perArea2', {'perArea': 2})):
    d = post2d.data(lambda b: b.state.vel[0], post2d.AxisFlatten(False, 2), stDev=.5, div=(3, 4), **kw)
    out['post2d'][name] = {k: (v.tolist() if hasattr(v, 'tolist') else v) for k, v in d.items() if k != 'grid'}
d = post2d.data(lambda b: b.state.vel, post2d.AxisFlatten(False, 2), stDev=.5, div=(3, 4))
out['post2d']['smooth_vector'] = {k: (v.tolist() if hasattr(v, 'tolist') else v) for k, v in d.items() if not k.startswith('grid')}
out['modify'] = {'spheresModify': catch(lambda: BH.spheresModify([0, 1], shift=(1, 2, 3), scale=2.0,
                                                                  orientation=Quaternion((0, 0, 1), math.pi / 2)))}
out['modify']['bodies'] = {i: {'pos': O.bodies[i].state.pos, 'radius': O.bodies[i].shape.radius, 'mass': O.bodies[i].state.mass,
                              'inertia': O.bodies[i].state.inertia} for i in (0, 1, 2)}
copies = BH.spheresModify([2], shift=(1, 0, 0), scale=.5, copy=True)
out['modify']['copies'] = [{'id': b.id, 'pos': b.state.pos, 'radius': b.shape.radius, 'mass': b.state.mass,
                            'inertia': b.state.inertia, 'mask': b.mask} for b in copies]
out['modify']['mask2_shift'] = catch(lambda: BH.spheresModify(mask=2, shift=(0, 0, 1)))
out['modify']['pos_after_mask2'] = [O.bodies[i].state.pos for i in range(4)]
dup = BH.sphereDuplicate(3)
out['modify']['sphereDuplicate'] = {'id': dup.id, 'pos': dup.state.pos, 'radius': dup.shape.radius, 'mass': dup.state.mass,
                                    'dynamic': dup.dynamic, 'blockedDOFs': dup.state.blockedDOFs, 'count': len(O.bodies)}
out['modify']['sphereDuplicate_facet'] = catch(lambda: BH.sphereDuplicate(4))
utils.calm(2)
out['calm_mask2'] = [[O.bodies[i].state.vel, O.bodies[i].state.angVel] for i in range(3)]
utils.calm()
out['calm_all'] = [[b.state.vel, b.state.angVel, b.state.angMom] for b in O.bodies]
out['pure'] = {
    'inscribedCircleCenter': catch(lambda: utils.inscribedCircleCenter((0, 0, 0), (1, 0, 0), (0, 1, 0))),
    'inscribedCircleCenter_2': catch(lambda: utils.inscribedCircleCenter((1, 2, 3), (4, -1, 0), (0, 0, 5))),
    'ptInAABB': [catch(lambda: utils.ptInAABB(p, (-1, -1, -1), (1, 1, 1))) for p in ((0, 0, 0), (0, 0, 2), (1, 1, 1), (-1, 0, 0))],
    'spher2cart': catch(lambda: utils.spher2cart((2, .3, .4))),
    'cart2spher': [catch(lambda: utils.cart2spher(p)) for p in ((1, -2, 3), (0, 0, 0), (-1, -1, 0))],
    'aabbExtrema2d': catch(lambda: utils.aabbExtrema2d([(0, 1), (2, -1), (1, 5)])),
    'xMirror': [catch(lambda: utils.xMirror(h)) for h in ([(0, 1), (1, 2), (2, 0)], [(1, 1), (1, 2), (2, 3)], [(1, 1), (0, 0)])],
    'getViscoelasticFromSpheresInteraction': catch(lambda: utils.getViscoelasticFromSpheresInteraction(1e-3, .5, .6)),
    'typedEngine_missing': catch(lambda: utils.typedEngine('Foo')),
}
x, y = [0, 1, 3, 4], [2, 4, 0, 1]
out['linterpolation'] = {
    'integral': catch(lambda: L.integral(x, y)), 'integral_one': catch(lambda: L.integral([0], [1])),
    'revIntegrateLinear': [catch(lambda: L.revIntegrateLinear(*a)) for a in ((2.5, 0, 2, 1, 4), (1, 0, 2, 1, 2), (1, 1, 4, 3, 0), (10, 0, 2, 1, 4))],
    'xFractionalFromIntegral': [catch(lambda: L.xFractionalFromIntegral(v, x, y)) for v in (4.5, 0, 100, 1)],
    'xFromIntegral': [catch(lambda: L.xFromIntegral(v, x, y)) for v in (4.5, 10, 25, 7.5)],
    'sanitizeInterpolation': [catch(lambda: L.sanitizeInterpolation([1, 2, 3], [5, 6, 7], *a)) for a in ((0, 4), (1, 3), (1.5, 5), (0, 2))],
}
dump('utils_extra', out)
