"""Broad phase in a periodic cell, with sheared cells and unwrapped positions.

Positions are never wrapped (YADE's convention): a pair across the boundary is
stored with the integer cell offset k of its second body, whose image is at
x2 + H k (YADE ``cellDist``). The search works in the cell's fractional
coordinates s = H^-1 x, where the cell is the unit cube in any shear state:

* each bound (the Cartesian box incl. the Verlet distance) maps to a box of
  half-widths hw_k = sum_j |H^-1_kj| half_j around s(centre), which contains it;
  a sphere's bound is a ball of radius R (its radius plus the Verlet distance),
  whose exact extent is hw_k = R |row k of H^-1| (Euclidean norm): in a cell
  sheared by g the box of the Cartesian cube would be (1 + g)/sqrt(1 + g^2) times
  wider (up to 1.41 at 45 degrees) and refuse spheres that fit;
* the wrapped centres s - floor(s) are binned on a grid with at least the largest
  box width per cell, periodic in all three directions;
* two bodies are a potential pair when their boxes overlap for the nearest image,
  |d - round(d)| <= hw1 + hw2 on every axis with d = s1 - s2 (wrapped).

A body wider than half the cell along an axis could meet a partner through two
images, of which only the nearest is kept. YADE 2023.02a's rule (measured:
tests/reference/yade/periodic_span.py) is followed: a pair of potential partners
i < j is refused when body j spans over half the cell along an axis of the cell's
frame (2 hw_k > 1/2), or body i over 0.99 of it (YADE aborts there); a lone wide body,
or the smaller id of a pair, is accepted. ``allowBiggerThanPeriod`` lifts the rule:
then every pair is taken through its nearest image. (YADE widens a sphere's box in a
sheared cell a little more than its exact extent, 1 + g^2/2 against sqrt(1 + g^2) for
a shear g, so near the limit YADE may refuse a sphere that granum accepts.)
"""

from __future__ import annotations

import math

import numpy as np

from granum._jit import BLOCK, PARALLEL_THRESHOLD, jit, kernel, prange
from granum.core.records import borrow
from granum.core.shapes import ShapeKind
from granum.kernels.pairing import may_collide, scratch_width
from granum.kernels.schedule import block_queue, next_block, queue_workers
from granum.kernels.sorting import argsort_keys
from granum.physics.vec import inv3

#: the widest span along an axis, in cells, of the body of larger id of a pair (YADE's check)
HALF_CELL = 0.5
#: the widest span of the body of smaller id (YADE 2023.02a asserts below 0.99 of the cell)
WHOLE_CELL = 0.99
_SPHERE = int(ShapeKind.SPHERE)


@jit
def fractional_boxes(S, nb):
    """Centres (wrapped) ``s``, their cell offsets ``p`` and half-widths ``hw`` in fractional coordinates,
    (nb, 3) each; ``hw`` is -1 for a body without a bound."""
    hinv = inv3(S.cell_hsize)
    row_norm = np.zeros(3)  # |row k of H^-1|: the fractional half-width of a ball of unit radius
    for k in range(3):
        row_norm[k] = math.sqrt(hinv[k, 0] ** 2 + hinv[k, 1] ** 2 + hinv[k, 2] ** 2)
    s = np.zeros((nb, 3))
    p = np.zeros((nb, 3), np.int64)
    hw = np.full((nb, 3), -1.0)
    for i in range(nb):
        if not S.bound_min[i, 0] <= S.bound_max[i, 0]:
            continue
        ball = 0.0  # the radius of a sphere's bound (a cube around the ball) [m]; 0: not a sphere
        if S.shape_kind[i] == _SPHERE:
            for j in range(3):
                ball = max(ball, 0.5 * (S.bound_max[i, j] - S.bound_min[i, j]))
        for k in range(3):
            acc = 0.0
            half = 0.0
            for j in range(3):
                c = 0.5 * (S.bound_min[i, j] + S.bound_max[i, j])
                acc += hinv[k, j] * c
                half += abs(hinv[k, j]) * 0.5 * (S.bound_max[i, j] - S.bound_min[i, j])
            fl = math.floor(acc)
            s[i, k] = acc - fl
            p[i, k] = int(fl)
            hw[i, k] = ball * row_norm[k] if ball > 0.0 else half
    return s, p, hw


@jit
def too_wide_pair(pairs, hw):
    """``(body, axis)`` of the first pair (in order) that YADE refuses (see the module docstring), or
    ``(-1, -1)``."""
    for n in range(pairs.shape[0]):
        for a in range(3):
            if 2.0 * hw[pairs[n, 1], a] > HALF_CELL:
                return pairs[n, 1], a
            if 2.0 * hw[pairs[n, 0], a] > WHOLE_CELL:
                return pairs[n, 0], a
    return -1, -1


@jit(inline="always")  # once per body, in its two passes: no call passing a dozen arrays
def partners_of(i, S, s, p, hw, cell, dims, order, start_cell, avoid_self, base, cap, ids, shifts):
    """Number of partners j > i of body ``i``; the first ``cap`` of them and their image shifts are written to
    ``ids[base:]`` and ``shifts[base:]`` (int32, (n,) and (n, 3)), sorted by j when all fit."""
    if hw[i, 0] < 0.0:
        return 0
    n = 0
    for dx in range(-1, 2):
        if dims[0] < 3 and dx < 0 or dims[0] == 1 and dx > 0:
            continue  # fewer than 3 cells: visit each distinct cell once
        cx = (cell[i, 0] + dx) % dims[0]
        for dy in range(-1, 2):
            if dims[1] < 3 and dy < 0 or dims[1] == 1 and dy > 0:
                continue
            cy = (cell[i, 1] + dy) % dims[1]
            for dz in range(-1, 2):
                if dims[2] < 3 and dz < 0 or dims[2] == 1 and dz > 0:
                    continue
                cz = (cell[i, 2] + dz) % dims[2]
                key = (cx * dims[1] + cy) * dims[2] + cz
                for t in range(start_cell[key], start_cell[key + 1]):
                    j = order[t]
                    if j <= i or not may_collide(S, i, j, avoid_self):
                        continue
                    hit = True
                    k0 = 0
                    k1 = 0
                    k2 = 0
                    for a in range(3):
                        d = s[i, a] - s[j, a]
                        img = round(d)
                        if abs(d - img) > hw[i, a] + hw[j, a]:
                            hit = False
                            break
                        if a == 0:
                            k0 = int(img) + p[i, 0] - p[j, 0]
                        elif a == 1:
                            k1 = int(img) + p[i, 1] - p[j, 1]
                        else:
                            k2 = int(img) + p[i, 2] - p[j, 2]
                    if hit:
                        if n < cap:
                            ids[base + n] = j
                            shifts[base + n, 0] = k0
                            shifts[base + n, 1] = k1
                            shifts[base + n, 2] = k2
                        n += 1
    if n <= cap:  # insertion sort by partner id (the shifts move with their ids)
        for u in range(base + 1, base + n):
            v = ids[u]
            c0 = shifts[u, 0]
            c1 = shifts[u, 1]
            c2 = shifts[u, 2]
            w = u - 1
            while w >= base and ids[w] > v:
                ids[w + 1] = ids[w]
                for a in range(3):
                    shifts[w + 1, a] = shifts[w, a]
                w -= 1
            ids[w + 1] = v
            shifts[w + 1, 0] = c0
            shifts[w + 1, 1] = c1
            shifts[w + 1, 2] = c2
    return n


@jit
def scratch_block(b, S, nb, s, p, hw, cell, dims, order, start_cell, avoid_self, count, width, ids, shifts):
    """First pass over the bodies of block ``b`` (borrowing the arrays: no reference counting per body): count
    each body's partners, keeping up to ``width`` of them, sorted, with their shifts, in its slots of ``ids``
    and ``shifts``."""
    s, p, hw, cell, dims, order, start_cell, count, ids, shifts = borrow(
        (s, p, hw, cell, dims, order, start_cell, count, ids, shifts))
    for i in range(b * BLOCK, min(nb, (b + 1) * BLOCK)):
        count[i] = partners_of(i, S, s, p, hw, cell, dims, order, start_cell, avoid_self, i * width, width, ids,
                               shifts)


def _scratch_pass(S, nb, s, p, hw, cell, dims, order, start_cell, avoid_self, count, width, ids, shifts):
    queue = block_queue((nb + BLOCK - 1) // BLOCK)
    for w in prange(queue_workers(queue)):
        b = next_block(queue, w, -1)
        while b >= 0:
            scratch_block(b, S, nb, s, p, hw, cell, dims, order, start_cell, avoid_self, count, width, ids, shifts)
            b = next_block(queue, w, b)


scratch_pass, scratch_pass_par = kernel(_scratch_pass, over="bodies")


@jit
def write_pass(S, nb, s, p, hw, cell, dims, order, start_cell, avoid_self, count, width, ids, shifts, start,
               out, out_cell):
    """Second pass, serial: each body's partners into its rows of ``out`` and ``out_cell``, copied from the
    first pass's slots, or searched again for a body with more than ``width``."""
    s, p, hw, cell, dims, order, start_cell, count, ids, shifts, start, out, out_cell = borrow(
        (s, p, hw, cell, dims, order, start_cell, count, ids, shifts, start, out, out_cell))
    for i in range(nb):
        n = count[i]
        row = start[i]
        if n <= width:
            first = i * width
            for t in range(n):
                out[row + t, 0] = i
                out[row + t, 1] = ids[first + t]
                for a in range(3):
                    out_cell[row + t, a] = shifts[first + t, a]
            continue
        more_ids = np.empty(n, np.int32)
        more_shifts = np.empty((n, 3), np.int32)
        partners_of(i, S, s, p, hw, cell, dims, order, start_cell, avoid_self, 0, n, more_ids, more_shifts)
        for t in range(n):
            out[row + t, 0] = i
            out[row + t, 1] = more_ids[t]
            for a in range(3):
                out_cell[row + t, a] = more_shifts[t, a]


@jit
def find_pairs_periodic(S, nb, avoid_self, allow_bigger, pairs_before):
    """Pairs (i < j) with overlapping boxes for the nearest image: ``(pairs, start, cells, too_large, axis)``.

    ``too_large`` is the id of a body too wide for a partner (:func:`too_wide_pair`; then the pairs are not
    valid) and ``axis`` the cell axis it is too wide along, else -1 and -1; ``allow_bigger``: YADE's
    ``allowBiggerThanPeriod``, no body is too wide; ``pairs_before``: the pair count of the last run (sizes the
    first pass, :func:`granum.kernels.pairing.scratch_width`).
    """
    s, p, hw = fractional_boxes(S, nb)
    width = np.zeros(3)
    for i in range(nb):
        for a in range(3):
            width[a] = max(width[a], 2.0 * hw[i, a])
    dims = np.ones(3, np.int64)
    for a in range(3):
        if width[a] > 0.0:
            dims[a] = max(1, min(int(1.0 / width[a]), 1 << 20))
    ncells = dims[0] * dims[1] * dims[2]
    cell = np.zeros((nb, 3), np.int64)
    keys = np.full(nb, ncells, np.int64)  # unbounded bodies sort last and are never visited
    for i in range(nb):
        if hw[i, 0] >= 0.0:
            for a in range(3):
                cell[i, a] = min(int(s[i, a] * dims[a]), dims[a] - 1)
            keys[i] = (cell[i, 0] * dims[1] + cell[i, 1]) * dims[2] + cell[i, 2]
    order = argsort_keys(keys).astype(np.int32)
    start_cell = np.zeros(ncells + 2, np.int64)
    for i in range(nb):
        start_cell[keys[i] + 1] += 1
    for k in range(ncells + 1):
        start_cell[k + 1] += start_cell[k]
    # one search per body, keeping its first partners; only bodies with more are searched again
    count = np.zeros(nb, np.int64)
    keep = scratch_width(pairs_before, nb)
    ids = np.empty(nb * keep, np.int32)
    shifts = np.empty((nb * keep, 3), np.int32)
    if nb >= PARALLEL_THRESHOLD:
        scratch_pass_par(S, nb, s, p, hw, cell, dims, order, start_cell, avoid_self, count, keep, ids, shifts)
    else:
        scratch_pass(S, nb, s, p, hw, cell, dims, order, start_cell, avoid_self, count, keep, ids, shifts)
    start = np.zeros(nb + 1, np.int64)
    for i in range(nb):
        start[i + 1] = start[i] + count[i]
    out = np.empty((start[nb], 2), np.int32)
    out_cell = np.empty((start[nb], 3), np.int32)
    write_pass(S, nb, s, p, hw, cell, dims, order, start_cell, avoid_self, count, keep, ids, shifts, start, out,
               out_cell)
    if not allow_bigger and max(width[0], width[1], width[2]) > HALF_CELL:
        body, axis = too_wide_pair(out, hw)
        return out, start, out_cell, body, axis
    return out, start, out_cell, -1, -1
