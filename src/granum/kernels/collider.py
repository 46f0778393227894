"""Broad phase: axis-aligned bounds, Verlet trigger and the potential-pair list.

YADE's ``InsertionSortCollider`` keeps the potential interactions of all bodies
whose axis-aligned bounds overlap; bounds are enlarged by a Verlet distance so that
the collider need only run again when some body has moved farther than that. granum
produces the same set of pairs with a uniform grid instead of sorted lists:

1. Bounds are computed by the registered bound functions and enlarged by the Verlet
   distance; the position and orientation at that moment are remembered.
2. Bodies whose bound fits in a grid cell ("small") are binned; each looks for
   partners with a larger id in the 27 neighbouring cells. Bodies with larger or
   infinite bounds (facets of a container, walls) are tested against all others.
3. Each body's partner list is sorted, so the pair list comes out ordered by
   (id1, id2), deterministically and without a global sort.

The collider runs again when a body has moved (or, for non-spheres, turned) by
more than the Verlet distance since its bound was computed, when the scene changed
(bodies added or erased, :data:`C_COLLIDE` set), or every step if the Verlet
distance is zero.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba.extending import overload

from granum._jit import BLOCK, PARALLEL_THRESHOLD, jit, kernel, prange
from granum.core.arrays import S_VERLET, SI_NBODIES, SI_PERIODIC
from granum.core.bodies import ShapeKind
from granum.core.contacts import (
    C_COLLIDE,
    C_COLLIDER_RUNS,
    C_CONTACTS,
    C_ERR_A,
    C_PAIRS,
    C_STATUS,
    FLAG_ALIVE,
    I_CELL,
    I_FLAGS,
    I_ID1,
    I_ID2,
    I_PAIR,
    STATUS_TOO_LARGE,
)
from granum.core.records import borrow, raw
from granum.kernels.collider_periodic import find_pairs_periodic
from granum.kernels.copy import copy_rows
from granum.kernels.dispatch import bound_call
from granum.kernels.pairing import may_collide
from granum.kernels.schedule import block_queue, next_block, queue_workers
from granum.kernels.sorting import argsort_keys, lower_bound, median
from granum.kernels.static import Static, static_value
from granum.physics.vec import load3, load4, quat_angle, quat_mul, sub


@jit
def body_reach(i, S):
    """Largest distance from the body position to a point of its shape (0 for spheres and walls) [m]."""
    kind = S.shape_kind[i]
    row = S.shape_row[i]
    if kind == ShapeKind.FACET:
        r = 0.0
        for k in range(3):
            r = max(r, math.sqrt(S.facet_vertices[row, k, 0] ** 2 + S.facet_vertices[row, k, 1] ** 2
                                 + S.facet_vertices[row, k, 2] ** 2))
        return r
    if kind == ShapeKind.BOX:
        e = S.box_extents[row]
        return math.sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2])
    return 0.0


@jit
def body_displacement(i, S):
    """``(dx, dy, dz, w)``: displacement of body ``i``'s centre since its bound was computed [m], and
    the rotation angle since then times the body's reach [m] (0 for spheres, whose geometry does not
    turn); all zero for a body without a bound."""
    if not S.alive[i] or S.bound_min[i, 0] > S.bound_max[i, 0]:
        return 0.0, 0.0, 0.0, 0.0
    d = sub(load3(S.pos, i), load3(S.bound_pos, i))
    w = 0.0
    if S.shape_kind[i] != ShapeKind.SPHERE:
        q = load4(S.ori, i)
        q0 = load4(S.bound_ori, i)
        w = quat_angle(quat_mul(q, (q0[0], -q0[1], -q0[2], -q0[3]))) * body_reach(i, S)
    return d[0], d[1], d[2], w


@jit
def body_motion(i, S):
    """How far any point of body ``i`` may have moved since its bound was computed [m]."""
    dx, dy, dz, w = body_displacement(i, S)
    return math.sqrt(dx * dx + dy * dy + dz * dz) + w


@jit
def moved_block(b, S, nb, flags):
    """Flag block ``b`` of bodies if one of them left its Verlet-enlarged bound."""
    verlet = S.scal[S_VERLET]
    for i in range(b * BLOCK, min(nb, (b + 1) * BLOCK)):
        d = body_motion(i, S)
        if d > verlet or (verlet == 0.0 and d > 0.0) or not d == d:
            flags[b] = 1
            return
    flags[b] = 0


def _moved_blocks(S, nb, flags):
    queue = block_queue(flags.shape[0])
    for w in prange(queue_workers(queue)):
        b = next_block(queue, w, -1)
        while b >= 0:
            moved_block(b, S, nb, flags)
            b = next_block(queue, w, b)


moved_blocks, moved_blocks_par = kernel(_moved_blocks)


@jit
def any_body_moved(S, nb):
    """Whether some body left its Verlet-enlarged bound since the collider last ran."""
    flags = np.zeros((nb + BLOCK - 1) // BLOCK, np.uint8)
    if nb < PARALLEL_THRESHOLD:
        moved_blocks(S, nb, flags)
    else:
        moved_blocks_par(S, nb, flags)
    return flags.any()


@jit
def bound_body(i, S, bound_code, bound_tab, verlet, out):
    """Bound of body ``i`` enlarged by ``verlet``, and the position and orientation it was taken at
    (``out``: (6,) scratch for the bound functor)."""
    code = bound_code[S.shape_kind[i]] if S.alive[i] else -1
    if code < 0:
        for k in range(3):
            S.bound_min[i, k] = math.inf   # no bound: never collides
            S.bound_max[i, k] = -math.inf
        return
    bound_call(code, i, S, bound_tab, out)
    for k in range(3):
        S.bound_min[i, k] = out[k] - verlet
        S.bound_max[i, k] = out[3 + k] + verlet
        S.bound_pos[i, k] = S.pos[i, k]
    for k in range(4):
        S.bound_ori[i, k] = S.ori[i, k]


@jit
def bounds_block(b, S, nb, bound_code, bound_tab, verlet):
    """Bounds of the bodies of block ``b``; the parameter arrays are borrowed (no reference counting
    per body: see ARCHITECTURE.md, "Kernel records")."""
    bound_code, bound_tab = borrow((bound_code, bound_tab))
    out = np.empty(6)
    for i in range(b * BLOCK, min(nb, (b + 1) * BLOCK)):
        bound_body(i, S, bound_code, bound_tab, verlet, out)


def _compute_bounds(S, nb, bound_code, bound_tab, verlet):
    queue = block_queue((nb + BLOCK - 1) // BLOCK)
    for w in prange(queue_workers(queue)):
        b = next_block(queue, w, -1)
        while b >= 0:
            bounds_block(b, S, nb, bound_code, bound_tab, verlet)
            b = next_block(queue, w, b)


compute_bounds, compute_bounds_par = kernel(_compute_bounds)


@jit
def overlap(S, i, j):
    for k in range(3):
        if S.bound_min[i, k] > S.bound_max[j, k] or S.bound_min[j, k] > S.bound_max[i, k]:
            return False
    return True


@jit
def cell_range(key, keys_sorted, dense_start):
    """Range [a, b) of ``keys_sorted`` equal to ``key`` (dense table or binary search)."""
    if dense_start.shape[0] > 0:
        if key < 0 or key >= dense_start.shape[0] - 1:
            return 0, 0
        return dense_start[key], dense_start[key + 1]
    return lower_bound(keys_sorted, key), lower_bound(keys_sorted, key + 1)


@jit
def partners_of(i, S, nb, small, cell, dims, order, keys_sorted, dense_start, large, avoid_self, count, start, out):
    """Partners j > i of body ``i``: counted into ``count[i]`` (``out`` empty) or written from ``start[i]``."""
    fill = out.shape[0] > 0
    if not (S.bound_min[i, 0] <= S.bound_max[i, 0]):
        return
    n = 0
    base = start[i] if fill else 0
    if small[i]:
        for dx in range(-1, 2):
            cx = cell[i, 0] + dx
            if cx < 0 or cx >= dims[0]:
                continue
            for dy in range(-1, 2):
                cy = cell[i, 1] + dy
                if cy < 0 or cy >= dims[1]:
                    continue
                for dz in range(-1, 2):
                    cz = cell[i, 2] + dz
                    if cz < 0 or cz >= dims[2]:
                        continue
                    a, b = cell_range((cx * dims[1] + cy) * dims[2] + cz, keys_sorted, dense_start)
                    for t in range(a, b):
                        j = order[t]
                        if j > i and overlap(S, i, j) and may_collide(S, i, j, avoid_self):
                            if fill:
                                out[base + n, 0] = i
                                out[base + n, 1] = j
                            n += 1
        for j in large:
            if j > i and overlap(S, i, j) and may_collide(S, i, j, avoid_self):
                if fill:
                    out[base + n, 0] = i
                    out[base + n, 1] = j
                n += 1
        if fill:  # insertion sort of the (short) partner list by id
            for u in range(base + 1, base + n):
                v = out[u, 1]
                w = u - 1
                while w >= base and out[w, 1] > v:
                    out[w + 1, 1] = out[w, 1]
                    w -= 1
                out[w + 1, 1] = v
    else:
        for j in range(i + 1, nb):  # in id order: already sorted
            if S.bound_min[j, 0] <= S.bound_max[j, 0] and overlap(S, i, j) and may_collide(S, i, j, avoid_self):
                if fill:
                    out[base + n, 0] = i
                    out[base + n, 1] = j
                n += 1
    if not fill:
        count[i] = n


@jit
def partners_block(b, S, nb, small, cell, dims, order, keys_sorted, dense_start, large, avoid_self, count, start,
                   out):
    """Bodies of block ``b`` (borrowing the arrays: no reference counting per body)."""
    small, cell, dims, order, keys_sorted, dense_start, large, count, start, out = borrow(
        (small, cell, dims, order, keys_sorted, dense_start, large, count, start, out))
    for i in range(b * BLOCK, min(nb, (b + 1) * BLOCK)):
        partners_of(i, S, nb, small, cell, dims, order, keys_sorted, dense_start, large, avoid_self, count, start,
                    out)


def _partners(S, nb, small, cell, dims, order, keys_sorted, dense_start, large, avoid_self, count, start, out):
    """Pass 1 (``out`` empty): count partners j > i of each body. Pass 2: write them."""
    queue = block_queue((nb + BLOCK - 1) // BLOCK)
    for w in prange(queue_workers(queue)):
        b = next_block(queue, w, -1)
        while b >= 0:
            partners_block(b, S, nb, small, cell, dims, order, keys_sorted, dense_start, large, avoid_self, count,
                           start, out)
            b = next_block(queue, w, b)


partners, partners_par = kernel(_partners)


@jit
def grid_bodies(S, nb):
    """Split the bodies with a bound into those binned in the grid and the large ones tested against all.

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
def find_pairs(S, nb, avoid_self):
    """All pairs (i < j) with overlapping bounds that may collide, sorted, shape (P, 2)."""
    small, idx, large, h = grid_bodies(S, nb)
    # bin the small bodies by the cell of their lower corner
    cell = np.zeros((nb, 3), np.int64)
    dims = np.ones(3, np.int64)
    if idx.shape[0] > 0:
        lo = np.empty(3)
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
    for t in range(idx.shape[0]):
        order[t] = idx[perm[t]]
        keys_sorted[t] = keys[perm[t]]
    ncells = dims[0] * dims[1] * dims[2]
    if ncells <= 4 * idx.shape[0] + 1024:
        dense_start = np.zeros(ncells + 1, np.int64)
        for key in keys_sorted:
            dense_start[key + 1] += 1
        for k in range(ncells):
            dense_start[k + 1] += dense_start[k]
    else:
        dense_start = np.zeros(0, np.int64)
    count = np.zeros(nb, np.int64)
    start = np.zeros(nb + 1, np.int64)
    none = np.zeros((0, 2), np.int32)
    par = nb >= PARALLEL_THRESHOLD
    if par:
        partners_par(S, nb, small, cell, dims, order, keys_sorted, dense_start, large, avoid_self, count, start, none)
    else:
        partners(S, nb, small, cell, dims, order, keys_sorted, dense_start, large, avoid_self, count, start, none)
    for i in range(nb):
        start[i + 1] = start[i] + count[i]
    out = np.empty((start[nb], 2), np.int32)
    if par:
        partners_par(S, nb, small, cell, dims, order, keys_sorted, dense_start, large, avoid_self, count, start, out)
    else:
        partners(S, nb, small, cell, dims, order, keys_sorted, dense_start, large, avoid_self, count, start, out)
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


relink, relink_par = kernel(_relink)


@jit
def cell_moved(S, verlet):
    """Whether the periodic cell changed enough since the last collider run to invalidate bounds."""
    change = 0.0
    for i in range(3):
        for j in range(3):
            change += (S.cell_hsize[i, j] - S.cell_bound_hsize[i, j]) ** 2
    # a point of the (wrapped) cell moves by at most |dH| |s| <= |dH|_F sqrt(3)
    return math.sqrt(3.0 * change) > 0.5 * verlet


def cell_pairs(cell, S, nb, avoid_self):
    """``(pairs, start, cells, too_large)`` of the broad phase for the kind of cell ``cell``, a static
    ``("cell", periodic)`` (:mod:`granum.kernels.static`): aperiodic scenes compile no periodic broad phase."""
    raise TypeError("cell_pairs is called from compiled kernels only")


@overload(cell_pairs)
def _cell_pairs(cell, S, nb, avoid_self):
    value = static_value(cell, "cell")
    if value is None:
        return None
    if value[1]:
        return lambda cell, S, nb, avoid_self: find_pairs_periodic(S, nb, avoid_self)

    def aperiodic(cell, S, nb, avoid_self):
        pairs, start = find_pairs(S, nb, avoid_self)
        return pairs, start, np.zeros((0, 3), np.int32), -1  # no images: pair_cell is read in periodic cells only

    return aperiodic


class ColliderParams(NamedTuple):
    """Parameters of :func:`collider_stage` (InsertionSortCollider)."""

    bound_code: np.ndarray  #: bound functor code per shape kind (-1: none), (NKINDS,) int32
    bound_tab: tuple        #: the bound functors' table (:func:`granum.engines.functors.functor_table`)
    verlet_dist: float      #: Verlet distance [m]; negative: that fraction of the smallest sphere radius
    avoid_self: int         #: YADE's avoidSelfInteractionMask
    cell: Static            #: ``("cell", periodic)`` of the scene: compiles one broad phase (:func:`cell_pairs`)


@jit
def collider_stage(S, C, P):
    """Engine stage of InsertionSortCollider; ``P``: :class:`ColliderParams`."""
    bound_code, bound_tab = P.bound_code, P.bound_tab
    nb = S.iscal[SI_NBODIES]
    periodic = S.iscal[SI_PERIODIC] != 0
    R = raw(S)  # loops over bodies read the scene through a raw view (see granum.core.records)
    if C.ctr[C_COLLIDE] == 0 and not any_body_moved(R, nb) and not (periodic and cell_moved(S, S.scal[S_VERLET])):
        return
    verlet = P.verlet_dist
    if verlet < 0.0:
        rmin = math.inf
        for i in range(nb):
            if S.alive[i] and S.shape_kind[i] == ShapeKind.SPHERE:
                rmin = min(rmin, S.sphere_radius[S.shape_row[i]])
        verlet = -verlet * rmin if rmin < math.inf else 0.0
    S.scal[S_VERLET] = verlet
    # drop the old pair list first: at a million bodies it takes hundreds of MB (relink needs only the contacts)
    C.ctr[C_PAIRS] = 0
    C.pair_ids = np.zeros((0, 2), np.int32)
    C.pair_cell = np.zeros((0, 3), np.int32)
    C.pair_con = np.zeros(0, np.int32)
    C.pair_gap = np.zeros(0, np.float32)
    C.pair_hit = np.zeros(0, np.uint8)
    if nb < PARALLEL_THRESHOLD:
        compute_bounds(R, nb, bound_code, bound_tab, verlet)
    else:
        compute_bounds_par(R, nb, bound_code, bound_tab, verlet)
    if periodic:
        # bodies and the cell share the Verlet budget: each may use half of it
        S.scal[S_VERLET] = 0.5 * verlet
        copy_rows(S.cell_bound_hsize, S.cell_hsize, 3)
    pairs, start, cells, too_large = cell_pairs(P.cell, R, nb, P.avoid_self)
    if too_large >= 0:
        C.ctr[C_STATUS] = STATUS_TOO_LARGE
        C.ctr[C_ERR_A] = too_large
        return
    n = pairs.shape[0]
    pair_con = np.full(n, -1, np.int32)
    pair_gap = np.full(n, -np.inf, np.float32)
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
    C.pair_hit = np.zeros(n, np.uint8)
