# Peri3dController (YADE 2023.02a): strain paths step by step (the cell, the strain vector, the rate), a path
# with intermediate points, a stress-controlled compression of a shared packing, and the defaults.
# Run: yade -n -x peri3d.py  (writes peri3d.json)
import os
import sys
sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from _common import dump, tojson
from yade import pack

HERE = os.path.dirname(os.path.abspath(sys.argv[0]))


def one_sphere(**kw):
    O.reset()
    O.periodic = True
    O.cell.setBox(1, 1, 1)
    O.bodies.append(sphere((0.5, 0.5, 0.5), 0.1))
    p3d = Peri3dController(label='p3d', **kw)
    O.engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb()]),
                 InteractionLoop([Ig2_Sphere_Sphere_ScGeom()], [Ip2_FrictMat_FrictMat_FrictPhys()],
                                 [Law2_ScGeom_FrictPhys_CundallStrack()]), NewtonIntegrator(), p3d]
    O.dt = 1e-3
    rows = []
    for i in range(13):
        O.step()
        rows.append({'iter': O.iter, 'progress': p3d.progress, 'strain': list(p3d.strain),
                     'strainRate': list(p3d.strainRate), 'strainGoal': list(p3d.strainGoal),
                     'trsf': tojson(O.cell.trsf), 'velGrad': tojson(O.cell.velGrad), 'dead': p3d.dead})
    return rows


out = {}
out['defaults'] = {k: tojson(v) for k, v in Peri3dController().dict().items()}
done = []
out['strain'] = one_sphere(goal=(0.01, -0.02, 0, 0.004, 0, 0.002), stressMask=0, nSteps=10,
                           doneHook='done.append(O.iter)')
out['strain_done_iters'] = list(done)
out['path'] = one_sphere(goal=(0.3, 0, 0, 0, 0, 0), stressMask=0, nSteps=10, xxPath=[(2, 3), (4, 1), (5, 2)])
out['path_dead_after'] = O.engines[-1].dead


def stress_run():
    O.reset()
    O.periodic = True
    O.cell.setBox(1, 1.2, .9)
    sp = pack.SpherePack()
    sp.load(os.path.join(HERE, 'periiso_pack.txt'))
    O.materials.append(FrictMat(young=30e9, frictionAngle=.1, poisson=.3, density=1e3))
    for c, r in sp:
        O.bodies.append(sphere(c, r * 1.25))
    p3d = Peri3dController(goal=(-2e7, -2e7, -2e7, 0, 0, 0), stressMask=0b000111, nSteps=300, maxStrain=.5,
                           youngEstimation=.5e9, doneHook='O.pause()', label='p3d')
    O.engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb()]),
                 InteractionLoop([Ig2_Sphere_Sphere_ScGeom()], [Ip2_FrictMat_FrictMat_FrictPhys()],
                                 [Law2_ScGeom_FrictPhys_CundallStrack()]), NewtonIntegrator(), p3d]
    O.dt = PWaveTimeStep() / 2
    rows = []
    for i in range(320):
        O.step()
        if i < 5 or O.iter % 20 == 0:
            rows.append({'iter': O.iter, 'stress': list(p3d.stress), 'strain': list(p3d.strain),
                         'strainRate': list(p3d.strainRate), 'stressIdeal': list(p3d.stressIdeal),
                         'progress': p3d.progress})
    return rows


out['stress'] = stress_run()
dump('peri3d', out)
