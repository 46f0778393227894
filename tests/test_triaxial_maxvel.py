"""TriaxialStressController's cap on the walls' speed on a non-cubic sample against real YADE
(tests/reference/yade/triaxial_maxvel.py): max_vel is scaled per axis by size / mean size."""

from __future__ import annotations

import numpy as np
from conftest import reference

REF = reference("triaxial_maxvel")


def test_wall_speed_cap_scaled_by_axis_size(yade):
    """The six walls' velocities and positions over 5 steps of a 4 x 1 x 1.5 sample whose walls close in at the
    capped speed, as YADE's (an unscaled cap would make the x walls 1.84 times too slow)."""
    y = yade
    y.O.materials.append(y.FrictMat(young=6e6, poisson=.4, frictionAngle=.1, density=2600))
    y.O.bodies.append([y.sphere(c, r) for c, r in REF["spheres"]])
    wid = y.O.bodies.append(y.aabbWalls(thickness=.05))
    np.testing.assert_allclose([list(y.O.bodies[i].state.pos) for i in wid], REF["walls0"], rtol=0, atol=1e-12)
    t = y.TriaxialStressController(wall_left_id=wid[0], wall_right_id=wid[1], wall_bottom_id=wid[2],
                                   wall_top_id=wid[3], wall_back_id=wid[4], wall_front_id=wid[5],
                                   internalCompaction=False, goal1=-1e4, goal2=-1e4, goal3=-1e4, stressMask=7,
                                   max_vel=.5, thickness=.05)
    y.O.engines = [y.ForceResetter(), y.InsertionSortCollider([y.Bo1_Sphere_Aabb(), y.Bo1_Box_Aabb()]),
                   y.InteractionLoop([y.Ig2_Sphere_Sphere_ScGeom(), y.Ig2_Box_Sphere_ScGeom()],
                                     [y.Ip2_FrictMat_FrictMat_FrictPhys()], [y.Law2_ScGeom_FrictPhys_CundallStrack()]),
                   t, y.NewtonIntegrator(damping=.4)]
    y.O.dt = 1e-3
    for k, s in enumerate(REF["steps"]):
        y.O.step()
        vel = [list(y.O.bodies[i].state.vel) for i in wid]
        np.testing.assert_allclose(vel, s["vel"], rtol=1e-9, atol=1e-12, err_msg=f"step {k + 1}")
        pos = [list(y.O.bodies[i].state.pos) for i in wid]
        np.testing.assert_allclose(pos, s["pos"], rtol=0, atol=1e-12, err_msg=f"step {k + 1}")
        np.testing.assert_allclose([t.width, t.height, t.depth], s["sizes"], rtol=1e-12)
        assert y.O.interactions.countReal() == s["contacts"]
