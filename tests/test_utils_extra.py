"""yade.utils measures/edits, bodiesHandling, linterpolation and post2d against real YADE
(tests/reference/yade/utils_extra.py) and closed forms."""

from __future__ import annotations

import math
import random

import numpy as np
import pytest
from conftest import reference

REF = reference("utils_extra")


def _vec(v):
    return np.asarray(v._a) if hasattr(v, "_a") else np.asarray(v, dtype=float)


def _close(got, want, rtol=1e-9, atol=1e-9):
    if isinstance(want, dict):
        assert set(got) == set(want), (set(got), set(want))
        for k in want:
            _close(got[k], want[k], rtol, atol)
    elif isinstance(want, list | tuple) and want and isinstance(want[0], list | tuple | dict):
        assert len(got) == len(want)
        for g, w in zip(got, want, strict=True):
            _close(g, w, rtol, atol)
    elif isinstance(want, str | bool | None):
        assert got == want
    else:
        np.testing.assert_allclose(np.asarray(_vec(got), dtype=float), np.asarray(want, dtype=float), rtol=rtol,
                                   atol=atol, equal_nan=True)


def _scene(y):
    """The reference scene: 4 spheres (one fixed), a tilted facet, a rotated box, velocities set."""
    u, O = y.utils, y.O
    O.materials.append(y.FrictMat(young=1e7, poisson=.3, density=2000, frictionAngle=.5))
    O.bodies.append([u.sphere((0, 0, 0), .5), u.sphere((0.95, 0, 0), .5), u.sphere((0, 0.9, 0.1), .4),
                     u.sphere((3, 0, 0), .3, fixed=True), u.facet([(-1, -1.3, -0.45), (2, -1, -0.35), (0, 2, -0.4)]),
                     u.box((5, 5, 5), (.1, .2, .3), orientation=y.Quaternion((1, 1, 0), .3))])
    for i, v in {0: (1, 2, 3), 1: (-1, 0, .5), 3: (7, 0, 0), 5: (0, 1, 0)}.items():
        O.bodies[i].state.vel = v
    O.bodies[0].state.angVel = (.1, .2, .3)
    O.bodies[2].state.angVel = (0, 0, 1)
    O.bodies[5].state.angMom = (1, 2, 3)
    O.bodies[1].mask = 3


def _step(y):
    bounds = [y.Bo1_Sphere_Aabb(), y.Bo1_Facet_Aabb(), y.Bo1_Box_Aabb()]
    y.O.engines = [y.ForceResetter(), y.InsertionSortCollider(bounds),
                   y.InteractionLoop([y.Ig2_Sphere_Sphere_ScGeom(), y.Ig2_Facet_Sphere_ScGeom()],
                                     [y.Ip2_FrictMat_FrictMat_FrictPhys()], [y.Law2_ScGeom_FrictPhys_CundallStrack()]),
                   y.NewtonIntegrator(gravity=(0, 0, -10), damping=0)]
    y.O.dt = 1e-4
    y.O.step()


def test_momenta_before_step_match_yade_and_closed_form(yade):
    _scene(yade)
    u, ref = yade.utils, REF["scene_before"]
    _close(u.momentum(), ref["momentum"])
    _close(u.angularMomentum(), ref["angularMomentum"])
    _close(u.angularMomentum((1, 2, 3)), ref["angularMomentum_123"])
    b = yade.O._scene.bodies
    n = b.count
    np.testing.assert_allclose(_vec(u.momentum()), (b.mass[:n, None] * b.vel[:n]).sum(axis=0))


def test_measures_after_one_step_match_yade(yade):
    _scene(yade)
    _step(yade)
    u, bh, ref = yade.utils, yade.bodiesHandling, REF["after_step"]
    _close(u.momentum(), ref["momentum"])
    _close(u.angularMomentum(), ref["angularMomentum"])
    _close(u.angularMomentum((1, 2, 3)), ref["angularMomentum_123"])
    _close(u.aabbDim(), ref["aabbDim"])
    _close(u.aabbDim(.1, True), ref["aabbDim_cut_centers"])
    _close(u.fractionalBox(), ref["fractionalBox"])
    _close(u.fractionalBox(.5), ref["fractionalBox_half"])
    _close(u.fractionalBox(.5, ((0, 0, 0), (1, 2, 3))), ref["fractionalBox_given"])
    _close([u.perpendicularArea(a) for a in range(3)], ref["perpendicularArea"])
    for a in (-1, 0, 1, 2):
        _close(u.sumFacetNormalForces([4], a), ref["sumFacetNormalForces"][str(a)], rtol=1e-7)
    _close(u.forcesOnPlane((0.5, 0, 0), (1, 0, 0)), ref["forcesOnPlane_x"], rtol=1e-7, atol=1e-6)
    _close(u.forcesOnPlane((0.5, 0, 0), (-2, 0, 0)), ref["forcesOnPlane_minus2x"], rtol=1e-7, atol=1e-6)
    _close(u.forcesOnPlane((0, 0, -0.3), (0, 0, 1)), ref["forcesOnPlane_z"], rtol=1e-7, atol=1e-6)
    _close(u.forcesOnCoordPlane(0.5, 0), ref["forcesOnCoordPlane_x"], rtol=1e-7, atol=1e-6)
    _close(u.forcesOnCoordPlane(0.5, 1), ref["forcesOnCoordPlane_y"], rtol=1e-7, atol=1e-6)
    _close(u.maxOverlapRatio(), ref["maxOverlapRatio"])
    _close(u.sumTorques([0, 1], (0, 2, 0), (1, 0, 0)), ref["sumTorques"], rtol=1e-7)
    assert u.numIntrsOfEachBody() == ref["numIntrsOfEachBody"]
    assert [list(x) for x in u.negPosExtremeIds(0, 1.0)] == ref["negPosExtremeIds_x"]
    _close(u.getSpheresVolume2D(), ref["getSpheresVolume2D"])
    for key, args, kw in (("spheresPackDimensions_01", ([0, 1],), {}),
                          ("spheresPackDimensions_mask2", ([0, 1, 2, 3],), {"mask": 2}),
                          ("spheresPackDimensions_23", ([yade.O.bodies[2], yade.O.bodies[3]],), {}),
                          ("spheresPackDimensions_04", ([0, 4],), {})):
        _close(bh.spheresPackDimensions(*args, **kw), ref[key])
    assert ref["spheresPackDimensions_empty"]["exception"] == "RuntimeWarning"
    with pytest.raises(RuntimeWarning):
        bh.spheresPackDimensions([])
    _close(bh.facetsDimensions([4]), ref["facetsDimensions_4"])


def test_psd_matches_yade(yade, capsys):
    _scene(yade)
    _step(yade)
    u, ref = yade.utils, REF["after_step"]
    for got, want in ((u.psd(), ref["psd"]), (u.psd(bins=3, mass=False), ref["psd_count3"])):
        for g, w in zip(got, want, strict=True):  # YADE's arrays are stored as their repr
            np.testing.assert_allclose(g, eval(w, {"array": np.array}), rtol=1e-7)
    assert ref["psd_mask2"] is False and u.psd(mask=2) is False
    assert "Monodisperse packing with diameter = 1.0" in capsys.readouterr().out


def test_post2d_matches_yade(yade):
    _scene(yade)
    _step(yade)
    p, ref = yade.post2d, REF["post2d"]
    _close(p.data(lambda b: b.state.vel[0], p.AxisFlatten(False, 2)), ref["raw_scalar"])
    _close(p.data(lambda b: b.state.vel[0], p.AxisFlatten(False, 1), onlyDynamic=False), ref["raw_all"])
    _close(p.data(lambda b: b.state.vel, p.AxisFlatten(True, 0)), ref["raw_vector_ref"])
    for name, kw in (("smooth", {}), ("smooth_thresh1", {"relThreshold": 1.})):
        _close(p.data(lambda b: b.state.vel[0], p.AxisFlatten(False, 2), stDev=.5, div=(3, 4), **kw), ref[name])
    _close(p.data(lambda b: b.state.vel, p.AxisFlatten(False, 2), stDev=.5, div=(3, 4)), ref["smooth_vector"])
    for kw in ({"perArea": 2}, {"margin": (.5, .2)}):
        with pytest.raises(NotImplementedError):
            p.data(lambda b: b.state.vel[0], p.AxisFlatten(False, 2), stDev=.5, **kw)


def test_post2d_smooth_is_gaussian_mean():
    """One cell, two points: exp(-d^2/(2 s^2)) weights, cut at relThreshold*stDev."""
    from granum.yade.post2d import _smooth

    pts = np.array([[0.0, 0.0], [1.0, 0.0]])
    val = np.array([1.0, 4.0])
    got = _smooth(pts, val, np.array([0.25]), np.array([0.0]), 0.5, 3.0)
    w = np.exp(-np.array([0.25, 0.75]) ** 2 / 0.5)
    np.testing.assert_allclose(got, [[(w @ val) / w.sum()]])
    assert np.isnan(_smooth(pts, val, np.array([5.0]), np.array([0.0]), 0.5, 3.0)[0, 0])


def test_cylinder_flatten_unrolls_around_axis(yade):
    yade.O.bodies.append(yade.utils.sphere((3, 4, 7), .5))
    f = yade.post2d.CylinderFlatten(False, 2)
    assert f(yade.O.bodies[0]) == pytest.approx((5.0, 7.0))
    assert f.planar(yade.O.bodies[0], (3, 4, 1)) == pytest.approx((5.0, 1.0))
    assert f.normal(yade.O.bodies[0], (-4, 3, 0)) == pytest.approx(5.0)
    with pytest.raises(NotImplementedError):
        yade.post2d.HelixFlatten(False, (0, 1), .1)


def test_spheres_modify_and_duplicate_match_yade(yade):
    _scene(yade)
    _step(yade)
    bh, O, ref = yade.bodiesHandling, yade.O, REF["modify"]
    assert bh.spheresModify([0, 1], shift=(1, 2, 3), scale=2.0, orientation=yade.Quaternion((0, 0, 1), math.pi / 2))
    for i, want in ref["bodies"].items():
        b = O.bodies[int(i)]
        _close({"pos": b.state.pos, "radius": b.shape.radius, "mass": b.state.mass, "inertia": b.state.inertia}, want)
    copies = bh.spheresModify([2], shift=(1, 0, 0), scale=.5, copy=True)
    got = [{"id": b.id, "pos": b.state.pos, "radius": b.shape.radius, "mass": b.state.mass,
            "inertia": b.state.inertia, "mask": b.mask} for b in copies]
    _close(got, ref["copies"])
    assert bh.spheresModify(mask=2, shift=(0, 0, 1)) == ref["mask2_shift"]
    _close([O.bodies[i].state.pos for i in range(4)], ref["pos_after_mask2"])
    dup = bh.sphereDuplicate(3)
    want = ref["sphereDuplicate"]
    assert (dup.id, dup.dynamic, dup.state.blockedDOFs, len(O.bodies)) == (want["id"], want["dynamic"],
                                                                           want["blockedDOFs"], want["count"])
    _close([dup.state.pos, dup.shape.radius, dup.state.mass], [want["pos"], want["radius"], want["mass"]])
    assert bh.sphereDuplicate(4) is ref["sphereDuplicate_facet"] is False


def test_calm_by_mask(yade):
    _scene(yade)
    _step(yade)
    u, O = yade.utils, yade.O
    u.calm(2)  # only body 1 has mask bit 2
    moving = [np.any(_vec(O.bodies[i].state.vel) != 0) for i in range(3)]
    assert moving == [True, False, True]
    assert not np.any(_vec(O.bodies[1].state.angVel))
    u.calm()
    assert not any(np.any(_vec(b.state.vel)) or np.any(_vec(b.state.angVel)) or np.any(_vec(b.state.angMom))
                   for b in O.bodies)


def test_pure_helpers_match_yade(yade):
    u, ref = yade.utils, REF["pure"]
    _close(u.inscribedCircleCenter((0, 0, 0), (1, 0, 0), (0, 1, 0)), ref["inscribedCircleCenter"])
    _close(u.inscribedCircleCenter((1, 2, 3), (4, -1, 0), (0, 0, 5)), ref["inscribedCircleCenter_2"])
    pts = ((0, 0, 0), (0, 0, 2), (1, 1, 1), (-1, 0, 0))
    assert [u.ptInAABB(p, (-1, -1, -1), (1, 1, 1)) for p in pts] == ref["ptInAABB"]
    _close(u.spher2cart((2, .3, .4)), ref["spher2cart"])
    _close([u.cart2spher(p) for p in ((1, -2, 3), (0, 0, 0), (-1, -1, 0))], ref["cart2spher"])
    _close(u.aabbExtrema2d([(0, 1), (2, -1), (1, 5)]), ref["aabbExtrema2d"])
    halves = ([(0, 1), (1, 2), (2, 0)], [(1, 1), (1, 2), (2, 3)], [(1, 1), (0, 0)])
    assert [[list(p) for p in u.xMirror(h)] for h in halves] == ref["xMirror"]
    assert ref["getViscoelasticFromSpheresInteraction"]["exception"] == "RuntimeError"
    with pytest.raises(RuntimeError):
        u.getViscoelasticFromSpheresInteraction(1e-3, .5, .6)
    with pytest.raises(IndexError):
        u.typedEngine("Foo")


def test_linterpolation_matches_yade():
    from granum.yade import linterpolation as L

    ref = REF["linterpolation"]
    x, y = [0, 1, 3, 4], [2, 4, 0, 1]
    _close(L.integral(x, y), ref["integral"])
    _close(L.integral([0], [1]), ref["integral_one"])
    for args, want in zip(((2.5, 0, 2, 1, 4), (1, 0, 2, 1, 2), (1, 1, 4, 3, 0), (10, 0, 2, 1, 4)),
                          ref["revIntegrateLinear"], strict=True):
        if isinstance(want, dict):
            with pytest.raises(ValueError):
                L.revIntegrateLinear(*args)
        else:
            _close(L.revIntegrateLinear(*args), want)
    for v, want in zip((4.5, 0, 100, 1), ref["xFractionalFromIntegral"], strict=True):
        if isinstance(want, dict):
            with pytest.raises(ValueError):
                L.xFractionalFromIntegral(v, x, y)
        else:
            _close(L.xFractionalFromIntegral(v, x, y), want)
    _close([L.xFromIntegral(v, x, y) for v in (4.5, 10, 25, 7.5)], ref["xFromIntegral"])
    got = [L.sanitizeInterpolation([1, 2, 3], [5, 6, 7], *a) for a in ((0, 4), (1, 3), (1.5, 5), (0, 2))]
    assert [[list(a), list(b)] for a, b in got] == ref["sanitizeInterpolation"]


def test_random_orientation_is_uniform_unit_quaternion(yade):
    random.seed(7)
    q = np.array([_vec(yade.utils.randomOrientation()) for _ in range(20000)])  # (w, x, y, z)
    np.testing.assert_allclose(np.linalg.norm(q, axis=1), 1.0, atol=1e-12)
    # uniform rotations: each component of q^2 has mean 1/4, and the rotation angle's cosine is uniform-ish
    np.testing.assert_allclose((q ** 2).mean(axis=0), 0.25, atol=0.01)
    # the rotated x axis is uniform on the sphere: mean 0, second moments 1/3
    ex = np.stack([1 - 2 * (q[:, 2] ** 2 + q[:, 3] ** 2), 2 * (q[:, 1] * q[:, 2] + q[:, 0] * q[:, 3]),
                   2 * (q[:, 1] * q[:, 3] - q[:, 0] * q[:, 2])], axis=1)
    np.testing.assert_allclose(ex.mean(axis=0), 0.0, atol=0.02)
    np.testing.assert_allclose((ex ** 2).mean(axis=0), 1 / 3, atol=0.02)
    random.seed(7)
    again = yade.utils.randomOrientation()
    assert list(_vec(again)) == list(q[0])


def test_edits_of_bodies(yade):
    _scene(yade)
    u, O = yade.utils, yade.O
    u.setBodyVelocity(0, (9, 8, 7), "xz")
    assert list(_vec(O.bodies[0].state.vel)) == [9, 2, 7]
    u.setBodyPosition(1, (5, 5, 5), "y")
    assert list(_vec(O.bodies[1].state.pos)) == [0.95, 5, 0]
    u.shiftBodies([2], (1, 1, 1))
    np.testing.assert_allclose(_vec(O.bodies[2].state.pos), (1, 1.9, 1.1))
    u.setRefSe3()
    np.testing.assert_allclose(_vec(O.bodies[2].state.refPos), (1, 1.9, 1.1))
    u.wireAll()
    assert all(b.shape.wire for b in O.bodies)
    u.wireNone()
    u.wireNoSpheres()
    assert [b.shape.wire for b in O.bodies] == [False] * 4 + [True, True]
    with pytest.raises(ValueError):
        u.setBodyVelocity(0, (1, 1, 1), "xw")


def test_post2d_plot_draws_each_kind(yade):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    _scene(yade)
    p = yade.post2d
    flat = p.AxisFlatten(False, 2)
    for d in (p.data(lambda b: b.state.vel[0], flat), p.data(lambda b: b.state.vel, flat),
              p.data(lambda b: b.state.vel[0], flat, stDev=2.0, div=(8, 8)),
              p.data(lambda b: b.state.vel, flat, stDev=2.0, div=(8, 8))):
        fig = plt.figure()
        axes, mappable = p.plot(d, cbar=True)
        assert axes is fig.gca() and mappable.get_array() is not None
        plt.close(fig)
