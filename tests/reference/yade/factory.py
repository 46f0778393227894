# factory: SpheresFactory's family (CircularFactory, BoxFactory): defaults; the mass metered per step (goalMass,
# totalMass, numParticles of equal spheres); velocities (speed per step, normalVel), mask, colour, blockedDOFs,
# iterBorn; PSD classes by count (deterministic order) and by mass; where centres fall (box: centre +- extents;
# circle: within radius - r of the axis, uniform in the distance, not the area; +- length/2 along the normal);
# no overlap among spheres; a facet's bound (not the facet) refuses a place; stopIfFailed, maxParticles, maxMass;
# what PyRunners before and after the factory see in its step.
# Positions are random (YADE seeds its generator itself): only their statistics are compared.
# Regenerate: cd tests/reference/yade && yade -n -x factory.py
# YADE 2023.02a
import sys; import os
sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from _common import dump, tojson
import math

out = {'defaults': {}}
for cls in (SpheresFactory, CircularFactory, BoxFactory):
    out['defaults'][cls.__name__] = {k: v for k, v in cls().dict().items() if k not in ('ompThreads',)}


def engines(*factories, facets=False):
    return [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb(), Bo1_Facet_Aabb()]),
            InteractionLoop([Ig2_Sphere_Sphere_ScGeom(), Ig2_Facet_Sphere_ScGeom()],
                            [Ip2_FrictMat_FrictMat_FrictPhys()], [Law2_ScGeom_FrictPhys_CundallStrack()]),
            NewtonIntegrator(gravity=(0, 0, 0))] + list(factories)


def gaps(ids):
    """The smallest gap between two of the spheres ``ids`` [m] (negative: an overlap)."""
    P = [O.bodies[i].state.pos for i in ids]
    R = [O.bodies[i].shape.radius for i in ids]
    return min((P[a] - P[b]).norm() - R[a] - R[b] for a in range(len(P)) for b in range(a + 1, len(P)))


# 1. metering: equal spheres in a big box, one sphere every ~2.4 steps
O.reset()
O.materials.append(FrictMat(density=2000, label='m0'))
O.materials.append(FrictMat(density=3000, label='m1'))
f = BoxFactory(center=(1, 2, 3), extents=(0.5, 0.4, 0.3), rMin=0.01, rMax=0.01, vMin=0.5, vMax=0.5,
               massFlowRate=3.5, normal=(0, 0, -1), normalVel=(0, 1, 0), maxParticles=7, mask=6, color=(0.1, 0.2, 0.3),
               blockedDOFs='xZ', materialId=-2, label='f')
O.engines = engines(f)
O.dt = 1e-3
steps = []
for k in range(20):
    O.step()
    steps.append({'iter': O.iter, 'numParticles': f.numParticles, 'totalMass': f.totalMass, 'goalMass': f.goalMass,
                  'totalVolume': f.totalVolume, 'ids': list(f.ids)})
b = O.bodies[f.ids[0]]
out['metering'] = {'steps': steps, 'iterBorn': [O.bodies[i].iterBorn for i in f.ids],
                   'vel': [O.bodies[i].state.vel for i in f.ids], 'mask': b.mask, 'color': b.shape.color,
                   'blockedDOFs': b.state.blockedDOFs, 'material': b.material.label, 'mass': b.state.mass,
                   'massFlowRate': f.massFlowRate}

# 2. speeds: uniform in [vMin, vMax], one per step; along the normal
O.reset()
O.materials.append(FrictMat(density=2000))
f = CircularFactory(center=(0, 0, 0), radius=1, length=1, rMin=0.002, rMax=0.006, vMin=1, vMax=3, massFlowRate=0.3,
                    normal=(1, 0, 0), maxParticles=-1, maxMass=0.0035, label='f')
O.engines = engines(f)
O.dt = 1e-4
for k in range(300):
    O.step()
out['speeds'] = {'iterBorn': [O.bodies[i].iterBorn for i in f.ids], 'vel': [O.bodies[i].state.vel for i in f.ids],
                 'radii': [O.bodies[i].shape.radius for i in f.ids], 'totalMass': f.totalMass,
                 'numParticles': f.numParticles, 'goalMass': f.goalMass}

# 3. PSD: two classes by count (alternate), by mass, and ranges (exactDiam=False)
O.reset()
O.materials.append(FrictMat(density=2000))
kw = dict(maxParticles=-1, radius=1, length=1, vMin=0, vMax=0, massFlowRate=0.3, normal=(1, 0, 0))
p = CircularFactory(center=(5, 0, 0), PSDsizes=[0.004, 0.008], PSDcum=[0.5, 1.0], label='p', **kw)
q = CircularFactory(center=(15, 0, 0), PSDsizes=[0.004, 0.008], PSDcum=[0.5, 1.0], PSDcalculateMass=False, label='q', **kw)
r = CircularFactory(center=(25, 0, 0), PSDsizes=[0.002, 0.004, 0.008], PSDcum=[0.3, 1.0], exactDiam=False, label='r', **kw)
O.engines = engines(p, q, r)
O.dt = 1e-4
for k in range(600):
    O.step()
out['psd'] = {name: {'radii': [O.bodies[i].shape.radius for i in F.ids], 'totalMass': F.totalMass}
              for name, F in (('mass', p), ('count', q), ('ranges', r))}

# 4. where the centres fall, and no overlaps: 3000 spheres in one step
O.reset()
O.materials.append(FrictMat(density=2000))
c = CircularFactory(center=(0, 0, 0), radius=1.001, length=2, rMin=0.001, rMax=0.001, vMin=0, vMax=0, massFlowRate=1e6,
                    normal=(0, 1, 1), maxParticles=3000, label='c')
d = CircularFactory(center=(5, 0, 0), radius=0.05, length=0, rMin=0.002, rMax=0.002, vMin=0, vMax=0, massFlowRate=1e6,
                    normal=(1, 0, 0), maxParticles=2000, maxAttempt=2000, silent=True, label='d')
e = BoxFactory(center=(-5, 0, 0), extents=(0.05, 0.04, 0.03), rMin=0.004, rMax=0.006, vMin=0, vMax=0, massFlowRate=1e6,
               normal=(0, 0, 1), maxParticles=2000, maxAttempt=1000, stopIfFailed=False, silent=True, label='e')
O.engines = engines(c, d, e)
O.dt = 1e-4
O.step()
n = Vector3(0, 1, 1).normalized()
P = [O.bodies[i].state.pos for i in c.ids]
rad = [(x - x.dot(n) * n).norm() for x in P]
ax = [x.dot(n) for x in P]
out['circle'] = {'n': len(P), 'max_axis_distance': max(rad), 'inner_half': sum(1 for x in rad if x < 0.5) / len(P),
                 'axial': [min(ax), max(ax)], 'axial_inner_half': sum(1 for a in ax if abs(a) < 0.5) / len(P)}
P = [O.bodies[i].state.pos for i in d.ids]
out['disk'] = {'n': len(P), 'x': [min(x[0] for x in P), max(x[0] for x in P)],
               'max_axis_distance': max(math.hypot(x[1], x[2]) for x in P), 'min_gap': gaps(d.ids),
               'massFlowRate': d.massFlowRate, 'goalMass': d.goalMass}
P = [O.bodies[i].state.pos for i in e.ids]
out['box'] = {'n': len(P), 'lo': [min(x[k] for x in P) for k in range(3)], 'hi': [max(x[k] for x in P) for k in range(3)],
              'min_gap': gaps(e.ids), 'massFlowRate': e.massFlowRate}
O.step()
out['box']['n_after'] = e.numParticles
out['disk']['n_after'] = d.numParticles

# 5. obstacles: a facet whose bound covers the region refuses every place; a flat one only where boxes overlap;
# a sphere already there
O.reset()
O.materials.append(FrictMat(density=2000))
O.bodies.append(facet([(-1, -1, -1), (1, -1, 1), (0, 1, 0)]))
O.bodies.append(facet([(9, -1, 0.02), (11, -1, 0.02), (10, 1, 0.02)]))
big = O.bodies.append(sphere((20.02, 0.02, 0.02), 0.03, fixed=True))
kw = dict(extents=(0.05, 0.05, 0.05), rMin=0.005, rMax=0.005, vMin=0, vMax=0, massFlowRate=1e5, normal=(0, 0, -1),
          maxParticles=300, maxAttempt=2000, silent=True)
f = BoxFactory(center=(0, 0, 0), label='f', **kw)
g = BoxFactory(center=(10, 0, 0), label='g', **kw)
h = BoxFactory(center=(20, 0, 0), label='h', **kw)
O.engines = engines(f, g, h)
O.dt = 1e-4
O.step()
out['obstacles'] = {'diagonal_n': f.numParticles, 'diagonal_rate': f.massFlowRate, 'flat_n': g.numParticles,
                    'flat_min_gap': min(abs(O.bodies[i].state.pos[2] - 0.02) - 0.005 for i in g.ids),
                    'sphere_n': h.numParticles,
                    'sphere_min_gap': min((O.bodies[i].state.pos - O.bodies[big].state.pos).norm() - 0.035 for i in h.ids)}
# 6. a PyRunner after the factory sees the spheres made in its step (and one before it does not)
O.reset()
O.materials.append(FrictMat(density=2000))
fsee = BoxFactory(center=(0, 0, 0), extents=(0.5, 0.5, 0.5), rMin=0.01, rMax=0.01, vMin=0, vMax=0, massFlowRate=3.5,
                  normal=(0, 0, -1), maxParticles=-1, label='fsee')
O.tags['before'] = ''
O.tags['after'] = ''
O.engines = (engines()[:-1] + [PyRunner(iterPeriod=1, command="O.tags['before'] += ' %d' % fsee.numParticles"),
                               NewtonIntegrator(gravity=(0, 0, 0)), fsee,
                               PyRunner(iterPeriod=1, command="O.tags['after'] += ' %d' % fsee.numParticles")])
O.dt = 1e-3
O.run(12, True)
out['pyrunner'] = {'before': [int(x) for x in O.tags['before'].split()], 'after': [int(x) for x in O.tags['after'].split()]}
dump('factory', out)
