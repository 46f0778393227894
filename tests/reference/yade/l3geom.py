# l3geom: a sphere-sphere contact with Ig2_Sphere_Sphere_L3Geom, Ip2_FrictMat_FrictMat_FrictPhys and
# Law2_L3Geom_FrictPhys_ElPerfPl, both spheres kinematic (fixed=True, velocities set), recorded after every
# step: the L3Geom (u, u0, trsf, F, normal, contactPoint, refR1, refR2), the FrictPhys (kn, ks,
# tangensOfFrictionAngle, normalForce, shearForce), the forces and torques on both bodies, the energies.
# Runs: 'default' (functor defaults; sliding after ~20 steps; O.trackEnergy), 'options' (noRatch=False,
# approxMask=3, trsfRenorm=3,
# distFactor=-1.2: created before touching, at rest there, then approaching; noSlip), 'mask4' (approxMask=4),
# 'separate' (the bodies move apart: the contact breaks) and 'separate_noBreak' (it stays, pulling).
# Regenerate: cd tests/reference/yade && yade -n -x l3geom.py
# YADE 2023.02a
import sys; import os; sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from _common import dump, tojson

DIRECTION = Vector3(0.6, 0.3, 0.74).normalized()


def scene(geom, law, dist, vel, angVel1, angVel2, steps, energy=False):
    O.reset()
    m1 = O.materials.append(FrictMat(young=1e7, poisson=.3, density=1000, frictionAngle=.5))
    m2 = O.materials.append(FrictMat(young=2e7, poisson=.2, density=1000, frictionAngle=.3))
    O.bodies.append([sphere((0, 0, 0), .5, material=m1, fixed=True),
                     sphere(dist * DIRECTION, .4, material=m2, fixed=True)])
    O.bodies[0].state.angVel = angVel1
    O.bodies[1].state.vel = vel
    O.bodies[1].state.angVel = angVel2
    O.engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb(aabbEnlargeFactor=1.5)]),
                 InteractionLoop([geom], [Ip2_FrictMat_FrictMat_FrictPhys()], [law]),
                 NewtonIntegrator(damping=0)]
    O.dt = 1e-3
    O.trackEnergy = energy
    out = []
    for step in range(steps):
        O.step()
        rec = {'iter': O.iter, 'real': O.interactions.has(0, 1) and O.interactions[0, 1].isReal,
               'f': [O.forces.f(k) for k in (0, 1)], 't': [O.forces.t(k) for k in (0, 1)],
               'pos2': O.bodies[1].state.pos}
        if rec['real']:
            i = O.interactions[0, 1]
            g, p = i.geom, i.phys
            rec.update({'geom_class': type(g).__name__, 'geom_keys': sorted(g.dict().keys()),
                        'u': g.u, 'u0': g.u0, 'trsf': g.trsf, 'F': g.F, 'normal': g.normal,
                        'contactPoint': g.contactPoint, 'refR1': g.refR1, 'refR2': g.refR2,
                        'kn': p.kn, 'ks': p.ks, 'tangensOfFrictionAngle': p.tangensOfFrictionAngle,
                        'normalForce': p.normalForce, 'shearForce': p.shearForce})
        if energy:
            rec['energy'] = {k: O.energy[k] for k in O.energy.keys()}
        out.append(tojson(rec))
    return out


# sliding: sphere 2 shears along the first tangent-ish direction, slowly approaching, both spinning
shear = Vector3(0.74, 0.0, -0.6).normalized() * 0.6 - 0.01 * DIRECTION
data = {
    'default': scene(Ig2_Sphere_Sphere_L3Geom(), Law2_L3Geom_FrictPhys_ElPerfPl(), .88, shear,
                     Vector3(0, 0, 1), Vector3(1, 0, 2), 60, energy=True),
    'options': scene(Ig2_Sphere_Sphere_L3Geom(noRatch=False, approxMask=3, trsfRenorm=3, distFactor=-1.2),
                     Law2_L3Geom_FrictPhys_ElPerfPl(noSlip=True), .91, shear - 0.3 * DIRECTION,
                     Vector3(0, 0, 1), Vector3(1, 0, 2), 60),
    'mask4': scene(Ig2_Sphere_Sphere_L3Geom(approxMask=4), Law2_L3Geom_FrictPhys_ElPerfPl(), .88, shear,
                   Vector3(0, 0, 1), Vector3(1, 0, 2), 60),
    'separate': scene(Ig2_Sphere_Sphere_L3Geom(), Law2_L3Geom_FrictPhys_ElPerfPl(), .895, 0.19 * DIRECTION,
                      Vector3(0, 0, 0), Vector3(0, 0, 0), 30),
    'separate_noBreak': scene(Ig2_Sphere_Sphere_L3Geom(), Law2_L3Geom_FrictPhys_ElPerfPl(noBreak=True), .895,
                              0.2 * DIRECTION + Vector3(0.05, 0, 0), Vector3(0, 0, 0), Vector3(0, 0, 0), 30),
}
dump('l3geom', data)
