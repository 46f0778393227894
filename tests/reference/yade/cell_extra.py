# Cell attributes granum added (YADE 2023.02a): prevHSize, shearTrsf, unshearTrsf, velGradChanged, flipCell
# (its matrix and the cell after), utils.flipCell, stressTensorOfPeriodicCell, totalForceInVolume.
# Run: yade -n -x cell_extra.py  (writes cell_extra.json)
import os
import sys
sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from _common import catch, dump, tojson
from yade import pack

out = {}
O.periodic = True
O.cell.hSize = Matrix3(1, 0.2, 0, 0, 1, 0, 0, 0, 1)
O.bodies.append(sphere((0.5, 0.5, 0.5), 0.1))
O.engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb()]),
             InteractionLoop([Ig2_Sphere_Sphere_ScGeom()], [Ip2_FrictMat_FrictMat_FrictPhys()],
                             [Law2_ScGeom_FrictPhys_CundallStrack()]), NewtonIntegrator()]
O.dt = 1e-3
O.cell.velGrad = Matrix3(0, 1, 0, 0, -.5, 0, 0, 0, 0)
steps = []
for i in range(3):
    steps.append({'iter': O.iter, 'hSize': tojson(O.cell.hSize), 'prevHSize': tojson(O.cell.prevHSize),
                  'shearTrsf': tojson(O.cell.shearTrsf), 'unshearTrsf': tojson(O.cell.unshearTrsf),
                  'velGradChanged': O.cell.velGradChanged, 'trsf': tojson(O.cell.trsf)})
    O.step()
out['steps'] = steps
flips = []
for h in ((1, 1.7, 0, 0, 1, 0, 0, 0, 1), (1, -2.7, 0.4, 0, 1, 1.3, 0, 0, 1), (1, 0.2, 0.3, 0.4, 1, 0, 0, 0, 1),
          (2, 3.1, 0, 0, 1, 0, 0, 0, 1), (1, 0, 0, 0.9, 1, 0, 0, 0, 1), (1, 0.6, 0, 0, 1, 0, 0, 0, 1),
          (1, 0.4, 0, 0, 1, 0, 0, 0, 1), (1, 0.5, 0, 0, 1, 0, 0, 0, 1), (1, -0.5, 0, 0, 1, 0, 0, 0, 1),
          (1.3, 2.9, -1.1, 0.2, 0.8, 2.4, 0.1, -0.3, 0.9)):
    O.cell.hSize = Matrix3(*h)
    O.cell.trsf = Matrix3.Identity
    f = tojson(O.cell.flipCell())
    flips.append({'hSize0': h, 'flip': f, 'hSize': tojson(O.cell.hSize), 'trsf': tojson(O.cell.trsf),
                  'refHSize': tojson(O.cell.refHSize), 'prevHSize': tojson(O.cell.prevHSize),
                  'pos': tojson(O.bodies[0].state.pos)})
out['flips'] = flips
O.cell.hSize = Matrix3(1, 1.7, 0, 0, 1, 0, 0, 0, 1)
out['utils_flipCell'] = catch(lambda: utils.flipCell())
out['utils_flipCell_hSize'] = tojson(O.cell.hSize)

O.reset()
O.periodic = True
O.cell.setBox(1, 1.2, 0.9)
sp = pack.SpherePack()
sp.load(os.path.join(os.path.dirname(os.path.abspath(sys.argv[0])), 'periiso_pack.txt'))
for c, r in sp:
    O.bodies.append(sphere(c, r * 1.6))
O.engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb()]),
             InteractionLoop([Ig2_Sphere_Sphere_ScGeom()], [Ip2_FrictMat_FrictMat_FrictPhys()],
                             [Law2_ScGeom_FrictPhys_CundallStrack()]), NewtonIntegrator()]
O.dt = 1e-6
O.step()
out['nReal'] = len([i for i in O.interactions if i.isReal])
out['stressTensorOfPeriodicCell'] = stressTensorOfPeriodicCell()
out['stressTensorOfPeriodicCell_v2'] = stressTensorOfPeriodicCell(2.0)
out['getStress'] = getStress()
out['totalForceInVolume'] = totalForceInVolume()
dump('cell_extra', out)
