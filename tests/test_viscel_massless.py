"""The visco-elastic contact of a sphere with a massless body (facet, wall) and with a fixed sphere, against real
YADE 2023.02a (tests/reference/yade/viscel_facet.py): the constants at first contact and the bounce."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import reference


@pytest.mark.parametrize("case", ["facet", "wall", "fixed_sphere"])
def test_sphere_on_a_massless_body_equals_yade(yade, case):
    ref = reference("viscel_facet")[case]
    y = yade
    fm = y.O.materials.append(y.ViscElMat(frictionAngle=0.6, tc=1e-3, en=0.3, et=0.4, density=1000))
    sm = y.O.materials.append(y.ViscElMat(frictionAngle=0.6, tc=1e-3, en=0.3, et=0.4, density=2400))
    if case == "facet":
        y.O.bodies.append(y.facet([(-1, -1, 0), (1, -1, 0), (0, 1, 0)], material=fm))
    elif case == "wall":
        y.O.bodies.append(y.wall(0, axis=2, material=fm))
    else:
        y.O.bodies.append(y.sphere((0, 0, -0.5), 0.5, fixed=True, material=fm))
    s = y.O.bodies.append(y.sphere((0.1, 0.05, 0.21), 0.2, material=sm))
    y.O.bodies[s].state.vel = (0.3, 0, -1)
    y.O.engines = [y.ForceResetter(), y.InsertionSortCollider([y.Bo1_Sphere_Aabb(), y.Bo1_Facet_Aabb(),
                                                               y.Bo1_Wall_Aabb()]),
                   y.InteractionLoop([y.Ig2_Sphere_Sphere_ScGeom(), y.Ig2_Facet_Sphere_ScGeom(),
                                      y.Ig2_Wall_Sphere_ScGeom()],
                                     [y.Ip2_ViscElMat_ViscElMat_ViscElPhys()], [y.Law2_ScGeom_ViscElPhys_Basic()]),
                   y.NewtonIntegrator(damping=0, gravity=(0, 0, -9.81))]
    y.O.dt = 1e-5
    y.O.run(ref["phys"]["iter"], True)
    i = [i for i in y.O.interactions if i.isReal][0]
    got = dict(kn=i.phys.kn, cn=i.phys.cn, ks=i.phys.ks, cs=i.phys.cs, tanphi=i.phys.tangensOfFrictionAngle)
    for k, v in got.items():
        assert v == pytest.approx(ref["phys"][k], rel=1e-12), k
    y.O.run(3000 - y.O.iter, True)
    b = y.O.bodies[s]
    np.testing.assert_allclose(list(b.state.vel), ref["vel"], rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(list(b.state.angVel), ref["angVel"], rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(list(b.state.pos), ref["pos"], rtol=1e-12)
