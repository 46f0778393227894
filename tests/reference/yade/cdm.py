# cdm: the extended Hertz-Mindlin law (conical damage model, pressure-dependent friction): FrictMatCDM,
# MindlinPhysCDM, Ip2_FrictMatCDM_FrictMatCDM_MindlinPhysCDM, Ip2_FrictMat_FrictMatCDM_MindlinPhysCDM,
# Law2_ScGeom_MindlinPhysCDM_HertzMindlinCDM, and Ig2_Facet/Wall_Sphere_ScGeom(hertzian=True).
# Two spheres (r .1) at x = 0 and x = dist, dt 1e-5, no gravity, no damping; after every step (after step 20:
# every `every` steps): the MindlinPhysCDM fields, the forces and torques of both bodies, sphere 2's position,
# the law's ratioYieldingContacts and ratioSlidingContacts.
# Runs: 'load_unload' (both spheres fixed, sphere 2 driven at (-2, .4, 0) m/s for 60 steps, then (+2, .4, 0):
# the contact yields, unloads with its damaged radius and ends; two CDM materials, c1/c2 given),
# 'never_erase' (the same with neverErase), 'frictmat' (a fixed FrictMat sphere hit by a free FrictMatCDM one),
# 'slide' (free sphere sliding and yielding on a fixed one), 'hertzian' (a sphere on a facet and one on a wall,
# hertzian=True). YADE 2023.02a aborts (not recorded here) for sigmaMax >= E* of the pair (its default 1e99
# included), sigmaMax <= 0, alpha outside (0, pi/2), and a FrictMatCDM body as id1 with a FrictMat id2.
# Regenerate: cd tests/reference/yade && yade -n -x cdm.py
# YADE 2023.02a
import sys; import os; sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from _common import dump, tojson

PHYS = ('kn', 'ks', 'kno', 'kso', 'normalForce', 'shearForce', 'shearElastic', 'usElastic', 'usTotal', 'isSliding',
        'tangensOfFrictionAngle', 'E', 'G', 'sigmaMax', 'alphaFac', 'R', 'isYielding', 'mu0', 'c1', 'c2', 'radius')
C = FrictMatCDM
MAT_A = dict(young=1e8, poisson=.25, density=2000, frictionAngle=.4, sigmaMax=2e6, alpha=1.3, c1=.3, c2=2e-6)
MAT_B = dict(young=2e8, poisson=.15, density=1000, frictionAngle=.3, sigmaMax=5e6, alpha=1.0, c1=.5, c2=1e-6)


def law():
    return O.engines[2].lawDispatcher.functors[0]


def record(a, b):
    rec = {'iter': O.iter, 'real': O.interactions.has(a, b) and O.interactions[a, b].isReal,
           'f': [O.forces.f(j) for j in (a, b)], 't': [O.forces.t(j) for j in (a, b)],
           'pos2': O.bodies[b].state.pos, 'vel2': O.bodies[b].state.vel,
           'ratioYielding': law().ratioYieldingContacts(), 'ratioSliding': law().ratioSlidingContacts()}
    if rec['real']:
        i = O.interactions[a, b]
        rec.update(id1=i.id1, pen=i.geom.penetrationDepth, refR1=i.geom.refR1, refR2=i.geom.refR2,
                   normal=i.geom.normal, contactPoint=i.geom.contactPoint)
        rec.update({k: getattr(i.phys, k) for k in PHYS})
    return tojson(rec)


def engines(neverErase=False):
    return [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb(), Bo1_Facet_Aabb(), Bo1_Wall_Aabb()]),
            InteractionLoop([Ig2_Sphere_Sphere_ScGeom(), Ig2_Facet_Sphere_ScGeom(hertzian=True),
                             Ig2_Wall_Sphere_ScGeom(hertzian=True)],
                            [Ip2_FrictMatCDM_FrictMatCDM_MindlinPhysCDM(), Ip2_FrictMat_FrictMatCDM_MindlinPhysCDM()],
                            [Law2_ScGeom_MindlinPhysCDM_HertzMindlinCDM(neverErase=neverErase)]),
            NewtonIntegrator(damping=0)]


def run(mat1, mat2, v2, w2=(0, 0, 0), fixed=(True, False), steps=60, dist=0.199, every=1, reverse_at=None,
        neverErase=False):
    O.reset()
    m1 = O.materials.append(mat1)
    m2 = O.materials.append(mat2)
    O.bodies.append([sphere((0, 0, 0), .1, material=m1, fixed=fixed[0]),
                     sphere((dist, 0, 0), .1, material=m2, fixed=fixed[1])])
    O.bodies[1].state.vel = v2
    O.bodies[1].state.angVel = w2
    O.engines = engines(neverErase)
    O.dt = 1e-5
    out = []
    for k in range(steps):
        if k == reverse_at:
            v = O.bodies[1].state.vel
            O.bodies[1].state.vel = (-v[0], v[1], v[2])
        O.step()
        if k < 20 or O.iter % every == 0:
            out.append(record(0, 1))
    return out


def hertzian(steps=30):
    O.reset()
    m = O.materials.append(C(young=1e8, poisson=.3, density=2000, frictionAngle=.3, sigmaMax=3e6, alpha=1.2))
    O.bodies.append([facet([(-1, -1, 0), (1, -1, 0), (0, 1, 0)], material=m),
                     sphere((0, 0, .0995), .1, material=m),
                     wall((0, 0, -5), axis=2, material=m),
                     sphere((3, 0, -4.9), .1, material=m)])
    O.bodies[1].state.vel = (.3, 0, -1)
    O.bodies[3].state.vel = (0, .2, -1)
    O.engines = engines()
    O.dt = 1e-5
    out = []
    for k in range(steps):
        O.step()
        out.append({'facet': record(0, 1), 'wall': record(2, 3)})
    return out


data = {
    'dicts': {c.__name__: c().dict() for c in (C, Ip2_FrictMatCDM_FrictMatCDM_MindlinPhysCDM,
                                                Ip2_FrictMat_FrictMatCDM_MindlinPhysCDM,
                                                Law2_ScGeom_MindlinPhysCDM_HertzMindlinCDM)},
    'load_unload': run(C(**MAT_A), C(**MAT_B), v2=(-2, .4, 0), fixed=(True, True), steps=180, reverse_at=60),
    'never_erase': run(C(**MAT_A), C(**MAT_B), v2=(-2, .4, 0), fixed=(True, True), steps=180, reverse_at=60,
                       every=10, neverErase=True),
    'frictmat': run(FrictMat(young=1e8, poisson=.25, density=2000, frictionAngle=.4), C(**MAT_B), v2=(-3, .5, 0),
                    w2=(0, 0, 10), steps=300, every=10),
    'slide': run(C(**MAT_A), C(**MAT_A), v2=(-3, 3, 0), w2=(0, 0, -40), steps=200, every=10),
    'hertzian': hertzian(),
}
dump('cdm', data)
