# PeriIsoCompressor (YADE 2023.02a): the servo step by step on a shared packing, a whole compression, errors.
# Run: yade -n -x periiso.py  (writes periiso.json and periiso_pack.txt)
import os
import sys
sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from _common import catch, dump, tojson
from yade import pack

HERE = os.path.dirname(os.path.abspath(sys.argv[0]))
PACK = os.path.join(HERE, 'periiso_pack.txt')
if not os.path.exists(PACK):
    sp = pack.SpherePack()
    sp.makeCloud((0, 0, 0), (1, 1.2, .9), .08, .3, -1, True, seed=5)
    sp.save(PACK)   # 6 digits: both programs start from the rounded positions


def scene(keepProportions, globalUpdateInt, stresses, maxUnbalanced, damping=.8):
    O.reset()
    O.periodic = True
    O.cell.setBox(1, 1.2, .9)
    sp = pack.SpherePack()
    sp.load(PACK)
    O.materials.append(FrictMat(young=30e9, frictionAngle=.1, poisson=.3, density=1e3))
    for c, r in sp:
        O.bodies.append(sphere(c, r))
    pic = PeriIsoCompressor(stresses=stresses, maxUnbalanced=maxUnbalanced, doneHook='O.pause()',
                            globalUpdateInt=globalUpdateInt, keepProportions=keepProportions, label='pic')
    O.engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb()], verletDist=.05 * .08),
                 InteractionLoop([Ig2_Sphere_Sphere_ScGeom()], [Ip2_FrictMat_FrictMat_FrictPhys()],
                                 [Law2_ScGeom_FrictPhys_CundallStrack()]), pic, NewtonIntegrator(damping=damping)]
    O.dt = PWaveTimeStep()
    return pic


def steps(keepProportions, globalUpdateInt):
    pic = scene(keepProportions, globalUpdateInt, [-1e8, -1e6], 1e-2)
    rows = []
    for i in range(40):
        O.step()
        rows.append({'iter': O.iter, 'size': list(O.cell.size), 'sigma': list(pic.sigma),  # copies: pic.sigma is live
                     'velGrad': tojson(O.cell.velGrad),
                     'nReal': len([i for i in O.interactions if i.isReal])})
    return {'charLen': pic.charLen, 'maxSpan': pic.maxSpan, 'dt': O.dt, 'rows': rows}


def whole():
    pic = scene(True, 20, [-100e9, -1e8], 1e-2)   # randomPeriPack's stresses: robust (no transient luck)
    states = {}
    while pic.state < 2 and O.iter < 60000:
        O.run(100, True)
        states.setdefault(pic.state, O.iter)
    vs = sum(4 / 3. * 3.141592653589793 * b.shape.radius ** 3 for b in O.bodies)
    return {'iter_done': O.iter, 'state_first_seen': states, 'size': list(O.cell.size), 'sigma': list(pic.sigma),
            'currUnbalanced': pic.currUnbalanced, 'porosity': 1 - vs / O.cell.volume}


def small_cell(**kw):
    # one small sphere: the collider is content, the compressor's own limits (maxSpan given) are hit
    O.reset()
    O.periodic = True
    O.cell.setBox(1, 1, 1)
    O.bodies.append(sphere((.5, .5, .5), .05))
    O.engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb()]),
                 InteractionLoop([Ig2_Sphere_Sphere_ScGeom()], [Ip2_FrictMat_FrictMat_FrictPhys()],
                                 [Law2_ScGeom_FrictPhys_CundallStrack()]),
                 PeriIsoCompressor(stresses=[-1e5], **kw), NewtonIntegrator()]
    O.dt = 1e-5
    O.run(3, True)
    return O.iter, O.cell.size


def too_small():
    return small_cell(maxSpan=.5)


def cannot_shrink():
    return small_cell(maxSpan=.47, charLen=2)


# (PeriIsoCompressor on an aperiodic scene aborts YADE: 'Being used on non-periodic simulation!', then terminate)


dump('periiso', {
    'steps_keep': steps(True, 1000),
    'steps_axes': steps(False, 20),
    'whole': whole(),
    'too_small': catch(too_small),
    'cannot_shrink': catch(cannot_shrink),
})
