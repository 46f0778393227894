# Reference data for the triaxial engines and TriaxialTest (YADE 2023.02a): run `yade -n -x triaxial_engines.py`.
# defaults: .dict() of fresh TriaxialCompressionEngine, ThreeDTriaxialEngine, UniaxialStrainer, TriaxialTest.
# triaxial_test: TriaxialTest(numberOfGrains=200).load() and the radiusMean case: walls, sorted radii, dt, engines.
# strainer: 4 spheres, UniaxialStrainer per step (velocities, positions, strain, avgStress) for several options.
# voxel: voxelPorosity of one sphere; total_force: totalForceInVolume of three overlapping spheres.
import sys; import os
sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from _common import tojson, catch, dump

out = {'defaults': {n: tojson(eval(n)().dict()) for n in
                    ('TriaxialCompressionEngine', 'ThreeDTriaxialEngine', 'UniaxialStrainer', 'TriaxialTest')}}


def scene_summary():
    sph = [b for b in O.bodies if isinstance(b.shape, Sphere)]
    return {'walls': [[tojson(O.bodies[i].state.pos), tojson(O.bodies[i].shape.extents)] for i in range(6)],
            'wall_mass': [O.bodies[i].state.mass for i in range(6)],
            'radii': sorted(b.shape.radius for b in sph), 'n': len(O.bodies), 'dt': O.dt,
            'engines': [type(e).__name__ for e in O.engines],
            'sphere_material': tojson(sph[0].material.dict()), 'wall_material': tojson(O.bodies[0].material.dict()),
            'sphere_mass0': sph[0].state.mass}


out['triaxial_test'] = {}
for name, kw in [('default200', dict(numberOfGrains=200)),
                 ('radiusMean', dict(numberOfGrains=100, radiusMean=0.1, upperCorner=(1, 2, 3), noFiles=True)),
                 ('thin', dict(numberOfGrains=50, seed=3, radiusStdDev=0, thickness=0, wallOversizeFactor=1.5,
                               noFiles=True))]:
    O.reset()
    TriaxialTest(**kw).load()
    out['triaxial_test'][name] = scene_summary()


def strainer(steps, forces=False, **kw):
    O.reset()
    O.bodies.append([sphere((0, 0, 0), .5), sphere((3, 0, 0.2), .5), sphere((0, 0, 10), .5), sphere((3, 0, 10.4), .5)])
    O.dt = 1e-3
    kw.setdefault('crossSectionArea', 2)
    s = UniaxialStrainer(negIds=[1, 0], posIds=[3, 2], **kw)
    engines = [ForceResetter(), s, NewtonIntegrator(damping=0)]
    if forces:
        engines.insert(1, PyRunner(iterPeriod=1, command='O.forces.addF(0,(0,0,1.0)); O.forces.addF(1,(0,0,3.0)); '
                                                           'O.forces.addF(2,(0,0,-10.0)); O.forces.addF(3,(0,0,-30.0))'))
    O.engines = engines
    rows = []
    for i in range(steps):
        O.run(1, True)
        rows.append({'iter': O.iter, 'vz': [b.state.vel[2] for b in O.bodies], 'z': [b.state.pos[2] for b in O.bodies],
                     'strain': s.strain, 'avgStress': s.avgStress, 'active': s.active,
                     'blocked': [b.state.blockedDOFs for b in O.bodies]})
    return {'rows': rows, 'originalLength': s.originalLength, 'absSpeed': s.absSpeed, 'strainRate': s.strainRate,
            'currentStrainRate': s.currentStrainRate}


out['strainer'] = {
    'rate': strainer(4, strainRate=0.01),
    'abs': strainer(3, absSpeed=0.1),
    'asym': strainer(3, strainRate=0.01, asymmetry=1),
    'asymneg': strainer(3, strainRate=0.01, asymmetry=-1),
    'block': strainer(2, strainRate=0.01, blockDisplacements=True, blockRotations=True),
    'stop': strainer(6, strainRate=1, stopStrain=0.0035),
    'stress': strainer(12, forces=True, strainRate=1),
}
O.reset()
out['strainer_no_area'] = catch(lambda: (O.bodies.append([sphere((0, 0, 0), .5), sphere((0, 0, 2), .5)]),
                                         O.engines.__len__(), setattr(O, 'engines', [UniaxialStrainer(
                                             negIds=[0], posIds=[1], strainRate=1)]), O.run(1, True)))

O.reset()
O.bodies.append(sphere((0.5, 0.5, 0.5), 0.3))
out['voxel'] = {str(r): utils.voxelPorosity(r, (0, 0, 0), (1, 1, 1)) for r in (50, 51, 64, 100)}
out['voxel']['offset'] = utils.voxelPorosity(50, (0.5, 0.5, 0.5), (1.5, 1.5, 1.5))
out['voxel']['aniso'] = utils.voxelPorosity(50, (0, 0, 0), (1, 2, 0.8))
out['voxel']['low_resolution'] = catch(lambda: utils.voxelPorosity(20, (0, 0, 0), (1, 1, 1)))
out['voxel']['empty_box'] = catch(lambda: utils.voxelPorosity(50))

O.reset()
O.bodies.append([sphere((0, 0, 0), 1), sphere((1.8, 0.1, 0), 1), sphere((0.9, 1.7, 0.2), 1)])
O.engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb()]),
             InteractionLoop([Ig2_Sphere_Sphere_ScGeom()], [Ip2_FrictMat_FrictMat_FrictPhys()],
                             [Law2_ScGeom_FrictPhys_CundallStrack()]), NewtonIntegrator()]
O.dt = 1e-6
O.run(1, True)
out['total_force'] = tojson(utils.totalForceInVolume())
dump('triaxial_engines', out)
