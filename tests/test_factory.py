"""SpheresFactory, CircularFactory, BoxFactory against real YADE 2023.02a (tests/reference/yade/factory.json) and
against their own rules: the mass made follows massFlowRate x time, centres inside the region, no overlaps, radii
in range, bad input refused, the same bits after a checkpoint."""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import granum_reference_run, reference

REF = reference("factory")


@pytest.fixture(scope="module")
def granum_run():
    """The reference script run unmodified under granum."""
    return granum_reference_run("factory.py")


def _same(got, want):
    if isinstance(want, float) and math.isnan(want):
        return isinstance(got, float) and math.isnan(got)
    if isinstance(want, list):
        return len(got) == len(want) and all(_same(g, w) for g, w in zip(got, want, strict=True))
    return got == want


def test_defaults(yade):
    for name, ref in REF["defaults"].items():
        f = getattr(yade, name)()
        for k, v in ref.items():
            got = list(getattr(f, k)) if k in ("center", "normal", "normalVel", "color") else getattr(f, k)
            assert _same(got, v), (name, k, got, v)


def test_metering_like_yade(granum_run):
    """Equal spheres: the count, masses and goal after every step, iterBorn, velocity along normalVel, mask, colour,
    blockedDOFs and material (materialId -2) are YADE's exactly."""
    got, ref = granum_run["metering"], REF["metering"]
    for g, r in zip(got["steps"], ref["steps"], strict=True):
        assert g["iter"] == r["iter"] and g["numParticles"] == r["numParticles"] and g["ids"] == r["ids"]
        for key in ("totalMass", "goalMass", "totalVolume"):
            assert g[key] == pytest.approx(r[key], rel=1e-14), (g["iter"], key)
    for key in ("iterBorn", "vel", "mask", "color", "blockedDOFs", "material", "massFlowRate"):
        assert _same(got[key], ref[key]), key
    assert got["mass"] == pytest.approx(ref["mass"], rel=1e-15)


def test_speeds_and_max_mass(granum_run):
    """One speed per step, uniform in [vMin, vMax], along the normal; radii in [rMin, rMax]; production stops
    once maxMass is passed while goalMass keeps growing."""
    got, ref = granum_run["speeds"], REF["speeds"]
    for run in (got, ref):
        v = np.array(run["vel"])
        assert (v[:, 1:] == 0).all() and ((v[:, 0] >= 1) & (v[:, 0] <= 3)).all()
        assert all(0.002 <= r <= 0.006 for r in run["radii"])
        assert run["totalMass"] >= 0.0035 > run["totalMass"] - 2000 * 4 / 3 * math.pi * run["radii"][-1] ** 3
    assert got["goalMass"] == pytest.approx(ref["goalMass"], rel=1e-12)


def _mass_share(radii, small):
    m = np.array(radii) ** 3
    return m[np.isclose(radii, small)].sum() / m.sum()


def test_psd_like_yade(granum_run):
    """By count the classes alternate (YADE's order exactly); by mass each class keeps its share (YADE's order
    may differ where a share equals its target up to round-off); ranges: diameters within the classes' bounds."""
    got, ref = granum_run["psd"], REF["psd"]
    assert got["count"]["radii"] == ref["count"]["radii"]
    for run in (got, ref):
        assert _mass_share(run["mass"]["radii"], 0.002) == pytest.approx(0.5, abs=0.03)
        r = np.array(run["ranges"]["radii"])
        assert ((r >= 0.001) & (r <= 0.004)).all()
        small = (r <= 0.002).sum()
        assert small / len(r) > 0.5    # 30 % of the mass in the small class: most of the spheres
    for key in ("mass", "count", "ranges"):
        assert got[key]["totalMass"] == pytest.approx(ref[key]["totalMass"], rel=0.1)


def test_region_like_yade(granum_run):
    """Circle: centres within radius - r of the axis, uniform in that distance (half of them in the inner half),
    uniform along the normal within length/2; disk (length 0): in its plane; box: centre +- extents; no two
    spheres overlap; a failed sphere stops the flow (stopIfFailed) or not (the box retries next step)."""
    got, ref = granum_run, REF
    c = got["circle"]
    assert c["n"] == ref["circle"]["n"] == 3000
    assert c["max_axis_distance"] <= 1.0 and c["axial"][0] >= -1 and c["axial"][1] <= 1
    assert c["inner_half"] == pytest.approx(ref["circle"]["inner_half"], abs=0.05)   # binomial sd 0.009
    assert c["axial_inner_half"] == pytest.approx(ref["circle"]["axial_inner_half"], abs=0.05)
    d = got["disk"]
    assert d["x"] == [5.0, 5.0] and d["max_axis_distance"] <= 0.048 and d["min_gap"] >= 0
    # random sequential filling, unseeded in both: YADE 292-308 (20 runs), granum 285-309 (20 runs)
    assert d["n"] == pytest.approx(ref["disk"]["n"], rel=0.08)
    assert d["massFlowRate"] == 0 and d["n_after"] == d["n"]
    assert d["goalMass"] == pytest.approx(d["n"] * 2000 * 4 / 3 * math.pi * 0.002 ** 3, rel=1e-12)
    b = got["box"]
    assert all(lo >= c0 - e for lo, c0, e in zip(b["lo"], (-5, 0, 0), (0.05, 0.04, 0.03), strict=True))
    assert all(hi <= c0 + e for hi, c0, e in zip(b["hi"], (-5, 0, 0), (0.05, 0.04, 0.03), strict=True))
    assert b["min_gap"] >= 0 and b["massFlowRate"] == 1e6 and b["n_after"] >= b["n"]
    # unseeded as well: YADE 282-330 (30 runs, sd 12), granum 286-332 (30 runs); CI drew 337 once
    assert b["n"] == pytest.approx(ref["box"]["n"], rel=0.2)


def test_obstacles_like_yade(granum_run):
    """A facet whose bound covers the region leaves no place (the flow stops); a flat facet and a sphere are
    kept clear of."""
    got, ref = granum_run["obstacles"], REF["obstacles"]
    for key in ("diagonal_n", "diagonal_rate", "flat_n", "sphere_n"):
        assert got[key] == ref[key], key
    assert got["flat_min_gap"] >= 0 and got["sphere_min_gap"] >= 0


def test_pyrunners_see_the_step_as_in_yade(granum_run):
    """A PyRunner after the factory sees the spheres made in its step; one before it, those of the steps before."""
    assert granum_run["pyrunner"] == REF["pyrunner"]


def _scene(y, seed=7, **kw):
    O = y.O
    O.materials.append(y.FrictMat(density=2500))
    args = dict(center=(0, 0, 0.5), radius=0.2, length=0.1, rMin=0.01, rMax=0.02, vMin=0.5, vMax=1.0,
                massFlowRate=20.0, normal=(0, 0, -1), maxParticles=-1, seed=seed, label="fac")
    args.update(kw)
    f = y.CircularFactory(**args)
    O.engines = [y.ForceResetter(), y.InsertionSortCollider([y.Bo1_Sphere_Aabb(), y.Bo1_Facet_Aabb()]),
                 y.InteractionLoop([y.Ig2_Sphere_Sphere_ScGeom(), y.Ig2_Facet_Sphere_ScGeom()],
                                   [y.Ip2_FrictMat_FrictMat_FrictPhys()], [y.Law2_ScGeom_FrictPhys_CundallStrack()]),
                 y.NewtonIntegrator(gravity=(0, 0, -9.81)), f]
    O.dt = 1e-4
    return f


def test_mass_follows_the_flow_rate(yade):
    """After n steps (run in compiled chunks), massFlowRate x n dt <= totalMass < that + one sphere's mass; the
    new spheres are in the region, radii in range, not overlapping; ids, masses and volumes add up."""
    O = yade.O
    f = _scene(yade)
    O.run(300, True)
    goal = 20.0 * 1e-4 * 300
    assert f.goalMass == pytest.approx(goal, rel=1e-12)
    m_max = 2500 * 4 / 3 * math.pi * 0.02 ** 3
    assert goal <= f.totalMass < goal + m_max
    a = O.bodies.arrays("pos", "mass")
    assert list(a["ids"]) == f.ids and f.numParticles == len(f.ids)
    assert a["mass"].sum() == pytest.approx(f.totalMass, rel=1e-12)
    r = np.array([O.bodies[i].shape.radius for i in f.ids])
    assert ((r >= 0.01) & (r <= 0.02)).all()
    assert f.totalVolume == pytest.approx((4 / 3 * math.pi * r ** 3).sum(), rel=1e-12)
    born = np.array([O.bodies[i].iterBorn for i in f.ids])
    assert born.min() == 0 and born.max() < 300


def test_placement_rules(yade):
    """Placed in one step (no motion yet): inside the cylinder, clear of each other."""
    O = yade.O
    f = _scene(yade, massFlowRate=1e6, maxParticles=150, vMin=0, vMax=0)
    O.step()
    assert f.numParticles == 150
    p = np.array([O.bodies[i].state.pos for i in f.ids])
    r = np.array([O.bodies[i].shape.radius for i in f.ids])
    assert (np.hypot(p[:, 0], p[:, 1]) <= 0.2 - r + 1e-15).all()
    assert (np.abs(p[:, 2] - 0.5) <= 0.05).all()
    d = np.linalg.norm(p[:, None] - p[None], axis=2) - r[:, None] - r[None]
    np.fill_diagonal(d, np.inf)
    assert d.min() >= 0


def test_same_seed_same_bits_and_checkpoint(yade, tmp_path):
    """A seed gives the same spheres whether run in one go or saved, loaded and continued."""
    O = yade.O
    _scene(yade)
    O.run(150, True)
    O.save(str(tmp_path / "f.yade"))
    O.run(150, True)
    whole = O.bodies.arrays("pos", "vel")
    O.load(str(tmp_path / "f.yade"))
    O.run(150, True)
    again = O.bodies.arrays("pos", "vel")
    assert np.array_equal(whole["ids"], again["ids"])
    assert np.array_equal(whole["pos"], again["pos"]) and np.array_equal(whole["vel"], again["vel"])


@pytest.mark.parametrize("kw, error, words", [
    (dict(massFlowRate=math.nan), ValueError, "massFlowRate"),
    (dict(rMin=0.03), ValueError, "rMin"),
    (dict(radius=-1.0), ValueError, "radius"),
    (dict(normal=(0, 0, 0)), ValueError, "normal"),
    (dict(PSDsizes=[0.01, 0.02], PSDcum=[1.0]), ValueError, "PSDsizes"),
    (dict(PSDsizes=[0.01], PSDcum=[1.5]), ValueError, "PSDcum"),
    (dict(materialId=5), ValueError, "materialId"),
    (dict(vMin=2.0), ValueError, "vMin"),
])
def test_bad_input(yade, kw, error, words):
    """Refused by name when the run starts, before any sphere is made."""
    O = yade.O
    _scene(yade, **kw)
    with pytest.raises(error, match=words):
        O.run(5, True)
    assert len(O.bodies) == 0


def test_refused_attributes(yade):
    with pytest.raises(NotImplementedError, match="vAngle"):
        yade.CircularFactory(vAngle=0.3)
    with pytest.raises(TypeError, match="maxParticles"):
        yade.BoxFactory(maxParticles=1.5)
    with pytest.raises(TypeError, match="radiuss"):
        yade.CircularFactory(radiuss=1)
    yade.O.engines = [yade.SpheresFactory(massFlowRate=1, rMin=1, rMax=1, vMin=0, vMax=0, normal=(0, 0, 1))]
    with pytest.raises(NotImplementedError, match="no region"):
        yade.O.step()
