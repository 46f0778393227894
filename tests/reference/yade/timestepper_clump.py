# timestepper_clump: GlobalStiffnessTimeStepper (YADE 2023.02a) with clumps. FrictMat (young 6e6, poisson .8 so
# that ks/kn = .8 and the rotational term can govern, density 2600), no gravity unless said, damping .4,
# timeStepUpdateInterval 1, safety .6.
#   touch_x, touch_z, touch_xz: a clump of 3 spheres (r .2) along z touched by fixed spheres (r .15) on its
#          bottom member along x, its top member along z, or both: O.dt after one step, the clump's mass,
#          inertia, the member's mass and the contacts (kn, ks, normal, refR).
#   two_clumps: a 2-sphere clump touching another 2-sphere clump (no fixed body): O.dt after one step.
#   drop: 4 clumps of 2-3 spheres falling (gravity -9.81 z) on a row of fixed spheres: O.dt and previousDt
#          after each of 60 steps, and every body's final position.
#   zero_force: a sphere (r .5, poisson .4) resting on a fixed box at exactly zero penetration and overlapping a
#          fixed sphere by .1 along x: O.dt after one step (the unloaded contact adds no stiffness) and the
#          contacts (with their normal forces).
# Regenerate: cd tests/reference/yade && yade -n -x timestepper_clump.py
import sys; import os; sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from _common import dump, tojson


def engines(gravity=(0, 0, 0)):
    ts = GlobalStiffnessTimeStepper(timestepSafetyCoefficient=.6, timeStepUpdateInterval=1)
    O.engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb()]),
                 InteractionLoop([Ig2_Sphere_Sphere_ScGeom()], [Ip2_FrictMat_FrictMat_FrictPhys()],
                                 [Law2_ScGeom_FrictPhys_CundallStrack()]),
                 ts, NewtonIntegrator(damping=.4, gravity=gravity)]
    return ts


def material():
    return O.materials.append(FrictMat(young=6e6, poisson=.8, frictionAngle=.1, density=2600))


def contacts():
    return [{'id1': i.id1, 'id2': i.id2, 'kn': i.phys.kn, 'ks': i.phys.ks, 'normal': i.geom.normal,
             'refR1': i.geom.refR1, 'refR2': i.geom.refR2} for i in O.interactions]


def touch(fixed_centers):
    O.reset()
    material()
    cid, members = O.bodies.appendClumped([sphere((0, 0, 0), .2), sphere((0, 0, .4), .2), sphere((0, 0, .8), .2)])
    O.bodies.append([sphere(c, .15, fixed=True) for c in fixed_centers])
    engines()
    O.dt = 1e-3
    O.step()
    c = O.bodies[cid].state
    return tojson({'dt': O.dt, 'clump_mass': c.mass, 'clump_inertia': c.inertia,
                   'member_mass': O.bodies[members[0]].state.mass, 'contacts': contacts()})


def two_clumps():
    O.reset()
    material()
    O.bodies.appendClumped([sphere((0, 0, 0), .2), sphere((0, .3, 0), .2)])
    O.bodies.appendClumped([sphere((.34, 0, 0), .15), sphere((.34, 0, .25), .15)])
    engines()
    O.dt = 1e-3
    O.step()
    return tojson({'dt': O.dt, 'contacts': contacts()})


def drop():
    O.reset()
    material()
    O.bodies.append([sphere((x * .4, 0, 0), .2, fixed=True) for x in range(-3, 4)])
    O.bodies.appendClumped([sphere((-1, 0, .45), .2), sphere((-.75, .1, .6), .15)])
    O.bodies.appendClumped([sphere((-.3, 0, .5), .18), sphere((-.1, .05, .62), .12), sphere((.05, -.1, .7), .1)])
    O.bodies.appendClumped([sphere((.45, 0, .38), .2), sphere((.55, .2, .55), .17)])
    O.bodies.appendClumped([sphere((1.1, .05, .45), .16), sphere((1.2, -.1, .7), .2), sphere((1.0, 0, .8), .1)])
    ts = engines((0, 0, -9.81))
    O.dt = 1e-3
    steps = []
    for k in range(60):
        O.step()
        steps.append({'iter': O.iter, 'dt': O.dt, 'previousDt': ts.previousDt, 'contacts': len(O.interactions)})
    return tojson({'steps': steps, 'final_pos': [b.state.pos for b in O.bodies]})


def zero_force():
    O.reset()
    O.materials.append(FrictMat(young=6e6, poisson=.4, frictionAngle=.1, density=2600))
    O.bodies.append([sphere((0, 0, 0), .5), box((0, 0, -1), (.5, .5, .5), fixed=True),
                     sphere((.9, 0, 0), .5, fixed=True)])
    O.engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb(), Bo1_Box_Aabb()]),
                 InteractionLoop([Ig2_Sphere_Sphere_ScGeom(), Ig2_Box_Sphere_ScGeom()],
                                 [Ip2_FrictMat_FrictMat_FrictPhys()], [Law2_ScGeom_FrictPhys_CundallStrack()]),
                 GlobalStiffnessTimeStepper(timestepSafetyCoefficient=.6, timeStepUpdateInterval=1),
                 NewtonIntegrator(damping=.4, gravity=(0, 0, 0))]
    O.dt = 1e-3
    O.step()
    out = {'dt': O.dt, 'mass': O.bodies[0].state.mass, 'contacts': contacts()}
    for c, i in zip(out['contacts'], O.interactions):
        c['normalForce'] = i.phys.normalForce
    return tojson(out)


data = {
    'zero_force': zero_force(),
    'touch_x': touch([(.34, 0, 0)]),
    'touch_z': touch([(0, 0, 1.14)]),
    'touch_xz': touch([(.34, 0, 0), (0, 0, 1.14)]),
    'two_clumps': two_clumps(),
    'drop': drop(),
}
dump('timestepper_clump', data)
