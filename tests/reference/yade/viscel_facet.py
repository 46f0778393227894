# ViscElPhys of a sphere on a massless body (a facet, a wall) with ViscElMat given by tc/en/et: the constants and
# the bounce, as YADE 2023.02a gives them. Writes viscel_facet.json.
import os, sys
sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from _common import dump

out = {}
for case in ('facet', 'wall', 'fixed_sphere'):
    O.reset()
    fm = O.materials.append(ViscElMat(frictionAngle=0.6, tc=1e-3, en=0.3, et=0.4, density=1000))
    sm = O.materials.append(ViscElMat(frictionAngle=0.6, tc=1e-3, en=0.3, et=0.4, density=2400))
    if case == 'facet':
        O.bodies.append(facet([(-1, -1, 0), (1, -1, 0), (0, 1, 0)], material=fm))
    elif case == 'wall':
        O.bodies.append(wall(0, axis=2, material=fm))
    else:
        O.bodies.append(sphere((0, 0, -0.5), 0.5, fixed=True, material=fm))
    s = O.bodies.append(sphere((0.1, 0.05, 0.21), 0.2, material=sm))
    O.bodies[s].state.vel = (0.3, 0, -1)
    O.engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb(), Bo1_Facet_Aabb(), Bo1_Wall_Aabb()]),
                 InteractionLoop([Ig2_Sphere_Sphere_ScGeom(), Ig2_Facet_Sphere_ScGeom(), Ig2_Wall_Sphere_ScGeom()],
                                 [Ip2_ViscElMat_ViscElMat_ViscElPhys()], [Law2_ScGeom_ViscElPhys_Basic()]),
                 NewtonIntegrator(damping=0, gravity=(0, 0, -9.81))]
    O.dt = 1e-5
    phys = None
    for k in range(3000):
        O.step()
        if phys is None and O.interactions.countReal():
            i = [i for i in O.interactions if i.isReal][0]
            phys = dict(iter=O.iter, kn=i.phys.kn, cn=i.phys.cn, ks=i.phys.ks, cs=i.phys.cs,
                        tanphi=i.phys.tangensOfFrictionAngle)
    b = O.bodies[s]
    out[case] = dict(phys=phys, mass=b.state.mass, pos=b.state.pos, vel=b.state.vel, angVel=b.state.angVel)
dump('viscel_facet', out)
