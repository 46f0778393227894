# timestepper: GlobalStiffnessTimeStepper (YADE 2023.02a) on small scenes, O.dt after every step.
# Scenes (no gravity unless said, FrictMat + Cundall-Strack, damping .2):
#   chain: 6 spheres of radii .5/.3/.4/.35/.45/.3 in a bent chain, overlapping, first one fixed, materials of
#          two Young's moduli and shear ratios; 40 steps with timeStepUpdateInterval 1, then the same with 3
#          and with maxDt; bodies (mass, inertia) and contacts (ids, kn, ks, normal, refR) after step 1.
#   release: a free sphere squeezed between two fixed ones, one of which moves away: the step grows at most
#          x1.05 per update when a contact ends.
#   apart: no contact: defaultDt -1 (safety * PWaveTimeStep) and defaultDt 1e-4.
#   viscel: two ViscElMat spheres (kn 5e6, ks 2e6) with dashpots cn/cs, viscEl False and True.
#   dynDt: O.dynDt and the stepper's `active` when switched; O.dynDt=True without a stepper.
# Regenerate: cd tests/reference/yade && yade -n -x timestepper.py
import sys; import os; sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from _common import dump, tojson, catch

CHAIN = [((0, 0, 0), .5), ((.75, .2, 0), .3), ((1.3, .2, .3), .4), ((1.8, .55, .45), .35), ((2.4, .6, .1), .45),
         ((2.9, .9, .1), .3)]


def engines(ts, damping=.2, viscel=False):
    ip2, law = ((Ip2_ViscElMat_ViscElMat_ViscElPhys(), Law2_ScGeom_ViscElPhys_Basic()) if viscel else
                (Ip2_FrictMat_FrictMat_FrictPhys(), Law2_ScGeom_FrictPhys_CundallStrack()))
    O.engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb()]),
                 InteractionLoop([Ig2_Sphere_Sphere_ScGeom()], [ip2], [law]),
                 ts, NewtonIntegrator(damping=damping, gravity=(0, 0, 0))]


def record(ts, n):
    out = []
    for k in range(n):
        O.step()
        out.append({'iter': O.iter, 'dt': O.dt, 'previousDt': ts.previousDt, 'contacts': len(O.interactions)})
    return out


def chain(**kw):
    O.reset()
    m1 = O.materials.append(FrictMat(young=1e7, poisson=.3, density=2600, frictionAngle=.5))
    m2 = O.materials.append(FrictMat(young=3e7, poisson=.8, density=1500, frictionAngle=.5))
    O.bodies.append([sphere(c, r, material=(m1 if k % 2 == 0 else m2), fixed=(k == 0)) for k, (c, r) in enumerate(CHAIN)])
    ts = GlobalStiffnessTimeStepper(**kw)
    engines(ts)
    O.dt = 1e-3
    steps = record(ts, 1)
    bodies = [{'mass': b.state.mass, 'inertia': b.state.inertia, 'dynamic': b.dynamic} for b in O.bodies]
    contacts = [{'id1': i.id1, 'id2': i.id2, 'kn': i.phys.kn, 'ks': i.phys.ks, 'normal': i.geom.normal,
                 'refR1': i.geom.refR1, 'refR2': i.geom.refR2, 'penetrationDepth': i.geom.penetrationDepth}
                for i in O.interactions]
    steps += record(ts, 39)
    return tojson({'kw': kw, 'steps': steps, 'bodies_after_1': bodies, 'contacts_after_1': contacts,
                   'final_pos': [b.state.pos for b in O.bodies]})


def release(interval):
    O.reset()
    m = O.materials.append(FrictMat(young=1e7, poisson=.3, density=2600, frictionAngle=.5))
    O.bodies.append([sphere((0, 0, 0), .5, material=m), sphere((.95, 0, 0), .5, material=m, fixed=True),
                     sphere((-.95, 0, 0), .5, material=m, fixed=True)])
    O.bodies[1].state.vel = (1, 0, 0)
    ts = GlobalStiffnessTimeStepper(timeStepUpdateInterval=interval)
    engines(ts, damping=0)
    O.dt = 1e-3
    return tojson({'interval': interval, 'steps': record(ts, 12), 'mass': O.bodies[0].state.mass})


def apart(default):
    O.reset()
    m = O.materials.append(FrictMat(young=1e7, poisson=.3, density=2600, frictionAngle=.5))
    O.bodies.append([sphere((0, 0, 0), .5, material=m), sphere((1.1, 0, 0), .3, material=m)])
    ts = GlobalStiffnessTimeStepper(defaultDt=default, timestepSafetyCoefficient=.7)
    engines(ts)
    O.dt = 1e-3
    return tojson({'defaultDt': default, 'steps': record(ts, 2), 'PWaveTimeStep': PWaveTimeStep()})


def viscel(cn, cs, on):
    O.reset()
    m = O.materials.append(ViscElMat(density=2600, kn=5e6, ks=2e6, cn=cn, cs=cs, frictionAngle=.5))
    O.bodies.append([sphere((0, 0, 0), .5, material=m), sphere((.9, 0, 0), .5, material=m)])
    ts = GlobalStiffnessTimeStepper(viscEl=on)
    engines(ts, damping=0, viscel=True)
    O.dt = 1e-3
    O.step()
    i = O.interactions[0, 1]
    return tojson({'cn': cn, 'cs': cs, 'viscEl': on, 'dt': O.dt, 'phys': {k: getattr(i.phys, k) for k in
                                                                        ('kn', 'ks', 'cn', 'cs')}})


def dyn():
    O.reset()
    out = {'fresh_engines_dynDt': O.dynDt}
    ts = GlobalStiffnessTimeStepper()
    engines(ts)
    out['with_stepper'] = [O.dynDt, ts.active]
    O.dynDt = False
    out['after_dynDt_False'] = [O.dynDt, ts.active]
    ts.active = True
    out['after_active_True'] = [O.dynDt, ts.active]
    O.engines = O.engines[:3] + O.engines[4:]
    out['without_stepper'] = O.dynDt
    def switch():
        O.dynDt = True
    out['switch_without_stepper'] = catch(switch)
    return out


data = {
    'chain_1': chain(timeStepUpdateInterval=1),
    'chain_3': chain(timeStepUpdateInterval=3, timestepSafetyCoefficient=.5),
    'chain_maxDt': chain(timeStepUpdateInterval=1, maxDt=.003),
    'release_1': release(1),
    'release_3': release(3),
    'apart_default': apart(-1),
    'apart_1e-4': apart(1e-4),
    'viscel': [viscel(cn, cs, on) for on in (False, True) for cn, cs in ((1e6, 5e5), (1e6, 1e4), (1e4, 1e6),
                                                                          (2e5, 1e5), (1e5, 5e4))],
    'dynDt': dyn(),
}
dump('timestepper', data)
