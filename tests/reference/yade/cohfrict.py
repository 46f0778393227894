# cohfrict: ScGeom6D and the cohesive-frictional law (CohFrictMat, Ip2_CohFrictMat_CohFrictMat_CohFrictPhys,
# Law2_ScGeom6D_CohFrictPhys_CohesionMoment) on two spheres whose motion is imposed (blockedDOFs='xyzXYZ',
# velocities set, dt=1e-4, no gravity, no damping), recorded after every step: the ScGeom6D (penetrationDepth,
# normal, twist, bending, initialOrientation1/2), the CohFrictPhys (kn, ks, kr, ktw, adhesions, maxRollPl,
# maxTwistPl, cohesionBroken, unp, moment_twist, moment_bending, normalForce, shearForce), forces and torques on
# both bodies, and whether the interaction is real.
# Runs: 'roll_total' and 'roll_incremental' (sphere 2 rolls about an axis normal to the contact normal, plus a
# twist; elastic moments), 'roll_plastic' (etaRoll, etaTwist > 0, incremental form, compressed contact: moments
# bounded by eta r |Fn|), 'tension_fragile' and 'tension_plastic' (pulled apart along the normal: cohesion
# breaks at normalCohesion min(r)^2; fragile=False: perfectly plastic), 'shear_fragile' (sheared: breaks at
# shearCohesion min(r)^2 + Fn tan phi), 'noncohesive' (setCohesionOnNewContacts=False: no moment unless
# always_use_moment_law), 'always' (always_use_moment_law=True on a non-cohesive contact), 'now' (the contact
# exists first, then setCohesionNow=True), 'mixed' (CohFrictMat against FrictMat: FrictPhys and Cundall-Strack),
# 'facet' and 'box' (a sphere rolling on a facet / a box with the ScGeom6D functors), 'shear_creep', 'clump' (the
# twisting moment on a clump member turns the clump: its angular velocity and position).
# 'defaults': the dict() of each class.
# Regenerate: cd tests/reference/yade && yade -n -x cohfrict.py
# YADE 2023.02a
import sys; import os; sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from _common import dump, tojson, catch

N = Vector3(0.6, 0.3, 0.74).normalized()   # direction from sphere 1 to sphere 2
T = N.cross(Vector3(0, 0, 1)).normalized()  # a tangent


def mat(**kw):
    base = dict(young=1e7, poisson=.3, density=1000, frictionAngle=.5, normalCohesion=1e5, shearCohesion=2e5,
                momentRotationLaw=True, alphaKr=2.0, alphaKtw=1.5)
    base.update(kw)
    return CohFrictMat(**base)


def record(out, extra=()):
    rec = {'iter': O.iter, 'real': O.interactions.has(0, 1) and O.interactions[0, 1].isReal,
           'f': [O.forces.f(k) for k in (0, 1)], 't': [O.forces.t(k) for k in (0, 1)],
           'pos2': O.bodies[1].state.pos, 'ori2': O.bodies[1].state.ori}
    if rec['real']:
        i = O.interactions[0, 1]
        g, p = i.geom, i.phys
        rec.update({'geom_class': type(g).__name__, 'phys_class': type(p).__name__,
                    'penetrationDepth': g.penetrationDepth, 'normal': g.normal, 'contactPoint': g.contactPoint,
                    'normalForce': p.normalForce, 'shearForce': p.shearForce, 'kn': p.kn, 'ks': p.ks,
                    'tangensOfFrictionAngle': p.tangensOfFrictionAngle})
        if type(g).__name__ == 'ScGeom6D':
            rec.update({'twist': g.twist, 'bending': g.bending, 'initialOrientation1': g.initialOrientation1,
                        'initialOrientation2': g.initialOrientation2})
        if type(p).__name__ == 'CohFrictPhys':
            for k in ('kr', 'ktw', 'normalAdhesion', 'shearAdhesion', 'maxRollPl', 'maxTwistPl', 'cohesionBroken',
                      'fragile', 'unp', 'unpMax', 'momentRotationLaw', 'moment_twist', 'moment_bending',
                      'cohesionDisablesFriction', 'initCohesion'):
                rec[k] = getattr(p, k)
    out.append(tojson(rec))


def scene(m1, m2, dist, vel, angVel1, angVel2, steps, ip2=None, law=None, r1=.5, r2=.4, before=None,
          ori1=None, ori2=None):
    O.reset()
    a = O.materials.append(m1)
    b = O.materials.append(m2)
    O.bodies.append([sphere((0, 0, 0), r1, material=a), sphere(dist * N, r2, material=b)])
    for k, (v, w, q) in enumerate(((Vector3.Zero, angVel1, ori1), (vel, angVel2, ori2))):
        s = O.bodies[k].state
        s.blockedDOFs = 'xyzXYZ'
        s.vel, s.angVel = v, w
        if q is not None:
            s.ori = q
    ip2 = ip2 or Ip2_CohFrictMat_CohFrictMat_CohFrictPhys(setCohesionOnNewContacts=True)
    law = law or Law2_ScGeom6D_CohFrictPhys_CohesionMoment()
    O.engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb(aabbEnlargeFactor=1.5)]),
                 InteractionLoop([Ig2_Sphere_Sphere_ScGeom6D(interactionDetectionFactor=1.5)],
                                 [Ip2_FrictMat_FrictMat_FrictPhys(), ip2], [Law2_ScGeom_FrictPhys_CundallStrack(), law]),
                 NewtonIntegrator(damping=0)]
    O.dt = 1e-4
    out = []
    if before is not None:
        before(out, ip2, law)
    for step in range(steps):
        O.step()
        record(out)
        out[-1]['setCohesionNow'] = ip2.setCohesionNow
    return out


def now_before(out, ip2, law):
    for k in range(3):
        O.step()
        record(out)
    ip2.setCohesionNow = True
    out.append({'setCohesionNow_before_step': ip2.setCohesionNow})


def shape_scene(kind, steps):
    O.reset()
    a = O.materials.append(mat())
    if kind == 'facet':
        O.bodies.append(facet([(-2, -2, 0), (2, -2, 0), (0, 2, 0)], material=a))
        ig2, bo1 = Ig2_Facet_Sphere_ScGeom6D(), Bo1_Facet_Aabb()
    else:
        O.bodies.append(box((0, 0, -0.5), (2, 2, 0.5), material=a))
        ig2, bo1 = Ig2_Box_Sphere_ScGeom6D(), Bo1_Box_Aabb()
    O.bodies.append(sphere((0.1, 0.2, 0.39), .4, material=a))
    for k in (0, 1):
        O.bodies[k].state.blockedDOFs = 'xyzXYZ'
    O.bodies[1].state.vel = Vector3(0.3, 0.1, -0.02)
    O.bodies[1].state.angVel = Vector3(1.0, -0.5, 2.0)
    O.engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb(), bo1]),
                 InteractionLoop([ig2, Ig2_Sphere_Sphere_ScGeom6D()],
                                 [Ip2_CohFrictMat_CohFrictMat_CohFrictPhys(setCohesionOnNewContacts=True)],
                                 [Law2_ScGeom6D_CohFrictPhys_CohesionMoment(always_use_moment_law=True)]),
                 NewtonIntegrator(damping=0)]
    O.dt = 1e-4
    out = []
    for step in range(steps):
        O.step()
        record(out)
    return out


def clump_scene(steps):
    # a clump (a sphere and a tiny far one) in cohesive contact with a fixed sphere spinning about the normal:
    # the twisting moment on the member turns the clump
    O.reset()
    m = O.materials.append(mat(frictionAngle=0, normalCohesion=1e6, shearCohesion=1e6))
    O.bodies.append(sphere((0, 0, 0), 0.5, material=m, fixed=True))
    O.bodies[0].state.angVel = (0, 0, 50.0)
    clump, members = O.bodies.appendClumped([sphere((0, 0, 0.89), 0.4, material=m),
                                             sphere((0.05, 0, 1.3), 1e-2, material=m)])
    O.engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb()]),
                 InteractionLoop([Ig2_Sphere_Sphere_ScGeom6D()],
                                 [Ip2_CohFrictMat_CohFrictMat_CohFrictPhys(setCohesionNow=True)],
                                 [Law2_ScGeom6D_CohFrictPhys_CohesionMoment()]),
                 NewtonIntegrator(damping=0)]
    O.dt = 1e-5
    out = []
    for step in range(steps):
        O.step()
        i = O.interactions[0, members[0]]
        c = O.bodies[clump].state
        out.append(tojson({'iter': O.iter, 'twist': i.geom.twist, 'moment_twist': i.phys.moment_twist,
                           't_member': O.forces.t(members[0]), 'clump_angVel': c.angVel,
                           'clump_pos': c.pos}))
    return out


roll = Vector3(0.3, -0.8, 0.2)   # angular velocity of sphere 2 [rad/s]: bending and twist
data = {
    'roll_total': scene(mat(), mat(young=2e7, poisson=.2), .88, Vector3.Zero, Vector3(0, 0, 1), roll * 20, 60),
    'roll_incremental': scene(mat(), mat(young=2e7, poisson=.2), .88, Vector3.Zero, Vector3(0, 0, 1), roll * 20, 60,
                              law=Law2_ScGeom6D_CohFrictPhys_CohesionMoment(useIncrementalForm=True)),
    'roll_plastic': scene(mat(etaRoll=.1, etaTwist=.2), mat(etaRoll=.3, etaTwist=.05), .88, Vector3.Zero,
                          Vector3.Zero, roll * 20, 60,
                          law=Law2_ScGeom6D_CohFrictPhys_CohesionMoment(useIncrementalForm=True)),
    'roll_large': scene(mat(), mat(), .88, Vector3.Zero, Vector3(0, 0, 0), roll * 3000, 40,
                        ori2=Quaternion((0.2, 0.9, -0.1), 0.7),
                        law=Law2_ScGeom6D_CohFrictPhys_CohesionMoment(always_use_moment_law=True)),
    'tension_fragile': scene(mat(normalCohesion=3e3), mat(normalCohesion=5e3), .899, N * 1.0, Vector3.Zero,
                             Vector3.Zero, 40),
    'tension_plastic': scene(mat(normalCohesion=3e3, fragile=False), mat(normalCohesion=5e3, fragile=False), .899, N * 1.0,
                             Vector3.Zero, Vector3.Zero, 40),
    'tension_default_strength': scene(mat(normalCohesion=-1), mat(normalCohesion=-1), .899, N * 1.0, Vector3.Zero,
                                      Vector3.Zero, 40),
    'shear_fragile': scene(mat(shearCohesion=2e3), mat(shearCohesion=4e3), .899, T * 1.0, Vector3.Zero,
                           Vector3.Zero, 40),
    'shear_plastic': scene(mat(shearCohesion=2e3, fragile=False), mat(shearCohesion=4e3, fragile=False), .899, T * 1.0,
                           Vector3.Zero, Vector3.Zero, 40),
    'noncohesive': scene(mat(), mat(), .88, T * 0.1, Vector3.Zero, roll * 20, 30,
                         ip2=Ip2_CohFrictMat_CohFrictMat_CohFrictPhys()),
    'always': scene(mat(etaRoll=.1), mat(etaRoll=.1), .88, T * 0.1, Vector3.Zero, roll * 20, 30,
                    ip2=Ip2_CohFrictMat_CohFrictMat_CohFrictPhys(),
                    law=Law2_ScGeom6D_CohFrictPhys_CohesionMoment(always_use_moment_law=True, useIncrementalForm=True)),
    'now': scene(mat(), mat(), .88, T * 0.1, Vector3.Zero, roll * 20, 20,
                 ip2=Ip2_CohFrictMat_CohFrictMat_CohFrictPhys(), before=now_before),
    'not_cohesive_material': scene(mat(isCohesive=False), mat(), .88, T * 0.1, Vector3.Zero, roll * 20, 10),
    'mixed': scene(mat(), FrictMat(young=2e7, poisson=.2, density=1000, frictionAngle=.3), .88, T * 0.5,
                   Vector3.Zero, roll * 20, 20),
    'shear_creep': scene(mat(), mat(), .88, T * 0.5, Vector3.Zero, Vector3.Zero, 30,
                         law=Law2_ScGeom6D_CohFrictPhys_CohesionMoment(shear_creep=True, creep_viscosity=2e3)),
    'facet': shape_scene('facet', 30),
    'box': shape_scene('box', 30),
    'clump': clump_scene(30),
}
O.reset()
data['defaults'] = {c.__name__: catch(lambda: c().dict()) for c in (
    CohFrictMat, CohFrictPhys, Ip2_CohFrictMat_CohFrictMat_CohFrictPhys, Law2_ScGeom6D_CohFrictPhys_CohesionMoment,
    ScGeom6D, Ig2_Sphere_Sphere_ScGeom6D, Ig2_Facet_Sphere_ScGeom6D, Ig2_Box_Sphere_ScGeom6D)}
dump('cohfrict', data)
