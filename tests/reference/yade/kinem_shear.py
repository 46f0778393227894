# YADE's simple-shear box engines (KinemSimpleShearBox family) on a packing: six boxes (ids 0-5 in SimpleShear's
# order: left, bottom, right, top, back, front) around a makeCloud packing (seed 1). KinemCTDEngine compresses it
# to targetSigma (100 kPa; the save it writes then is removed). The packing it reached (centres, radii, top box
# height) is then rebuilt at rest and sheared from there by KinemCNDEngine, KinemCNLEngine and KinemCNSEngine.
# Writes kinem_shear.json: every EVERY steps the left (0), right (2) and top (3) boxes' state, the force on the
# top box and the engine's attributes; 'packing': the rebuilt state. kinem_shear_j2.json: the same with another
# summation order, the shear phases from kinem_shear.json's packing (KINEM_PACKING=kinem_shear.json
# KINEM_TOPIC=kinem_shear_j2 yade -n -j2 -x kinem_shear.py). KINEM_CTD and KINEM_SHEAR shorten the phases (the tests'
# quick run under granum). KINEM_CTD_END=1 writes only the compression's last record (kinem_shear_ctd_j3/_j4.json:
# KINEM_CTD_END=1 KINEM_TOPIC=kinem_shear_ctd_j3 yade -n -j3 -x kinem_shear.py; the same with -j4).
import os, sys, math
sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from _common import dump
from yade import pack

L, H, W, t = 0.012, 0.008, 0.008, 0.001
EVERY = 20
NCTD = int(os.environ.get('KINEM_CTD', '6000'))
NSHEAR = int(os.environ.get('KINEM_SHEAR', '2000'))

def scene(top_y, spheres):
    O.reset()
    wallMat = O.materials.append(FrictMat(young=4e8, poisson=.04, frictionAngle=0, density=1000, label='wall'))
    grainMat = O.materials.append(FrictMat(young=4e8, poisson=.04, frictionAngle=math.radians(37), density=2600,
                                           label='grain'))
    def box(c, e, m): return utils.box(center=c, extents=e, fixed=True, material=m)
    O.bodies.append([box((-t/2, H/2, 0), (t/2, 1.4*H, W/2), wallMat),
                     box((L/2, -t/2, 0), (L/2, t/2, W/2), grainMat),
                     box((L+t/2, H/2, 0), (t/2, 1.4*H, W/2), wallMat),
                     box((L/2, top_y, 0), (L/2, t/2, W/2), grainMat),
                     box((L/2, H/2, -W/2-t/2), (1.25*L, 0.55*H, t/2), wallMat),
                     box((L/2, H/2, W/2+t/2), (1.25*L, 0.55*H, t/2), wallMat)])
    O.bodies.append([utils.sphere(c, r, material=grainMat) for c, r in spheres])
    O.dt = 4e-7

def engines(last):
    return [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb(), Bo1_Box_Aabb()]),
            InteractionLoop([Ig2_Sphere_Sphere_ScGeom(), Ig2_Box_Sphere_ScGeom()], [Ip2_FrictMat_FrictMat_FrictPhys()],
                            [Law2_ScGeom_FrictPhys_CundallStrack()]),
            NewtonIntegrator(damping=.2), last]

def drive(eng, nsteps):
    O.engines = engines(eng)
    rows = []
    for k in range(nsteps // EVERY):
        O.run(EVERY, True)
        row = {'iter': O.iter, 'fTop': Vector3(O.forces.f(3)),
               'attrs': {k: v for k, v in eng.dict().items() if k in ('gamma', 'alpha', 'f0', 'y0', 'firstRun')}}
        for i in (0, 2, 3):
            s = O.bodies[i].state
            row[str(i)] = {'pos': Vector3(s.pos), 'vel': Vector3(s.vel), 'ori': Quaternion(s.ori),
                           'angVel': Vector3(s.angVel)}
        rows.append(row)
    return rows

sp = pack.SpherePack()
sp.makeCloud((0, 0, -W/2), (L, H, W/2), rMean=5e-4, rRelFuzz=.15, num=500, seed=1)
scene(H + t/2, [(c, r) for c, r in sp])
out = {'nSpheres': len(sp), 'CTD': drive(KinemCTDEngine(compSpeed=2.0, targetSigma=100.0), NCTD)}
if os.environ.get('KINEM_CTD_END'):  # only where the compression ended (the spread of the thread counts)
    dump(os.environ['KINEM_TOPIC'], {'threads': O.numThreads, 'CTD_end': out['CTD'][-1]})
    sys.exit(0)
if os.path.exists('Sigmax_100kPaReached.xml'):
    os.remove('Sigmax_100kPaReached.xml')
packing = {'top_y': O.bodies[3].state.pos[1], 'spheres': [(Vector3(b.state.pos), b.shape.radius) for b in O.bodies
                                                          if isinstance(b.shape, Sphere)]}
if os.environ.get('KINEM_PACKING'):
    import json
    with open(os.environ['KINEM_PACKING']) as f:
        packing = json.load(f)['packing']
out['packing'] = packing
for name, eng in [('CND', lambda: KinemCNDEngine(shearSpeed=0.5, gammalim=6e-4)),
                  ('CNL', lambda: KinemCNLEngine(shearSpeed=0.5, gammalim=6e-4)),
                  ('CNS', lambda: KinemCNSEngine(shearSpeed=0.5, gammalim=6e-4, KnC=0.05))]:
    scene(packing['top_y'], packing['spheres'])
    out[name] = drive(eng(), NSHEAR)
dump(os.environ.get('KINEM_TOPIC', 'kinem_shear'), out)
