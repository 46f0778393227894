# A sphere falls under gravity onto a fixed sphere and bounces, losing energy to
# numerical damping; the height of its centre is recorded and plotted.
# Run with:  granum examples/bouncing_sphere.py
from yade import plot

O.bodies.append([
    sphere(center=(0, 0, 0), radius=.5, fixed=True),  # the support
    sphere((0, 0, 2), .5),                            # the falling sphere
])
O.engines = [
    ForceResetter(),
    InsertionSortCollider([Bo1_Sphere_Aabb()]),
    InteractionLoop([Ig2_Sphere_Sphere_ScGeom()], [Ip2_FrictMat_FrictMat_FrictPhys()],
                    [Law2_ScGeom_FrictPhys_CundallStrack()]),
    NewtonIntegrator(gravity=(0, 0, -9.81), damping=0.1),
    PyRunner(command='plot.addData(t=O.time, z=O.bodies[1].state.pos[2])', iterPeriod=2000),
]
O.dt = .5e-4 * PWaveTimeStep()
plot.plots = {'t': ('z',)}

O.run(2000000, True)
z = O.bodies[1].state.pos[2]
print(f"after {O.iter} steps ({O.time:.3f} s): the sphere is at z = {z:.4f} m, "
      f"{len(plot.data['z'])} samples recorded")
plot.plot()
