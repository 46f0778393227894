# Run with real YADE:  yade -n -x make_checkpoint.py
# Writes YADE's own checkpoints of a two-sphere scene (boost::serialization, binary and XML), which
# granum must recognise and refuse with a clear error (it cannot read YADE's archives).
O.bodies.append([sphere((0, 0, 0), .5, fixed=True), sphere((0, 0, 2), .5)])
O.engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb()]),
             InteractionLoop([Ig2_Sphere_Sphere_ScGeom()], [Ip2_FrictMat_FrictMat_FrictPhys()],
                             [Law2_ScGeom_FrictPhys_CundallStrack()]),
             NewtonIntegrator(gravity=(0, 0, -9.81), damping=.1)]
O.dt = 1e-5
O.run(10, True)
O.save('yade_scene.yade')
O.save('yade_scene.xml')
