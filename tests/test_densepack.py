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


@pytest.mark.slow
def test_random_dense_pack_between_walls_is_as_dense_as_yades(yade):
    """Aperiodic: YADE returns spheres of .072 for radius=.05 in a unit box (its TriaxialTest's sizing), at solid
    fraction .402-.409 after filtering; granum asked for .072 directly (same sphere-to-box ratio) lies within
    .03 of that range (measured .411-.421)."""
    box = yade.pack.inAlignedBox((0, 0, 0), (1, 1, 1))
    sp = yade.pack.randomDensePack(box, radius=.072, returnSpherePack=True, seed=1)
    solids = [w["solid"] for w in ref()["randomDensePack_box"]]
    assert min(solids) - 0.03 <= _solid(sp, 1.0) <= max(solids) + 0.03
    assert np.asarray(sp.radii) == pytest.approx(0.072, rel=1e-12)


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
