"""Tests of granum.yade.pack (YADE's yade.pack) against numbers recorded from real YADE 2023.02a.

The reference file tests/reference/yade/pack_lattice/pack_reference.json is written by
gen_pack_reference.py in the same folder (run under YADE). No scene is needed: toSimulation
and the lattice bodies are tested with stand-in ``utils``/``O`` modules.
"""

from __future__ import annotations

import itertools
import json
import math
import pathlib
import sys
import types
import warnings

import numpy as np
import pytest

import granum.yade
from granum.mathtypes import Matrix3, Quaternion, Vector3
from granum.yade import pack

REF_FILE = pathlib.Path(__file__).parent / "reference/yade/pack_lattice/pack_reference.json"
REF = json.loads(REF_FILE.read_text())
LATTICES = {c["name"]: c for c in REF["lattices"]}
CLOUDS = {c["name"]: c for c in REF["clouds"]}
PRED_CASES = REF["predicates"]["cases"]


def make_pred(spec):
    """Predicate from the reference file's spec: [name, args] or [operator, specA, specB]."""
    ops = {"&": lambda a, b: a & b, "|": lambda a, b: a | b, "-": lambda a, b: a - b, "^": lambda a, b: a ^ b}
    if spec[0] in ops:
        return ops[spec[0]](make_pred(spec[1]), make_pred(spec[2]))
    return getattr(pack, spec[0])(*spec[1])


def cloud(*args, **kw):
    sp = pack.SpherePack()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ret = sp.makeCloud(*args, **kw)
    return sp, ret


def arrays(sp):
    return np.array(sp.centers), np.array(sp.radii)


def assert_no_overlap(c, r, period=None):
    """Brute force over all pairs (minimum image if ``period`` is given)."""
    d = c[:, None, :] - c[None, :, :]
    if period is not None:
        per = np.asarray(period, dtype=float)
        d -= per * np.round(d / per)
    dist = np.linalg.norm(d, axis=-1)
    gap = dist - (r[:, None] + r[None, :])
    np.fill_diagonal(gap, np.inf)
    assert gap.min() >= 0.0, f"overlap of {-gap.min():g}"


# ----------------------------------------------------------------------------- lattices
@pytest.mark.parametrize("name", sorted(LATTICES))
def test_lattice_centres_equal_yade(name):
    case = LATTICES[name]
    fn = pack.regularHexaCenters if case["kind"] == "hexa" else pack.regularOrthoCenters
    got = fn(make_pred(case["pred"]), case["radius"], case["gap"])
    want = np.array(case["centers"]).reshape(-1, 3)
    assert got.shape == want.shape
    np.testing.assert_array_equal(got, want)  # same points, same order, bit for bit


def test_lattice_spacing_and_counts():
    hexa = pack.regularHexaCenters(pack.inAlignedBox((0, 0, 0), (2, 2, 2)), 0.1, 0)
    assert len(hexa) == 990  # tutorial 04's packing in YADE
    d = np.linalg.norm(hexa[:, None] - hexa[None], axis=-1)
    np.fill_diagonal(d, np.inf)
    assert d.min() == pytest.approx(0.2)  # touching spheres, 12 neighbours inside the bulk
    assert np.max(np.sum(np.isclose(d, 0.2), axis=1)) == 12
    assert len(pack.regularOrthoCenters(pack.inAlignedBox((0, 0, 0), (1, 1, 1)), 0.05, 0)) == 729


@pytest.fixture
def fake_scene(monkeypatch):
    """Stand-in ``utils.sphere`` and ``O`` recording what pack hands to the scene."""
    calls = []
    utils = types.ModuleType("granum.yade.utils")

    def sphere(center, radius, **kw):
        calls.append((np.array(center, dtype=float), radius, kw))
        return ("body", len(calls) - 1)

    utils.sphere = sphere
    bodies = []

    class Bodies:
        def append(self, items):
            ids = list(range(len(bodies), len(bodies) + len(items)))
            bodies.extend(items)
            return ids

    cell = types.SimpleNamespace(hSize=None, trsf=None)
    O = types.SimpleNamespace(periodic=False, cell=cell, bodies=Bodies())
    omega = types.ModuleType("granum.yade.omega")
    omega.O = O
    for name, mod in (("utils", utils), ("omega", omega)):
        monkeypatch.setitem(sys.modules, f"granum.yade.{name}", mod)
        monkeypatch.setattr(granum.yade, name, mod, raising=False)
    return types.SimpleNamespace(calls=calls, O=O, bodies=bodies)


def test_regular_packings_create_bodies_with_utils_sphere(fake_scene):
    pred = pack.inSphere((0, 0, 0), 0.5)
    out = pack.regularHexa(pred, radius=0.1, gap=0.01, color=(0, 0, 1), wire=True)
    centres = pack.regularHexaCenters(pred, 0.1, 0.01)
    assert out == [("body", i) for i in range(len(centres))]
    np.testing.assert_array_equal([c for c, _, _ in fake_scene.calls], centres)
    assert all(r == 0.1 and kw == {"color": (0, 0, 1), "wire": True} for _, r, kw in fake_scene.calls)
    assert len(pack.regularOrtho(pred, 0.1, 0)) == len(pack.regularOrthoCenters(pred, 0.1, 0)) > 0


def test_lattice_rejects_infinite_predicate():
    with pytest.raises(ValueError):
        pack.regularOrthoCenters(pack.inSpace(), 0.1, 0)


# ----------------------------------------------------------------------------- predicates
@pytest.mark.parametrize("name", sorted(PRED_CASES))
def test_predicates_equal_yade(name):
    case = PRED_CASES[name]
    pred = make_pred(case["pred"])
    pts, pads = REF["predicates"]["points"], REF["predicates"]["pads"]
    got = [[pred(pt, pad) for pad in pads] for pt in pts]
    wrong = [(pt, pad) for pt, g, w in zip(pts, got, case["inside"], strict=True)
             for pad, a, b in zip(pads, g, w, strict=True) if a != b]
    assert not wrong
    mn, mx = pred.aabb()
    np.testing.assert_allclose(np.array([mn, mx], dtype=float), case["aabb"], rtol=1e-15, atol=0)
    np.testing.assert_allclose(np.asarray(pred.center(), dtype=float), case["center"], rtol=1e-15)
    np.testing.assert_allclose(np.asarray(pred.dim(), dtype=float), case["dim"], rtol=1e-15)


def test_predicate_inputs_and_algebra():
    box = pack.inAlignedBox((0, 0, 0), (1, 1, 1))
    ball = pack.inSphere(Vector3(1, 1, 1), 0.5)
    for pt in ((0.5, 0.5, 0.5), [0.5, 0.5, 0.5], np.array([0.5, 0.5, 0.5]), Vector3(0.5, 0.5, 0.5)):
        assert box(pt) and box(pt, 0.5) and not box(pt, 0.51)
    assert isinstance(box((2, 0, 0)), bool) and not box((2, 0, 0))
    assert (box & ball)((0.9, 0.9, 0.9)) and not (box & ball)((1.2, 1.2, 1.2))
    assert (box | ball)((1.2, 1.2, 1.2)) and not (box | ball)((2, 2, 2))
    assert (box - ball)((0.1, 0.1, 0.1)) and not (box - ball)((0.9, 0.9, 0.9))
    assert (box ^ ball)((1.2, 1.2, 1.2)) and not (box ^ ball)((0.9, 0.9, 0.9))
    assert isinstance(box - ball, pack.PredicateDifference) and isinstance(box, pack.Predicate)
    np.testing.assert_array_equal(np.asarray((box | ball).aabb(), dtype=float), [[0, 0, 0], [1.5, 1.5, 1.5]])
    np.testing.assert_array_equal(np.asarray((box & ball).aabb(), dtype=float), [[0.5, 0.5, 0.5], [1, 1, 1]])
    cyl = pack.inCylinder((0, 0, 0), (0, 0, 2), 1)
    assert cyl((0.99, 0, 1)) and not cyl((0, 0, 2.01)) and not cyl((0.5, 0, 1), 0.6)
    ell = pack.inEllipsoid((0, 0, 0), (1, 2, 3))
    assert ell((0, 0, 2.99)) and not ell((0.8, 1.5, 0))


def test_python_subclass_predicate_works_with_lattices():
    class Slab(pack.Predicate):
        def __call__(self, pt, pad=0.0):
            return 0 + pad <= pt[2] <= 0.3 - pad and 0 <= pt[0] <= 1 and 0 <= pt[1] <= 1

        def aabb(self):
            return Vector3(0, 0, 0), Vector3(1, 1, 0.3)

    got = pack.regularOrthoCenters(Slab(), 0.05, 0)
    assert len(got) > 0 and np.all(got[:, 2] <= 0.25 + 1e-12)
    assert np.asarray(Slab().center(), dtype=float).tolist() == [0.5, 0.5, 0.15]
    assert (Slab() & pack.inSphere((0.5, 0.5, 0), 0.2))((0.5, 0.5, 0.1))

    class Empty(pack.Predicate):
        pass

    with pytest.raises(NotImplementedError):
        Empty()((0, 0, 0))
    with pytest.raises(NotImplementedError):
        Empty().aabb()


# ----------------------------------------------------------------------------- makeCloud
def test_cloud_in_box_without_overlaps():
    sp, n = cloud((0, 0, 0), (1, 1, 1), rMean=0.05, rRelFuzz=0.5, seed=3)
    c, r = arrays(sp)
    assert n == len(sp) == len(r) > 200
    assert np.all(c - r[:, None] >= 0) and np.all(c + r[:, None] <= 1)
    assert np.all((r >= 0.025) & (r <= 0.075))
    assert_no_overlap(c, r)


STOCHASTIC = ["tutorial02", "monodisperse", "periodic_tutorial04", "periodic_doc", "num_rmean_too_many",
              "flat_2d", "psd_number", "psd_mass", "num_porosity_retry"]


@pytest.mark.parametrize("name", STOCHASTIC)
def test_cloud_statistics_comparable_to_yade(name):
    ref = CLOUDS[name]
    counts, means, lo, hi = [], [], [], []
    for seed in ref["seeds"]:
        sp, ret = cloud(*ref["args"], seed=seed, **ref["kwargs"])
        c, r = arrays(sp)
        counts.append(len(sp))
        means.append(r.mean())
        lo.append(r.min())
        hi.append(r.max())
        assert ret == len(sp)  # fresh pack: YADE returns the count in every mode
        if seed == ref["seeds"][0]:
            assert_no_overlap(c, r, period=sp.cellSize if sp.isPeriodic else None)
            np.testing.assert_array_equal(np.asarray(sp.cellSize, dtype=float), ref["cellSize"])
            assert sp.isPeriodic == ref["isPeriodic"]
    n = len(counts)
    se = math.sqrt((np.var(counts, ddof=1) + np.var(ref["count"], ddof=1)) / n)
    assert abs(np.mean(counts) - np.mean(ref["count"])) <= 4 * se + 1, (counts, ref["count"])
    assert np.mean(means) == pytest.approx(np.mean(ref["mean_radius"]), rel=0.03)
    # the sizes span the same range (YADE's extremes over its seeds, 2 % slack for sampling)
    assert min(ref["min_radius"]) * 0.98 <= min(lo) and max(hi) <= max(ref["max_radius"]) * 1.02


@pytest.mark.parametrize("name", ["num_porosity_positional", "num_rmean", "num_periodic_doc",
                                  "psd_number_num", "psd_mass_num", "num_rmean_too_many"])
def test_deterministic_sizes_equal_yade(name):
    """With ``num`` the sizes are deterministic: YADE's radii are reproduced one by one."""
    ref = CLOUDS[name]
    sp, ret = cloud(*ref["args"], seed=1, **ref["kwargs"])
    r = arrays(sp)[1]
    want = np.array(ref["radii_seed1"])
    k = min(len(r), len(want))  # num_rmean_too_many: both stop early, at different counts
    np.testing.assert_allclose(r[:k], want[:k], rtol=1e-12)
    if name != "num_rmean_too_many":
        assert len(r) == len(want) == ret
    assert np.all(np.diff(r) <= 0)  # largest first


def test_num_with_porosity_gives_num_spheres():
    sp, n = cloud((0, 0, 0), (1, 1, 1), -1, 0.3333, 200, False, 0.95, seed=1)  # positional, as scripts do
    c, r = arrays(sp)
    assert n == len(sp) == 200
    rm = (1 * (1 - 0.95) / (4 / 3 * math.pi * (1 + 0.3333 ** 2) * 200)) ** (1 / 3)
    assert r.mean() == pytest.approx(rm * (1 + 0.3333 / 201))
    assert_no_overlap(c, r)
    with pytest.warns(UserWarning, match="porosity"):  # too dense: retried with more porosity
        sp2 = pack.SpherePack()
        assert sp2.makeCloud((0, 0, 0), (1, 1, 1), rRelFuzz=0.3333, num=200, porosity=0.5, seed=1) == 200
    assert_no_overlap(*arrays(sp2))


def test_periodic_cloud_has_no_overlap_across_faces():
    sp, n = cloud((0, 0, 0), (2, 2, 2), rMean=0.1, rRelFuzz=0.6, periodic=True, seed=7)
    c, r = arrays(sp)
    assert sp.isPeriodic and np.asarray(sp.cellSize, dtype=float).tolist() == [2, 2, 2]
    assert np.all((c >= 0) & (c < 2))
    assert np.any(c - r[:, None] < 0)  # spheres do cross the faces...
    assert_no_overlap(c, r, period=(2, 2, 2))  # ...without touching their periodic images


def test_flat_box_gives_2d_packing():
    with pytest.warns(UserWarning, match="2D"):
        sp = pack.SpherePack()
        sp.makeCloud((0, 0, 0), (1, 1, 0), rMean=0.05, rRelFuzz=0.5, seed=2)
    c, r = arrays(sp)
    assert len(c) > 30 and np.all(c[:, 2] == 0)
    assert np.all(c[:, :2] - r[:, None] >= 0) and np.all(c[:, :2] + r[:, None] <= 1)
    assert_no_overlap(c, r)


def test_seed_reproducibility():
    a, _ = cloud((0, 0, 0), (1, 1, 1), rMean=0.05, rRelFuzz=0.5, seed=11)
    b, _ = cloud((0, 0, 0), (1, 1, 1), rMean=0.05, rRelFuzz=0.5, seed=11)
    c, _ = cloud((0, 0, 0), (1, 1, 1), rMean=0.05, rRelFuzz=0.5, seed=12)
    np.testing.assert_array_equal(a.centers, b.centers)
    np.testing.assert_array_equal(a.radii, b.radii)
    assert len(a) != len(c) or not np.array_equal(a.centers, c.centers)
    # as in YADE: seed 0 is a seed like any other, the default (negative) is random per call
    assert REF["seed_behaviour"] == {"default_seed_repeats": False, "seed0_repeats": True,
                                     "seed1_repeats": True}
    z1, z2 = (cloud((0, 0, 0), (1, 1, 1), rMean=0.05, seed=0)[0] for _ in range(2))
    np.testing.assert_array_equal(z1.centers, z2.centers)
    d1, d2 = (cloud((0, 0, 0), (1, 1, 1), rMean=0.05)[0] for _ in range(2))
    assert not np.array_equal(d1.centers[:5], d2.centers[:5])


def test_cloud_appends_and_avoids_existing_spheres():
    sp = pack.SpherePack([((0.5, 0.5, 0.5), 0.3)])
    assert sp.makeCloud((0, 0, 0), (1, 1, 1), rMean=0.05, seed=1) == len(sp) - 1  # returns the new count
    c, r = arrays(sp)
    assert_no_overlap(c, r)
    assert sp.makeCloud((0, 0, 0), (1, 1, 1), rMean=0.02, num=10, seed=2) == len(sp)  # num: the total


def _periodic_neighbour_pairs(c: np.ndarray, reach: float) -> np.ndarray:
    """Every pair (i, j), i < j, of centres ``c`` (n, 3) in the unit periodic box that may lie closer than
    ``reach``: centres binned into cells at least ``reach`` wide, each compared with the 27 cells around
    (NumPy only; an independent check of the packing, not granum's collider)."""
    m = int(1.0 // reach)
    assert m >= 3
    cell = np.floor(c * m).astype(np.int64) % m
    key = (cell[:, 0] * m + cell[:, 1]) * m + cell[:, 2]
    order = np.argsort(key, kind="stable")
    first = np.searchsorted(key[order], np.arange(m ** 3))
    last = np.searchsorted(key[order], np.arange(m ** 3), side="right")
    pairs = []
    for off in itertools.product((-1, 0, 1), repeat=3):
        nb = (((cell[:, 0] + off[0]) % m) * m + (cell[:, 1] + off[1]) % m) * m + (cell[:, 2] + off[2]) % m
        counts = last[nb] - first[nb]
        i = np.repeat(np.arange(len(c)), counts)
        within = np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts, counts)
        j = order[np.repeat(first[nb], counts) + within]
        keep = i < j
        pairs.append(np.stack([i[keep], j[keep]], axis=1))
    return np.unique(np.concatenate(pairs), axis=0)


def test_large_periodic_cloud_has_no_overlap():
    """A cloud of more than 1e5 spheres (a quadratic search would take hours; its speed is a benchmark's
    concern) in which no two spheres overlap across the periodic boundaries."""
    sp, n = cloud((0, 0, 0), (1, 1, 1), rMean=0.0075, rRelFuzz=0.3, periodic=True, seed=5)
    assert n > 100_000
    c, r = arrays(sp)
    pairs = _periodic_neighbour_pairs(c, 2 * r.max())
    assert len(pairs) > n   # the check sees neighbours at all
    d = c[pairs[:, 0]] - c[pairs[:, 1]]
    d -= np.round(d)
    assert np.all(np.linalg.norm(d, axis=1) >= r[pairs[:, 0]] + r[pairs[:, 1]])


def test_make_cloud_argument_errors():
    with pytest.raises(ValueError):
        pack.SpherePack().makeCloud((0, 0, 0), (1, 1, 1))  # neither rMean, num nor a PSD


# ----------------------------------------------------------------------------- SpherePack API
def test_sequence_protocol_and_round_trips():
    data = [((0, 0, 0), 1.0), ((1, 2, 3), 0.5)]
    sp = pack.SpherePack(data)
    assert len(sp) == 2
    c, r = sp[1]
    assert isinstance(c, Vector3) and isinstance(r, float)
    assert np.asarray(c, dtype=float).tolist() == [1, 2, 3] and r == 0.5
    assert [(np.asarray(c, dtype=float).tolist(), r) for c, r in sp] == [([0, 0, 0], 1.0), ([1, 2, 3], 0.5)]
    assert np.asarray(sp[-1][0], dtype=float).tolist() == [1, 2, 3]
    with pytest.raises(IndexError):
        sp[2]
    with pytest.raises(RuntimeError):  # YADE's exception type
        sp[5]
    sp.add(Vector3(4, 4, 4), 0.25)
    for _ in range(40):  # grows past the initial storage
        sp.add(np.zeros(3), 0.1)
    assert len(sp) == 43 and sp[2][1] == 0.25
    lst = sp.toList()
    sp2 = pack.SpherePack()
    sp2.fromList(lst)
    np.testing.assert_array_equal(sp2.centers, sp.centers)
    np.testing.assert_array_equal(sp2.radii, sp.radii)
    sp2.fromList([(0, 0, 0), Vector3(3, 3, 3)], [1, 2])  # replaces the content
    got = [(tuple(np.asarray(c, dtype=float)), r) for c, r in sp2.toList()]
    assert got == [((0, 0, 0), 1.0), ((3, 3, 3), 2.0)]


def test_geometry_operations_as_yade():
    sp = pack.SpherePack()
    assert np.all(np.isinf(np.asarray(sp.aabb(), dtype=float)))  # empty: (inf, -inf) like YADE
    sp.fromList([(0, 0, 0), (3, 3, 3)], [1, 2])
    sp.translate((1, 0, 0))
    sp.scale(2)  # about center(), radii too (values observed in YADE)
    assert [(tuple(np.asarray(c, dtype=float)), r) for c, r in sp] == [((-1, -2, -2), 2.0), ((5, 4, 4), 4.0)]
    assert np.asarray(sp.center(), dtype=float).tolist() == [3, 2, 2]
    np.testing.assert_array_equal(np.asarray(sp.aabb(), dtype=float), [[-3, -4, -4], [9, 8, 8]])
    assert np.asarray(sp.dim(), dtype=float).tolist() == [12, 12, 12]
    sp.rotate((0, 0, 1), math.pi / 2)
    np.testing.assert_allclose(np.asarray(sp[0][0], dtype=float), [3 + 4, 2 - 4, -2], atol=1e-12)
    per = pack.SpherePack([((0.5, 0.5, 0.5), 0.1), ((1.5, 1.5, 1.7), 0.1)])
    assert not per.isPeriodic
    per.cellSize = (2, 2, 2)
    assert per.isPeriodic
    per.scale(2)
    assert np.asarray(per.cellSize, dtype=float).tolist() == [4, 4, 4]
    np.testing.assert_allclose(np.asarray(per[0][0], dtype=float), [0, 0, -0.1], atol=1e-15)


def test_save_load(tmp_path):
    f = tmp_path / "yade_written.txt"
    f.write_text("##PERIODIC:: 2 2 3\n0.5 0.5 0.5 0.1 -1\n1.5 1.5 1.7 0.1 -1\n")  # YADE's format
    sp = pack.SpherePack()
    sp.load(str(f))
    assert len(sp) == 2 and sp.isPeriodic and np.asarray(sp.cellSize, dtype=float).tolist() == [2, 2, 3]
    sp.save(str(tmp_path / "again.txt"))
    sp2 = pack.SpherePack()
    sp2.load(str(tmp_path / "again.txt"))
    np.testing.assert_array_equal(sp2.centers, sp.centers)
    np.testing.assert_array_equal(sp2.radii, sp.radii)
    assert np.asarray(sp2.cellSize, dtype=float).tolist() == [2, 2, 3]


def test_to_simulation(fake_scene):
    sp = pack.SpherePack([((1, 0, 0), 0.1), ((3, 0, 0), 0.2)])
    assert sp.toSimulation(color=(0, 0, 1)) == [0, 1]
    assert not fake_scene.O.periodic
    assert [(c.tolist(), r, kw) for c, r, kw in fake_scene.calls] == [
        ([1, 0, 0], 0.1, {"color": (0, 0, 1)}), ([3, 0, 0], 0.2, {"color": (0, 0, 1)})]
    fake_scene.calls.clear()
    # rotation about the origin, as YADE: (1,0,0) -> (0,1,0) for 90 degrees about z
    sp.cellSize = (4, 4, 4)
    assert sp.toSimulation(rot=Quaternion((0, 0, 1), math.pi / 2)) == [2, 3]
    np.testing.assert_allclose([c for c, _, _ in fake_scene.calls], [[0, 1, 0], [0, 3, 0]], atol=1e-15)
    assert fake_scene.O.periodic
    np.testing.assert_allclose(np.asarray(fake_scene.O.cell.hSize, dtype=float),
                               [[0, -4, 0], [4, 0, 0], [0, 0, 4]], atol=1e-15)
    assert isinstance(fake_scene.O.cell.hSize, Matrix3)
    np.testing.assert_array_equal(np.asarray(fake_scene.O.cell.trsf, dtype=float), np.eye(3))
