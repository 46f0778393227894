# mindlin: Hertz-Mindlin contacts (Ip2_FrictMat_FrictMat_MindlinPhys, Law2_ScGeom_MindlinPhys_Mindlin,
# Law2_ScGeom_MindlinPhys_HertzWithLinearShear) between two spheres of different FrictMats (r .1, E 1e7/2e7,
# nu .3/.2, density 1000/2000, friction .5/.3), sphere 2 starting at x = dist with a velocity and spin,
# dt 1e-5, no gravity, no damping, recorded after every step (after step 40: every `every` steps): the MindlinPhys fields, the forces and torques
# of both bodies, the position of sphere 2 and, with calcEnergy, the law's energy accumulators and methods.
# Runs: 'default' (sliding reached), 'fixed' (sphere 1 fixed, betan/betas), 'damped' (free, betan .3,
# betas .2, through the collision and the separation), 'restitution' (en .5, es .3), 'es_only', 'en1' (en = 1), 'en_near1',
# 'adhesion' (gamma 10, includeAdhesion, separating past zero overlap), 'neverErase', 'hwls' (nonLin 0..3),
# 'moment' (includeMoment: krot, ktwist), 'moment_plastic' (eta: the bending moment capped),
# 'box' (Ig2_Box_Sphere_ScGeom). Also: the functors' dict() and the error of en and betan together.
# Regenerate: cd tests/reference/yade && yade -n -x mindlin.py
# YADE 2023.02a
import sys; import os; sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from _common import dump, tojson

PHYS = ('kn', 'ks', 'kno', 'kso', 'normalForce', 'shearForce', 'shearElastic', 'normalViscous', 'shearViscous',
        'usElastic', 'usTotal', 'betan', 'betas', 'adhesionForce', 'isSliding', 'isAdhesive',
        'tangensOfFrictionAngle', 'radius', 'kr', 'ktw', 'maxBendPl', 'momentBend', 'momentTwist')


def run(ip2, law, v2=(-1, 0.3, 0), w2=(0, 0, 5), w1=(0, 0, 0), fixed1=False, steps=40, dist=0.199, box=False, every=1):
    O.reset()
    m1 = O.materials.append(FrictMat(young=1e7, poisson=.3, density=1000, frictionAngle=.5))
    m2 = O.materials.append(FrictMat(young=2e7, poisson=.2, density=2000, frictionAngle=.3))
    if box:
        b1 = utils.box((0, 0, 0), (.1, .2, .2), material=m1, fixed=fixed1)
    else:
        b1 = sphere((0, 0, 0), .1, material=m1, fixed=fixed1)
    O.bodies.append([b1, sphere((dist, 0, 0), .1, material=m2)])
    O.bodies[0].state.angVel = w1
    O.bodies[1].state.vel = v2
    O.bodies[1].state.angVel = w2
    O.engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb(), Bo1_Box_Aabb()]),
                 InteractionLoop([Ig2_Sphere_Sphere_ScGeom(), Ig2_Box_Sphere_ScGeom()], [ip2], [law]),
                 NewtonIntegrator(damping=0)]
    O.dt = 1e-5
    out = []
    for k in range(steps):
        O.step()
        if k >= 40 and O.iter % every:
            continue
        rec = {'iter': O.iter, 'real': O.interactions.has(0, 1) and O.interactions[0, 1].isReal,
               'f': [O.forces.f(j) for j in (0, 1)], 't': [O.forces.t(j) for j in (0, 1)],
               'pos2': O.bodies[1].state.pos, 'vel2': O.bodies[1].state.vel}
        if rec['real']:
            i = O.interactions[0, 1]
            rec['pen'] = i.geom.penetrationDepth
            rec.update({a: getattr(i.phys, a) for a in PHYS})
        if isinstance(law, Law2_ScGeom_MindlinPhys_Mindlin) and law.calcEnergy:
            rec.update({a: getattr(law, a) for a in ('frictionDissipation', 'shearEnergy', 'normDampDissip',
                                                       'shearDampDissip')})
            rec.update({a: getattr(law, a)() for a in ('normElastEnergy', 'ratioSlidingContacts',
                                                         'contactsAdhesive')})
        out.append(tojson(rec))
    return out


M = Ip2_FrictMat_FrictMat_MindlinPhys
L = Law2_ScGeom_MindlinPhys_Mindlin
data = {
    'dicts': {c.__name__: c().dict() for c in (M, L, Law2_ScGeom_MindlinPhys_HertzWithLinearShear)},
    'default': run(M(), L(calcEnergy=True), v2=(-1, 3, 0), w1=(0, 1, 2)),
    'fixed': run(M(betan=.3, betas=.1), L(calcEnergy=True), fixed1=True),
    'damped': run(M(betan=.3, betas=.2), L(calcEnergy=True), v2=(-2, .8, .4), steps=1500, every=10),
    'restitution': run(M(en=.5, es=.3), L(calcEnergy=True), v2=(-2, .8, .4), steps=1500, every=10),
    'es_only': run(M(es=.3), L(), steps=5),
    'en1': run(M(en=1.), L(), steps=5),
    'en_near1': run(M(en=.999), L(), steps=5),
    'adhesion': run(M(gamma=10), L(includeAdhesion=True, calcEnergy=True), v2=(3, 0.3, 0), steps=40,
                    dist=0.1995),
    'adhesion_approach': run(M(gamma=10, betan=.2), L(includeAdhesion=True, calcEnergy=True), v2=(-.5, 2, 0),
                             steps=40),
    'neverErase': run(M(), L(neverErase=True), v2=(3, 0.3, 0), steps=30, dist=0.1995),
    'hwls0': run(M(), Law2_ScGeom_MindlinPhys_HertzWithLinearShear(), v2=(-1, 3, 0), w1=(0, 1, 2)),
    'hwls1': run(M(), Law2_ScGeom_MindlinPhys_HertzWithLinearShear(nonLin=1), v2=(-1, 3, 0), w1=(0, 1, 2)),
    'hwls2': run(M(), Law2_ScGeom_MindlinPhys_HertzWithLinearShear(nonLin=2), v2=(-1, 3, 0), w1=(0, 1, 2)),
    'hwls3': run(M(), Law2_ScGeom_MindlinPhys_HertzWithLinearShear(nonLin=3), v2=(-1, 3, 0), w1=(0, 1, 2)),
    'moment': run(M(krot=3, ktwist=2), L(includeMoment=True), v2=(-1, .3, .2), w2=(5, 20, -10), w1=(3, -4, 6)),
    'moment_plastic': run(M(krot=3000, ktwist=2, eta=.5, betan=.1), L(includeMoment=True, calcEnergy=True),
                          v2=(-1, .3, .2), w2=(5, 20, -10), w1=(3, -4, 6)),
    'box': run(M(betan=.2), L(calcEnergy=True), v2=(-1, .5, .2), w2=(1, 2, 3), dist=0.199, box=True),
}
dump('mindlin', data)
