# viscel: binary collisions with ViscElMat / ViscElPhys / Law2_ScGeom_ViscElPhys_Basic,
# no gravity, no damping, dt=1e-6. Records the contact's kn, cn, ks, cs, friction,
# the velocities every 10 steps during contact, the contact duration in steps,
# the velocities after separation and the normal restitution ratio.
# Runs: head-on en=.3/.7, explicit kn/cn/ks/cs, sphere vs fixed sphere, oblique impacts.
# Regenerate: cd tests/reference/yade && yade -n -x viscel.py
# YADE 2023.02a
import sys; import os; sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from _common import dump, tojson

R = 0.01
GAP = 1e-6  # head-on: centres at -(R+GAP) and +(R+GAP)
C = 3 ** .5 / 2 * R
OBLIQUE = ((-(C + GAP), -R / 2, 0), (C + GAP, R / 2, 0))  # line of centres at 30 deg to x, nearly touching

def run(matkw, desc, fixed2=False, v1=(1, 0, 0), v2=(-1, 0, 0),
        pos=((-(R + GAP), 0, 0), (R + GAP, 0, 0))):
    O.reset()
    O.engines = [ForceResetter(),
                 InsertionSortCollider([Bo1_Sphere_Aabb()]),
                 InteractionLoop([Ig2_Sphere_Sphere_ScGeom()], [Ip2_ViscElMat_ViscElMat_ViscElPhys()],
                                 [Law2_ScGeom_ViscElPhys_Basic()]),
                 NewtonIntegrator(gravity=(0, 0, 0), damping=0)]
    O.dt = 1e-6
    m = O.materials.append(ViscElMat(density=2300, **matkw))
    a = utils.sphere(pos[0], R, material=m)
    b = utils.sphere(pos[1], R, material=m, fixed=fixed2)
    O.bodies.append([a, b])
    a.state.vel = v1
    if not fixed2:
        b.state.vel = v2
    state = lambda: tojson({'iter': O.iter, 'v0': a.state.vel, 'v1': b.state.vel,
                            'w0': a.state.angVel, 'w1': b.state.angVel})
    before = state()
    first = last = None
    phys = None
    during = []
    steps_in_contact = 0
    for k in range(20000):
        O.step()
        real = O.interactions.has(0, 1) and O.interactions[0, 1].isReal
        if real:
            i = O.interactions[0, 1]
            steps_in_contact += 1
            if first is None:
                first = O.iter
                phys = tojson({'class': type(i.phys).__name__, 'dict': i.phys.dict(),
                               'geom_dict': i.geom.dict(), 'iter': O.iter})
            last = O.iter
            if (O.iter - first) % 10 == 0:
                s = state()
                s.update(tojson({'penetrationDepth': i.geom.penetrationDepth,
                                 'normalForce': i.phys.normalForce, 'shearForce': i.phys.shearForce,
                                 'f0': O.forces.f(0), 't0': O.forces.t(0)}))
                during.append(s)
        elif first is not None and O.iter > last + 100:
            break
    after = state()
    vrel_b = before['v1'][0] - before['v0'][0]
    vrel_a = after['v1'][0] - after['v0'][0]
    n = (b.state.pos - a.state.pos).normalized()  # line of centres at the end (for oblique runs)
    vn = lambda s: sum((s['v1'][j] - s['v0'][j]) * n[j] for j in range(3))
    return {'description': desc, 'material': matkw, 'R': R, 'density': 2300, 'dt': O.dt,
            'mass': a.state.mass, 'initial_pos': pos,
            'fixed2': fixed2, 'phys_at_first_contact': phys,
            'first_contact_iter': first, 'last_contact_iter': last,
            'contact_duration_steps': steps_in_contact, 'before': before, 'after': after,
            'restitution_x': -vrel_a / vrel_b,
            'restitution_along_final_centre_line': -vn(after) / vn(before), 'during_every_10_steps': during,
            'final_pos': [a.state.pos, b.state.pos]}

out = {}
base = dict(tc=0.001, en=0.3, et=0.3, frictionAngle=0.5)
out['headon_en0.3'] = run(base, 'head-on, equal spheres, tc=1ms en=et=.3')
out['headon_en0.7'] = run(dict(base, en=0.7, et=0.7), 'head-on, equal spheres, tc=1ms en=et=.7')
out['headon_kn_cn'] = run(dict(kn=2e5, cn=2.0, ks=1e5, cs=1.0, frictionAngle=0.5),
                          'head-on, material given as kn=2e5 cn=2 ks=1e5 cs=1')
out['vs_fixed_en0.3'] = run(base, 'moving sphere (+1,0,0) hits a fixed sphere, tc=1ms en=et=.3', fixed2=True)
out['oblique_en0.3_phi0.5'] = run(base, 'velocities +-1 along x, centres %s: line of centres at 30 deg '
                                  'to x, tc=1ms en=et=.3, frictionAngle=.5' % (OBLIQUE,), pos=OBLIQUE)
out['oblique_en0.3_phi0.05'] = run(dict(base, frictionAngle=0.05), 'as oblique_en0.3_phi0.5 but frictionAngle=.05 '
                                   '(sliding)', pos=OBLIQUE)
dump('viscel', out)
