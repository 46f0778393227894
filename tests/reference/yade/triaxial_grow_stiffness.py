# triaxial_grow_stiffness: TriaxialStressController(internalCompaction=True) (YADE 2023.02a) multiplies, with the
# radii, the stiffnesses kn and ks of every existing interaction by the radius multiplier, even between bodies
# that do not grow. Scene: aabbWalls of the unit box (thickness 0, frictionless walls material), spheres of
# radius .1 (FrictMat E 5e6, poisson .5): two overlapping spheres with all DOFs blocked (they keep their radii),
# two free overlapping spheres, a free sphere touching the left wall; maxMultiplier 1.01, goals -1e4,
# O.dt 1e-5 fixed, damping .2. Per step (12 steps): the radii, and per real interaction (id1, id2, kn, ks,
# |normalForce|, penetrationDepth); and previousMultiplier.
# Regenerate: cd tests/reference/yade && yade -n -x triaxial_grow_stiffness.py
import sys; import os; sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from _common import dump

O.materials.append(FrictMat(young=5e6, poisson=.5, frictionAngle=.5, density=2600, label='spheres'))
O.materials.append(FrictMat(young=5e6, poisson=.5, frictionAngle=0, density=0, label='walls'))
O.bodies.append(aabbWalls([(0, 0, 0), (1, 1, 1)], thickness=0, material='walls'))
ids = O.bodies.append([sphere(c, .1, material='spheres') for c in
                       [(.3, .7, .5), (.49, .7, .5), (.6, .3, .5), (.79, .3, .5), (.099, .3, .2)]])
for i in ids[:2]:
    O.bodies[i].state.blockedDOFs = 'xyzXYZ'
t = TriaxialStressController(internalCompaction=True, stressMask=7, goal1=-1e4, goal2=-1e4, goal3=-1e4,
                             thickness=0, maxMultiplier=1.01)
O.engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb(), Bo1_Box_Aabb()]),
             InteractionLoop([Ig2_Sphere_Sphere_ScGeom(), Ig2_Box_Sphere_ScGeom()], [Ip2_FrictMat_FrictMat_FrictPhys()],
                             [Law2_ScGeom_FrictPhys_CundallStrack()]), t, NewtonIntegrator(damping=.2)]
O.dt = 1e-5
steps = []
for k in range(12):
    O.step()
    steps.append({'radii': [O.bodies[i].shape.radius for i in ids], 'previousMultiplier': t.previousMultiplier,
                  'contacts': sorted([[I.id1, I.id2, I.phys.kn, I.phys.ks, I.phys.normalForce.norm(),
                                       I.geom.penetrationDepth] for I in O.interactions if I.isReal])})
dump('triaxial_grow_stiffness', {'ids': list(ids), 'steps': steps})
