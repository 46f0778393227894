"""Contact geometry, physics and forces against real YADE (tests/reference/yade/contacts.py).

The scenes are those of the reference script; after one step (and, for the sheared
contact, after each of 50 steps) every recorded quantity must agree with YADE's.
"""

from __future__ import annotations

import numpy as np
import pytest
from conftest import frict_engines, reference

F = [(-1, -1, 0), (2, -1, 0), (-1, 2, 0)]


def _setup(y):
    y.O.engines = frict_engines(y, gravity=(0, 0, -10), damping=0)
    y.O.dt = 1e-5
    return y.O.materials.append(y.FrictMat(young=1e7, poisson=0.3, density=1000, frictionAngle=0.5))


def _two_spheres(y, m):
    m1 = y.O.materials.append(y.FrictMat(young=1e7, poisson=0.3, density=1000, frictionAngle=0.5))
    m2 = y.O.materials.append(y.FrictMat(young=2e7, poisson=0.2, density=1000, frictionAngle=0.3))
    return [y.sphere((0, 0, 0), 0.5, material=m1), y.sphere((0, 0, 0.99), 0.5, material=m2)]


SCENES = {
    "a_sphere_sphere": _two_spheres,
    "b_facet_sphere": lambda y, m: [y.facet(F, material=m), y.sphere((0.2, 0.3, 0.49), 0.5, material=m)],
    "c1_facet_edge": lambda y, m: [y.facet(F, material=m), y.sphere((0.5, -1.3, 0.3), 0.5, material=m)],
    "c2_facet_vertex": lambda y, m: [y.facet(F, material=m), y.sphere((-1.3, -1.3, 0.2), 0.5, material=m)],
    "d_wall_sphere": lambda y, m: [y.wall(0, axis=2, material=m), y.sphere((0, 0, 0.49), 0.5, material=m)],
    "d2_wall_below_sphere": lambda y, m: [y.wall(0, axis=2, material=m), y.sphere((0, 0, -0.49), 0.5, material=m)],
    "e_box_sphere": lambda y, m: [y.box((0, 0, -1), (1, 1, 1), fixed=True, material=m),
                                  y.sphere((0.1, 0.2, 0.49), 0.5, material=m)],
    "f_sphere_then_facet": lambda y, m: [y.sphere((0.2, 0.3, 0.49), 0.5, material=m), y.facet(F, material=m)],
    "f_sphere_then_wall": lambda y, m: [y.sphere((0, 0, 0.49), 0.5, material=m), y.wall(0, axis=2, material=m)],
    "f_sphere_then_box": lambda y, m: [y.sphere((0.1, 0.2, 0.49), 0.5, material=m),
                                       y.box((0, 0, -1), (1, 1, 1), fixed=True, material=m)],
    "f_three_spheres_reverse": lambda y, m: [y.sphere((0, 0, 1.98), 0.5, material=m),
                                             y.sphere((0, 0, 0.99), 0.5, material=m),
                                             y.sphere((0, 0, 0), 0.5, material=m)],
}
SCALARS = ("penetrationDepth", "refR1", "refR2", "kn", "ks", "tangensOfFrictionAngle")
VECTORS = ("normal", "contactPoint", "normalForce", "shearForce")


def _check_interaction(i, ref, rtol):
    assert (i.id1, i.id2) == (ref["id1"], ref["id2"])
    assert i.isReal == ref["isReal"]
    assert type(i.geom).__name__ == ref["geom_class"]
    assert type(i.phys).__name__ == ref["phys_class"]
    g, p = i.geom, i.phys
    for k in SCALARS:
        obj = g if hasattr(type(g), "_fields") and k in type(g)._fields else p
        assert getattr(obj, k) == pytest.approx(ref[k], rel=rtol, abs=1e-12), k
    for k in VECTORS:
        obj = g if k in type(g)._fields else p
        scale = max(1.0, np.abs(ref[k]).max())
        np.testing.assert_allclose(np.asarray(getattr(obj, k)), ref[k], rtol=rtol, atol=rtol * scale, err_msg=k)


@pytest.mark.parametrize("scene", list(SCENES))
def test_one_step_contacts_match_yade(yade, scene):
    """Ids (functor order), geometry, stiffness, forces and body state after one step equal YADE's."""
    ref = reference("contacts")[scene]
    m = _setup(yade)
    yade.O.bodies.append(SCENES[scene](yade, m))
    yade.O.step()
    real = list(yade.O.interactions)
    assert len(real) == len(ref["interactions"])
    for r in ref["interactions"]:
        _check_interaction(yade.O.interactions[r["id1"], r["id2"]], r, 1e-12)
    for b in ref["bodies"]:
        scale = max(1.0, np.abs(b["f"]).max())
        np.testing.assert_allclose(np.asarray(yade.O.forces.f(b["id"])), b["f"], rtol=1e-12, atol=1e-12 * scale)
        np.testing.assert_allclose(np.asarray(yade.O.forces.t(b["id"])), b["t"], rtol=1e-12, atol=1e-9)
        np.testing.assert_allclose(np.asarray(yade.O.bodies[b["id"]].state.vel), b["vel"], rtol=1e-12, atol=1e-15)


@pytest.mark.parametrize("case,vel,ang_vel", [
    ("g_sheared_sphere_sphere", (1, 0, -0.1), (0, 2, 0)),
    ("g2_sheared_sphere_sphere", (1, 0, -0.1), (0, -2, 0)),
    ("g3_sliding_sphere_sphere", (100, 30, -0.1), (1, 0, 3)),
])
def test_incremental_shear_history_matches_yade(yade, case, vel, ang_vel):
    """The shear force (rotation of the tangent plane, increments, Coulomb slip) follows YADE step by step."""
    ref = reference("contacts")[case]["steps"]
    _setup(yade)
    b1, b2 = _two_spheres(yade, None)
    yade.O.bodies.append([b1, b2])
    b2.state.vel, b2.state.angVel = vel, ang_vel
    for step in ref:
        yade.O.step()
        assert yade.O.iter == step["iter"]
        if step["intr"] is None:
            assert not yade.O.interactions.has(0, 1, onlyReal=True)
            continue
        # the same arithmetic as YADE up to the order of floating-point operations
        _check_interaction(yade.O.interactions[0, 1], step["intr"], 1e-9)
        for k in ("pos", "vel", "angVel"):
            np.testing.assert_allclose(np.asarray(getattr(b2.state, k)), step[f"b1_{k}"], rtol=1e-9, atol=1e-12)
        np.testing.assert_allclose(np.asarray(yade.O.forces.t(0)), step["t0"], rtol=1e-8, atol=1e-8)
