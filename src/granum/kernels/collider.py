"""Broad phase: axis-aligned bounds, Verlet trigger and the potential-pair list.

YADE's ``InsertionSortCollider`` keeps the potential interactions of all bodies
whose axis-aligned bounds overlap; bounds are enlarged by a Verlet distance so that
the collider need only run again when some body has moved farther than that. granum
produces the same set of pairs with a uniform grid instead of sorted lists:

1. Bounds are computed by the registered bound functions and enlarged by the Verlet
   distance; the position and orientation at that moment are remembered.
2. Bodies whose bound fits in a grid cell ("small") are binned; each looks for
   partners with a larger id in the 27 neighbouring cells. Larger bodies whose bound
   covers few cells (the facets of a drum or a hopper) are listed in each cell it covers,
   and meet the small bodies there; bodies with infinite or huge bounds (walls) are
   tested against all others.
3. Each body's partner list is sorted, so the pair list comes out ordered by
   (id1, id2), deterministically and without a global sort.

The collider runs again when a body has moved (or, for non-spheres, turned) by
more than the Verlet distance since its bound was computed, when the scene changed
(bodies added or erased, :data:`C_COLLIDE` set), or every step if the Verlet
distance is zero. When bodies were only appended since its last run (a factory's), it
may bound and pair only them (:mod:`granum.kernels.collider_append`). The bounds and the
trigger are in :mod:`granum.kernels.bounds`.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from granum._jit import BLOCK, PARALLEL_THRESHOLD, jit, kernel, overload, prange
from granum.core.arrays import S_PAIR_REF_UNIT, S_TURN_ALLOWANCE, S_TURN_SEEN, S_VERLET, SI_NBODIES, SI_PERIODIC
from granum.core.contacts import (
    C_COLLIDE,
    C_COLLIDER_RUNS,
    C_CONTACTS,
    C_ERR_A,
    C_ERR_B,
    C_MOTIONS_STAGE,
    C_PAIRS,
    C_REPLACED,
    C_STAGE,
    C_STATUS,
    COLLIDE_APPENDED,
    FLAG_ALIVE,
    I_CELL,
    I_FLAGS,
    I_ID1,
    I_ID2,
    I_PAIR,
    STATUS_TOO_LARGE,
)
from granum.core.records import RecordSpec, borrow, raw
from granum.core.shapes import ShapeKind
from granum.kernels.bounds import bounds_overlap, compute_bounds, compute_bounds_par
from granum.kernels.collider_append import append_bodies
from granum.kernels.collider_periodic import find_pairs_periodic
from granum.kernels.copy import copy_rows
from granum.kernels.motion import (
    any_body_moved,
    budgets_from_now,
    carry_budgets,
    carry_budgets_par,
    motion_words,
    take_motions,
)
from granum.kernels.pairing import masks_may_refuse, may_collide, scratch_width
from granum.kernels.schedule import block_queue, next_block, queue_workers
from granum.kernels.scratch import area
from granum.kernels.sorting import argsort_keys, lower_bound, median
from granum.kernels.static import Static, static_switch, static_value


@jit(inline="always")  # per body or per candidate: no call
def cell_run(first, last, keys_sorted, dense_start):
    """Range [a, b) of ``keys_sorted`` with keys ``first`` to ``last`` (dense table or binary search)."""
    if dense_start.shape[0] > 0:
        first = max(first, 0)
        last = min(last, dense_start.shape[0] - 2)
        if first > last:
            return 0, 0
        return dense_start[first], dense_start[last + 1]
    return lower_bound(keys_sorted, first), lower_bound(keys_sorted, last + 1)


#: The uniform grid of the aperiodic broad phase (:func:`find_pairs`), a record: the per-body functions take
#: its raw view, one pointer. As a named tuple its 14 arrays went by value through each body's three calls, about
#: 100 words each time: a 4,416-sphere search took 3.1-3.4 ms so (its per-candidate helpers inlined), 0.83 ms now.
#:
#: Small bodies (bound no wider than the spacing ``h``) are binned by the cell of their bound's lower corner:
#: ``order`` lists them by cell key and, within a cell, by the lower z of their bound; ``keys_sorted`` holds
#: their keys, ``box`` their bounds in that order (the scan over a cell's bodies reads contiguous memory) and
#: ``dense_start`` the start of each cell in ``order`` (empty when the cells are too many for a table: binary
#: search then). Large bodies whose bound covers few cells are listed in every cell it covers
#: (``large_order``, ``large_keys``, ``large_dense``, the same layout); the others (walls, infinite or huge
#: bounds) are tested against all bodies (``rest``). Fields:
#:
#: - ``small`` (nb,) bool: whether body i is binned;
#: - ``cell`` (nb, 3) int64: cell of a small body's lower corner (0 for the others);
#: - ``dims`` (3,) int64: cells per axis; ``lo`` (3,): lower corner of cell (0, 0, 0) [m]; ``h`` (1,): cell size [m];
#: - ``order`` (small,) int32: small bodies by cell key, then lower z; ``keys_sorted`` (small,) int64: their
#:   keys; ``box`` (small, 6): their bounds, min then max [m];
#: - ``dense_start`` (cells + 1,) int64 or (0,): start of each cell in ``order``;
#: - ``large`` (large,) int32: every body with a bound that is not small, in id order;
#: - ``large_order`` int32: the binned large bodies, once per cell covered, by cell key then id; ``large_keys``
#:   int64: their cell keys; ``large_dense`` (cells + 1,) int64 or (0,): start of each cell in ``large_order``;
#: - ``rest`` int32: large bodies tested against all bodies, in id order;
#: - ``filtered`` (1,) bool: whether the masks or clumps may refuse a pair (:func:`masks_may_refuse`).
GRID = RecordSpec("BodyGrid", [
    ("small", "b1", 1), ("cell", "i8", 2), ("dims", "i8", 1), ("lo", "f8", 1), ("h", "f8", 1),
    ("order", "i4", 1), ("keys_sorted", "i8", 1), ("box", "f8", 2), ("dense_start", "i8", 1),
    ("large", "i4", 1), ("large_order", "i4", 1), ("large_keys", "i8", 1), ("large_dense", "i8", 1),
    ("rest", "i4", 1), ("filtered", "b1", 1)])
body_grid = GRID.compiled_constructor()


@jit(inline="always")  # per body or per candidate: no call
def grid_index(x, lo, h, n):
    """Cell index along one axis of coordinate ``x`` [m], clamped to 0..n-1 (clamping keeps the cells of
    two overlapping intervals overlapping)."""
    v = (x - lo) / h
    if not v >= 0.0:
        return 0
    if v >= n:
        return n - 1
    return int(v)


@jit  # called: five copies inlined by Numba, each with six grid_index, took 2 s of a first run's compiling
def cell_span(S, i, lo, h, dims):
    """Cells covered by body ``i``'s bound in the grid of cell (0, 0, 0) at ``lo`` [m], spacing ``h`` [m] and
    ``dims`` cells per axis: (first x, y, z, last x, y, z)."""
    return corner_cell(S.bound_min, i, lo, h, dims) + corner_cell(S.bound_max, i, lo, h, dims)


@jit(inline="always")  # per body: no call
def corner_cell(corner, i, lo, h, dims):
    """The cell (x, y, z) of row ``i`` of ``corner`` (N, 3) [m] (a bound's lower or upper corners) in the grid of
    :func:`cell_span`."""
    return (grid_index(corner[i, 0], lo[0], h, dims[0]), grid_index(corner[i, 1], lo[1], h, dims[1]),
            grid_index(corner[i, 2], lo[2], h, dims[2]))


@jit(inline="always")  # per body or per candidate: no call
def add_partner(j, n, base, cap, out):
    """Record partner ``j`` as the ``n``-th at ``out[base + n]`` when ``n < cap``; returns n + 1."""
    if n < cap:
        out[base + n] = j
    return n + 1


@jit
def small_in_cells(i, S, grid, avoid_self, first, last, n, base, cap, out):
    """Partners j > i of body ``i`` among the small bodies binned in the cells ``first`` to ``last`` (cell
    indices per axis, clipped to the grid). The cells of one (x, y) column are consecutive keys: one run
    of ``order`` each, sorted by the lower z of the bounds: it is read from the first body that may reach up to
    ``i`` to the first that starts above it.

    Each candidate is tested without a branch and written at the next free slot whether it passes or not (the
    count advances when it does): which candidates pass is as good as random, and the mispredicted branches cost
    most of the search (the falling ball's 4,428 bodies, 47.8 candidates each: 11 ns a candidate before). So
    ``out`` holds a spare slot after the ``cap`` kept: past ``cap`` partners the candidates go there, and the
    count stays exact (:func:`write_block` searches such a body again). The masks and clumps are read only
    where the grid says that some pair may be refused by them (``filtered``)."""
    dims = grid.dims
    lo0, lo1, lo2 = S.bound_min[i, 0], S.bound_min[i, 1], S.bound_min[i, 2]
    hi0, hi1, hi2 = S.bound_max[i, 0], S.bound_max[i, 1], S.bound_max[i, 2]
    z0 = max(first[2], 0)
    z1 = min(last[2], dims[2] - 1)
    if z0 > z1:
        return n
    box = grid.box
    order = grid.order
    filtered = grid.filtered[0]
    # a binned bound is at most h tall: one whose lower z is below lo2 - h ends below lo2 (the margin covers the
    # rounding of both differences)
    h = grid.h[0]
    below = lo2 - h - 1e-9 * (abs(lo2) + h)
    for cx in range(max(first[0], 0), min(last[0], dims[0] - 1) + 1):
        for cy in range(max(first[1], 0), min(last[1], dims[1] - 1) + 1):
            column = (cx * dims[1] + cy) * dims[2]
            a, b = cell_run(column + z0, column + z1, grid.keys_sorted, grid.dense_start)
            while a < b and box[a, 2] < below:
                a += 1
            for t in range(a, b):
                if box[t, 2] > hi2:
                    break  # the run is sorted by the bounds' lower z: no later body reaches down to i
                j = order[t]
                hit = (j > i) & (box[t, 0] <= hi0) & (box[t, 3] >= lo0) & (box[t, 1] <= hi1) & \
                    (box[t, 4] >= lo1) & (box[t, 5] >= lo2)
                if filtered:  # the same for every candidate: predicted
                    hit &= may_collide(S, i, j, avoid_self)
                out[base + min(n, cap)] = j
                n += hit
    return n


@jit
def listed_partners(i, S, ids, avoid_self, n, base, cap, out):
    """Partners j > i of body ``i`` among the bodies ``ids`` (in id order)."""
    for j in ids:
        if j > i and bounds_overlap(S, i, j) and may_collide(S, i, j, avoid_self):
            n = add_partner(j, n, base, cap, out)
    return n


@jit
def small_partners(i, S, grid, avoid_self, base, cap, out):
    """Partners j > i of small body ``i``: small bodies in the 27 cells around its cell, binned large bodies
    in the cells its bound covers (each counted in the first cell both cover), and the ``rest``."""
    c = grid.cell
    n = small_in_cells(i, S, grid, avoid_self, (c[i, 0] - 1, c[i, 1] - 1, c[i, 2] - 1),
                       (c[i, 0] + 1, c[i, 1] + 1, c[i, 2] + 1), 0, base, cap, out)
    if grid.large_order.shape[0] > 0:
        dims = grid.dims
        # the cells the bound covers (cell_span's): its lower corner's is the one it is binned in
        x0, y0, z0 = c[i, 0], c[i, 1], c[i, 2]
        x1, y1, z1 = corner_cell(S.bound_max, i, grid.lo, grid.h[0], dims)
        for cx in range(x0, x1 + 1):
            for cy in range(y0, y1 + 1):
                for cz in range(z0, z1 + 1):
                    key = (cx * dims[1] + cy) * dims[2] + cz
                    a, b = cell_run(key, key, grid.large_keys, grid.large_dense)
                    for t in range(a, b):
                        j = grid.large_order[t]
                        if j <= i or not bounds_overlap(S, i, j):
                            continue
                        u0, v0, w0, _, _, _ = cell_span(S, j, grid.lo, grid.h[0], dims)
                        if cx == max(x0, u0) and cy == max(y0, v0) and cz == max(z0, w0) and \
                                may_collide(S, i, j, avoid_self):
                            n = add_partner(j, n, base, cap, out)
    if grid.rest.shape[0] == 0:  # often: no call (passing the array costs two reference counts a body)
        return n
    return listed_partners(i, S, grid.rest, avoid_self, n, base, cap, out)


@jit
def binned_large_partners(i, S, grid, avoid_self, base, cap, out):
    """Partners j > i of binned large body ``i``: small bodies binned in the cells its bound covers or just
    below them (a small bound reaches one cell above its own), and the large bodies."""
    x0, y0, z0, x1, y1, z1 = cell_span(S, i, grid.lo, grid.h[0], grid.dims)
    n = small_in_cells(i, S, grid, avoid_self, (x0 - 1, y0 - 1, z0 - 1), (x1, y1, z1), 0, base, cap, out)
    return listed_partners(i, S, grid.large, avoid_self, n, base, cap, out)


@jit
def partners_of(i, S, nb, grid, avoid_self, base, cap, out):
    """Number of partners j > i of body ``i``; the first ``cap`` of them are written to ``out[base:]``, in
    increasing j when all fit. ``out`` has ``cap + 1`` slots from ``base`` (:func:`small_in_cells`' spare)."""
    if not (S.bound_min[i, 0] <= S.bound_max[i, 0]):
        return 0
    if grid.small[i]:
        n = small_partners(i, S, grid, avoid_self, base, cap, out)
    elif is_binned_large(i, grid):
        n = binned_large_partners(i, S, grid, avoid_self, base, cap, out)
    else:
        n = 0
        for j in range(i + 1, nb):  # in id order: already sorted
            if bounds_overlap(S, i, j) and may_collide(S, i, j, avoid_self):   # none with a body without a bound
                n = add_partner(j, n, base, cap, out)
        return n
    if n <= cap:
        sort_partners(out, base, n)
    return n


@jit
def sort_partners(out, base, n):
    """Sort the partner ids ``out[base:base + n]`` (insertion sort for the short lists of small bodies; the
    broad phase's radix sort for longer ones: ``np.sort`` and slice assignment would add 3.5 s to a first
    run's compilation)."""
    if n > 32:
        ids = np.empty(n, np.int64)
        for t in range(n):
            ids[t] = out[base + t]
        order = argsort_keys(ids)
        for t in range(n):
            out[base + t] = ids[order[t]]
        return
    for u in range(base + 1, base + n):
        v = out[u]
        w = u - 1
        while w >= base and out[w] > v:
            out[w + 1] = out[w]
            w -= 1
        out[w + 1] = v


@jit
def is_binned_large(i, grid):
    """Whether large body ``i`` is listed in the cells it covers (else it is in ``grid.rest``)."""
    k = lower_bound(grid.rest, i)
    return not (k < grid.rest.shape[0] and grid.rest[k] == i)


@jit
def scratch_block(b, S, nb, grid, avoid_self, count, scratch, width):
    """First pass over the bodies of block ``b`` (``grid``: a raw view; borrowing the arrays: no reference
    counting per body): count each body's partners, keeping up to ``width - 1`` of them, sorted, in its
    ``width`` slots of ``scratch`` (the last is the search's spare)."""
    count, scratch = borrow((count, scratch))
    for i in range(b * BLOCK, min(nb, (b + 1) * BLOCK)):
        count[i] = partners_of(i, S, nb, grid, avoid_self, i * width, width - 1, scratch)


def _scratch_pass(S, nb, grid, avoid_self, count, scratch, width):
    """``grid``: the :data:`GRID` record (the blocks get its raw view, valid while this call lasts)."""
    grid = raw(grid)
    queue = block_queue((nb + BLOCK - 1) // BLOCK)
    for w in prange(queue_workers(queue)):
        b = next_block(queue, w, -1)
        while b >= 0:
            scratch_block(b, S, nb, grid, avoid_self, count, scratch, width)
            b = next_block(queue, w, b)


scratch_pass, scratch_pass_par = kernel(_scratch_pass, over="bodies")


@jit
def write_block(b, S, nb, grid, avoid_self, count, scratch, width, start, out):
    """Second pass over block ``b``: each body's partners into its rows of ``out`` (copied from ``scratch``,
    or searched again for a body with ``width`` or more)."""
    count, scratch, start, out = borrow((count, scratch, start, out))
    for i in range(b * BLOCK, min(nb, (b + 1) * BLOCK)):
        n = count[i]
        s = start[i]
        if n < width:
            for t in range(n):
                out[s + t, 0] = i
                out[s + t, 1] = scratch[i * width + t]
            continue
        ids = np.empty(n + 1, np.int32)
        partners_of(i, S, nb, grid, avoid_self, 0, n, ids)
        for t in range(n):
            out[s + t, 0] = i
            out[s + t, 1] = ids[t]


@jit
def write_pass(S, nb, grid, avoid_self, count, scratch, width, start, out):
    """:func:`write_block` over all bodies, serially: mostly a copy (a parallel twin would cost more to compile
    than it saves). ``grid``: the :data:`GRID` record (the blocks get its raw view)."""
    grid = raw(grid)
    for b in range((nb + BLOCK - 1) // BLOCK):
        write_block(b, S, nb, grid, avoid_self, count, scratch, width, start, out)


@jit
def grid_bodies(S, nb):
    """Split the bodies with a bound into those binned in the grid and the large ones.

    The grid spacing ``h`` is the largest bound width (largest extent) not above four times the median
    finite width; bodies no wider than ``h`` are binned. Returns ``(small, idx, large, h)``: the mask (nb,)
    of binned bodies, their ids (int64) and the ids of the others with a bound (int32), in id order.
    """
    width = np.zeros(nb)
    bounded = np.zeros(nb, np.bool_)
    nfinite = 0
    for i in range(nb):
        if S.bound_min[i, 0] <= S.bound_max[i, 0]:
            bounded[i] = True
            w = 0.0
            for k in range(3):
                w = max(w, S.bound_max[i, k] - S.bound_min[i, k])
            width[i] = w
            nfinite += math.isfinite(w)
    finite = np.empty(nfinite)
    t = 0
    for i in range(nb):
        if bounded[i] and math.isfinite(width[i]):
            finite[t] = width[i]
            t += 1
    h = 0.0
    if nfinite > 0:
        ref = median(finite)
        for w in finite:
            if w <= 4.0 * ref:
                h = max(h, w)
    small = np.zeros(nb, np.bool_)
    nsmall = 0
    nlarge = 0
    for i in range(nb):
        small[i] = bounded[i] and math.isfinite(width[i]) and width[i] <= h and h > 0.0
        nsmall += small[i]
        nlarge += bounded[i] and not small[i]
    idx = np.empty(nsmall, np.int64)
    large = np.empty(nlarge, np.int32)
    nsmall = 0
    nlarge = 0
    for i in range(nb):
        if small[i]:
            idx[nsmall] = i
            nsmall += 1
        elif bounded[i]:
            large[nlarge] = i
            nlarge += 1
    return small, idx, large, h


@jit
def cell_table(keys_sorted, ncells, dense):
    """Start of each cell in a list sorted by cell key, (ncells + 1,); empty when not ``dense``."""
    if not dense:
        return np.zeros(0, np.int64)
    table = np.zeros(ncells + 1, np.int64)
    for key in keys_sorted:
        table[key + 1] += 1
    for k in range(ncells):
        table[k + 1] += table[k]
    return table


@jit
def bin_large(S, large, nsmall, lo, h, dims, dense):
    """List the large bodies whose bound covers few cells in each cell it covers: ``(order, keys, table,
    rest)`` (see :class:`BodyGrid`). Visiting a cell costs about as much as testing a body, so a body is
    binned when it covers at most ``nsmall / 8 + 64`` cells, as long as the list stays below
    ``8 nsmall + 4096`` entries (in id order: the same bodies every time)."""
    per_body = nsmall // 8 + 64
    budget = 8 * nsmall + 4096
    binned = np.zeros(large.shape[0], np.bool_)
    total = 0
    for t in range(large.shape[0]):
        i = large[t]
        finite = True
        for k in range(3):
            finite = finite and math.isfinite(S.bound_min[i, k]) and math.isfinite(S.bound_max[i, k])
        if not finite or nsmall == 0:
            continue
        x0, y0, z0, x1, y1, z1 = cell_span(S, i, lo, h, dims)
        cells = (x1 - x0 + 1) * (y1 - y0 + 1) * (z1 - z0 + 1)
        if cells <= per_body and total + cells <= budget:
            binned[t] = True
            total += cells
    keys = np.empty(total, np.int64)
    ids = np.empty(total, np.int32)
    rest = np.empty(large.shape[0] - binned.sum(), np.int32)
    m = 0
    r = 0
    for t in range(large.shape[0]):
        i = large[t]
        if not binned[t]:
            rest[r] = i
            r += 1
            continue
        x0, y0, z0, x1, y1, z1 = cell_span(S, i, lo, h, dims)
        for cx in range(x0, x1 + 1):
            for cy in range(y0, y1 + 1):
                for cz in range(z0, z1 + 1):
                    keys[m] = (cx * dims[1] + cy) * dims[2] + cz
                    ids[m] = i
                    m += 1
    perm = argsort_keys(keys)  # stable: within a cell, in id order
    order = np.empty(total, np.int32)
    keys_sorted = np.empty(total, np.int64)
    for t in range(total):
        order[t] = ids[perm[t]]
        keys_sorted[t] = keys[perm[t]]
    return order, keys_sorted, cell_table(keys_sorted, dims[0] * dims[1] * dims[2], dense), rest


@jit
def sort_cells_by_z(keys_sorted, order, box):
    """Sort the bodies of each cell by the lower z of their bounds (insertion sort, stable: the few bodies of a
    cell stay in id order on ties). The cells of a column along z are then one run sorted by lower z."""
    for t in range(1, order.shape[0]):
        u = t
        while u > 0 and keys_sorted[u - 1] == keys_sorted[u] and box[u - 1, 2] > box[u, 2]:
            order[u - 1], order[u] = order[u], order[u - 1]
            for k in range(6):
                box[u - 1, k], box[u, k] = box[u, k], box[u - 1, k]
            u -= 1


@jit
def find_pairs(S, nb, avoid_self, pairs_before):
    """All pairs (i < j) with overlapping bounds that may collide, sorted, shape (P, 2), and the start of each
    body's pairs, (nb + 1,); ``pairs_before``: the pair count of the last run (sizes the first pass)."""
    small, idx, large, h = grid_bodies(S, nb)
    # bin the small bodies by the cell of their lower corner
    cell = np.zeros((nb, 3), np.int64)
    dims = np.ones(3, np.int64)
    lo = np.zeros(3)
    if idx.shape[0] > 0:
        hi = np.empty(3)
        for k in range(3):
            lo[k] = S.bound_min[idx[0], k]
            hi[k] = lo[k]
        for i in idx:
            for k in range(3):
                lo[k] = min(lo[k], S.bound_min[i, k])
                hi[k] = max(hi[k], S.bound_min[i, k])
        # at most 2**20 cells per axis (keys must fit in int64): coarser cells only add candidates
        for k in range(3):
            h = max(h, (hi[k] - lo[k]) / (1 << 20))
        for k in range(3):
            dims[k] = int((hi[k] - lo[k]) / h) + 1
        for i in idx:
            for k in range(3):
                cell[i, k] = min(int((S.bound_min[i, k] - lo[k]) / h), dims[k] - 1)
    keys = np.empty(idx.shape[0], np.int64)
    for t in range(idx.shape[0]):
        i = idx[t]
        keys[t] = (cell[i, 0] * dims[1] + cell[i, 1]) * dims[2] + cell[i, 2]
    perm = argsort_keys(keys)
    order = np.empty(idx.shape[0], np.int32)
    keys_sorted = np.empty(idx.shape[0], np.int64)
    box = np.empty((idx.shape[0], 6))
    for t in range(idx.shape[0]):
        i = idx[perm[t]]
        order[t] = i
        keys_sorted[t] = keys[perm[t]]
        for k in range(3):
            box[t, k] = S.bound_min[i, k]
            box[t, 3 + k] = S.bound_max[i, k]
    sort_cells_by_z(keys_sorted, order, box)
    ncells = dims[0] * dims[1] * dims[2]
    dense = ncells <= 4 * idx.shape[0] + 1024
    large_order, large_keys, large_dense, rest = bin_large(S, large, idx.shape[0], lo, h, dims, dense)
    grid = body_grid(small, cell, dims, lo, np.full(1, h), order, keys_sorted, box,
                     cell_table(keys_sorted, ncells, dense), large, large_order, large_keys, large_dense, rest,
                     np.full(1, masks_may_refuse(S, nb, avoid_self)))
    # one search per body, keeping its first partners; only bodies with more are searched again
    count = np.zeros(nb, np.int64)
    width = scratch_width(pairs_before, nb)
    scratch = np.empty(nb * width, np.int32)
    par = nb >= PARALLEL_THRESHOLD
    if par:
        scratch_pass_par(S, nb, grid, avoid_self, count, scratch, width)
    else:
        scratch_pass(S, nb, grid, avoid_self, count, scratch, width)
    start = np.zeros(nb + 1, np.int64)
    for i in range(nb):
        start[i + 1] = start[i] + count[i]
    out = np.empty((start[nb], 2), np.int32)
    write_pass(S, nb, grid, avoid_self, count, scratch, width, start, out)
    return out, start


@jit
def find_pair(pairs, start, a, b):
    """Index of pair (a, b), a < b, in a sorted pair list with per-body offsets ``start``; -1 if absent."""
    lo = start[a]
    hi = start[a + 1]
    while lo < hi:
        mid = (lo + hi) // 2
        if pairs[mid, 1] < b:
            lo = mid + 1
        else:
            hi = mid
    if lo < start[a + 1] and pairs[lo, 1] == b:
        return lo
    return -1


@jit
def relink_contact(c, C, pairs, start, cells, pair_con, pair_gap):
    """Attach live contact ``c`` to its pair in the new pair list (or to none: -1); the pair's budget
    becomes +inf (a pair with a contact is not detected)."""
    if not C.con_i[c, I_FLAGS] & FLAG_ALIVE:
        return
    id1 = C.con_i[c, I_ID1]
    id2 = C.con_i[c, I_ID2]
    a = min(id1, id2)
    b = max(id1, id2)
    p = find_pair(pairs, start, a, b)
    if p >= 0 and cells.shape[0] > 0 and C.con_i.shape[1] > I_CELL:
        # the pair must join the same periodic images as the contact
        sign = 1 if a == id1 else -1
        for k in range(3):
            if cells[p, k] != sign * C.con_i[c, I_CELL + k]:
                p = -1
                break
    C.con_i[c, I_PAIR] = p
    if p >= 0:
        pair_con[p] = c
        pair_gap[p] = math.inf


@jit
def relink_block(b, C, pairs, start, cells, pair_con, pair_gap):
    """Contacts of block ``b`` (borrowing the lists: no reference counting per contact)."""
    pairs, start, cells, pair_con, pair_gap = borrow((pairs, start, cells, pair_con, pair_gap))
    for c in range(b * BLOCK, min(C.ctr[C_CONTACTS], (b + 1) * BLOCK)):
        relink_contact(c, C, pairs, start, cells, pair_con, pair_gap)


def _relink(C, pairs, start, cells, pair_con, pair_gap):
    queue = block_queue((C.ctr[C_CONTACTS] + BLOCK - 1) // BLOCK)
    for w in prange(queue_workers(queue)):
        b = next_block(queue, w, -1)
        while b >= 0:
            relink_block(b, C, pairs, start, cells, pair_con, pair_gap)
            b = next_block(queue, w, b)


relink, relink_par = kernel(_relink, over="contacts")


@jit
def cell_moved(S, verlet):
    """Whether the periodic cell changed enough since the last collider run to invalidate bounds."""
    change = 0.0
    for i in range(3):
        for j in range(3):
            change += (S.cell_hsize[i, j] - S.cell_bound_hsize[i, j]) ** 2
    # a point of the (wrapped) cell moves by at most |dH| |s| <= |dH|_F sqrt(3)
    return math.sqrt(3.0 * change) > 0.5 * verlet


def cell_pairs(cell, S, nb, avoid_self, allow_bigger, pairs_before):
    """``(pairs, start, cells, too_large, axis)`` of the broad phase for the kind of cell ``cell``, a static
    ``("cell", periodic)`` (:mod:`granum.kernels.static`): aperiodic scenes compile no periodic broad phase."""
    raise TypeError("cell_pairs is called from compiled kernels only")


@overload(cell_pairs)
def _cell_pairs(cell, S, nb, avoid_self, allow_bigger, pairs_before):
    value = static_value(cell, "cell")
    if value is None:
        return None
    if value[1]:
        return lambda cell, S, nb, avoid_self, allow_bigger, pairs_before: find_pairs_periodic(
            S, nb, avoid_self, allow_bigger, pairs_before)

    def aperiodic(cell, S, nb, avoid_self, allow_bigger, pairs_before):
        pairs, start = find_pairs(S, nb, avoid_self, pairs_before)
        # no images: pair_cell is read in periodic cells only
        return pairs, start, np.zeros((0, 3), np.int32), -1, -1

    return aperiodic


def appended_run(appends, S, C, nb, bound_code, bound_tab, verlet_dist, avoid_self, motion, spread):
    """The collider's run for bodies only appended (:func:`granum.kernels.collider_append.append_bodies`); for
    ``appends``, a static ``("appends", bool)``: whether an engine of the plan adds bodies as the run goes.
    Without one, always False, and the stage compiles no code for it."""
    raise TypeError("appended_run is called from compiled kernels only")


@jit
def nothing_appended(S, C, nb, bound_code, bound_tab, verlet_dist, avoid_self, motion, spread):
    """:func:`appended_run` in a plan without an engine that adds bodies: never such a run."""
    return False


static_switch(appended_run, "appends", append_bodies, nothing_appended)


class ColliderParams(NamedTuple):
    """Parameters of :func:`collider_stage` (InsertionSortCollider)."""

    bound_code: np.ndarray  #: bound functor code per shape kind (-1: none), (NKINDS,) int32
    bound_tab: tuple        #: the bound functors' table (:func:`granum.engines.functors.functor_table`)
    verlet_dist: float      #: Verlet distance [m]; negative: that fraction of the smallest sphere radius
    avoid_self: int         #: YADE's avoidSelfInteractionMask
    allow_bigger: bool      #: YADE's allowBiggerThanPeriod: no periodic body is refused as too wide
    cell: Static            #: ``("cell", periodic)`` of the scene: compiles one broad phase (:func:`cell_pairs`)
    #: ``("appends", bool)``: an engine of the plan adds bodies as the run goes (a factory): the collider's run for
    #: appended bodies is compiled (:func:`appended_run`)
    appends: Static


@jit
def collider_stage(S, C, P):
    """Engine stage of InsertionSortCollider; ``P``: :class:`ColliderParams`."""
    bound_code, bound_tab = P.bound_code, P.bound_tab
    nb = S.iscal[SI_NBODIES]
    periodic = S.iscal[SI_PERIODIC] != 0
    C.ctr[C_MOTIONS_STAGE] = 0
    # the bodies' motions, at the start of the work area (granum.kernels.scratch), where the interaction loop takes
    # them
    motion, spread, _ = take_motions(area(C, motion_words(nb)), nb)
    R = raw(S)  # loops over bodies read the scene through a raw view (see granum.core.records)
    if C.ctr[C_COLLIDE] == COLLIDE_APPENDED and not periodic and appended_run(
            P.appends, R, C, nb, bound_code, bound_tab, P.verlet_dist, P.avoid_self, motion, spread):
        return
    if C.ctr[C_COLLIDE] == 0 and not any_body_moved(R, nb, motion, spread):
        if not (periodic and cell_moved(S, S.scal[S_VERLET])):
            # no run: the motions stand for the interaction loop if it is the next stage (one pass over the bodies
            # instead of two: see ARCHITECTURE.md, "Collider")
            C.ctr[C_MOTIONS_STAGE] = C.ctr[C_STAGE]
            return
    pairs_before = C.ctr[C_PAIRS]
    # a run because bodies moved, not a scene edit: the pairs found again keep their budgets, measured from the
    # present, where the bounds are taken now (granum.kernels.motion.carry_budgets; before the reference unit
    # changes); in periodic cells the images' budgets move with the cell: evaluated again
    carry = C.ctr[C_COLLIDE] == 0 and not periodic and pairs_before > 0
    if carry:
        budgets_from_now(R, C, motion)   # the check's motions (a run because bodies moved)
        old_ids, old_gap = C.pair_ids, C.pair_gap
    else:
        old_ids, old_gap = np.zeros((0, 2), np.int32), np.zeros(0, np.float32)
    verlet = P.verlet_dist
    if verlet < 0.0:
        rmin = math.inf
        for i in range(nb):
            if S.alive[i] and S.shape_kind[i] == ShapeKind.SPHERE:
                rmin = min(rmin, S.sphere_radius[S.shape_row[i]])
        verlet = -verlet * rmin if rmin < math.inf else 0.0
    S.scal[S_VERLET] = verlet
    # a relative displacement of two bodies between collider runs stays near 2 verlet: int16 units cover 4
    S.scal[S_PAIR_REF_UNIT] = verlet / 8192.0 if verlet > 0.0 else 1e-9
    # the new budgets of pairs with a turning body hold as much rotation as the last interval between runs saw
    # (see granum.kernels.interaction.detect_block)
    S.scal[S_TURN_ALLOWANCE] = S.scal[S_TURN_SEEN]
    S.scal[S_TURN_SEEN] = 0.0
    # drop the rest of the old pair list first: at a million bodies it takes hundreds of MB (relink needs only
    # the contacts)
    C.ctr[C_PAIRS] = 0
    C.pair_ids = np.zeros((0, 2), np.int32)
    C.pair_cell = np.zeros((0, 3), np.int32)
    C.pair_con = np.zeros(0, np.int32)
    C.pair_gap = np.zeros(0, np.float32)
    C.pair_ref = np.zeros((0, 3), np.int16)
    C.pair_hit = np.zeros(0, np.uint8)
    C.ctr[C_REPLACED] += 1
    if nb < PARALLEL_THRESHOLD:
        compute_bounds(R, nb, bound_code, bound_tab, verlet)
    else:
        compute_bounds_par(R, nb, bound_code, bound_tab, verlet)
    if periodic:
        # bodies and the cell share the Verlet budget: each may use half of it
        S.scal[S_VERLET] = 0.5 * verlet
        copy_rows(S.cell_bound_hsize, S.cell_hsize, 3)
    pairs, start, cells, too_large, axis = cell_pairs(P.cell, R, nb, P.avoid_self, P.allow_bigger,
                                                          pairs_before)
    if too_large >= 0:
        C.ctr[C_STATUS] = STATUS_TOO_LARGE
        C.ctr[C_ERR_A] = too_large
        C.ctr[C_ERR_B] = axis
        return
    n = pairs.shape[0]
    pair_con = np.full(n, -1, np.int32)
    pair_gap = np.full(n, -np.inf, np.float32)
    if carry and n > 0:
        if n < PARALLEL_THRESHOLD:
            carry_budgets(R, old_ids, pairs_before, old_gap, pairs, pair_gap)
        else:
            carry_budgets_par(R, old_ids, pairs_before, old_gap, pairs, pair_gap)
    old_ids, old_gap = np.zeros((0, 2), np.int32), np.zeros(0, np.float32)   # freed before the rest is made
    if C.ctr[C_CONTACTS] < PARALLEL_THRESHOLD:
        relink(raw(C), pairs, start, cells, pair_con, pair_gap)
    else:
        relink_par(raw(C), pairs, start, cells, pair_con, pair_gap)
    C.ctr[C_PAIRS] = n
    C.ctr[C_COLLIDE] = 0
    C.ctr[C_COLLIDER_RUNS] += 1
    C.pair_ids = pairs
    C.pair_cell = cells
    C.pair_con = pair_con
    C.pair_gap = pair_gap
    C.pair_ref = np.zeros((n, 3), np.int16)
    C.pair_hit = np.zeros(n, np.uint8)
