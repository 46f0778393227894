# triaxial_maxvel: TriaxialStressController (YADE 2023.02a) moving the walls of a non-cubic sample: the cap
# max_vel on the walls' speed is scaled by each axis' size over the mean of width, height and depth.
# Scene: makeCloud in (0,0,0)-(4,1,1.5) (rMean .1, rRelFuzz .2, seed 1; spheres read back from the json),
# aabbWalls(thickness .05), stressMask 7, goals -1e4, max_vel .5, thickness .05, O.dt 1e-3 fixed, damping .4:
# the walls' velocities, positions and the sizes after each of 5 steps (the walls touch nothing: capped moves).
# Regenerate: cd tests/reference/yade && yade -n -x triaxial_maxvel.py
import sys; import os; sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from _common import dump, tojson
from yade import pack

O.materials.append(FrictMat(young=6e6, poisson=.4, frictionAngle=.1, density=2600))
sp = pack.SpherePack()
sp.makeCloud((0, 0, 0), (4, 1, 1.5), rMean=.1, rRelFuzz=.2, seed=1)
sp.toSimulation()
spheres = tojson([(b.state.pos, b.shape.radius) for b in O.bodies])
wid = O.bodies.append(aabbWalls(thickness=.05))
t = TriaxialStressController(wall_left_id=wid[0], wall_right_id=wid[1], wall_bottom_id=wid[2], wall_top_id=wid[3],
                             wall_back_id=wid[4], wall_front_id=wid[5], internalCompaction=False, goal1=-1e4,
                             goal2=-1e4, goal3=-1e4, stressMask=7, max_vel=.5, thickness=.05)
O.engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb(), Bo1_Box_Aabb()]),
             InteractionLoop([Ig2_Sphere_Sphere_ScGeom(), Ig2_Box_Sphere_ScGeom()], [Ip2_FrictMat_FrictMat_FrictPhys()],
                             [Law2_ScGeom_FrictPhys_CundallStrack()]), t, NewtonIntegrator(damping=.4)]
O.dt = 1e-3
walls0 = tojson([O.bodies[i].state.pos for i in wid])  # converted now: YADE's vectors are views
steps = []
for k in range(5):
    O.step()
    steps.append(tojson({'vel': [O.bodies[i].state.vel for i in wid], 'pos': [O.bodies[i].state.pos for i in wid],
                         'sizes': [t.width, t.height, t.depth], 'contacts': O.interactions.countReal()}))
dump('triaxial_maxvel', tojson({'spheres': spheres, 'walls0': walls0, 'steps': steps}))
