# kinematic: kinematic engines combined with '+' (CombinedKinematicEngine), HelixEngine, dead parts and
# ParallelEngine. Every scene records after each O.step() the pos, vel, angVel and ori of its bodies.
#  comb_tr: ForceResetter, TranslationEngine(0.7, axis (1,1,0)) + RotationEngine(2.3 about z through
#           (0.5,-0.2,0), rotateAroundZero), NewtonIntegrator(gravity (0,0,-9.81), damping 0); body 0 free
#           (initial vel/angVel set), body 1 fixed; dt = 0.01, 10 steps.
#  comb_rth: RotationEngine(-1.1 about (1,2,2) through (0,1,0), rotateAroundZero) + TranslationEngine(0.3 along
#           (0,0,1)) + HelixEngine(0.8 about (0,1,0) through (1,0,1), linearVelocity 0.25), on bodies 0 and
#           2 of three (body 1 is not listed and keeps falling); dt = 0.05, 8 steps; angleTurned per step.
#  helix:   HelixEngine alone (angularVelocity 1.5 about (0,0,2), zeroPoint (1,1,0), linearVelocity -0.4,
#           rotateAroundZero left False) on a free and a fixed sphere; dt = 0.1, 6 steps; angleTurned and
#           rotateAroundZero after each step.
#  dead_part: TranslationEngine + a dead RotationEngine: the dead part is skipped (velocities still reset).
#  parallel: ParallelEngine([TranslationEngine, [ForceResetter, RotationEngine]]) then NewtonIntegrator.
# Also: the ids/comb of a combination, 'c + d' returning c, and sums with non-kinematic engines.
# Regenerate: cd tests/reference/yade && yade -n -x kinematic.py
# YADE 2023.02a
import sys; import os; sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from _common import catch, dump


def state(ids):
    # copies: state.vel and state.angVel are references to the body's vectors, which later steps change
    return {str(i): {'pos': Vector3(O.bodies[i].state.pos), 'vel': Vector3(O.bodies[i].state.vel),
                     'angVel': Vector3(O.bodies[i].state.angVel), 'ori': Quaternion(O.bodies[i].state.ori)}
            for i in ids}


def run(engines, bodies, dt, steps, extra=lambda: {}):
    O.reset()
    for pos, fixed, vel, angVel in bodies:
        b = utils.sphere(pos, 0.1, fixed=fixed)
        b.state.vel = vel
        b.state.angVel = angVel
        O.bodies.append(b)
    O.engines = engines
    O.dt = dt
    steps_out = []
    for _ in range(steps):
        O.step()
        s = {'iter': O.iter, 'bodies': state(range(len(O.bodies)))}
        s.update(extra())
        steps_out.append(s)
    return {'dt': dt, 'steps': steps_out}


out = {}
t = TranslationEngine(velocity=0.7, translationAxis=(1, 1, 0), ids=[0, 1])
r = RotationEngine(angularVelocity=2.3, rotationAxis=(0, 0, 1), rotateAroundZero=True, zeroPoint=(0.5, -0.2, 0), ids=[5])
out['comb_tr'] = run([ForceResetter(), t + r, NewtonIntegrator(gravity=(0, 0, -9.81), damping=0)],
                     [((1, 0.3, 0.2), False, (0.1, -0.2, 0.3), (1, 2, 3)), ((-0.4, 0.9, -0.1), True, (0, 0, 0), (0, 0, 0))],
                     0.01, 10)

h = HelixEngine(angularVelocity=0.8, rotationAxis=(0, 1, 0), zeroPoint=(1, 0, 1), linearVelocity=0.25)
c = RotationEngine(angularVelocity=-1.1, rotationAxis=(1, 2, 2), rotateAroundZero=True, zeroPoint=(0, 1, 0), ids=[0, 2]) \
    + TranslationEngine(velocity=0.3, translationAxis=(0, 0, 1))
c2 = c + h
out['comb_rth'] = run([ForceResetter(), c, NewtonIntegrator(gravity=(0, 0, -9.81), damping=0)],
                      [((0.2, 0.1, 0.3), False, (0, 0, 0), (0, 0, 0)), ((3, 3, 3), False, (0, 0, 0), (0, 0, 0)),
                       ((-0.5, 0.4, 1.2), True, (0, 0, 0), (0, 0, 0))],
                      0.05, 8, lambda: {'angleTurned': h.angleTurned})
out['comb_rth']['same_object'] = c2 is c
out['comb_rth']['ids'] = list(c.ids)
out['comb_rth']['comb'] = [type(e).__name__ for e in c.comb]

h1 = HelixEngine(angularVelocity=1.5, rotationAxis=(0, 0, 2), zeroPoint=(1, 1, 0), linearVelocity=-0.4, ids=[0, 1])
out['helix'] = run([ForceResetter(), h1, NewtonIntegrator(damping=0)],
                   [((2, 1.5, 0.5), False, (0, 0, 0), (0, 0, 0)), ((0.2, 1, -1), True, (0, 0, 0), (0, 0, 0))],
                   0.1, 6, lambda: {'angleTurned': h1.angleTurned, 'rotateAroundZero': h1.rotateAroundZero})

out['dead_part'] = run([ForceResetter(), TranslationEngine(velocity=1, translationAxis=(0, 0, 1), ids=[0])
                        + RotationEngine(angularVelocity=2, rotationAxis=(1, 0, 0), dead=True), NewtonIntegrator(damping=0)],
                       [((0, 0, 0), False, (1, 2, 3), (4, 5, 6))], 0.01, 2)

out['parallel'] = run([ParallelEngine([TranslationEngine(velocity=2, translationAxis=(0, 1, 0), ids=[0]),
                                       [ForceResetter(), RotationEngine(angularVelocity=3, rotationAxis=(0, 0, 1),
                                                                        rotateAroundZero=True, ids=[1])]]),
                       NewtonIntegrator(damping=0)],
                      [((0, 0, 0), False, (1, 2, 3), (4, 5, 6)), ((1, 0, 0), False, (0, 0, 0), (0, 0, 0))], 0.01, 3)

out['sums'] = {'translation_plus_force': catch(lambda: TranslationEngine() + ForceEngine()),
               'translation_plus_combined': catch(lambda: TranslationEngine() + (TranslationEngine() + RotationEngine()))}
dump('kinematic', out)
sys.exit(0)
