"""The loops that replace NumPy conveniences inside kernels (granum.kernels.sorting, granum.kernels.copy) give
NumPy's results, on random data with ties and on the edge cases; prefetching changes no result; the block
queue of the parallel loops (granum.kernels.schedule) runs every block once; the pieces of the stages' work
area (granum.kernels.scratch) are the memory NumPy's views of it name."""

from __future__ import annotations

import math

import numba
import numpy as np
import pytest
from conftest import frict_engines

from granum.core.contacts import CONTACTS, new_contact_arrays
from granum.kernels.copy import copy_items, copy_rows, copy_to_row
from granum.kernels.schedule import (
    block_queue,
    fetch_add,
    next_block,
    queue_of,
    queue_workers,
    serial_block_queue,
    serial_next_block,
    serial_queue_workers,
)
from granum.kernels.scratch import area, rows_of, take_f8, take_i4, take_i8
from granum.kernels.sorting import argsort_keys, lower_bound, median


@pytest.mark.parametrize("n", [1, 2, 3, 4, 5, 10, 11, 100, 1001])
def test_median_equals_numpys(n):
    rng = np.random.default_rng(n)
    for values in (rng.random(n), rng.integers(0, 4, n).astype(float), np.full(n, 2.5), -rng.random(n) * 1e9):
        before = values.copy()
        assert median(values) == np.median(values)
        assert (values == before).all(), "median must not reorder its argument"


@pytest.mark.parametrize("top", [1, 3, 2**11, 2**20, 2**60])
def test_argsort_keys_is_numpys_stable_sort(top):
    rng = np.random.default_rng(top % 1000)
    for n in (0, 1, 2, 7, 1000, 5000):
        keys = rng.integers(0, top, n)
        assert (argsort_keys(keys) == np.argsort(keys, kind="stable")).all()


def test_lower_bound_is_searchsorted():
    rng = np.random.default_rng(7)
    a = np.sort(rng.integers(0, 50, 200))
    for x in range(-2, 53):
        assert lower_bound(a, x) == np.searchsorted(a, x, side="left")
    assert lower_bound(a[:0], 3) == 0


def test_copies_equal_slice_assignment():
    rng = np.random.default_rng(3)
    src2 = rng.random((6, 3))
    dst2 = np.zeros((8, 5))
    copy_rows(dst2, src2, 4)   # narrower source: its columns only
    expected = np.zeros((8, 5))
    expected[:4, :3] = src2[:4]
    assert (dst2 == expected).all()
    src1 = rng.integers(0, 9, 10)
    dst1 = np.full(12, -1)
    copy_items(dst1, src1, 7)
    assert (dst1[:7] == src1[:7]).all() and (dst1[7:] == -1).all()
    copy_to_row(dst2, 6, np.arange(5.0))
    assert (dst2[6] == np.arange(5.0)).all()


def test_prefetching_gather_gives_the_same_forces(yade):
    """The force gather prefetches contact rows only for pools larger than the caches; with prefetching
    forced on, at every distance ahead, every body's force and torque are the same bits as without, and
    as the InteractionLoop's own gather left them in the last step."""
    from granum._jit import call
    from granum.core.contacts import CONTACTS
    from granum.kernels.dispatch import code_of, functor_set
    from granum.kernels.interaction import gather, index_contacts

    O = yade.O
    r, n = 0.01, 7
    s = 2 * r * (1 - 1e-3)  # overlapping neighbours: about 3 n^3 contacts
    O.bodies.append([yade.sphere((i * s, j * s, k * s), r) for k in range(n) for j in range(n) for i in range(n)])
    rng = np.random.default_rng(1)
    for b in O.bodies:  # spins and slips: shear forces and torques
        b.state.vel = tuple(rng.normal(0, 0.01, 3))
        b.state.angVel = tuple(rng.normal(0, 1, 3))
    O.engines = frict_engines(yade, gravity=(0, 0, -9.81))
    O.dt = 0.5 * yade.PWaveTimeStep()
    O.run(3, True)
    scene = O._scene
    S, C = scene.arrays(), CONTACTS.to_record(scene.contacts)
    nb = len(O.bodies)
    stepped = (scene.bodies.force[:nb].copy(), scene.bodies.torque[:nb].copy())  # the last step's gather
    call(index_contacts, C, nb)   # the per-body index, as the stage builds it before its gather when stale
    results = []
    for ahead in (0, 1, 4, 16, n**3):
        scene.bodies.force[:nb] = 0.0
        scene.bodies.torque[:nb] = 0.0
        call(gather, S, C, nb, ahead, functor_set("law", [code_of("Law2_ScGeom_FrictPhys_CundallStrack")]))
        results.append((scene.bodies.force[:nb].copy(), scene.bodies.torque[:nb].copy()))
    force, torque = results[0]
    assert np.abs(force).max() > 0 and np.abs(torque).max() > 0
    for f, t in [stepped] + results[1:]:
        assert (f.view(np.int64) == force.view(np.int64)).all() and (t.view(np.int64) == torque.view(np.int64)).all()


def test_a_collider_run_carries_the_budgets_of_the_pairs_it_finds_again(yade):
    """granum.kernels.motion.carry_budgets: each new pair (both lists sorted by (id1, id2)) that the old list had
    gets its old budget, unless one of its bodies turns (a facet: it gets -inf, as every new pair), whatever the
    blocks the new list falls into; serial and parallel alike."""
    from granum._jit import call
    from granum.kernels.motion import carry_budgets, carry_budgets_par

    O = yade.O
    nb = 1200
    O.bodies.append([yade.sphere((3 * i, 0, 0), 1) for i in range(nb - 2)])
    O.bodies.append([yade.facet([(0, 0, 0), (1, 0, 0), (0, 1, 0)]) for _ in range(2)])
    turning = {nb - 2, nb - 1}
    S = O._scene.arrays()
    rng = np.random.default_rng(4)
    every = [(i, j) for i in range(0, nb, 7) for j in range(i + 1, nb, 37)] + [(i, nb - 1) for i in range(0, nb, 5)]
    every = sorted(set(every))
    new = sorted(e for e in every if rng.random() < 0.6)
    last = max(e for e in new if not turning & set(e))
    old = sorted(e for e in every if rng.random() < 0.6 and e < last)   # `last`, a new pair, after every old one
    assert len(new) > 3 * 512   # several blocks
    old_gap = rng.uniform(-0.01, 0.05, len(old)).astype(np.float32)
    old_gap[::11], old_gap[5::11] = np.inf, -np.inf
    old_gap = np.concatenate([old_gap, np.full(9, 0.5, np.float32)])   # the rows past the count: never read
    budget = dict(zip(old, old_gap[:len(old)].tolist(), strict=True))
    expected = np.array([budget.get(e, -np.inf) if not turning & set(e) else -np.inf for e in new], np.float32)
    assert np.isfinite(expected).sum() > 500 and (expected == -np.inf).sum() > 500
    # room past the old count, as a pair list may have, holding `last`: a walk past the count would find it there
    old_ids = np.array(old + [last] * 9, np.int32)
    for kernel in (carry_budgets, carry_budgets_par):
        gap = np.full(len(new), -np.inf, np.float32)
        call(kernel, S, old_ids, len(old), old_gap, np.array(new, np.int32), gap)
        assert np.array_equal(gap, expected)


def test_rotation_quaternion_is_sine_and_cosine():
    """quat_from_rotvec(r) = (cos(|r|/2), r sin(|r|/2)/|r|) to rounding, on both sides of the 0.1 rad below
    which it sums Taylor series (reference in extended precision)."""
    from granum.physics.vec import quat_from_rotvec

    rng = np.random.default_rng(3)
    angles = np.r_[np.geomspace(1e-12, 3.0, 60), 0.1 * (1 + np.linspace(-1e-6, 1e-6, 5))]
    for angle in angles:
        axis = rng.normal(size=3)
        axis /= np.linalg.norm(axis)
        r = axis * angle
        q = np.array(quat_from_rotvec((r[0], r[1], r[2])))
        half = np.longdouble(angle) / 2
        rl = r.astype(np.longdouble)
        norm = np.sqrt(np.sum(rl * rl))
        expected = np.r_[np.cos(half), rl * np.sin(norm / 2) / norm]
        assert abs(q[0] - expected[0]) <= 2.3e-16
        assert np.linalg.norm(q[1:] - expected[1:]) <= 4.5e-16 * np.linalg.norm(expected[1:].astype(float))
    assert quat_from_rotvec((0.0, 0.0, 0.0)) == (1.0, 0.0, 0.0, 0.0)


def test_quat_renormalized_is_the_normalized_quaternion():
    """quat_renormalized(q) = q/|q| (computed in long double): to rounding for products of unit quaternions
    (NewtonIntegrator's case), within 3 e^2/8 for |q|^2 = 1 + e off unit by up to 1e-6 (the series' limit),
    and exactly quat_normalized beyond it."""
    from granum.physics.vec import quat_mul, quat_normalized, quat_renormalized

    rng = np.random.default_rng(8)

    def exact(q):
        ql = np.array(q, np.longdouble)
        return ql / np.sqrt(np.sum(ql * ql))

    for _ in range(2000):
        a, b = (tuple(x / np.linalg.norm(x)) for x in rng.normal(size=(2, 4)))
        q = quat_mul(a, b)
        got = np.array(quat_renormalized(q), np.longdouble)
        assert np.max(np.abs(got - exact(q))) <= 4.5e-16
    for e in (-9e-7, -1e-9, 3e-8, 9e-7):
        q = tuple(x / np.linalg.norm(x) * math.sqrt(1 + e) for x in rng.normal(size=4))
        got = np.array(quat_renormalized(q), np.longdouble)
        assert np.max(np.abs(got - exact(q))) <= 3 / 8 * e * e + 4.5e-16
    q = (1.0, 0.002, 0.0, 0.0)  # |q|^2 - 1 = 4e-6: the library path
    assert quat_renormalized(q) == quat_normalized(q)


def test_motion_bound_exceeds_every_pairs_motion(yade):
    """The detection's common bound (random displacements in blocks, brute force over every two bodies): at
    least |d_a - d_b| for every pair, and |d_a - d_b| + w_a + w_b - T for a pair with a turning body whose
    budget holds the allowance T; infinite when a displacement is not finite."""
    from granum._jit import call
    from granum.core.arrays import S_TURN_ALLOWANCE, S_TURN_SEEN
    from granum.kernels.motion import motion_bound, quick_bound

    yade.O.bodies.append(yade.sphere((0, 0, 0), 1))
    scene = yade.O._scene
    S = scene.arrays()
    rng = np.random.default_rng(4)
    for _ in range(20):
        d = rng.normal(0, 1e-3, (40, 3)) + rng.normal(0, 1, 3)  # a common drift and a spread
        w = rng.uniform(0, 1e-3, 40) * (rng.uniform(size=40) < 0.3)
        blocks = np.array_split(np.arange(40), 5)
        spread = np.array([np.r_[d[b].min(0), d[b].max(0), w[b].max()] for b in blocks])
        shift = max(np.linalg.norm(d[a] - d[b]) for a in range(40) for b in range(40))
        turning = max(np.linalg.norm(d[a] - d[b]) + w[a] + w[b] for a in range(40) for b in range(40))
        extent = np.linalg.norm(d.max(0) - d.min(0))
        for allowance in (0.0, 0.5 * w.max(), 3 * w.max()):
            scene.scal[S_TURN_ALLOWANCE] = allowance
            scene.scal[S_TURN_SEEN] = 0.0
            bound = call(quick_bound, S, *call(motion_bound, S, spread))
            assert max(shift, turning - allowance) <= bound
            assert bound <= 1.01 * (extent + max(0.0, 2 * w.max() - allowance))
            assert scene.scal[S_TURN_SEEN] == 2 * w.max()  # the collider's next allowance
    nan_x = np.array([[np.inf, 0, 0, -np.inf, 0, 0, np.inf]])  # a block whose only body has a NaN x
    assert call(quick_bound, S, *call(motion_bound, S, nan_x)) == np.inf


@pytest.mark.parametrize("workers", [1, 2, 3, 5])
def test_block_queue_hands_out_every_block_once_own_range_first(workers):
    """Workers claiming in a random interleaving: each block comes out exactly once, each range's blocks in
    increasing order; a worker takes blocks of its own range before any other, and is told "no more" only
    when every block is taken."""
    rng = np.random.default_rng(workers)
    for nblocks in (0, 1, 2, 4, 7, 100):
        queue = queue_of(nblocks, workers)
        claims = {w: [] for w in range(workers)}
        taken = []
        active = list(range(workers))
        while active:
            w = active[rng.integers(len(active))]
            b = next_block(queue, w, claims[w][-1] if claims[w] else -1)
            if b < 0:
                assert sorted(taken) == list(range(nblocks)), "a worker stopped while blocks were left"
                active.remove(w)
                continue
            claims[w].append(b)
            taken.append(b)
        assert sorted(taken) == list(range(nblocks))
        for w, got in claims.items():
            own = range(w * nblocks // workers, (w + 1) * nblocks // workers)
            mine = [b for b in got if b in own]
            assert got[:len(mine)] == mine
            assert [b for b in taken if b in own] == list(own)


def test_serial_block_loop_counts_the_blocks_up():
    for nblocks in (0, 1, 2, 9):
        queue = serial_block_queue(nblocks)
        assert serial_queue_workers(queue) == 1
        got, b = [], serial_next_block(queue, 0, -1)
        while b >= 0:
            got.append(b)
            b = serial_next_block(queue, 0, b)
        assert got == list(range(nblocks))


@numba.njit(parallel=True)
def _claim_all(nblocks, heavy, claimant, count, work):
    queue = block_queue(nblocks)
    for w in numba.prange(queue_workers(queue)):
        b = next_block(queue, w, -1)
        while b >= 0:
            fetch_add(count, b, 1)
            claimant[b] = w
            x = 0.0
            for k in range(heavy if b < nblocks // 2 else 0):  # the first range is slow
                x = math.sqrt(k + x)
            work[b] = x
            b = next_block(queue, w, b)


def test_parallel_block_queue_runs_each_block_once_and_shares_a_slow_range():
    """Threads claiming through atomic counters: every block runs exactly once; with the first half of the
    blocks slow, some of them are run by a worker whose own range they are not in."""
    for nblocks in (0, 1, 3, 64, 1000):
        claimant = np.full(nblocks, -1, np.int64)
        count = np.zeros(nblocks, np.int64)
        _claim_all(nblocks, 0, claimant, count, np.zeros(nblocks))
        assert (count == 1).all()
    if numba.get_num_threads() < 2:
        pytest.skip("needs two threads")
    claimant = np.full(200, -1, np.int64)
    count = np.zeros(200, np.int64)
    _claim_all(200, 200_000, claimant, count, np.zeros(200))  # about 0.5 ms per slow block
    assert (count == 1).all()
    workers = numba.get_num_threads()
    # the worker whose range holds block b: the last one starting at or before it
    owner = np.array([max(w for w in range(workers) if w * 200 // workers <= b) for b in range(200)])
    assert (claimant[:100] != owner[:100]).any(), "no worker took blocks of another's slow range"


@numba.njit
def _fill_pieces(C, words):
    w = area(C, words)
    a, at = take_i4(w, 1, 5)
    b, at = take_i4(w, at, 3)   # an odd count: the next piece starts on a word
    c, at = take_i8(w, at, 2)
    d, at = take_f8(w, at, 4)
    for k in range(5):
        a[k] = k + 1
    for k in range(3):
        b[k] = 200 + k
    c[0] = -7
    c[1] = 1 << 40
    rows_of(d, 2)[1, 1] = 3.5
    return at, a.shape[0], b.shape[0], c.shape[0], d.shape[0]


@numba.njit
def _grow(C, words):
    area(C, words)


def test_work_area_pieces_are_the_views_numpy_names():
    """Pieces taken one after the other lie where NumPy's views of the same words find them, in their own
    dtypes, each starting on a word; the area grows to what is asked, and keeps its contents, in the same array
    when it need not grow and at the start of the larger one when it must."""
    C = CONTACTS.to_record(new_contact_arrays(4))
    assert _fill_pieces(C, 20) == (12, 5, 3, 2, 4)
    w = CONTACTS.from_record(C).scratch
    assert w.shape == (20,)
    assert list(w[1:4].view(np.int32)[:5]) == [1, 2, 3, 4, 5]
    assert list(w[4:6].view(np.int32)[:3]) == [200, 201, 202]
    assert list(w[6:8].view(np.int64)) == [-7, 1 << 40]
    assert w[11] == 3.5   # row 1, column 1 of the (2, 2) rows from word 8
    _fill_pieces(C, 10)   # smaller: the same array
    assert CONTACTS.from_record(C).scratch.ctypes.data == w.ctypes.data
    before = CONTACTS.from_record(C).scratch.copy()
    _grow(C, 25)   # larger: grown by half at least, the words of the smaller area first
    grown = CONTACTS.from_record(C).scratch
    assert grown.shape == (30,) and grown.ctypes.data != w.ctypes.data
    assert np.array_equal(grown[:20].view(np.int64), before.view(np.int64))


def test_sphere_motions_count_the_spheres_that_left_their_bound():
    """The collider's trigger for blocks of live bounded spheres (the count sphere_motions gives with the
    motions, granum.kernels.motion) counts the bodies whose centre moved farther than the Verlet distance (any
    motion at all for a distance of 0; a NaN position counts), computed here in NumPy; live_bounded_spheres
    accepts exactly such blocks."""
    from granum.core.shapes import ShapeKind
    from granum.kernels.bounds import live_bounded_spheres
    from granum.kernels.motion import SPREAD, SPREAD_LEFT, sphere_motions

    rng = np.random.default_rng(12)
    n = 600
    bound_pos = rng.random((n, 3))
    pos = bound_pos + rng.normal(size=(n, 3)) * 0.01
    pos[::9] = bound_pos[::9]          # not moved
    pos[5, 1] = np.nan
    for lo, hi in ((0, 512), (512, 600), (7, 8), (3, 3 + 1)):
        for verlet in (0.0, 0.005, 0.02, 1.0):
            d = pos[lo:hi] - bound_pos[lo:hi]
            dist = np.sqrt(d[:, 0] * d[:, 0] + d[:, 1] * d[:, 1] + d[:, 2] * d[:, 2])
            left = (dist > verlet) | ((verlet == 0.0) & (dist > 0.0)) | np.isnan(dist)
            spread = np.zeros(SPREAD)
            sphere_motions(lo, hi, pos, bound_pos, np.zeros((n, 3)), verlet, np.zeros((n, 4)), spread)
            assert spread[SPREAD_LEFT] == np.count_nonzero(left)
    bound_max = bound_pos + 0.1
    columns = {"alive": np.ones(n, bool), "kind": np.full(n, ShapeKind.SPHERE, np.int8), "bound_min": bound_pos - 0.1}

    def spheres(hi=n, **changed):
        c = {name: column.copy() for name, column in columns.items()}
        for name, (row, value) in changed.items():
            c[name][row] = value
        return live_bounded_spheres(0, hi, c["alive"], c["kind"], c["bound_min"], bound_max)

    assert spheres()
    assert spheres(bound_min=(40, np.nan))   # a bound not taken yet: body_displacement measures it as bounded
    for name, value in (("alive", False), ("kind", ShapeKind.FACET), ("bound_min", np.inf)):
        assert not spheres(**{name: (41, value)})
        assert spheres(hi=41, **{name: (41, value)})


def test_sphere_motions_are_the_displacements_and_their_box():
    """The detection's motions of a block of live bounded spheres (granum.kernels.motion.sphere_motions):
    each row the centre's displacement since its bound less the detection's shift, and a zero rotation term, the
    block's spread the least and greatest of these per axis, computed here in NumPy; an infinite or NaN
    displacement makes the rotation entry infinite (no bound), and rows outside the block are left alone."""
    from granum.kernels.motion import SPREAD, sphere_motions

    rng = np.random.default_rng(14)
    n = 700
    bound_pos = rng.random((n, 3))
    pos = bound_pos + rng.normal(size=(n, 3)) * 0.01
    shift = rng.normal(size=(n, 3)) * 0.01 * (rng.random((n, 1)) < 0.5)
    for lo, hi in ((0, 512), (512, 700), (9, 10)):
        motion = np.full((n, 4), 7.0)
        spread = np.zeros(SPREAD)
        sphere_motions(lo, hi, pos, bound_pos, shift, 1.0, motion, spread)
        d = (pos[lo:hi] - bound_pos[lo:hi]) - shift[lo:hi]
        assert np.array_equal(motion[lo:hi, :3], d) and not motion[lo:hi, 3].any()
        assert (np.delete(motion, np.s_[lo:hi], axis=0) == 7.0).all()
        assert np.array_equal(spread, np.r_[d.min(0), d.max(0), 0.0, 0.0])
    for bad in (np.nan, np.inf, -np.inf):
        moved = pos.copy()
        moved[30, 2] = bad
        spread = np.zeros(SPREAD)
        sphere_motions(0, 512, moved, bound_pos, shift, 1.0, np.zeros((n, 4)), spread)
        assert spread[6] == np.inf


def test_a_moved_origin_keeps_each_pair_s_condition(yade):
    """The detection's re-origin (granum.kernels.motion.reorigin_pair_block): a pair with a finite budget g and
    reference u ref gets a zero reference and the budget g' = g + |u ref| - |D - u ref| (D: its bodies' relative
    displacement now), rounded down, so that whatever moves the bodies next (D'), |D' - D| < g' implies the old
    condition |D' - u ref| < g + |u ref|; infinite budgets and their references stay."""
    from granum._jit import call
    from granum.core.arrays import S_PAIR_REF_UNIT
    from granum.core.contacts import C_PAIRS
    from granum.kernels.motion import reorigin_pair_block

    yade.O.bodies.append(yade.sphere((0, 0, 0), 1))
    scene = yade.O._scene
    S = scene.arrays()
    unit = 1e-5
    scene.scal[S_PAIR_REF_UNIT] = unit
    rng = np.random.default_rng(15)
    nb, n = 40, 300
    motion = np.zeros((nb, 4))
    motion[:, :3] = rng.normal(0, 0.01, (nb, 3))
    arrays = new_contact_arrays(nb, pair_capacity=n)
    ids = rng.integers(0, nb, (n, 2)).astype(np.int32)
    gap = rng.uniform(-0.01, 0.05, n).astype(np.float32)
    gap[::7], gap[3::7] = np.inf, -np.inf
    ref = rng.integers(-2000, 2000, (n, 3)).astype(np.int16)
    arrays.pair_ids[:] = ids
    arrays.pair_gap[:] = gap
    arrays.pair_ref[:] = ref
    arrays.ctr[C_PAIRS] = n
    call(reorigin_pair_block, 0, S, CONTACTS.to_record(arrays), motion)
    finite = np.isfinite(gap)
    assert np.array_equal(arrays.pair_gap[~finite], gap[~finite]) and np.array_equal(arrays.pair_ref[~finite],
                                                                                      ref[~finite])
    assert not arrays.pair_ref[finite].any()
    D = motion[ids[:, 0], :3] - motion[ids[:, 1], :3]
    reach = np.linalg.norm(unit * ref.astype(float), axis=1)
    exact = gap.astype(float) + reach - np.linalg.norm(D - unit * ref, axis=1)
    new = arrays.pair_gap.astype(float)
    assert np.all(new[finite] <= exact[finite]) and np.allclose(new[finite], exact[finite], rtol=1e-6, atol=1e-9)
    for p in np.flatnonzero(finite & (new > 0)):
        for step in rng.normal(size=(20, 3)):
            moved = D[p] + step / np.linalg.norm(step) * new[p] * rng.uniform(0, 1)
            assert np.linalg.norm(moved - unit * ref[p]) < gap[p] + reach[p]


def test_budgets_exceeded_is_whether_a_pair_passes_the_quick_test():
    """detect_block lists a block's pairs only when one of them has a budget not above the bound
    (granum.kernels.interaction.budgets_exceeded): NumPy's answer, with infinite and NaN budgets."""
    from granum.kernels.interaction import budgets_exceeded

    rng = np.random.default_rng(13)
    gaps = (rng.random(2000) * 1e-3).astype(np.float32)
    gaps[::5] = np.inf
    gaps[7] = np.nan   # not above any bound: tested
    for lo, hi in ((0, 512), (8, 512), (512, 1024), (1500, 2000), (3, 3)):
        for bound in (0.0, 1e-5, 5e-4, 2e-3):
            assert budgets_exceeded(lo, hi, gaps, bound) == bool(np.any(~(gaps[lo:hi] > bound)))
