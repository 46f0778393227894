# utilities: tutorial-02-like scene (facetBox + 20 spheres from makeCloud, seed=1,
# gravity -9.81, damping .4, O.dt=.5*PWaveTimeStep()) after 2000 steps. Records the
# full state (positions, radii, velocities, forces, interactions) and the values of the
# utils helpers, so each helper can be recomputed from the recorded state.
# Regenerate: cd tests/reference/yade && yade -n -x utilities.py
# YADE 2023.02a
import sys; import os; sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from _common import catch, dump
from yade import geom, pack

facets = O.bodies.append(geom.facetBox((.5, .5, .5), (.5, .5, .5), wallMask=31))
sp = pack.SpherePack()
n = sp.makeCloud((0, 0, 0), (1, 1, 1), rMean=.1, rRelFuzz=.3, num=20, seed=1)
spheres = sp.toSimulation()
O.engines = [
    ForceResetter(),
    InsertionSortCollider([Bo1_Sphere_Aabb(), Bo1_Facet_Aabb()]),
    InteractionLoop([Ig2_Sphere_Sphere_ScGeom(), Ig2_Facet_Sphere_ScGeom()],
                    [Ip2_FrictMat_FrictMat_FrictPhys()],
                    [Law2_ScGeom_FrictPhys_CundallStrack()]),
    NewtonIntegrator(gravity=(0, 0, -9.81), damping=0.4)]
out = {'makeCloud_returned': n, 'facet_ids': facets, 'sphere_ids': spheres,
       'PWaveTimeStep_initial': utils.PWaveTimeStep()}
O.dt = .5 * utils.PWaveTimeStep()
out['O.dt'] = O.dt
out['initial_spheres'] = [{'id': b.id, 'pos': b.state.pos, 'radius': b.shape.radius} for b in O.bodies if b.id in spheres]
O.run(2000, True)

def body(b):
    d = {'id': b.id, 'shape': type(b.shape).__name__, 'pos': b.state.pos, 'ori': b.state.ori,
         'vel': b.state.vel, 'angVel': b.state.angVel, 'mass': b.state.mass, 'inertia': b.state.inertia,
         'dynamic': b.dynamic, 'f': O.forces.f(b.id), 't': O.forces.t(b.id),
         'aabb': [b.bound.min, b.bound.max] if b.bound else None}
    if type(b.shape).__name__ == 'Sphere':
        d['radius'] = b.shape.radius
    else:
        d['global_vertices'] = [b.state.pos + b.state.ori * v for v in b.shape.vertices]
    return d

out.update({
    'O.iter': O.iter, 'O.time': O.time,
    'material': O.materials[0].dict(),
    'bodies': [body(b) for b in O.bodies],
    'interactions': [{'id1': i.id1, 'id2': i.id2, 'isReal': i.isReal,
                      'penetrationDepth': i.geom.penetrationDepth if i.isReal else None,
                      'normalForce': i.phys.normalForce if i.isReal else None,
                      'shearForce': i.phys.shearForce if i.isReal else None} for i in O.interactions],
    'pairs_in_O.interactions': [(i.id1, i.id2) for i in O.interactions],  # iteration: real ones only?
    'pairs_in_O.interactions.all(onlyReal=False)': catch(lambda: [(i.id1, i.id2, i.isReal) for i in O.interactions.all(onlyReal=False)]),
    'O.interactions.countReal()': O.interactions.countReal(),
    'len(O.interactions)': len(O.interactions),
})
calls = {
    'PWaveTimeStep()': lambda: utils.PWaveTimeStep(),
    'unbalancedForce()': lambda: utils.unbalancedForce(),
    'unbalancedForce(True)': lambda: utils.unbalancedForce(True),
    'kineticEnergy()': lambda: utils.kineticEnergy(),
    'avgNumInteractions()': lambda: utils.avgNumInteractions(),
    'avgNumInteractions(skipFree=True)': lambda: utils.avgNumInteractions(skipFree=True),
    'porosity()': lambda: utils.porosity(),
    'porosity(1.0)': lambda: utils.porosity(1.0),
    'aabbExtrema()': lambda: utils.aabbExtrema(),
    'aabbExtrema(centers=True)': lambda: utils.aabbExtrema(centers=True),
    'aabbDim()': lambda: utils.aabbDim(),
    'getSpheresVolume()': lambda: utils.getSpheresVolume(),
    'getSpheresMass()': lambda: utils.getSpheresMass(),
    'sumForces(facet_ids,(0,0,1))': lambda: utils.sumForces(facets, (0, 0, 1)),
    'sumForces(sphere_ids,(0,0,1))': lambda: utils.sumForces(spheres, (0, 0, 1)),
}
out['utils'] = {k: catch(f) for k, f in calls.items()}
dump('utilities', out)
