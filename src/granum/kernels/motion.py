"""The interaction loop's detection budgets: each body's motion since the collider ran, their bound, the
detection's origin, and the budgets a collider run carries over.

A potential pair without a contact holds a budget (``pair_gap``) and a reference motion (``pair_ref``): while
the relative motion of its two bodies measured from there stays below the budget they cannot touch, and the
detection (:func:`granum.kernels.interaction.detect_block`) does not evaluate their geometry. This module computes
the motions the budgets are compared with (:func:`body_motions`; the collider's trigger counts on the way the
bodies that left their bound, :func:`any_body_moved`), the bound of every pair's motion
(:func:`motion_bound`, :func:`quick_bound`), and moves the origin the motions are measured from to the present,
each budget measured again from there: within a step when many pairs have outgrown their budgets
(:func:`reorigin`), and when the collider runs because bodies moved, for the pairs it finds again
(:func:`carry_budgets`): the budgets then outlive the run instead of every pair being evaluated again.
"""

from __future__ import annotations

import math

import numpy as np

from granum._jit import BLOCK, PARALLEL_THRESHOLD, VECTOR_MIN_ITEMS, jit, kernel, prange
from granum.core.arrays import S_PAIR_REF_UNIT, S_TURN_ALLOWANCE, S_TURN_SEEN, S_VERLET, SI_PERIODIC
from granum.core.contacts import C_PAIRS
from granum.core.records import borrow, raw
from granum.kernels.bounds import (
    body_displacement,
    body_reach,
    left_bound,
    live_bounded_spheres,
    motion_length,
    sphere_shift,
)
from granum.kernels.schedule import block_queue, next_block, queue_workers
from granum.kernels.scratch import rows_of, take_f8


@jit(inline="always")  # per candidate pair: no call
def reference_length(pair_ref, p, unit):
    """|unit * pair_ref[p]| [m], computed alike wherever it is needed (the budget must not see another rounding)."""
    x = unit * float(pair_ref[p, 0])
    y = unit * float(pair_ref[p, 1])
    z = unit * float(pair_ref[p, 2])
    return math.sqrt(x * x + y * y + z * z)


#: 2**-23, the least positive float32 (2**-149) and the greatest (FLT_MAX): :func:`budget_f32`'s step down
F32_STEP = 1.1920928955078125e-07
F32_TINY = 1.401298464324817e-45
F32_MAX = 3.4028234663852886e38


@jit(inline="always")  # per evaluated pair: no call
def budget_f32(x):
    """``x`` rounded down to float32, the type of ``pair_gap`` (a budget may be smaller than the true
    one, never larger: a pair that could touch is always evaluated). When rounding to nearest went up, the value
    rounded is y = x - 2**-23 |x| - 2**-149 (FLT_MAX at most: above it float32 is +inf), whose rounding (at most
    2**-24 |y| + 2**-150 away) stays below x: at most three float32 steps below x. ``np.nextafter`` would give the
    step just below, but through a call of the C library that kept the re-origin's loop over pairs scalar: 22 -> 9
    ns a pair, stand-alone."""
    g = np.float32(x)
    below = np.float32(min(x - abs(x) * F32_STEP - F32_TINY, F32_MAX))
    return below if g > x else g


#: columns of a block's row of ``spread`` (:func:`motion_block`): the least and the greatest displacement per axis, the
#: greatest rotation term, and (column :data:`SPREAD_LEFT`) how many of its bodies left their bound enlarged by the
#: Verlet distance
SPREAD = 8
SPREAD_LEFT = 7


@jit(shared=True)   # the collider's check and the interaction loop both call it: compiled once (granum._linking)
def motion_block(b, S, nb, motion, spread):
    """Rows of ``motion`` (nb, 4) for the bodies of block ``b``: displacement since the collider ran, less the
    detection's shift (``detect_shift``: zero until :func:`reorigin`), and rotation times reach
    (:func:`granum.kernels.bounds.body_displacement`); in ``spread[b]`` (:data:`SPREAD`,) the
    least and the greatest displacement per axis and the greatest rotation term of its live bodies
    (inf when one of them is not finite), and how many of its bodies left their bound enlarged by the Verlet
    distance (``scal[S_VERLET]``: the collider's trigger, :func:`any_body_moved`)."""
    lo, hi = b * BLOCK, min(nb, (b + 1) * BLOCK)
    verlet = S.scal[S_VERLET]
    if hi - lo >= VECTOR_MIN_ITEMS and live_bounded_spheres(lo, hi, S.alive, S.shape_kind, S.bound_min, S.bound_max):
        sphere_motions(lo, hi, S.pos, S.bound_pos, S.detect_shift, verlet, motion, spread[b])
        return
    lo_x = lo_y = lo_z = math.inf  # scalars, not lists: a list would live on the heap
    hi_x = hi_y = hi_z = -math.inf
    w_max = 0.0
    left = 0
    alive, shift = S.alive, S.detect_shift
    for i in range(lo, hi):
        dx, dy, dz, w = body_displacement(i, S)
        left += left_bound(motion_length(dx, dy, dz, w), verlet)
        dx, dy, dz = dx - shift[i, 0], dy - shift[i, 1], dz - shift[i, 2]
        motion[i, 0] = dx
        motion[i, 1] = dy
        motion[i, 2] = dz
        motion[i, 3] = w
        if alive[i]:
            lo_x, lo_y, lo_z = min(lo_x, dx), min(lo_y, dy), min(lo_z, dz)
            hi_x, hi_y, hi_z = max(hi_x, dx), max(hi_y, dy), max(hi_z, dz)
            # w >= 0; NaN anywhere makes the sum fail the test: no bound
            w_max = max(w_max, w) if abs(dx) + abs(dy) + abs(dz) + w < math.inf else math.inf
    spread[b, 0], spread[b, 1], spread[b, 2] = lo_x, lo_y, lo_z
    spread[b, 3], spread[b, 4], spread[b, 5] = hi_x, hi_y, hi_z
    spread[b, 6] = w_max
    spread[b, SPREAD_LEFT] = left


@jit
def sphere_motions(lo, hi, pos, bound_pos, shift, verlet, motion, spread):
    """:func:`motion_block` for the bodies lo..hi-1, all :func:`live_bounded_spheres` (no rotation term): the same
    rows of ``motion`` and the same ``spread`` (:data:`SPREAD`,), from loops over flat views without a branch:
    what the per-body path branches on (shape, life, bound) is tested once for the block (the falling ball's 4,428
    bodies: 23.5 -> 19-20 us, measured before the count was added). ``verlet`` [m]: the Verlet distance of the
    bounds."""
    n = hi - lo
    p, q, m = pos[lo:hi].reshape(3 * n), bound_pos[lo:hi].reshape(3 * n), motion[lo:hi].reshape(4 * n)
    s = shift[lo:hi].reshape(3 * n)
    left = 0
    for i in range(n):
        dx, dy, dz = sphere_shift(i, p, q)
        left += left_bound(motion_length(dx, dy, dz, 0.0), verlet)   # no rotation term
        m[4 * i] = dx - s[3 * i]
        m[4 * i + 1] = dy - s[3 * i + 1]
        m[4 * i + 2] = dz - s[3 * i + 2]
        m[4 * i + 3] = 0.0
    lo_x = lo_y = lo_z = math.inf
    hi_x = hi_y = hi_z = -math.inf
    finite = 0
    for i in range(n):
        dx, dy, dz = m[4 * i], m[4 * i + 1], m[4 * i + 2]
        lo_x, lo_y, lo_z = min(lo_x, dx), min(lo_y, dy), min(lo_z, dz)
        hi_x, hi_y, hi_z = max(hi_x, dx), max(hi_y, dy), max(hi_z, dz)
        finite += abs(dx) + abs(dy) + abs(dz) < math.inf
    spread[0], spread[1], spread[2] = lo_x, lo_y, lo_z
    spread[3], spread[4], spread[5] = hi_x, hi_y, hi_z
    spread[6] = 0.0 if finite == n else math.inf   # NaN or inf somewhere: no bound (as motion_block)
    spread[SPREAD_LEFT] = left


def _body_motions(S, nb, motion, spread):
    queue = block_queue(spread.shape[0])
    for w in prange(queue_workers(queue)):
        b = next_block(queue, w, -1)
        while b >= 0:
            motion_block(b, S, nb, motion, spread)
            b = next_block(queue, w, b)


body_motions, body_motions_par = kernel(_body_motions, over="bodies")


@jit(inline="always")  # a few instructions: no call
def take_motions(w, nb):
    """The pieces :func:`body_motions` fills, from the start of the work area ``w`` (:mod:`granum.kernels.scratch`):
    ``(motion, spread, at)``, ``motion`` (nb, 4), ``spread`` (blocks of bodies, :data:`SPREAD`), ``at`` the word
    after them. At the start, so that the interaction loop finds there what the collider's check left
    (:func:`any_body_moved`)."""
    nblocks = (nb + BLOCK - 1) // BLOCK
    motion, at = take_f8(w, 0, nb * 4)
    spread, at = take_f8(w, at, nblocks * SPREAD)
    return rows_of(motion, 4), rows_of(spread, SPREAD), at


@jit(inline="always")  # a few instructions: no call
def motion_words(nb):
    """Work-area words of :func:`take_motions`' pieces for ``nb`` bodies."""
    return nb * 4 + (nb + BLOCK - 1) // BLOCK * SPREAD


@jit
def any_body_moved(S, nb, motion, spread):
    """Whether some body left its Verlet-enlarged bound since the collider last ran (the collider's trigger), from
    :func:`body_motions`, which fills ``motion`` and ``spread`` (:func:`take_motions`) on the way: the
    interaction loop right after the collider reads them instead of computing them again
    (``C_MOTIONS_STAGE``). ``S``: a raw view of the scene."""
    if nb < PARALLEL_THRESHOLD:
        body_motions(S, nb, motion, spread)
    else:
        body_motions_par(S, nb, motion, spread)
    for b in range(spread.shape[0]):
        if spread[b, SPREAD_LEFT] > 0.0:
            return True
    return False


@jit
def motion_bound(S, spread):
    """Upper bounds [m] of the relative motion of any two bodies (see
    :func:`granum.kernels.interaction.detect_block`), from the blocks' ``spread`` (:func:`motion_block`): (E, W)
    with |d_a - d_b| <= E and w_a + w_b <= W. Every displacement lies in the box [lo, hi], so
    |d_a - d_b| <= |hi - lo|, and w_a + w_b <= 2 max w. Bodies that move together (a packing at rest, a rigidly
    falling cluster without walls) give a small bound. E is infinite while a periodic cell has changed since the
    collider ran (the images then move with the cell)."""
    if S.iscal[SI_PERIODIC] != 0:
        for i in range(3):
            for j in range(3):
                if S.cell_hsize[i, j] != S.cell_bound_hsize[i, j]:
                    return math.inf, 0.0
    lo_x = lo_y = lo_z = math.inf  # scalars, not arrays: an array would live on the heap
    hi_x = hi_y = hi_z = -math.inf
    w_max = 0.0
    for b in range(spread.shape[0]):
        lo_x, lo_y, lo_z = min(lo_x, spread[b, 0]), min(lo_y, spread[b, 1]), min(lo_z, spread[b, 2])
        hi_x, hi_y, hi_z = max(hi_x, spread[b, 3]), max(hi_y, spread[b, 4]), max(hi_z, spread[b, 5])
        w_max = max(w_max, spread[b, 6])
    if w_max == math.inf:  # a displacement is not finite (min and max pass over NaN: look here first)
        return math.inf, math.inf
    if lo_x > hi_x:  # no live body
        return 0.0, 0.0
    extent = math.sqrt((hi_x - lo_x) ** 2 + (hi_y - lo_y) ** 2 + (hi_z - lo_z) ** 2)
    return extent, 2.0 * w_max


#: The detection moves its origin (:func:`reorigin`) when more than one potential pair in REORIGIN_ONE_IN (contacts
#: included) was tested one by one and passed in a step: the box of the displacements since the collider ran has
#: outgrown their budgets.
REORIGIN_ONE_IN = 4


@jit(shared=True)   # the collider and the interaction loop both call it: compiled once (granum._linking)
def reorigin_pair_block(b, S, C, motion):
    """:func:`reorigin` for the pairs of block ``b``: each pair with a finite budget g and reference ``unit ref``
    gets the budget g' = g + |unit ref| - |D - unit ref| (less a rounding allowance) and a zero reference, D the
    relative displacement of its bodies now (``motion``). Before, the pair could not touch while
    |D(t) - unit ref| + turns < g + |unit ref|; since |D(t) - unit ref| <= |D(t) - D| + |D - unit ref|, it cannot
    while |D(t) - D| + turns < g', which is the same condition measured from D: the displacement from the new
    origin. A pair with an infinite budget (a contact, shapes that never interact: +inf; evaluated at the next
    step: -inf) keeps it."""
    unit = S.scal[S_PAIR_REF_UNIT]
    motion, pair_ids, pair_gap, pair_ref = borrow((motion, C.pair_ids, C.pair_gap, C.pair_ref))
    for p in range(b * BLOCK, min(C.ctr[C_PAIRS], (b + 1) * BLOCK)):
        g = float(pair_gap[p])
        if not abs(g) < math.inf:
            continue
        i = pair_ids[p, 0]
        j = pair_ids[p, 1]
        ex = motion[i, 0] - motion[j, 0] - unit * float(pair_ref[p, 0])   # as detect_block's test computes it
        ey = motion[i, 1] - motion[j, 1] - unit * float(pair_ref[p, 1])
        ez = motion[i, 2] - motion[j, 2] - unit * float(pair_ref[p, 2])
        offset = math.sqrt(ex * ex + ey * ey + ez * ez)
        reach = reference_length(pair_ref, p, unit)
        # the rounding of these sums, and of the motions measured from the new origin (a few ulps of the motions)
        moved = (abs(motion[i, 0]) + abs(motion[i, 1]) + abs(motion[i, 2]) + abs(motion[j, 0]) + abs(motion[j, 1])
                 + abs(motion[j, 2]))
        pair_gap[p] = budget_f32(g + reach - offset - 1e-12 * (abs(g) + reach + offset) - 1e-15 * moved)
        for k in range(3):
            pair_ref[p, k] = 0


def _reorigin_pairs(S, C, motion):
    queue = block_queue((C.ctr[C_PAIRS] + BLOCK - 1) // BLOCK)
    for w in prange(queue_workers(queue)):
        b = next_block(queue, w, -1)
        while b >= 0:
            reorigin_pair_block(b, S, C, motion)
            b = next_block(queue, w, b)


reorigin_pairs, reorigin_pairs_par = kernel(_reorigin_pairs, over="pairs")


@jit
def shift_block(b, S, nb):
    """The detection's shift of the bodies of block ``b``: their displacement since their bound now, so that their
    motion measured from it is zero (:func:`reorigin`)."""
    shift = S.detect_shift
    for i in range(b * BLOCK, min(nb, (b + 1) * BLOCK)):
        dx, dy, dz, _ = body_displacement(i, S)   # the rotation terms keep their reference (bound_ori)
        shift[i, 0] = dx
        shift[i, 1] = dy
        shift[i, 2] = dz


def _shift_bodies(S, nb):
    queue = block_queue((nb + BLOCK - 1) // BLOCK)
    for w in prange(queue_workers(queue)):
        b = next_block(queue, w, -1)
        while b >= 0:
            shift_block(b, S, nb)
            b = next_block(queue, w, b)


shift_bodies, shift_bodies_par = kernel(_shift_bodies, over="bodies")


@jit
def reorigin(S, C, nb, motion):
    """Move the detection's origin to the bodies' positions now (aperiodic scenes): every pair's budget measured
    from its bodies' present relative displacement (:func:`reorigin_pair_block`), every body's motion from its
    present position (``detect_shift``). When the box of the displacements since the collider ran has outgrown
    the budgets of many pairs, each such pair is listed and tested one by one at every step until the collider
    runs again (a falling ball after its impact: half of its 44,000 pairs, at about 7 ns each, in a third of the
    steps); measured from here, the box is small again. Fewer pairs are tested, but every pair that may touch
    still is, so each step finds the same touching pairs and the results do not change. The budgets now follow
    the path of the motion (each re-origin spends a pair's offset from its reference): in a flow whose one step
    outgrows a quarter of the budgets it would run at every step, which costs speed, not results.
    ``S``, ``C``: raw views; ``motion``: this step's."""
    if C.ctr[C_PAIRS] < PARALLEL_THRESHOLD:
        reorigin_pairs(S, C, motion)
    else:
        reorigin_pairs_par(S, C, motion)
    if nb < PARALLEL_THRESHOLD:
        shift_bodies(S, nb)
    else:
        shift_bodies_par(S, nb)


@jit
def quick_bound(S, extent, turn):
    """``bound`` of :func:`granum.kernels.interaction.detect_block` [m] from :func:`motion_bound`'s (E, W):
    E + max(0, W - T), T the allowance set aside in turning pairs' budgets; W is kept in ``scal[S_TURN_SEEN]`` for
    the collider's next allowance."""
    S.scal[S_TURN_SEEN] = max(S.scal[S_TURN_SEEN], turn)
    return (extent + max(0.0, turn - S.scal[S_TURN_ALLOWANCE])) * (1.0 + 1e-12)  # above the rounding of the sum


@jit
def budgets_from_now(S, C, motion):
    """Every pair's budget measured from its bodies' present relative displacement, with a zero reference
    (:func:`reorigin_pair_block`): what the collider calls before it bounds the bodies again where they are now
    (aperiodic scenes, a run because bodies moved), for :func:`carry_budgets`. ``motion``: the bodies' motions
    its check (:func:`any_body_moved`) has just computed. ``S``: a raw view, ``C``: the contacts' record."""
    V = raw(C)
    if V.ctr[C_PAIRS] < PARALLEL_THRESHOLD:
        reorigin_pairs(S, V, motion)
    else:
        reorigin_pairs_par(S, V, motion)


@jit
def carry_block(b, S, old_ids, nold, old_gap, pairs, gap):
    """:func:`carry_budgets` for the new pairs of block ``b``."""
    old_ids, old_gap, pairs, gap = borrow((old_ids, old_gap, pairs, gap))
    lo = b * BLOCK
    hi = min(pairs.shape[0], lo + BLOCK)
    # the first old pair not before the block's first new pair (both lists in (id1, id2) order): then one walk
    i, j = pairs[lo, 0], pairs[lo, 1]
    q, top = 0, nold
    while q < top:
        mid = (q + top) // 2
        if old_ids[mid, 0] < i or (old_ids[mid, 0] == i and old_ids[mid, 1] < j):
            q = mid + 1
        else:
            top = mid
    for p in range(lo, hi):
        i, j = pairs[p, 0], pairs[p, 1]
        while q < nold and (old_ids[q, 0] < i or (old_ids[q, 0] == i and old_ids[q, 1] < j)):
            q += 1
        if q < nold and old_ids[q, 0] == i and old_ids[q, 1] == j and body_reach(i, S) == 0.0 \
                and body_reach(j, S) == 0.0:
            gap[p] = old_gap[q]


def _carry_budgets(S, old_ids, nold, old_gap, pairs, gap):
    queue = block_queue((pairs.shape[0] + BLOCK - 1) // BLOCK)
    for w in prange(queue_workers(queue)):
        b = next_block(queue, w, -1)
        while b >= 0:
            carry_block(b, S, old_ids, nold, old_gap, pairs, gap)
            b = next_block(queue, w, b)


#: ``carry_budgets(S, old_ids, nold, old_gap, pairs, gap)``: the budgets ``gap`` (P,) float32 of the collider's new
#: pairs ``pairs`` (P, 2), which the old list of ``nold`` pairs ``old_ids`` had, with their budgets ``old_gap``
#: measured from the present (:func:`budgets_from_now`): the bounds of the run are taken where the bodies are now,
#: the origin of the new motions, so such a budget holds as it is. Pairs of a body whose shape has a reach
#: (``body_reach`` > 0: a facet, a box, a clump, which may turn) keep what ``gap`` held (the caller's -inf: evaluated at
#: the next detection): the run also moves the orientations their rotation terms are measured from.
#: Both lists are sorted by (id1, id2). The pairs found again keep their budgets and are not evaluated all at once
#: after the run (the falling ball's 43,725 pairs at each of its runs after the first).
carry_budgets, carry_budgets_par = kernel(_carry_budgets, over="pairs")
