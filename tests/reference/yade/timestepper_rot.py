# timestepper_rot: GlobalStiffnessTimeStepper (YADE 2023.02a) with contacts that have rolling and twisting
# stiffness (RotStiffFrictPhys: CohFrictPhys's kr, ktw; MindlinPhys's kr, ktw from the Ip2's krot, ktwist).
# Scenes (no gravity, damping .2, timeStepUpdateInterval 1, safety .8 unless said):
#   chain: the 6 spheres of timestepper.py's chain (first one fixed), two CohFrictMats (alphaKr 3 and 20,
#          alphaKtw 1 and 8, momentRotationLaw), ScGeom6D + CohesionMoment: O.dt, previousDt after each of
#          30 steps; the bodies and contacts (kn, ks, kr, ktw, normal, refR) after step 1; safety .5 also.
#   pair_cohfrict: a free sphere (r .4) on a fixed one (r .5), normal along (1,2,3) (and x), for several
#          (alphaKr, alphaKtw, momentRotationLaw): O.dt after one step and the contact's stiffnesses.
#   pair_mindlin: the same pair with Ip2_FrictMat_FrictMat_MindlinPhys(krot, ktwist), includeMoment on/off.
# Regenerate: cd tests/reference/yade && yade -n -x timestepper_rot.py
import sys; import os; sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from _common import dump, tojson

CHAIN = [((0, 0, 0), .5), ((.75, .2, 0), .3), ((1.3, .2, .3), .4), ((1.8, .55, .45), .35), ((2.4, .6, .1), .45),
         ((2.9, .9, .1), .3)]
COH = (Ig2_Sphere_Sphere_ScGeom6D, Ip2_CohFrictMat_CohFrictMat_CohFrictPhys, Law2_ScGeom6D_CohFrictPhys_CohesionMoment)


def engines(ts, ig2, ip2, law):
    O.engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb()]),
                 InteractionLoop([ig2], [ip2], [law]), ts, NewtonIntegrator(damping=.2, gravity=(0, 0, 0))]


def contacts():
    return [{'id1': i.id1, 'id2': i.id2, 'kn': i.phys.kn, 'ks': i.phys.ks, 'kr': i.phys.kr, 'ktw': i.phys.ktw,
             'normal': i.geom.normal, 'refR1': i.geom.refR1, 'refR2': i.geom.refR2} for i in O.interactions]


def chain(safety):
    O.reset()
    m1 = O.materials.append(CohFrictMat(young=1e7, poisson=.3, density=2600, frictionAngle=.5, alphaKr=3,
                                        alphaKtw=1, momentRotationLaw=True, isCohesive=False))
    m2 = O.materials.append(CohFrictMat(young=3e7, poisson=.8, density=1500, frictionAngle=.5, alphaKr=20,
                                        alphaKtw=8, momentRotationLaw=True, isCohesive=False))
    O.bodies.append([sphere(c, r, material=(m1 if k % 2 == 0 else m2), fixed=(k == 0))
                     for k, (c, r) in enumerate(CHAIN)])
    O.bodies[5].state.angVel = (0, 0, 3)
    ts = GlobalStiffnessTimeStepper(timeStepUpdateInterval=1, timestepSafetyCoefficient=safety)
    engines(ts, *(f() for f in COH))
    O.dt = 1e-3
    steps = []
    for k in range(30):
        O.step()
        steps.append({'iter': O.iter, 'dt': O.dt, 'previousDt': ts.previousDt, 'contacts': len(O.interactions)})
        if k == 0:
            after_1 = {'bodies': [{'mass': b.state.mass, 'inertia': b.state.inertia} for b in O.bodies],
                       'contacts': contacts()}
    return tojson({'safety': safety, 'steps': steps, 'after_1': after_1})


def pair(ip2, law, mat, normal=(1, 2, 3)):
    O.reset()
    m = O.materials.append(mat)
    n = Vector3(*normal).normalized()
    O.bodies.append([sphere((0, 0, 0), .5, material=m, fixed=True), sphere(n * .89, .4, material=m)])
    ts = GlobalStiffnessTimeStepper(timeStepUpdateInterval=1)
    engines(ts, Ig2_Sphere_Sphere_ScGeom6D(), ip2, law)
    O.dt = 1e-3
    O.step()
    b = O.bodies[1].state
    return tojson({'normal': normal, 'dt': O.dt, 'mass': b.mass, 'inertia': b.inertia, 'contacts': contacts()})


def cohfrict(akr, aktw, mrl, normal=(1, 2, 3)):
    mat = CohFrictMat(young=1e7, poisson=.3, density=2600, frictionAngle=.5, alphaKr=akr, alphaKtw=aktw,
                      momentRotationLaw=mrl, isCohesive=False)
    out = pair(COH[1](), COH[2](), mat, normal)
    out.update(alphaKr=akr, alphaKtw=aktw, momentRotationLaw=mrl)
    return out


def mindlin(krot, ktwist, moment):
    mat = FrictMat(young=1e7, poisson=.3, density=2600, frictionAngle=.5)
    out = pair(Ip2_FrictMat_FrictMat_MindlinPhys(krot=krot, ktwist=ktwist),
               Law2_ScGeom_MindlinPhys_Mindlin(includeMoment=moment), mat)
    out.update(krot=krot, ktwist=ktwist, includeMoment=moment)
    return out


data = {
    'chain': chain(.8),
    'chain_safety_.5': chain(.5),
    'pair_cohfrict': [cohfrict(akr, aktw, mrl) for mrl in (False, True)
                      for akr, aktw in ((0, 0), (2, 0), (0, 2), (50, 0), (0, 50), (50, 50), (5, 3))]
                     + [cohfrict(akr, aktw, True, (1, 0, 0)) for akr, aktw in ((2, 0), (0, 2))],
    'pair_mindlin': [mindlin(*k) for k in ((0, 0, False), (1e5, 0, False), (0, 1e5, True), (1e5, 2e5, True))],
}
dump('timestepper_rot', data)
