# unbalanced_clump: utils.unbalancedForce and TriaxialCompressionEngine.UnbalancedForce (YADE 2023.02a) with clumps.
#   midstep: a 2-sphere clump overlapping a fixed sphere and a free sphere without contact (no gravity, damping 0,
#          O.dt 2e-3): utils.unbalancedForce() from PyRunners before and after NewtonIntegrator, steps 1 and 2
#          (before NewtonIntegrator the clump's own force is still 0: YADE counts its members' forces).
#   triax: 8 two-sphere clumps (r .3) on a 2x2x2 grid in aabbWalls, frictionless, TriaxialCompressionEngine
#          (sigmaIsoCompaction -1e4, max_vel 1, StabilityCriterion .01, testEquilibriumInterval 1), O.dt 1e-3 fixed,
#          damping .4: the engine's UnbalancedForce and currentState after each of 30 steps.
# Regenerate: cd tests/reference/yade && yade -n -x unbalanced_clump.py
import sys; import os; sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from _common import dump, tojson

rows = []


def rep(tag):
    rows.append({'iter': O.iter, 'where': tag, 'unbalanced': utils.unbalancedForce()})


def midstep():
    O.reset()
    O.materials.append(FrictMat(young=6e6, poisson=.8, frictionAngle=.5, density=2600))
    O.bodies.append(sphere((0.4, 0, 0), .2, fixed=True))
    O.bodies.appendClumped([sphere((.45, 0, .38), .2), sphere((.55, .2, .55), .17)])
    O.bodies.append(sphere((-.3, 0, 0), .2))
    O.engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb()]),
                 InteractionLoop([Ig2_Sphere_Sphere_ScGeom()], [Ip2_FrictMat_FrictMat_FrictPhys()],
                                 [Law2_ScGeom_FrictPhys_CundallStrack()]),
                 PyRunner(iterPeriod=1, initRun=True, command='rep("before")'),
                 NewtonIntegrator(damping=0, gravity=(0, 0, 0)),
                 PyRunner(iterPeriod=1, initRun=True, command='rep("after")')]
    O.dt = 2e-3
    O.step()
    O.step()
    return tojson(rows)


def triax():
    O.reset()
    O.materials.append(FrictMat(young=6e6, poisson=.4, frictionAngle=0, density=2600))
    for x in (0, 1):
        for y in (0, 1):
            for z in (0, 1):
                O.bodies.appendClumped([sphere((x, y, z), .3), sphere((x + .25, y + .1 * z, z + .2), .3)])
    wid = O.bodies.append(aabbWalls())
    t = TriaxialCompressionEngine(wall_left_id=wid[0], wall_right_id=wid[1], wall_bottom_id=wid[2],
                                  wall_top_id=wid[3], wall_back_id=wid[4], wall_front_id=wid[5],
                                  internalCompaction=False, sigmaIsoCompaction=-1e4, sigmaLateralConfinement=-1e4,
                                  max_vel=1, StabilityCriterion=.01, testEquilibriumInterval=1)
    O.engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb(), Bo1_Box_Aabb()]),
                 InteractionLoop([Ig2_Sphere_Sphere_ScGeom(), Ig2_Box_Sphere_ScGeom()],
                                 [Ip2_FrictMat_FrictMat_FrictPhys()], [Law2_ScGeom_FrictPhys_CundallStrack()]),
                 t, NewtonIntegrator(damping=.4)]
    O.dt = 1e-3
    out = []
    for k in range(30):
        O.step()
        out.append({'iter': O.iter, 'UnbalancedForce': t.UnbalancedForce, 'state': t.currentState,
                    'contacts': O.interactions.countReal()})
    return tojson(out)


dump('unbalanced_clump', {'midstep': midstep(), 'triax': triax()})
