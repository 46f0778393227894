# contacts: one O.step() on small sphere/sphere, sphere/facet, sphere/wall and
# sphere/box scenes with the FrictMat/FrictPhys/CundallStrack chain; records,
# for every interaction, ids (order), geometry (ScGeom), physics (FrictPhys) and
# the resulting per-body forces/torques, plus the state after the step.
# Scene (g) records a sheared sphere-sphere contact step by step for 50 steps.
# Regenerate: cd tests/reference/yade && yade -n -x contacts.py
# YADE 2023.02a
import sys; import os; sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from _common import dump, tojson


def setup():
    O.reset()
    O.engines = [
        ForceResetter(),
        InsertionSortCollider([Bo1_Sphere_Aabb(), Bo1_Facet_Aabb(), Bo1_Wall_Aabb(), Bo1_Box_Aabb()]),
        InteractionLoop(
            [Ig2_Sphere_Sphere_ScGeom(), Ig2_Facet_Sphere_ScGeom(), Ig2_Wall_Sphere_ScGeom(), Ig2_Box_Sphere_ScGeom()],
            [Ip2_FrictMat_FrictMat_FrictPhys()],
            [Law2_ScGeom_FrictPhys_CundallStrack()]),
        NewtonIntegrator(gravity=(0, 0, -10), damping=0)]
    O.dt = 1e-5
    return O.materials.append(FrictMat(young=1e7, poisson=.3, density=1000, frictionAngle=.5))

def intr(i):  # (g.dict() / p.dict() hold nothing beyond these fields)
    g, p = i.geom, i.phys
    return {'id1': i.id1, 'id2': i.id2, 'isReal': i.isReal,
            'geom_class': type(g).__name__, 'penetrationDepth': g.penetrationDepth,
            'normal': g.normal, 'contactPoint': g.contactPoint,
            'refR1': g.refR1, 'refR2': g.refR2,
            'shearInc': g.shearInc,
            'phys_class': type(p).__name__, 'kn': p.kn, 'ks': p.ks,
            'tangensOfFrictionAngle': p.tangensOfFrictionAngle,
            'normalForce': p.normalForce, 'shearForce': p.shearForce}

def record():
    return {'interactions': [intr(i) if i.isReal else {'id1': i.id1, 'id2': i.id2, 'isReal': False}
                             for i in O.interactions],
            'bodies': [{'id': b.id, 'shape': type(b.shape).__name__, 'f': O.forces.f(b.id),
                        't': O.forces.t(b.id), 'pos': b.state.pos, 'vel': b.state.vel,
                        'angVel': b.state.angVel, 'mass': b.state.mass} for b in O.bodies]}

def run_scene(make_bodies, desc):
    try:
        m = setup()
        O.bodies.append(make_bodies(m))
        O.step()
        r = record()
    except Exception as e:
        r = {'exception': type(e).__name__, 'message': str(e)}
    r['description'] = desc
    return r

def two_spheres(m):
    m1 = O.materials.append(FrictMat(young=1e7, poisson=.3, density=1000, frictionAngle=.5))
    m2 = O.materials.append(FrictMat(young=2e7, poisson=.2, density=1000, frictionAngle=.3))
    return [utils.sphere((0, 0, 0), .5, material=m1), utils.sphere((0, 0, .99), .5, material=m2)]

F = [(-1, -1, 0), (2, -1, 0), (-1, 2, 0)]
S = lambda pos, m: utils.sphere(pos, .5, material=m)
scenes = {
 'a_sphere_sphere': (two_spheres, 'spheres r=.5 at (0,0,0) [E=1e7,nu=.3,phi=.5] and (0,0,.99) [E=2e7,nu=.2,phi=.3]'),
 'b_facet_sphere': (lambda m: [utils.facet(F, material=m), S((.2, .3, .49), m)],
                    'facet %s (id0) then sphere r=.5 at (.2,.3,.49) (id1)' % (F,)),
 'c1_facet_edge': (lambda m: [utils.facet(F, material=m), S((.5, -1.3, .3), m)],
                   'facet %s (id0), sphere r=.5 at (.5,-1.3,.3): contact on edge y=-1' % (F,)),
 'c2_facet_vertex': (lambda m: [utils.facet(F, material=m), S((-1.3, -1.3, .2), m)],
                     'facet %s (id0), sphere r=.5 at (-1.3,-1.3,.2): contact on vertex (-1,-1,0)' % (F,)),
 'd_wall_sphere': (lambda m: [utils.wall(0, axis=2, material=m), S((0, 0, .49), m)],
                   'wall(0,axis=2) (id0) then sphere r=.5 at (0,0,.49)'),
 'd2_wall_below_sphere': (lambda m: [utils.wall(0, axis=2, material=m), S((0, 0, -.49), m)],
                          'wall(0,axis=2) (id0) then sphere r=.5 at (0,0,-.49) (below the wall)'),
 'e_box_sphere': (lambda m: [utils.box((0, 0, -1), (1, 1, 1), fixed=True, material=m), S((.1, .2, .49), m)],
                  'box((0,0,-1),(1,1,1),fixed=True) (id0) then sphere r=.5 at (.1,.2,.49)'),
 'f_sphere_then_facet': (lambda m: [S((.2, .3, .49), m), utils.facet(F, material=m)],
                         'sphere r=.5 at (.2,.3,.49) (id0) then facet %s (id1)' % (F,)),
 'f_sphere_then_wall': (lambda m: [S((0, 0, .49), m), utils.wall(0, axis=2, material=m)],
                        'sphere (id0) then wall(0,axis=2) (id1)'),
 'f_sphere_then_box': (lambda m: [S((.1, .2, .49), m), utils.box((0, 0, -1), (1, 1, 1), fixed=True, material=m)],
                       'sphere (id0) then fixed box (id1)'),
 'f_three_spheres_reverse': (lambda m: [S((0, 0, 1.98), m), S((0, 0, .99), m), S((0, 0, 0), m)],
                             'three spheres r=.5 stacked, created top-down (ids 0,1,2 at z=1.98,.99,0)'),
}
out = {'engines': 'ForceResetter, InsertionSortCollider(4 Bo1), InteractionLoop(4 Ig2, Ip2_FrictMat_FrictMat_FrictPhys, '
                  'Law2_ScGeom_FrictPhys_CundallStrack), NewtonIntegrator(gravity=(0,0,-10),damping=0); O.dt=1e-5; one O.step()',
       'material': 'FrictMat(young=1e7,poisson=.3,density=1000,frictionAngle=.5) unless stated'}
for name, (mk, desc) in scenes.items():
    out[name] = run_scene(mk, desc)

# (g) sheared, approaching sphere-sphere contact, 50 steps
def sheared(vel, angVel):
    setup()
    b1, b2 = two_spheres(None)
    O.bodies.append([b1, b2])
    b2.state.vel, b2.state.angVel = vel, angVel
    steps = []
    for k in range(50):
        O.step()
        i = O.interactions[0, 1] if O.interactions.has(0, 1) else None
        rec = {'iter': O.iter, 'intr': intr(i) if i is not None and i.isReal else None}
        rec.update({'b%d_%s' % (b.id, a): getattr(b.state, a) for b in O.bodies for a in ('pos', 'vel', 'angVel', 'ori')})
        rec.update({'f%d' % b.id: O.forces.f(b.id) for b in O.bodies})
        rec.update({'t%d' % b.id: O.forces.t(b.id) for b in O.bodies})
        steps.append(tojson(rec))  # convert now: some attributes are live references
    return {'description': 'scene (a) with sphere 2 given vel=%s, angVel=%s; same engines, dt=1e-5; '
                           'record after each of 50 O.step() calls (forces are those computed in that step, '
                           'state is after NewtonIntegrator of that step)' % (vel, angVel),
            'steps': steps}
# as in the brief: the rotation (0,2,0) nearly cancels the tangential velocity at the contact
out['g_sheared_sphere_sphere'] = sheared((1, 0, -.1), (0, 2, 0))
# variants with real sliding: relative tangential velocity 2 m/s; then fast enough to reach Coulomb slip
out['g2_sheared_sphere_sphere'] = sheared((1, 0, -.1), (0, -2, 0))
out['g3_sliding_sphere_sphere'] = sheared((100, 30, -.1), (1, 0, 3))
dump('contacts', out)
