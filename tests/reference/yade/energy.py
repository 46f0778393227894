# energy: bouncing-sphere scene (sphere r=.5 at z=2 falling on a fixed sphere r=.5 at
# the origin, default material from utils.sphere), O.trackEnergy=True, dt=1e-5,
# NewtonIntegrator(gravity=(0,0,-9.81)) with damping=0.1 and with damping=0.
# Every 1000 steps for 60000 steps: all O.energy terms, O.energy.total(), position,
# velocity of body 1, utils.kineticEnergy(), utils.unbalancedForce(), contact state;
# the same every 100 steps while the spheres are in contact.
# Regenerate: cd tests/reference/yade && yade -n -x energy.py
# YADE 2023.02a
import sys; import os; sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from _common import catch, dump, tojson


def run(damping):
    O.reset()
    O.bodies.append([utils.sphere((0, 0, 0), .5, fixed=True), utils.sphere((0, 0, 2), .5)])
    O.engines = [ForceResetter(),
                 InsertionSortCollider([Bo1_Sphere_Aabb()]),
                 InteractionLoop([Ig2_Sphere_Sphere_ScGeom()], [Ip2_FrictMat_FrictMat_FrictPhys()],
                                 [Law2_ScGeom_FrictPhys_CundallStrack()]),
                 NewtonIntegrator(gravity=(0, 0, -9.81), damping=damping)]
    O.dt = 1e-5
    O.trackEnergy = True
    b = O.bodies[1]
    rows = []
    contact_steps = []
    fine = []
    def row():
        i = O.interactions[0, 1] if O.interactions.has(0, 1) and O.interactions[0, 1].isReal else None
        return tojson({
            'iter': O.iter, 'time': O.time, 'energy': dict(O.energy.items()),
            'energy_total': O.energy.total(), 'pos': b.state.pos, 'vel': b.state.vel,
            'kineticEnergy': utils.kineticEnergy(), 'unbalancedForce': catch(utils.unbalancedForce),
            'f1': O.forces.f(1), 'contact': None if i is None else
            {'penetrationDepth': i.geom.penetrationDepth, 'normalForce': i.phys.normalForce,
             'shearForce': i.phys.shearForce}})
    for k in range(60):
        for j in range(1000):
            O.step()
            if O.interactions.countReal() and (not contact_steps or contact_steps[-1][1] != O.iter - 1):
                contact_steps.append([O.iter, O.iter])
            elif O.interactions.countReal():
                contact_steps[-1][1] = O.iter
            if O.interactions.countReal() and O.iter % 100 == 0:
                fine.append(row())
        rows.append(row())
    return {'damping': damping, 'mass': b.state.mass, 'material': O.materials[0].dict(),
            'energy_keys': list(O.energy.keys()),
            'contact_periods_[first_iter,last_iter]': contact_steps, 'every_1000_steps': rows,
            'during_contact_every_100_steps': fine}

out = {'scene': 'fixed sphere r=.5 at (0,0,0) (id 0), free sphere r=.5 at (0,0,2) (id 1), default material; '
                'ForceResetter, InsertionSortCollider(Bo1_Sphere_Aabb), InteractionLoop(Ig2_Sphere_Sphere_ScGeom, '
                'Ip2_FrictMat_FrictMat_FrictPhys, Law2_ScGeom_FrictPhys_CundallStrack), '
                'NewtonIntegrator(gravity=(0,0,-9.81), damping=d); O.dt=1e-5; O.trackEnergy=True',
       'damping_0.1': tojson(run(0.1)), 'damping_0': tojson(run(0.0))}
dump('energy', out)
