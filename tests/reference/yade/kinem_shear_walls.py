# The simple-shear box engines' kinematic path (no spheres: no force on the top box): the six boxes of
# kinem_shear.py driven step by step by KinemCTDEngine (compression, unloading, the stop and the file it saves,
# none while it stays stopped), KinemCNDEngine (the first step from upright boxes, the stop at gammalim and its
# save, again after one more move), KinemCNLEngine and KinemCNSEngine (f0, y0 and firstRun), and KinemCNDEngine
# from tilted lateral boxes. Writes kinem_shear_walls.json: after each
# step the left (0), right (2) and top (3) boxes' state, the engine's attributes and the .xml files in the
# directory (removed afterwards); 'defaults': each engine's dict() as constructed.
import os, sys, math, glob
sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from _common import dump

L, H, W, t = 0.012, 0.008, 0.008, 0.001

def scene(tilt_left=0.0, tilt_right=0.0):
    O.reset()
    m = O.materials.append(FrictMat(young=4e8, poisson=.04, frictionAngle=0, density=1000))
    def box(c, e): return utils.box(center=c, extents=e, fixed=True, material=m)
    O.bodies.append([box((-t/2, H/2, 0), (t/2, 1.4*H, W/2)), box((L/2, -t/2, 0), (L/2, t/2, W/2)),
                     box((L+t/2, H/2, 0), (t/2, 1.4*H, W/2)), box((L/2, H+t/2, 0), (L/2, t/2, W/2)),
                     box((L/2, H/2, -W/2-t/2), (1.25*L, 0.55*H, t/2)), box((L/2, H/2, W/2+t/2), (1.25*L, 0.55*H, t/2))])
    O.bodies[0].state.ori = Quaternion((0, 0, 1), tilt_left)
    O.bodies[2].state.ori = Quaternion((0, 0, 1), tilt_right)
    O.dt = 1e-5

def drive(eng, nsteps):
    O.engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb(), Bo1_Box_Aabb()]),
                 InteractionLoop([Ig2_Sphere_Sphere_ScGeom(), Ig2_Box_Sphere_ScGeom()],
                                 [Ip2_FrictMat_FrictMat_FrictPhys()], [Law2_ScGeom_FrictPhys_CundallStrack()]),
                 NewtonIntegrator(damping=.2), eng]
    rows = []
    for k in range(nsteps):
        O.step()
        row = {'iter': O.iter, 'attrs': {k: v for k, v in eng.dict().items()
                                         if k in ('gamma', 'alpha', 'f0', 'y0', 'firstRun')},
               'files': sorted(glob.glob('*.xml'))}
        for i in (0, 2, 3):
            s = O.bodies[i].state
            row[str(i)] = {'pos': Vector3(s.pos), 'vel': Vector3(s.vel), 'ori': Quaternion(s.ori),
                           'angVel': Vector3(s.angVel)}
        rows.append(row)
    for f in glob.glob('*.xml'):
        os.remove(f)
    return rows

out = {'defaults': {c.__name__: c().dict() for c in (KinemSimpleShearBox, KinemCTDEngine, KinemCNDEngine,
                                                      KinemCNLEngine, KinemCNSEngine)}}
scene()
out['CTD_down'] = drive(KinemCTDEngine(compSpeed=3.0, targetSigma=50.0), 4)
cnd = KinemCNDEngine(shearSpeed=7.0, gammalim=3.5e-4)
out['CND'] = drive(cnd, 8)
cnd.gammalim = 4.2e-4  # one more step, then a stop: saved again
out['CND_resumed'] = drive(cnd, 3)
out['CNL'] = drive(KinemCNLEngine(shearSpeed=-4.0, gammalim=1e-4), 4)
out['CNS'] = drive(KinemCNSEngine(shearSpeed=5.0, gammalim=1e-4, KnC=2.0), 4)
out['CTD_up'] = drive(KinemCTDEngine(compSpeed=-2.0, targetSigma=-1.0), 3)
ctd = KinemCTDEngine(compSpeed=-2.0, targetSigma=5.5, Key='k_')
out['CTD_stop'] = drive(ctd, 3)
out['CTD_stopped'] = drive(ctd, 2)  # still stopped: no new save
out['CTD_stop0'] = drive(KinemCTDEngine(compSpeed=0.0, targetSigma=-7.9), 2)
scene(0.1, -0.2)
out['CND_tilted'] = drive(KinemCNDEngine(shearSpeed=7.0, gammalim=1e-3), 4)
scene(-0.1, 0.2)
out['CND_tilted2'] = drive(KinemCNDEngine(shearSpeed=7.0, gammalim=1e-3), 4)
dump('kinem_shear_walls', out)
