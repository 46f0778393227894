# Spheres of random sizes fall into a box made of facets and settle; the run stops by
# itself once the packing is at rest (unbalanced force below 0.05).
# Run with:  granum examples/gravity_deposition.py
from yade import pack, plot

O.bodies.append(geom.facetBox((.5, .5, .5), (.5, .5, .5), wallMask=31))  # open top
sp = pack.SpherePack()
sp.makeCloud((0, 0, 0), (1, 1, 1), rMean=.05, rRelFuzz=.5, seed=1)
sp.toSimulation()

O.engines = [
    ForceResetter(),
    InsertionSortCollider([Bo1_Sphere_Aabb(), Bo1_Facet_Aabb()]),
    InteractionLoop([Ig2_Sphere_Sphere_ScGeom(), Ig2_Facet_Sphere_ScGeom()],
                    [Ip2_FrictMat_FrictMat_FrictPhys()], [Law2_ScGeom_FrictPhys_CundallStrack()]),
    NewtonIntegrator(gravity=(0, 0, -9.81), damping=0.4),
    PyRunner(command='checkUnbalanced()', iterPeriod=1000),
    PyRunner(command='plot.addData(i=O.iter, unbalanced=unbalancedForce(), **O.energy)', iterPeriod=100),
]
O.dt = .5 * PWaveTimeStep()
O.trackEnergy = True


def checkUnbalanced():
    if O.iter > 2000 and unbalancedForce() < .05:
        O.pause()


plot.plots = {'i': ('unbalanced', None, O.energy.keys)}
O.run(200000, True)
print(f"settled after {O.iter} steps: {len(sp)} spheres, {O.interactions.countReal()} contacts, "
      f"porosity {porosity():.3f}")
plot.plot()
