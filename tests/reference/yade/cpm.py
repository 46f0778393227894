# cpm: the concrete particle model (CpmMat, Ip2_CpmMat_CpmMat_CpmPhys, Law2_ScGeom_CpmPhys_Cpm, CpmStateUpdater,
# Ip2_FrictMat_CpmMat_FrictPhys) on two spheres (r .5 and .4) whose motion is imposed (blockedDOFs='xyzXYZ',
# velocity set, dt=1e-6, no gravity, no damping), the contact made with interactionDetectionFactor 1.5 as in
# YADE's concrete examples (which reset it to 1 after the first step: 'tension' does so), recorded at steps 1, 2,
# then 1 past each multiple of 20 up to 300 and of `every`: the CpmPhys (all its attributes), penetrationDepth
# and normal, forces and torques on both bodies, and
# CpmStateUpdater's outputs (it runs every 20 steps, in the step before a record: normDmg, numBrokenCohesive,
# numContacts, stress, epsVolumetric of both bodies; avgRelResidual, maxOmega). The steps between records run in
# one O.run(n, True).
# Runs: 'tension' (exponential softening, damLaw=1, from a gap: refPD < 0), 'tension_linear' (damLaw=0,
# omegaThreshold .999: the contact breaks, numBrokenCohesive), 'shear' (two different CpmMats: averaged
# parameters; Mohr-Coulomb plasticity), 'compression' (epsSoft=-1e-3: plastic compression, then unloading and
# tension), 'prestress' (isoPrestress and equivStrainShearContrib, oblique motion), 'noncohesive'
# (cohesiveThresholdIter=0: compression then separation, the contact ends), 'neverDamage', 'frict_cpm'
# (FrictMat against CpmMat: Ip2_FrictMat_CpmMat_FrictPhys and Cundall-Strack), 'rate' (dmgTau, plTau and
# their exponents set, and Law2's yieldSurfType=0: YADE 2023.02a's build ignores them; 'rate_equals_tension'
# says whether the run equals 'tension').
# 'defaults': the dict() of each class; 'yieldSigmaTMagnitude': what YADE says when it is called;
# 'linear_default': damLaw=0 with the default omegaThreshold 1: the contact ends when omega passes 1 (past
# epsFracture); 'funcG', 'funcGInv': [arguments, value] of CpmPhys's damage law and its inverse;
# 'elasticEnergy': [step, Law2_ScGeom_CpmPhys_Cpm.elasticEnergy(), omega] after 500 steps of oblique pulling.
# Regenerate: cd tests/reference/yade && yade -n -x cpm.py
# YADE 2023.02a
import sys; import os; sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from math import atan
from _common import dump, tojson, catch

N = Vector3(0.6, 0.3, 0.74).normalized()   # direction from sphere 1 to sphere 2
T = N.cross(Vector3(0, 0, 1)).normalized()  # a tangent
PHYS = ('E', 'G', 'crossSection', 'refLength', 'refPD', 'kn', 'ks', 'epsFracture', 'undamagedCohesion',
        'tanFrictionAngle', 'isCohesive', 'omega', 'Fn', 'Fs', 'epsN', 'epsT', 'sigmaN', 'sigmaT', 'kappaD', 'epsNPl',
        'epsTPl', 'relResidualStrength', 'normalForce', 'shearForce', 'epsCrackOnset', 'relDuctility', 'isoPrestress',
        'equivStrainShearContrib', 'damLaw', 'neverDamage', 'dmgTau', 'dmgRateExp', 'plTau', 'plRateExp')
CONCRETE = dict(young=24e9, poisson=.2, sigmaT=3.5e6, frictionAngle=atan(.8), epsCrackOnset=1e-4, relDuctility=30,
                density=4800)


def cpm(**kw):
    base = dict(CONCRETE)
    base.update(kw)
    return CpmMat(**base)


def record(out, updater):
    rec = {'iter': O.iter, 'real': O.interactions.has(0, 1) and O.interactions[0, 1].isReal,
           'f': [O.forces.f(k) for k in (0, 1)], 't': [O.forces.t(k) for k in (0, 1)],
           'pos2': O.bodies[1].state.pos}
    for k in (0, 1):
        s = O.bodies[k].state
        if type(s).__name__ == 'CpmState':
            rec['state%d' % k] = {a: getattr(s, a) for a in ('normDmg', 'numBrokenCohesive', 'numContacts', 'stress',
                                                             'epsVolumetric')}
    if updater is not None:
        rec['avgRelResidual'], rec['maxOmega'] = updater.avgRelResidual, updater.maxOmega
    if rec['real']:
        i = O.interactions[0, 1]
        g, p = i.geom, i.phys
        rec.update({'phys_class': type(p).__name__, 'penetrationDepth': g.penetrationDepth, 'normal': g.normal,
                    'contactPoint': g.contactPoint})
        if type(p).__name__ == 'CpmPhys':
            rec.update({k: getattr(p, k) for k in PHYS})
        else:
            rec.update({k: getattr(p, k) for k in ('kn', 'ks', 'tangensOfFrictionAngle', 'normalForce', 'shearForce')})
    out.append(tojson(rec))


def recorded(i, every):
    """Whether step i is recorded: 1, 2, then 1 past each multiple of 20 up to 300 and of `every` (the updater,
    with iterPeriod 20, has just run)."""
    return i < 3 or i % every == 1 or (i <= 301 and i % 20 == 1)


def next_record(i, every):
    j = i + 1
    while not recorded(j, every):
        j += 1
    return j


def scene(m1, m2, dist, legs, every, ip2=None, law=None, reset_factor=False):
    """legs: [(velocity of sphere 2, steps), ...]"""
    O.reset()
    a = O.materials.append(m1)
    b = O.materials.append(m2)
    O.bodies.append([sphere((0, 0, 0), .5, material=a), sphere(dist * N, .4, material=b)])
    for k in (0, 1):
        O.bodies[k].state.blockedDOFs = 'xyzXYZ'
    updater = CpmStateUpdater(iterPeriod=20)   # runs in the steps before the records (iter % 20 == 1)
    bo1, ig2 = Bo1_Sphere_Aabb(aabbEnlargeFactor=1.5), Ig2_Sphere_Sphere_ScGeom(interactionDetectionFactor=1.5)
    O.engines = [ForceResetter(), InsertionSortCollider([bo1]),
                 InteractionLoop([ig2],
                                 [ip2 or Ip2_CpmMat_CpmMat_CpmPhys(), Ip2_FrictMat_CpmMat_FrictPhys(),
                                  Ip2_FrictMat_FrictMat_FrictPhys()],
                                 [law or Law2_ScGeom_CpmPhys_Cpm(), Law2_ScGeom_FrictPhys_CundallStrack()]),
                 NewtonIntegrator(damping=0), updater]
    O.dt = 1e-6
    out = []
    for vel, steps in legs:
        O.bodies[1].state.vel = vel
        end = O.iter + steps
        while O.iter < end:
            O.run(min(end, next_record(O.iter, every)) - O.iter, True)
            if reset_factor and O.iter == 1:
                bo1.aabbEnlargeFactor = ig2.interactionDetectionFactor = 1.
            if recorded(O.iter, every):
                record(out, updater)
    return out


data = {}
data['tension'] = scene(cpm(), cpm(), .95, [(N * 1.0, 3000)], 100, reset_factor=True)
data['tension_linear'] = scene(cpm(damLaw=0), cpm(damLaw=0), .9, [(N * 1.0, 3000)], 100,
                               law=Law2_ScGeom_CpmPhys_Cpm(omegaThreshold=.999))
data['linear_default'] = scene(cpm(damLaw=0), cpm(damLaw=0), .9, [(N * 1.0, 3000)], 100)
data['shear'] = scene(cpm(), cpm(young=30e9, poisson=.25, sigmaT=3e6, frictionAngle=.5, epsCrackOnset=1.2e-4,
                                 relDuctility=20), .9, [(T * 1.0, 3000)], 100)
data['compression'] = scene(cpm(), cpm(), .9, [(-N * 1.0, 1500), (N * 1.0, 3000)], 100,
                            law=Law2_ScGeom_CpmPhys_Cpm(epsSoft=-1e-3, relKnSoft=.3))
data['prestress'] = scene(cpm(isoPrestress=-2e6, equivStrainShearContrib=.5),
                          cpm(isoPrestress=-1e6, equivStrainShearContrib=.3), .9, [((N + T) * .7, 3000)], 100)
data['noncohesive'] = scene(cpm(), cpm(), .9, [(-N * 1.0, 500), (N * 1.0, 1000)], 100,
                            ip2=Ip2_CpmMat_CpmMat_CpmPhys(cohesiveThresholdIter=0))
data['neverDamage'] = scene(cpm(neverDamage=True), cpm(), .9, [(N * 1.0, 1000)], 100)
data['frict_cpm'] = scene(FrictMat(young=1e9, poisson=.3, frictionAngle=.4, density=2000), cpm(), .88,
                          [(-N * 1.0 + T * .5, 500)], 100)
def rate_run():
    return scene(cpm(dmgTau=1e-5, dmgRateExp=2, plTau=1e-5, plRateExp=2),
                 cpm(dmgTau=1e-5, dmgRateExp=2, plTau=1e-5, plRateExp=2), .95, [(N * 1.0, 3000)], 100,
                 law=Law2_ScGeom_CpmPhys_Cpm(yieldSurfType=0, yieldLogSpeed=.5), reset_factor=True)


import json
same = lambda a, b: json.dumps(tojson(a)) == json.dumps(tojson(b))   # NaN == NaN here
strip = lambda recs, keys: [{k: v for k, v in r.items() if k not in keys} for r in recs]
data['rate_equals_tension'] = catch(lambda: same(strip(rate_run(), PHYS[-4:]), strip(data['tension'], PHYS[-4:])))
energyLaw = Law2_ScGeom_CpmPhys_Cpm()
scene(cpm(), cpm(), .9, [(N * .5 + T, 500)], 1000, law=energyLaw)
data['elasticEnergy'] = [O.iter, energyLaw.elasticEnergy(), O.interactions[0, 1].phys.omega]
G_ARGS = [(2e-4, 1e-4, 3e-3), (5e-5, 1e-4, 3e-3), (2e-4, 1e-4, 3e-3, True), (2e-4, 1e-4, 3e-3, False, 0),
          (5e-3, 1e-4, 3e-3, False, 0), (1e-2, 2e-4, 1e-3)]
G_INV_ARGS = [(0.5, 1e-4, 3e-3), (0.0, 1e-4, 3e-3), (0.9, 1e-4, 3e-3, False, 0), (0.99, 1e-4, 3e-3),
              (0.3, 2e-4, 1e-3, True)]
data['funcG'] = [[list(a), CpmPhys.funcG(*a)] for a in G_ARGS]
data['funcGInv'] = [[list(a), CpmPhys.funcGInv(*a)] for a in G_INV_ARGS]
data['yieldSigmaTMagnitude'] = catch(lambda: Law2_ScGeom_CpmPhys_Cpm().yieldSigmaTMagnitude(-1e6, 0., 3.5e6, .8))
data["defaults"] = {type(c).__name__: catch(lambda c=c: c.dict()) for c in (CpmMat(), CpmPhys(), Ip2_CpmMat_CpmMat_CpmPhys(),
                                                               Ip2_FrictMat_CpmMat_FrictPhys(),
                                                               Law2_ScGeom_CpmPhys_Cpm(), CpmState())}
data['defaults']['CpmStateUpdater'] = {k: v for k, v in CpmStateUpdater().dict().items() if k != 'realLast'}
data['newAssocState'] = type(CpmMat().newAssocState()).__name__
data['sphere_state'] = type(sphere((0, 0, 0), 1, material=CpmMat()).state).__name__
dump('cpm', data)
