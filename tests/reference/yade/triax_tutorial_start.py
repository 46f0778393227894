# triax_tutorial_start: the first 70 steps of the triax tutorial's confinement (examples/triax-tutorial/
# script-session1-stages.py: makeCloud seed 1, 1000 spheres in the unit box, aabbWalls thickness 0, FrictMat E 5e6,
# TriaxialStressController internalCompaction, maxMultiplier 1.004, goals -1e4, GlobalStiffnessTimeStepper every
# 100 steps, damping .2) under YADE 2023.02a. Both codes start from the same packing bit for bit; until step 71 no
# contact event depends on the collider's schedule (from step 72 YADE's collider, which does not follow the radii's
# growth, finds some new contacts of grown spheres a few steps late), so every step is comparable to round-off.
# Per step: O.dt, meanStress, porosity, and the real interactions (id1, id2, penetrationDepth, kn, |normalForce|).
# Regenerate: cd tests/reference/yade && yade -n -x triax_tutorial_start.py
import sys; import os; sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from _common import dump
from yade import pack

young = 5e6
O.materials.append(FrictMat(young=young, poisson=0.5, frictionAngle=radians(30), density=2600, label='spheres'))
O.materials.append(FrictMat(young=young, poisson=0.5, frictionAngle=0, density=0, label='walls'))
O.bodies.append(aabbWalls([Vector3(0, 0, 0), Vector3(1, 1, 1)], thickness=0, material='walls'))
sp = pack.SpherePack()
sp.makeCloud(Vector3(0, 0, 0), Vector3(1, 1, 1), -1, 0.3333, 1000, False, 0.95, seed=1)
O.bodies.append([sphere(center, rad, material='spheres') for center, rad in sp])
triax = TriaxialStressController(maxMultiplier=1. + 2e4 / young, finalMaxMultiplier=1. + 2e3 / young, thickness=0,
                                 stressMask=7, internalCompaction=True, goal1=-10000, goal2=-10000, goal3=-10000)
O.engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb(), Bo1_Box_Aabb()]),
             InteractionLoop([Ig2_Sphere_Sphere_ScGeom(), Ig2_Box_Sphere_ScGeom()], [Ip2_FrictMat_FrictMat_FrictPhys()],
                             [Law2_ScGeom_FrictPhys_CundallStrack()]),
             GlobalStiffnessTimeStepper(active=1, timeStepUpdateInterval=100, timestepSafetyCoefficient=0.8), triax,
             NewtonIntegrator(damping=0.2)]
steps = []
for k in range(70):
    O.run(1, True)
    steps.append({'dt': O.dt, 'meanStress': triax.meanStress, 'porosity': triax.porosity,
                  'contacts': sorted([[I.id1, I.id2, I.geom.penetrationDepth, I.phys.kn, I.phys.normalForce.norm()]
                                      for I in O.interactions if I.isReal])})
dump('triax_tutorial_start', {'steps': steps})
