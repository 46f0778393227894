# engines_extra: the kinematic, force and field engines of issue #21 (YADE 2023.02a), each on a small scene
# without contacts (except the servo) with dt = 0.01; after every O.step() the pos, vel, angVel, ori, force and
# torque of every body (force/torque as O.forces reads them, i.e. after the step) and the engine's changing
# attributes.
#  harmonic_motion:   HarmonicMotionEngine(A=(0.1,0.2,0), f=(2,1,0), fi default) on a free sphere (NewtonIntegrator,
#                     no gravity) and a fixed one, 30 steps.
#  harmonic_motion_fi: A=(.1,.2,.3), f=(2,1,3), fi=(0,1,0) on a fixed sphere.
#  harmonic_rotation: HarmonicRotationEngine(A=0.3, f=1.5, rotationAxis (0,0,1), rotateAroundZero, zeroPoint
#                     (1,0,0)) on a fixed sphere at (2,0,0), 30 steps.
#  interp_helix:      InterpolatingHelixEngine(times [0,0.1,0.2], angularVelocities [1,3,-2], slope 0.5, axis
#                     (0,1,0), zeroPoint (0,0,1)) on a fixed sphere; wrap False and True, 30 steps.
#  interp_force:      InterpolatingDirectedForceEngine(times [0.05,0.15], magnitudes [2,-1], direction (0,3,4))
#                     on a free sphere; wrap False and True, 25 steps; the engine's force after each step.
#  step_displacer:    StepDisplacer(mov, rot) with setVelocities False and True on a free sphere under gravity (rot
#                     about a unit axis: YADE's Quaternion(axis, angle) does not normalise the axis).
#  torque:            TorqueEngine(moment (1,2,3)) on a free sphere, ForceEngine-like.
#  axial_gravity:     AxialGravityEngine(axisPoint (0,0,1), axisDirection (0,2,0), acceleration 3, mask 2) on
#                     spheres with masks 1, 2, 3 (one on the axis).
#  central_accel:     CentralConstantAccelerationEngine(centralBody 0, accel 2, reciprocal False/True, mask 0) on
#                     spheres of radius .1 (one fixed) and .2.
#  drag / linear_drag: DragEngine(Rho 1000, Cd 0.5) and LinearDragEngine(nu 0.2) on two moving spheres and a
#                     moving (fixed) facet listed in ids.
#  pedal:             BicyclePedalEngine(angularVelocity 2, rotationAxis (0,0,1), radius 0.5 / -1, fi default)
#                     on a fixed sphere.
#  servo:             ServoPIDController (after NewtonIntegrator, as in examples/PIDController.py) on two fixed
#                     spheres, one pressing on a third (FrictMat contact), one with a permanent force; dt = 1e-4,
#                     40 steps; iterPeriod 3 and (servo_clamped, velocity clamped to -maxVelocity) the default.
# Regenerate: cd tests/reference/yade && yade -n -x engines_extra.py
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from _common import catch, dump  # noqa: E402

DT = 0.01


def state():
    return [{'pos': Vector3(b.state.pos), 'vel': Vector3(b.state.vel), 'angVel': Vector3(b.state.angVel),
             'ori': Quaternion(b.state.ori), 'f': Vector3(O.forces.f(b.id, sync=True)), 't': Vector3(O.forces.t(b.id, sync=True))}
            for b in O.bodies]


def scene(bodies, engines, steps, attrs=(), gravity=(0, 0, 0)):
    O.reset()
    O.bodies.append(bodies)
    O.engines = [ForceResetter()] + engines + [NewtonIntegrator(gravity=gravity, damping=0)]
    O.dt = DT
    out = []
    for _ in range(steps):
        O.step()
        out.append({'state': state(), 'attrs': {a: getattr(engines[0], a) for a in attrs}})
    return out


def spheres(*specs):
    return [sphere(p, .1, fixed=fx, mask=m) for p, fx, m in specs]


R = {}
R['harmonic_motion'] = catch(lambda: scene(spheres(((0, 0, 0), False, 1), ((1, 0, 0), True, 1)),
                                           [HarmonicMotionEngine(ids=[0, 1], A=(.1, .2, 0), f=(2, 1, 0))], 30))
R['harmonic_motion_fi'] = catch(lambda: scene(spheres(((0, 0, 0), True, 1)),
                                              [HarmonicMotionEngine(ids=[0], A=(.1, .2, .3), f=(2, 1, 3),
                                                                    fi=(0, 1, 0))], 30))
R['harmonic_rotation'] = catch(lambda: scene(spheres(((2, 0, 0), True, 1)), [HarmonicRotationEngine(
    ids=[0], A=.3, f=1.5, rotationAxis=(0, 0, 1), rotateAroundZero=True, zeroPoint=(1, 0, 0))], 30))
for wrap in (False, True):
    R['interp_helix_wrap%d' % wrap] = catch(lambda: scene(spheres(((0, 0, 0), True, 1)), [InterpolatingHelixEngine(
        ids=[0], times=[0, .1, .2], angularVelocities=[1, 3, -2], slope=.5, rotationAxis=(0, 1, 0),
        zeroPoint=(0, 0, 1), wrap=wrap)], 30, attrs=('angularVelocity', 'linearVelocity', 'angleTurned',
                                                       'rotateAroundZero')))
    R['interp_force_wrap%d' % wrap] = catch(lambda: scene(spheres(((0, 0, 0), False, 1)), [
        InterpolatingDirectedForceEngine(ids=[0], times=[.05, .15], magnitudes=[2, -1], direction=(0, 3, 4),
                                         wrap=wrap)], 25, attrs=('force', 'direction')))
for sv in (False, True):
    R['step_displacer_vel%d' % sv] = catch(lambda: scene(spheres(((0, 0, 0), False, 1)), [StepDisplacer(
        ids=[0], mov=(.01, 0, -.02), rot=Quaternion((0.6, 0.8, 0), .05), setVelocities=sv)], 10, gravity=(0, 0, -10)))
R['torque'] = catch(lambda: scene(spheres(((0, 0, 0), False, 1)), [TorqueEngine(ids=[0], moment=(1, 2, 3))], 5))
R['axial_gravity'] = catch(lambda: scene(spheres(((1, 0, 0), False, 1), ((1, 3, 2), False, 2), ((0, 1, 3), False, 3),
                                                 ((0, 5, 1), False, 2)),
                                         [AxialGravityEngine(axisPoint=(0, 0, 1), axisDirection=(0, 2, 0),
                                                             acceleration=3, mask=2)], 5))
for rec in (False, True):
    R['central_accel_rec%d' % rec] = catch(lambda: scene(
        spheres(((0, 0, 0), False, 1), ((1, 2, 2), False, 1), ((0, -1, 0), True, 1)) + [sphere((0, 0, 2), .2)],
        [CentralConstantAccelerationEngine(centralBody=0, accel=2, reciprocal=rec)], 5))


def drag_scene(engine):
    b = spheres(((0, 0, 0), False, 1), ((1, 0, 0), False, 1))
    b[0].state.vel = (3, -4, 0)
    b[1].state.vel = (0, 0, 2)
    f = facet([(0, 0, 1), (1, 0, 1), (0, 1, 1)])  # fixed, moving: the drag engines skip it
    f.state.vel = (1, 0, 0)
    return scene(b + [f], [engine], 5)


R['drag'] = catch(lambda: drag_scene(DragEngine(ids=[0, 1, 2], Rho=1000, Cd=.5)))
R['linear_drag'] = catch(lambda: drag_scene(LinearDragEngine(ids=[0, 1, 2], nu=.2)))
R['drag_default'] = catch(lambda: drag_scene(DragEngine(ids=[0, 1, 2])))
for rad in (.5, -1):
    R['pedal_r%g' % rad] = catch(lambda: scene(spheres(((0, 1, 0), True, 1)), [BicyclePedalEngine(
        ids=[0], angularVelocity=2, rotationAxis=(0, 0, 1), radius=rad)], 20))
R['pedal_fi'] = catch(lambda: scene(spheres(((0, 1, 0), True, 1)), [BicyclePedalEngine(
    ids=[0], angularVelocity=2, rotationAxis=(1, 1, 0), radius=.3, fi=.4)], 20))


def servo(**kw):
    O.reset()
    O.bodies.append([sphere((0, 0, 0), .5, fixed=True), sphere((0, 0, 0.95), .5, fixed=True),
                     sphere((3, 0, 0), .5, fixed=True)])
    eng = ServoPIDController(ids=[1, 2], **kw)
    O.engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb()]),
                 InteractionLoop([Ig2_Sphere_Sphere_ScGeom()], [Ip2_FrictMat_FrictMat_FrictPhys()],
                                 [Law2_ScGeom_FrictPhys_CundallStrack()]),
                 NewtonIntegrator(damping=0), eng]  # after NewtonIntegrator: before it, YADE 2023.02a's servo raises
    # 'ForceContainer not thread-synchronized' (NewtonIntegrator synchronises the forces)
    O.forces.setPermF(2, (1000, 2000, 3000))
    O.dt = 1e-4
    out = []
    for _ in range(40):
        O.step()
        out.append({'state': state(), 'attrs': {a: getattr(eng, a) for a in (
            'current', 'curVel', 'iTerm', 'errorCur', 'errorPrev', 'iterPrevStart', 'velocity', 'translationAxis')}})
    return out


R['servo'] = catch(lambda: servo(axis=(0, 1, -1), maxVelocity=0.5, target=1e5, kP=1e-6, kI=1e-7, kD=1e-7,
                                 iterPeriod=3))
R['servo_clamped'] = catch(lambda: servo(axis=(0, 0, 1), maxVelocity=0.2, target=4e5, kP=1e-5, kI=0, kD=0))
dump('engines_extra', R)
