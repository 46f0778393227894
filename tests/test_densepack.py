"""Dense packings and SpherePack statistics against YADE 2023.02a (tests/reference/yade/pack_dense.py): psd,
cellRepeat/cellFill, relDensity, makeCloud in a sheared cell, randomPeriPack, randomDensePack (periodic and
aperiodic), filterSpherePack and the memoization database."""

from __future__ import annotations

import sqlite3

import numpy as np
import pytest
from conftest import reference

from granum.yade import _densepack

REF = None


def ref():
    global REF
    REF = REF or reference("pack_dense")
    return REF


def five(pack):
    return pack.SpherePack([((0, 0, 0), .1), ((1, 0, 0), .2), ((0, 1, 0), .3), ((0, 0, 1), .4), ((1, 1, 1), .25)])


def two(pack):
    sp = pack.SpherePack([((0.1, 0.2, 0.3), .1), ((0.6, 0.5, 0.4), .2)])
    sp.cellSize = (1, 1, 1)
    return sp


def test_psd_and_rel_density_equal_yades(yade):
    sp = five(yade.pack)
    r = ref()["psd"]
    for got, want in ((sp.psd(bins=5), r["mass5"]), (sp.psd(bins=5, mass=False), r["count5"]),
                      (sp.psd(bins=1), r["mass1"]), (sp.psd(), r["default"])):
        assert np.allclose(got[0], want[0], rtol=1e-15) and np.allclose(got[1], want[1], rtol=1e-14, atol=1e-15)
    assert yade.pack.SpherePack().psd() == tuple(r["empty"])
    assert sp.relDensity() == pytest.approx(ref()["relDensity"], rel=1e-14)
    assert two(yade.pack).relDensity() == pytest.approx(ref()["relDensity_periodic"], rel=1e-14)
    with pytest.raises(ValueError, match="bins"):
        sp.psd(bins=0)


def test_cell_repeat_and_fill_equal_yades(yade):
    sp = two(yade.pack)
    sp.cellRepeat((2, 1, 3))
    assert [(list(c), r) for c, r in sp] == [(list(c), r) for c, r in ref()["cellRepeat"]["list"]]
    assert list(sp.cellSize) == ref()["cellRepeat"]["cellSize"]
    sp = two(yade.pack)
    sp.cellFill((2.5, 1, 0.5))
    assert [(list(c), r) for c, r in sp] == [(list(c), r) for c, r in ref()["cellFill"]["list"]]
    assert list(sp.cellSize) == ref()["cellFill"]["cellSize"]
    for call, case in ((lambda: five(yade.pack).cellFill((3, 3, 3)), "cellFill_aperiodic"),
                       (lambda: five(yade.pack).cellRepeat((2, 2, 2)), "cellRepeat_aperiodic"),
                       (lambda: sp.cellRepeat((0, 1, 1)), "cellRepeat_zero")):
        want = ref()[case]
        with pytest.raises((RuntimeError, ValueError)) as err:
            call()
        assert type(err.value).__name__ == want["exception"] and str(err.value) == want["message"]


def test_psd_of_a_generated_pack_follows_the_requested_distribution(yade):
    """examples/test/psd.py's distribution by mass with num=5000: the pack's cumulative mass fraction at each
    requested size is the requested one to within one bin's share (deterministic sizes at quantiles)."""
    sizes, cumm = [.02, 0.04, 0.045, .05, .06, .08, .12], [0., 0.1, 0.3, 0.3, .3, .7, 1.]
    sp = yade.pack.SpherePack()
    sp.makeCloud((0, 0, 0), (1, 1, 1), psdSizes=sizes, psdCumm=cumm, distributeMass=True, num=5000, seed=1)
    d = 2 * np.asarray(sp.radii) / sp.appliedPsdScaling
    m = d ** 3
    got = [m[d <= s * (1 + 1e-12)].sum() / m.sum() for s in sizes]
    assert got == pytest.approx(cumm, abs=0.01)
    edges, frac = sp.psd(bins=30, mass=True)
    assert len(edges) == len(frac) == 31 and frac[0] == 0 and frac[-1] == 1 and np.all(np.diff(frac) >= 0)


def test_make_cloud_in_a_sheared_cell(yade):
    """examples/PeriodicBoundaries/periodic-triax-settingHsize.py's cell: 500 spheres whose sizes come from the
    porosity retries as in YADE (the same radii), centres inside the parallelepiped, no overlap across its
    sheared faces (brute force over the 27 images), cellSize zero as YADE leaves it."""
    H = np.array([[1.0, -0.15, -0.10], [-0.2, 1.5, 0.3], [0.3, -0.3, 1.0]])
    sp = yade.pack.SpherePack()
    with pytest.warns(UserWarning):
        n = sp.makeCloud(hSize=yade.Matrix3(*H.ravel()), rMean=-0.01, rRelFuzz=.2, num=500, periodic=True,
                         porosity=0.52, distributeMass=False, seed=3)
    want = ref()["makeCloud_sheared"][0]
    c, r = np.asarray(sp.centers), np.asarray(sp.radii)
    assert n == len(sp) == want["n"] and list(sp.cellSize) == [0, 0, 0] and sp.isPeriodic
    assert (r.min(), r.max()) == pytest.approx((want["rmin"], want["rmax"]), rel=1e-12)
    assert (4 / 3 * np.pi * r ** 3).sum() / np.linalg.det(H) == pytest.approx(want["solid"], rel=1e-12)
    f = np.linalg.solve(H, c.T).T
    assert f.min() >= 0 and f.max() < 1
    shifts = np.array([[i, j, k] for i in (-1, 0, 1) for j in (-1, 0, 1) for k in (-1, 0, 1)]) @ H.T
    for i in range(len(r)):
        d = np.linalg.norm(c[None, :, :] + shifts[:, None, :] - c[i], axis=2) - r - r[i]
        d[13, i] = np.inf   # itself, unshifted
        assert d.min() >= 0


def test_make_cloud_refuses_a_flat_sheared_cell(yade):
    with pytest.raises(ValueError, match="hSize"):
        yade.pack.SpherePack().makeCloud(hSize=yade.Matrix3(1, 1, 0, 1, 1, 0, 0, 0, 1), rMean=.05, periodic=True)
    with pytest.raises(ValueError, match="half a layer"):
        yade.pack.SpherePack().makeCloud(hSize=yade.Matrix3(1, .9, 0, 0, .1, 0, 0, 0, 1), rMean=.05, num=3,
                                         periodic=True)


def _solid(sp, volume):
    return 4 / 3 * np.pi * np.sum(np.asarray(sp.radii) ** 3) / volume


def test_random_peri_pack_is_as_dense_as_yades_and_leaves_the_scene(yade):
    """radius .1 in a 1.2 cell: YADE's three seeds give 117-126 spheres at solid fraction .617-.619; granum's
    run (another random cloud) lies within 10 % of the count and .02 of the fraction. The script's scene is
    untouched."""
    yade.O.bodies.append(yade.sphere((0, 0, 0), 1))
    sp = yade.pack.randomPeriPack(radius=.1, initSize=yade.Vector3(1.2, 1.2, 1.2), seed=1)
    want = ref()["small"]["peri"]
    ns, solids = [w["n"] for w in want], [w["solid"] for w in want]
    assert 0.9 * min(ns) <= len(sp) <= 1.1 * max(ns)
    assert min(solids) - 0.02 <= _solid(sp, np.prod(list(sp.cellSize))) <= max(solids) + 0.02
    assert sp.isPeriodic and len(yade.O.bodies) == 1 and not yade.O.periodic


def test_random_dense_pack_periodic_compression_ends_as_yades(yade):
    """spheresInCell=300, radius .05, seed 1 (YADE's cloud): YADE's PeriIsoCompressor passes a stress reached
    between two unbalanced-force updates at once (its currUnbalanced stays -1), so the compression ends after 1,073
    steps (seeds 1-3: 1,047-3,651); granum's within 25 % of YADE's seed 1 (it took 4,741 when it measured the
    unbalanced force at once), the cell within 1 % and the count within YADE's seeds' range widened by 3 %."""
    sp = yade.pack.randomDensePack(yade.pack.inAlignedBox((0, 0, 0), (1, 1, 1)), radius=.05, spheresInCell=300,
                                   returnSpherePack=True, seed=1)
    runs = ref()["randomDensePack_cell"]
    yade.O.switchScene()
    iters, cell = yade.O.iter, list(yade.O.cell.size)
    yade.O.switchScene()
    assert abs(iters / runs[0]["iter"] - 1) <= 0.25
    np.testing.assert_allclose(cell, runs[0]["cell"], rtol=0.01)
    ns = [w["n"] for w in runs]
    assert 0.97 * min(ns) <= len(sp) <= 1.03 * max(ns)


def test_random_dense_pack_periodic_and_memoized(yade, tmp_path):
    """spheresInCell=100, radius .1, unit box: the count and solid fraction in YADE's range (66-71, .277-.297)
    widened by 10 % and .02; memoizeDb stores it once, a second call returns the same spheres without a DEM
    run, and the file holds float64 blobs, no pickle."""
    db = str(tmp_path / "packs.sqlite")
    box = yade.pack.inAlignedBox((0, 0, 0), (1, 1, 1))
    sp = yade.pack.randomDensePack(box, radius=.1, spheresInCell=100, returnSpherePack=True, seed=2,
                                   memoizeDb=db)
    want = ref()["small"]["cell"]
    ns, solids = [w["n"] for w in want], [w["solid"] for w in want]
    assert 0.9 * min(ns) <= len(sp) <= 1.1 * max(ns)
    assert min(solids) - 0.02 <= _solid(sp, 1.0) <= max(solids) + 0.02
    yade.O.switchScene()
    iters = yade.O.iter
    yade.O.switchScene()
    again = yade.pack.randomDensePack(box, radius=.1, spheresInCell=100, returnSpherePack=True, memoizeDb=db)
    yade.O.switchScene()
    assert yade.O.iter == iters   # no second compression ran in the alternative scene
    yade.O.switchScene()
    np.testing.assert_array_equal(again.centers, sp.centers)
    np.testing.assert_array_equal(again.radii, sp.radii)
    half = yade.pack.randomDensePack(box, radius=.05, spheresInCell=100, returnSpherePack=True, memoizeDb=db)
    assert np.all(np.asarray(half.radii) == 0.05) and len(half) > 4 * len(sp)   # the stored cell, scaled by 1/2
    rows = sqlite3.connect(db).execute(f"select n, centers, radii from {_densepack.TABLE}").fetchall()
    assert len(rows) == 1 and len(rows[0][1]) == 24 * rows[0][0] and len(rows[0][2]) == 8 * rows[0][0]


def test_memoized_random_peri_pack_reuses_the_same_request_only(yade, tmp_path):
    db = str(tmp_path / "packs.sqlite")
    a = yade.pack.randomPeriPack(radius=.1, initSize=yade.Vector3(1.2, 1.2, 1.2), memoizeDb=db, seed=1)
    b = yade.pack.randomPeriPack(radius=.2, initSize=yade.Vector3(2.4, 2.4, 2.4), memoizeDb=db)
    np.testing.assert_allclose(b.centers, 2 * np.asarray(a.centers), rtol=1e-15)
    assert list(b.cellSize) == pytest.approx(2 * np.asarray(list(a.cellSize)), rel=1e-15)
    with sqlite3.connect(db) as con:
        con.execute(f"update {_densepack.TABLE} set radii = x'00'")
    with pytest.raises(ValueError, match="damaged"):
        yade.pack.randomPeriPack(radius=.1, initSize=yade.Vector3(1.2, 1.2, 1.2), memoizeDb=db)


def _compaction(yade):
    """What the last aperiodic randomDensePack left in the alternative scene: its steps, sphere count, mean
    radius, unbalanced force and TriaxialCompressionEngine."""
    yade.O.switchScene()
    try:
        radii = [b.shape.radius for b in yade.O.bodies if type(b.shape).__name__ == "Sphere"]
        triax = next(e for e in yade.O.engines if type(e).__name__ == "TriaxialCompressionEngine")
        return {"iter": yade.O.iter, "spheres": len(radii), "rmean": float(np.mean(radii)),
                "unbalanced": yade.utils.unbalancedForce(), "box0": [triax.width0, triax.height0, triax.depth0]}
    finally:
        yade.O.switchScene()


def _as_yades_box_packing(yade, sp, runs, center):
    """YADE's rules against its ``runs`` of the same call (dense_box.py, seeds 1-4 or 1-3): a TriaxialTest of as
    many spheres in the same box, run by 500 steps to an unbalanced force of at most .005; the spheres' growth (the
    compacted cloud's mean radius: its density) within YADE's seeds widened by .5 % (they spread .65 %); the
    spheres returned around the predicate's centre, their solid fraction in the unit box within .03 of YADE's
    seeds (one sphere of the 20-25 returned weighs .012)."""
    got = _compaction(yade)
    assert got["spheres"] == runs[0]["compaction"]["spheres"]
    np.testing.assert_allclose(got["box0"], runs[0]["compaction"]["box0"], rtol=1e-12)
    assert got["iter"] % 500 == 0 and got["unbalanced"] <= 0.005
    grown = [w["compaction"]["rmean"] for w in runs]
    assert min(grown) * 0.995 <= got["rmean"] <= max(grown) * 1.005
    np.testing.assert_allclose(np.asarray(sp.aabb()).mean(axis=0), center, atol=2 * max(sp.radii))
    solids = [w["solid"] for w in runs]
    assert min(solids) - 0.03 <= _solid(sp, 1.0) <= max(solids) + 0.03
    return got


def test_random_dense_pack_in_a_box_as_yade_and_memoized(yade, tmp_path):
    """radius .1 in a unit box: YADE compacts 143 spheres grown to about 1.4 times the radius (its TriaxialTest's
    box holds them at porosity .8, three times the requested volume) and returns them unscaled; the memoizeDb row
    holds the request (radius, rRelFuzz, box, count, aperiodic) as YADE's; granum reuses it (YADE 2023.02a compacts
    again), scaled for another radius, and gives bodies with the material asked for."""
    want = reference("dense_box")
    db = str(tmp_path / "packs.sqlite")
    unit = yade.pack.inAlignedBox((0, 0, 0), (1, 1, 1))
    sp = yade.pack.randomDensePack(unit, radius=.1, returnSpherePack=True, seed=1, memoizeDb=db)
    first = _as_yades_box_packing(yade, sp, want["unit"], (.5, .5, .5))
    assert np.all(np.asarray(sp.radii) == pytest.approx(first["rmean"], rel=1e-12)) and not sp.isPeriodic
    rows = sqlite3.connect(db).execute(f"select radius, rRelFuzz, dimx, dimy, dimz, n, periodic from "
                                       f"{_densepack.TABLE}").fetchall()
    assert [list(r) for r in rows] == want["memo_rows"][:1]
    half = yade.pack.randomDensePack(yade.pack.inAlignedBox((0, 0, 0), (.5, .5, .5)), radius=.05, memoizeDb=db,
                                     returnSpherePack=True)
    assert _compaction(yade)["iter"] == first["iter"]   # no second compaction
    np.testing.assert_allclose(half.radii, 0.5 * np.asarray(sp.radii), rtol=1e-14)
    np.testing.assert_allclose(half.aabb(), 0.5 * np.asarray(sp.aabb()), rtol=1e-12, atol=1e-15)
    mat = yade.FrictMat(young=1e7)
    bodies = yade.pack.randomDensePack(unit, radius=.1, memoizeDb=db, returnSpherePack=False, material=mat)
    # YADE: the same count as its SpherePack for the same call, none added to the scene
    assert want["bodies"]["n"] == want["unit"][0]["n"] and want["bodies"]["inScene"] == 0
    assert len(bodies) == len(sp) and len(yade.O.bodies) == 0
    assert {type(b.shape).__name__ for b in bodies} == set(want["bodies"]["types"])
    assert [b.material.young for b in bodies[:2]] == want["bodies"]["young"]


def test_random_dense_pack_with_fuzz_as_yade(yade):
    """rRelFuzz .3: the same count, box and growth as YADE's calls, the radii within (1 -+ .3) of the grown mean."""
    sp = yade.pack.randomDensePack(yade.pack.inAlignedBox((0, 0, 0), (1, 1, 1)), radius=.1, rRelFuzz=.3,
                                   returnSpherePack=True, seed=1)
    got = _as_yades_box_packing(yade, sp, reference("dense_box")["fuzz"], (.5, .5, .5))
    assert 0.7 * got["rmean"] * 0.97 <= min(sp.radii) and max(sp.radii) <= 1.3 * got["rmean"] * 1.03


class _Made(Exception):
    pass


def test_random_dense_pack_box_of_other_predicates_as_yades(yade, monkeypatch):
    """A 2 x 1 x .5 box (radius .08), cropLayers=1 (radius .1: a box of 1.4) and a sphere of radius .6: the
    TriaxialTest made holds YADE's count of spheres in YADE's box (dense_box.py; stopped before it runs)."""
    from granum.yade import preprocessors

    made = []

    def load(self):
        made.append(self)
        raise _Made

    monkeypatch.setattr(preprocessors.TriaxialTest, "load", load)
    want = reference("dense_box")
    unit = yade.pack.inAlignedBox((0, 0, 0), (1, 1, 1))
    for pred, kw, case in ((yade.pack.inAlignedBox((1, 1, 1), (3, 2, 1.5)), dict(radius=.08), "flat"),
                           (unit, dict(radius=.1, cropLayers=1), "crop"),
                           (yade.pack.inSphere((0, 0, 0), .6), dict(radius=.1), "sphere")):
        with pytest.raises(_Made):
            yade.pack.randomDensePack(pred, returnSpherePack=True, seed=1, **kw)
        lo, hi = made[-1].corners()
        assert made[-1].numberOfGrains == want[case]["compaction"]["spheres"]
        np.testing.assert_allclose(hi - lo, want[case]["compaction"]["box0"], rtol=1e-12)
    assert len(yade.O.bodies) == 0 and not yade.O.periodic


@pytest.mark.slow
def test_random_dense_pack_between_walls_is_as_dense_as_yades(yade):
    """radius .05 in a unit box (1,145 spheres compacted): YADE returns 257-261 spheres of .0720-.0721 at solid
    fraction .402-.409 (pack_dense.json, seeds 1 and 2); granum's porosity within .01 of that range (issue #19's
    criterion), its radius within .5 %."""
    box = yade.pack.inAlignedBox((0, 0, 0), (1, 1, 1))
    sp = yade.pack.randomDensePack(box, radius=.05, returnSpherePack=True, seed=1)
    runs = ref()["randomDensePack_box"]
    solids, radii = [w["solid"] for w in runs], [w["rmin"] for w in runs]
    assert min(solids) - 0.01 <= _solid(sp, 1.0) <= max(solids) + 0.01
    assert min(radii) * 0.995 <= float(np.mean(sp.radii)) <= max(radii) * 1.005


def test_filter_returns_bodies_and_warns_as_yade(yade):
    sp = two(yade.pack)
    sp.cellFill((3, 3, 3))
    pred = yade.pack.inSphere((0, 0, 0), 1.0)
    with pytest.warns(FutureWarning):
        bodies = yade.pack.filterSpherePack(pred, sp)
    assert bodies and all(type(b.shape).__name__ == "Sphere" for b in bodies)
    with pytest.warns(UserWarning, match="doesn't fully contain"):
        yade.pack.filterSpherePack(yade.pack.inSphere((0, 0, 0), 5.0), sp, returnSpherePack=True)


def test_bad_input_is_refused(yade):
    box = yade.pack.inAlignedBox((0, 0, 0), (1, 1, 1))
    want = ref()["infinite"]
    with pytest.raises(RuntimeError) as err:
        yade.pack.randomDensePack(yade.pack.inSpace(), radius=.1, returnSpherePack=True)
    assert str(err.value) == want["message"]
    for kw, what in ((dict(radius=0), "radius"), (dict(radius=.1, rRelFuzz=1), "rRelFuzz"),
                     (dict(radius=.1, spheresInCell=-3), "spheresInCell")):
        with pytest.raises(ValueError, match=what):
            yade.pack.randomDensePack(box, returnSpherePack=True, **kw)
    with pytest.raises(NotImplementedError, match="useOBB"):
        yade.pack.randomDensePack(box, radius=.1, useOBB=True)
    with pytest.raises(ValueError, match="initSize"):
        yade.pack.randomPeriPack(radius=.1, initSize=(1, 0, 1))
    assert not yade.O.periodic and len(yade.O.bodies) == 0


def test_refused_while_running(yade):
    """YADE's core.testPythonToCppToPythonThrow: from a PyRunner the alternative scene is refused."""
    yade.O.engines = [yade.PyRunner(iterPeriod=1, command="from granum.yade import pack; pack.randomDensePack("
                                    "pack.inSphere((0, 0, 0), .3), spheresInCell=100, radius=8e-2)")]
    with pytest.raises(RuntimeError, match="Please stop the simulation first"):
        yade.O.run(5, True)
