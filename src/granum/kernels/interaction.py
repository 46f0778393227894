"""InteractionLoop stage: contact detection, geometry, physics, laws and force gather.

Each step:

1. Every potential pair without a contact asks its geometry function whether the
   two bodies touch (parallel, read-only).
2. Touching pairs become contacts, appended to the pool in pair order (serial, so
   the pool order is deterministic). The geometry, physics and law functors are
   resolved here from the dispatch tables; a missing combination stops the run
   with a status naming the two bodies.
3. Every contact updates its geometry, gets its physics constants if new, and runs
   its law (parallel over contacts, each writing only its own row).
4. Contacts ended by their law are unlinked from their pair by the block that updated
   them; the per-body contact index (CSR) is marked stale when the contact set changed (its next reader
   rebuilds it: the gather below, the stages that read a body's contacts, :func:`index_contacts`).
5. Forces and torques are gathered per body through the CSR index, in increasing
   contact order: the sums are the same whatever the number of threads. Where the
   stage updates the contacts on one thread (one thread in all, or fewer contacts than
   PARALLEL_THRESHOLD_CONTACTS), it adds each contact's force and torque to its bodies
   as it goes instead: the same terms in the same order, one pass less. The pool is
   compacted after that.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from granum._jit import (
    BLOCK,
    PARALLEL_THRESHOLD,
    PARALLEL_THRESHOLD_CONTACTS,
    jit,
    kernel,
    overload,
    prange,
)
from granum.core.arrays import (
    E_ELAST_POT,
    E_PLAST_DISSIP,
    S_PAIR_REF_UNIT,
    S_TURN_ALLOWANCE,
    SI_ITER,
    SI_NBODIES,
    SI_PERIODIC,
    SI_TRACK_ENERGY,
)
from granum.core.contacts import (
    C_CONTACTS,
    C_CSR_DIRTY,
    C_DEAD,
    C_ERR_A,
    C_ERR_B,
    C_MOTIONS_STAGE,
    C_PAIRS,
    C_REPLACED,
    C_STAGE,
    C_STATUS,
    F_E_DISSIP,
    F_E_ELAST,
    F_FN,
    F_FS,
    F_MOMENT,
    F_NORMAL,
    F_PEN,
    F_POINT,
    F_R1,
    F_R2,
    FLAG_ALIVE,
    FLAG_NEW,
    FLAG_PHYS_AGAIN,
    FLAG_RADIAL_ARMS,
    I_BORN,
    I_CELL,
    I_FLAGS,
    I_GEOM,
    I_ID1,
    I_ID2,
    I_LAW,
    I_PAIR,
    I_PHYS,
    STATUS_NO_GEOM,
    STATUS_NO_LAW,
    STATUS_NO_PHYS,
)
from granum.core.records import borrow, raw
from granum.kernels.bounds import body_reach
from granum.kernels.copy import copy_rows
from granum.kernels.dispatch import functors, geom_call, law_call, phys_call
from granum.kernels.motion import (
    REORIGIN_ONE_IN,
    body_motions,
    body_motions_par,
    budget_f32,
    motion_bound,
    motion_words,
    quick_bound,
    reference_length,
    reorigin,
    take_motions,
)
from granum.kernels.prefetch import prefetch_row
from granum.kernels.schedule import block_queue, next_block, queue_workers, thread_count
from granum.kernels.scratch import area, rows_of, take_f8, take_i4, take_i8, words_i4
from granum.kernels.sorting import argsort_keys
from granum.kernels.static import static_value
from granum.physics.scgeom import contact_shift, scgeom_incident_vel
from granum.physics.vec import add, cross, inv3, load3, matvec, scale, sub

#: how many bodies ahead the force gather prefetches contact rows (4-16 measured alike at 1e5 spheres)
GATHER_AHEAD = 4
#: contact pools from this size [bytes of con_f] on are prefetched by the gather (larger than the caches)
GATHER_PREFETCH_BYTES = 16 << 20

FLAG_PHYS_SWAP = 8   # the physics functor is declared for (material 2, material 1)
HIT_TOUCH = 1        # pair_hit: the pair touches and becomes a contact
HIT_NO_FUNCTOR = 2   # pair_hit: a geometry functor exists for the shapes but is not listed


@jit(inline="always")  # per evaluated pair: no call
def pair_shift(S, C, p):
    """Offset H k of the second body's periodic image for pair ``p`` (zero if aperiodic)."""
    if S.iscal[SI_PERIODIC] == 0:
        return (0.0, 0.0, 0.0)
    k = (float(C.pair_cell[p, 0]), float(C.pair_cell[p, 1]), float(C.pair_cell[p, 2]))
    return matvec(S.cell_hsize, k)


@jit
def detect_pair(p, S, C, geom_code, geom_swap, geom_tab, pair_ok, rel, turn):
    """Evaluate potential pair ``p`` (no contact, budget used up): the ``HIT_*`` outcome; when the bodies do
    not touch, the pair's new budget and reference motion (see :func:`detect_block`). ``rel``: the relative
    displacement d_a - d_b of its bodies since the collider ran [m], ``turn``: w_a + w_b [m]."""
    a = C.pair_ids[p, 0]
    b = C.pair_ids[p, 1]
    ka = S.shape_kind[a]
    kb = S.shape_kind[b]
    code = geom_code[ka, kb]
    if code < 0:
        if pair_ok[ka, kb] == 2:
            return HIT_NO_FUNCTOR
        C.pair_gap[p] = math.inf  # shapes that never interact
        return 0
    shift = pair_shift(S, C, p)
    if geom_swap[ka, kb]:  # the functor's body 2 is the pair's first body: opposite image
        a, b, shift = b, a, scale(shift, -1.0)
    sep = geom_call(code, -1, a, b, shift, S, C, geom_tab)  # one call site: the functors are inlined
    if sep <= 0.0:
        return HIT_TOUCH
    unit = S.scal[S_PAIR_REF_UNIT]
    per_unit = 1.0 / unit
    err2 = 0.0
    for k in range(3):  # a near representable reference (int16 units), its rounding error taken from the budget
        q = min(max(round(rel[k] * per_unit), -32767.0), 32767.0)
        C.pair_ref[p, k] = np.int16(q)
        err2 += (rel[k] - q * unit) ** 2
    budget = sep - turn - math.sqrt(err2) - reference_length(C.pair_ref, p, unit)
    if body_reach(a, S) > 0.0 or body_reach(b, S) > 0.0:  # a turning pair: the allowance is set aside
        budget -= S.scal[S_TURN_ALLOWANCE]
    C.pair_gap[p] = budget_f32(budget)
    return 0


@jit
def budgets_exceeded(lo, hi, pair_gap, bound):
    """Whether a pair lo..hi-1 has a budget ``pair_gap`` not above ``bound`` [m] (:func:`detect_block`'s quick
    test): a count over a view from 0, which LLVM vectorizes, read before listing the pairs one by one."""
    gaps = pair_gap[lo:hi]
    count = 0
    for t in range(hi - lo):
        count += not gaps[t] > bound
    return count > 0


@jit
def detect_block(b, S, C, geom_code, geom_swap, geom_tab, pair_ok, motion, bound, hits, candidates):
    """Which pairs of block ``b`` without a contact touch now: ``pair_hit``; ``hits[b]`` (3,): how many, the
    first of them, and how many pairs were tested one by one and passed (what
    :func:`granum.kernels.motion.reorigin` would spare). ``candidates`` (BLOCK,) int32: the worker's scratch list
    of the pairs to test.

    The geometry of a pair is evaluated only when the relative motion of its two bodies since
    its last evaluation reaches what the separation then found allows. With d_a, d_b the
    displacements of the bodies' centres since the collider ran (less the detection's shift, zero until
    :func:`granum.kernels.motion.reorigin` moves the origin) and w_a, w_b their rotations
    times their reach (``motion``, see :func:`granum.kernels.motion.body_motions`), D = d_a - d_b: any point of
    body a moved relative to body b by at most |D(t) - D(t0)| + w_a(t) + w_b(t) + w_a(t0) + w_b(t0)
    between t0 and t (rotations measured from the same reference orientations add). An
    evaluation at t0 finding a separation s > 0 stores D(t0), rounded to int16 units
    (``pair_ref``, ``unit * ref``), and the budget g = s - w_a(t0) - w_b(t0) - |D(t0) - unit ref|
    - |unit ref| (``pair_gap``). The pair cannot touch while
    |D(t) - unit ref| + w_a(t) + w_b(t) < g + |unit ref|. A pair whose bodies slide past each
    other is evaluated once per separation's worth of relative motion, however far they moved
    before. In a periodic cell body b's image sits at x_b + H k, so d_b also holds H k - H0 k,
    H0 the cell when the collider ran (``cell_bound_hsize``): still the exact displacement of
    the image.

    Bodies whose shape has no reach (spheres) never turn (w = 0): a pair of two such bodies needs only
    the translations bounded, while a turning pair (a facet, a box, a clump) needs the rotations too.
    So the budget of a turning pair is stored less the allowance T (``scal[S_TURN_ALLOWANCE]``, fixed
    between collider runs: the largest 2 max w of the previous interval), and ``bound`` [m] is
    E + max(0, 2 max w - T), E bounding |D(t)| over all pairs (:func:`granum.kernels.motion.motion_bound`).
    Since |D(t) - unit ref| <= |D(t)| + |unit ref|, a pair whose stored budget exceeds ``bound`` cannot touch
    and is passed over without reading more (+inf when it has a contact): in a quasi-static packing
    the pass reads 4 bytes per pair (the budget). In a drum the rotating facets no longer widen the bound of the
    sphere pairs. The per-pair test gives T back to a pair whose bodies turn now (w_a + w_b > 0: it is
    a turning pair); a turning pair whose bodies have not turned yet is tested without it (smaller,
    still safe). The arrays are read into locals (borrowed: no reference counting per pair).

    When E has outgrown the budgets of many pairs, they are listed and pass the per-pair test at every step until
    the collider runs again: the stage then moves the origin of D to the present
    (:func:`granum.kernels.motion.reorigin`). A collider run because bodies moved does the same for the pairs it
    finds again (:func:`granum.kernels.motion.carry_budgets`): only its new pairs, and those of turning bodies, are
    evaluated at the next step.
    """
    motion, hits, candidates, pair_con, pair_ids, pair_gap, pair_hit, pair_ref = borrow(
        (motion, hits, candidates, C.pair_con, C.pair_ids, C.pair_gap, C.pair_hit, C.pair_ref))
    geom_code, geom_swap, geom_tab, pair_ok = borrow((geom_code, geom_swap, geom_tab, pair_ok))
    periodic = S.iscal[SI_PERIODIC] != 0
    unit = S.scal[S_PAIR_REF_UNIT]
    allowance = S.scal[S_TURN_ALLOWANCE]
    pair_cell = borrow(C.pair_cell)
    found = 0
    first = 0
    # the pairs to test listed first, without a branch: which pass the quick test is as good as random, and
    # a mispredicted branch per pair cost more than the listing. A pair with a contact has an infinite budget,
    # above any finite bound: only an infinite bound needs pair_con read (pair_hit is zero here: see
    # create_contacts)
    listed = passed = 0
    end = min(C.ctr[C_PAIRS], (b + 1) * BLOCK)
    if bound < math.inf:
        if budgets_exceeded(b * BLOCK, end, pair_gap, bound):   # else nothing to test in the block (often)
            for p in range(b * BLOCK, end):
                candidates[listed] = p
                listed += not pair_gap[p] > bound
    else:
        for p in range(b * BLOCK, end):
            candidates[listed] = p
            listed += pair_con[p] < 0
    for t in range(listed):
        p = candidates[t]
        i = pair_ids[p, 0]
        j = pair_ids[p, 1]
        dx = motion[i, 0] - motion[j, 0]
        dy = motion[i, 1] - motion[j, 1]
        dz = motion[i, 2] - motion[j, 2]
        if periodic and (pair_cell[p, 0] != 0 or pair_cell[p, 1] != 0 or pair_cell[p, 2] != 0):
            k = load3_row(pair_cell, p, 0)
            img = sub(matvec(S.cell_hsize, k), matvec(S.cell_bound_hsize, k))  # the image's move with the cell
            dx -= img[0]
            dy -= img[1]
            dz -= img[2]
        ex = dx - unit * float(pair_ref[p, 0])
        ey = dy - unit * float(pair_ref[p, 1])
        ez = dz - unit * float(pair_ref[p, 2])
        turn = motion[i, 3] + motion[j, 3]
        slack = pair_gap[p] + reference_length(pair_ref, p, unit) - turn
        if turn > 0.0:
            slack += allowance
        # |D - unit ref| < slack, compared squared: no square root per pair
        if slack > 0.0 and ex * ex + ey * ey + ez * ez < slack * slack:
            passed += 1
        else:
            hit = detect_pair(p, S, C, geom_code, geom_swap, geom_tab, pair_ok, (dx, dy, dz), turn)
            if hit != 0:
                pair_hit[p] = hit
                if found == 0:
                    first = p
                found += 1
    hits[b, 0] = found
    hits[b, 1] = first
    hits[b, 2] = passed


def _detect(S, C, geom_code, geom_swap, geom_tab, pair_ok, motion, bound, hits, lists):
    """``lists`` (workers, BLOCK) int32: a scratch list of candidates per worker (a row per thread at least)."""
    queue = block_queue(hits.shape[0])
    for w in prange(queue_workers(queue)):
        b = next_block(queue, w, -1)
        while b >= 0:
            detect_block(b, S, C, geom_code, geom_swap, geom_tab, pair_ok, motion, bound, hits, lists[w])
            b = next_block(queue, w, b)


detect, detect_par = kernel(_detect, over="pairs")


@jit
def grow_contacts(C, need):
    """Make room for at least ``need`` contacts (rows copied; the capacity grows by half at least, so that
    contacts appearing a few at a time are copied O(1) times each, and to ``need`` when more are asked)."""
    cap = max(need, C.con_i.shape[0] + C.con_i.shape[0] // 2, 64)
    con_i = np.zeros((cap, C.con_i.shape[1]), np.int32)
    con_f = np.zeros((cap, C.con_f.shape[1]), np.float64)
    n = C.ctr[C_CONTACTS]
    copy_rows(con_i, C.con_i, n)
    copy_rows(con_f, C.con_f, n)
    C.con_i = con_i
    C.con_f = con_f
    C.csr_con = np.zeros(2 * cap, np.int32)
    C.ctr[C_REPLACED] += 1


@jit
def widen_contacts(C, width):
    """Give ``con_f`` at least ``width`` columns (new ones zero: history starts empty), and ``ended`` as many."""
    if C.con_f.shape[1] < width:
        con_f = np.zeros((C.con_f.shape[0], width), np.float64)
        copy_rows(con_f, C.con_f, C.con_f.shape[0])
        C.con_f = con_f
        C.ctr[C_REPLACED] += 1
    if C.ended.shape[0] < width:
        ended = np.zeros(width, np.float64)
        for k in range(C.ended.shape[0]):
            ended[k] = C.ended[k]
        C.ended = ended
        C.ctr[C_REPLACED] += 1


@jit
def fail(C, status, a, b):
    C.ctr[C_STATUS] = status
    C.ctr[C_ERR_A] = a
    C.ctr[C_ERR_B] = b


@jit
def new_contact(S, C, a, b, p, geom_code, geom_swap, geom_type, phys_code, phys_swap, phys_type, law_code,
                need_law=True):
    """Append a contact between bodies a and b (pair p or -1) with its functors resolved, in a row the caller
    made room for.

    Returns the new row, or -1 with an error status when a functor is missing. Without ``need_law``
    (``utils.createInteraction``, which needs only geometry and physics, as in YADE) a missing law leaves
    the contact's law code -1: the first step that updates it stops with the "no Law2" status.
    """
    ka = S.shape_kind[a]
    kb = S.shape_kind[b]
    g = geom_code[ka, kb]
    if g < 0:
        fail(C, STATUS_NO_GEOM, a, b)
        return -1
    id1, id2 = (b, a) if geom_swap[ka, kb] else (a, b)
    m1 = S.mat_kind[S.material[id1]]
    m2 = S.mat_kind[S.material[id2]]
    ph = phys_code[m1, m2]
    if ph < 0:
        fail(C, STATUS_NO_PHYS, id1, id2)
        return -1
    law = law_code[geom_type[g], phys_type[ph]]
    if law < 0 and need_law:
        fail(C, STATUS_NO_LAW, id1, id2)
        return -1
    c = C.ctr[C_CONTACTS]  # the caller made room (C may be a raw view, whose arrays cannot be replaced)
    C.con_f[c, :] = 0.0
    C.con_i[c, I_ID1] = id1
    C.con_i[c, I_ID2] = id2
    C.con_i[c, I_PAIR] = p
    C.con_i[c, I_FLAGS] = FLAG_ALIVE | FLAG_NEW | (FLAG_PHYS_SWAP if phys_swap[m1, m2] else 0)
    C.con_i[c, I_GEOM] = g
    C.con_i[c, I_PHYS] = ph
    C.con_i[c, I_LAW] = law
    if C.con_i.shape[1] > I_CELL:  # periodic scene
        if p >= 0 and C.pair_cell.shape[0] > 0:
            sign = -1 if id1 == b else 1
            for k in range(3):
                C.con_i[c, I_CELL + k] = sign * C.pair_cell[p, k]
        else:   # no pair (createInteraction): body 2's image nearest to body 1, k = round(H^-1 (x1 - x2))
            hinv = inv3(S.cell_hsize)
            d = sub(load3(S.pos, id1), load3(S.pos, id2))
            for k in range(3):
                C.con_i[c, I_CELL + k] = round(hinv[k, 0] * d[0] + hinv[k, 1] * d[1] + hinv[k, 2] * d[2])
    C.con_i[c, I_BORN] = S.iscal[SI_ITER]
    if p >= 0:
        C.pair_con[p] = c
        C.pair_gap[p] = math.inf  # never detected while its contact lives (see detect_block)
    C.ctr[C_CONTACTS] = c + 1
    C.ctr[C_CSR_DIRTY] = 1
    return c


@jit
def create_contacts(S, C, geom_code, geom_swap, geom_type, phys_code, phys_swap, phys_type, law_code, hits, new):
    """Turn the ``new`` touching pairs into contacts, in pair order, visiting only the pairs of each block from
    the first in which the detection found something to the last (``hits``: count and first pair per block); the
    storage grows once, to what is needed."""
    if C.ctr[C_CONTACTS] + new > C.con_i.shape[0]:
        grow_contacts(C, C.ctr[C_CONTACTS] + new)
    # raw views and borrowed arrays from here on (the storage has grown): no reference counting per contact
    S = raw(S)
    C = raw(C)
    geom_code, geom_swap, geom_type, phys_code, phys_swap, phys_type, law_code = borrow(
        (geom_code, geom_swap, geom_type, phys_code, phys_swap, phys_type, law_code))
    for b in range(hits.shape[0]):
        left = hits[b, 0]
        p = hits[b, 1] - 1
        while left > 0:  # from the block's first hit to its last: a block often holds one or two
            p += 1
            hit = C.pair_hit[p]
            if hit == 0:
                continue
            C.pair_hit[p] = 0   # consumed: pair_hit is zero outside the interaction loop (see detect_block)
            left -= 1
            if hit == HIT_NO_FUNCTOR:
                fail(C, STATUS_NO_GEOM, C.pair_ids[p, 0], C.pair_ids[p, 1])
            elif new_contact(S, C, C.pair_ids[p, 0], C.pair_ids[p, 1], p, geom_code, geom_swap, geom_type,
                             phys_code, phys_swap, phys_type, law_code) >= 0:
                continue
            for q in range(C.ctr[C_PAIRS]):   # the step stops with the error: no hit may outlive it
                C.pair_hit[q] = 0
            return


class InteractionParams(NamedTuple):
    """Parameters of :func:`interaction_stage` and :func:`create_contact_now` (InteractionLoop): its dispatch
    tables (:meth:`granum.engines.pipeline.InteractionLoop.tables`) and functor tables
    (:func:`granum.engines.functors.functor_table`)."""

    geom_code: np.ndarray  #: Ig2 functor code per pair of shape kinds (-1: none), (NKINDS, NKINDS) int32
    geom_swap: np.ndarray  #: 1 where the functor takes the two bodies in the other order, (NKINDS, NKINDS) uint8
    geom_tab: tuple        #: the Ig2 functors' table
    geom_type: np.ndarray  #: IGeom type code each Ig2 functor produces, (geom functors,) int32
    phys_code: np.ndarray  #: Ip2 functor code per pair of material kinds (-1: none), (M kinds, M kinds) int32
    phys_swap: np.ndarray  #: 1 where the functor takes the two materials in the other order, uint8
    phys_tab: tuple        #: the Ip2 functors' table
    phys_type: np.ndarray  #: IPhys type code each Ip2 functor produces, (phys functors,) int32
    law_code: np.ndarray   #: Law2 functor code per (IGeom type, IPhys type) (-1: none), int32
    law_tab: tuple         #: the Law2 functors' table
    pair_ok: np.ndarray    #: Ig2 per pair of shape kinds: 1 listed, 2 only unlisted ones, 0 none; (NKINDS, NKINDS) int8
    width: int             #: ``con_f`` columns the functors use (and the energy columns while O.trackEnergy)
    #: per Law2 functor code, the running totals its contacts keep after ending (first ``con_f`` column, count;
    #: count 0: none; :func:`granum.core.contacts.register_totals`), (law functors, 2) int64
    law_totals: np.ndarray


@jit
def create_contact_now(S, C, a, b, P):
    """Make bodies a and b interact now, whatever their distance (``utils.createInteraction``); ``P``:
    :class:`InteractionParams`.

    The geometry and physics are computed immediately; the law acts from the next step.
    """
    geom_code, geom_swap, geom_tab, geom_type = P.geom_code, P.geom_swap, P.geom_tab, P.geom_type
    phys_code, phys_swap, phys_tab, phys_type = P.phys_code, P.phys_swap, P.phys_tab, P.phys_type
    law_code = P.law_code
    widen_contacts(C, P.width)
    lo = min(a, b)
    hi = max(a, b)
    p = -1
    for q in range(C.ctr[C_PAIRS]):
        if C.pair_ids[q, 0] == lo and C.pair_ids[q, 1] == hi:
            p = q
    if p >= 0 and C.pair_con[p] >= 0:
        return
    if C.ctr[C_CONTACTS] >= C.con_i.shape[0]:
        grow_contacts(C, C.ctr[C_CONTACTS] + 1)
    c = new_contact(S, C, lo, hi, p, geom_code, geom_swap, geom_type, phys_code, phys_swap, phys_type, law_code,
                    False)
    if c < 0:
        return
    id1, id2 = contact_geometry(c, S, C, geom_tab)
    contact_physics(c, id1, id2, S, C, phys_tab)


@jit(inline="always")  # once per contact: no call (see granum.kernels.dispatch)
def contact_geometry(c, S, C, geom_tab):
    """Current geometry of contact ``c``; returns its bodies ``(id1, id2)``."""
    id1 = C.con_i[c, I_ID1]
    id2 = C.con_i[c, I_ID2]
    shift, _ = contact_shift(c, S, C)
    geom_call(C.con_i[c, I_GEOM], c, id1, id2, shift, S, C, geom_tab)
    return id1, id2


@jit
def contact_physics(c, id1, id2, S, C, phys_tab):
    """IPhys of new contact ``c`` (once, in the functor's body order), or again for an existing one that asked
    for it (``FLAG_PHYS_AGAIN``: the functor sees FLAG_NEW clear); clears both flags.

    A call of its own (not inlined): it runs once per contact, and one call site types the dispatch once (measured
    when Numba also inlined the functors at every site)."""
    if C.con_i[c, I_FLAGS] & FLAG_PHYS_SWAP:
        id1, id2 = id2, id1
    phys_call(C.con_i[c, I_PHYS], c, id1, id2, S, C, phys_tab)
    C.con_i[c, I_FLAGS] &= ~(FLAG_NEW | FLAG_PHYS_AGAIN)


@jit(inline="always")  # once per contact: no call (see granum.kernels.dispatch)
def update_contact(c, S, C, geom_tab, phys_tab, law_tab, died):
    """Geometry, physics (new contacts) and law of contact ``c``; flags its block in ``died`` if it ends.
    Returns whether its law ran and kept the contact (what the force gather adds; False too when the step fails for
    want of a law, and the step's forces are then incomplete on every path)."""
    flags = C.con_i[c, I_FLAGS]
    if not flags & FLAG_ALIVE:
        return False
    id1, id2 = contact_geometry(c, S, C, geom_tab)
    if C.con_i[c, I_FLAGS] & (FLAG_NEW | FLAG_PHYS_AGAIN):
        contact_physics(c, id1, id2, S, C, phys_tab)
    law = C.con_i[c, I_LAW]
    if law < 0:   # made real by createInteraction while the InteractionLoop had no law for it
        fail(C, STATUS_NO_LAW, id1, id2)
        return False
    # functors may set flags of their own (geometry, law): change only the bits owned here
    if not law_call(law, c, id1, id2, S, C, law_tab):
        C.con_i[c, I_FLAGS] &= ~FLAG_ALIVE
        died[c // BLOCK] = 1
        return False
    return True


@jit
def update_block(b, S, C, geom_tab, phys_tab, law_tab, died, law_totals, totals, scatter):
    """Contacts of block ``b``, then those of them that ended unlinked (:func:`unlink_block`); the arrays are
    borrowed (no reference counting per contact: see ARCHITECTURE.md, "Kernel records"). With ``scatter`` (only
    where the blocks run one after the other, in order: :func:`update_scatter`), each live contact's force and
    torque are added to its two bodies as soon as its law has run (:func:`scatter_contact`)."""
    geom_tab, phys_tab, law_tab, died = borrow((geom_tab, phys_tab, law_tab, died))
    for c in range(b * BLOCK, min(C.ctr[C_CONTACTS], (b + 1) * BLOCK)):
        if update_contact(c, S, C, geom_tab, phys_tab, law_tab, died) and scatter:
            scatter_contact(c, S, C, law_tab[0])
    if died[b] != 0:
        unlink_block(b, C, died, law_totals, totals)


def _update(S, C, geom_tab, phys_tab, law_tab, died, law_totals, totals):
    queue = block_queue(died.shape[0])
    for w in prange(queue_workers(queue)):
        b = next_block(queue, w, -1)
        while b >= 0:
            update_block(b, S, C, geom_tab, phys_tab, law_tab, died, law_totals, totals, False)
            b = next_block(queue, w, b)


update, update_par = kernel(_update, over="contacts")


@jit
def update_scatter(S, C, geom_tab, phys_tab, law_tab, died, law_totals, totals):
    """The update of every contact on one thread, block after block, each live contact's force and torque added
    to its bodies right after its law: the force gather's sums, term for term (each body's contacts in increasing
    contact order, from the force it had), in one pass over the contacts instead of a second one through the
    per-body index (:func:`interaction_stage`)."""
    for b in range(died.shape[0]):
        update_block(b, S, C, geom_tab, phys_tab, law_tab, died, law_totals, totals, True)


@jit
def unlink_block(b, C, died, law_totals, totals):
    """Detach the contacts of block ``b`` ended in this step from their pairs (each pair has one contact: the
    blocks run in parallel), count them in ``died[b]``, and sum their running totals in ``totals[b]`` (shape of
    ``C.ended``; ``law_totals``: :attr:`InteractionParams.law_totals`), in contact order."""
    law_totals, totals = borrow((law_totals, totals))
    dead = 0
    for c in range(b * BLOCK, min(C.ctr[C_CONTACTS], (b + 1) * BLOCK)):
        if C.con_i[c, I_FLAGS] & FLAG_ALIVE or C.con_i[c, I_ID1] < 0:
            continue
        law = C.con_i[c, I_LAW]
        if 0 <= law < law_totals.shape[0]:
            for k in range(law_totals[law, 0], law_totals[law, 0] + law_totals[law, 1]):
                totals[b, k] += C.con_f[c, k]
        p = C.con_i[c, I_PAIR]
        if p >= 0:
            C.pair_con[p] = -1
            C.pair_gap[p] = -math.inf  # evaluate the pair again from the next step
        C.con_i[c, I_ID1] = -1   # marks the row as already unlinked
        C.con_i[c, I_PAIR] = -1
        dead += 1
    died[b] = dead


@jit
def count_dead(C, died, totals):
    """After the update: the contacts that ended (``died``, per block) counted in ``C.ctr``, their blocks'
    running totals added to ``C.ended`` in block order (the same sums whatever the number of threads)."""
    for b in range(died.shape[0]):
        if died[b] == 0:
            continue
        C.ctr[C_DEAD] += died[b]
        C.ctr[C_CSR_DIRTY] = 1
        for k in range(totals.shape[1]):
            C.ended[k] += totals[b, k]


#: live contact rows (bytes of ``con_f``) from which the compaction also sorts them (about a core's L2 cache:
#: smaller pools are read from cache in any order, and the sort would cost more than it saves)
SORT_ROWS_BYTES = 1 << 20


@jit
def compact(C):
    """Remove dead rows, keeping the order of the live contacts; a pool of :data:`SORT_ROWS_BYTES` or more is
    also put in the order of the pairs (smaller body id, then larger; stable), so that the rows of a body's
    contacts come close together again, where the force gather reads them (:func:`build_csr`; at 10,000
    triaxial spheres, one thread, with the gather, 0.88 -> 0.66 ms a step). The order of the rows is that of each
    body's force sum: it depends only on the steps' contacts, never on the thread count. Rows move: the per-body
    index is marked stale (``C_CSR_DIRTY``)."""
    n = C.ctr[C_CONTACTS]
    live = 0
    top = 0
    for c in range(n):
        if C.con_i[c, I_FLAGS] & FLAG_ALIVE:
            live += 1
            top = max(top, C.con_i[c, I_ID1] + 1, C.con_i[c, I_ID2] + 1)
    if live * C.con_f.shape[1] * C.con_f.itemsize < SORT_ROWS_BYTES:
        k = 0
        for c in range(n):  # in place: row k comes from row c >= k
            if C.con_i[c, I_FLAGS] & FLAG_ALIVE:
                move_row(C, k, c)
                k += 1
    else:
        rows = np.empty(live, np.int64)
        keys = np.empty(live, np.int64)
        k = 0
        for c in range(n):
            if C.con_i[c, I_FLAGS] & FLAG_ALIVE:
                a = C.con_i[c, I_ID1]
                b = C.con_i[c, I_ID2]
                rows[k] = c
                keys[k] = min(a, b) * top + max(a, b)
                k += 1
        perm = argsort_keys(keys)
        con_i = np.empty((live, C.con_i.shape[1]), np.int32)
        con_f = np.empty((live, C.con_f.shape[1]))
        for t in range(live):
            c = rows[perm[t]]
            for j in range(con_i.shape[1]):
                con_i[t, j] = C.con_i[c, j]
            for j in range(con_f.shape[1]):
                con_f[t, j] = C.con_f[c, j]
        copy_rows(C.con_i, con_i, live)
        copy_rows(C.con_f, con_f, live)
        for t in range(live):
            p = C.con_i[t, I_PAIR]
            if p >= 0:
                C.pair_con[p] = t
    C.ctr[C_CONTACTS] = live
    C.ctr[C_DEAD] = 0
    C.ctr[C_CSR_DIRTY] = 1


@jit
def move_row(C, dst, src):
    """Contact row ``src`` copied to row ``dst`` (its pair relinked)."""
    if dst == src:
        return
    for j in range(C.con_i.shape[1]):
        C.con_i[dst, j] = C.con_i[src, j]
    for j in range(C.con_f.shape[1]):
        C.con_f[dst, j] = C.con_f[src, j]
    p = C.con_i[dst, I_PAIR]
    if p >= 0:
        C.pair_con[p] = dst


@jit
def build_csr(C, nb):
    """Per-body index of live contacts, each body's list in increasing contact order.

    The counts become each body's end (a running sum kept in a register: ``start[i + 1] += start[i]`` would
    wait for the store of the previous element), and the contacts are placed walking backwards, each
    taking the slot before its body's current end: the lists come out in increasing contact order and
    ``start`` ends as the begins, with no second array."""
    start = C.csr_start
    csr = C.csr_con
    con_i = C.con_i
    start[:] = 0
    n = C.ctr[C_CONTACTS]
    for c in range(n):
        if con_i[c, I_FLAGS] & FLAG_ALIVE:
            start[con_i[c, I_ID1]] += 1
            start[con_i[c, I_ID2]] += 1
    total = 0
    for i in range(nb):
        total += start[i]
        start[i] = total
    start[nb] = total
    for c in range(n - 1, -1, -1):
        if con_i[c, I_FLAGS] & FLAG_ALIVE:
            for k in range(2):
                i = con_i[c, I_ID1 + k]
                start[i] -= 1
                csr[start[i]] = c
    C.ctr[C_CSR_DIRTY] = 0


@jit
def index_contacts(C, nb):
    """Build the per-body index of the contacts record ``C`` for ``nb`` bodies if it is stale (``C_CSR_DIRTY``):
    for Python's lookups of a body's contacts (:func:`granum.yade.interactions.body_contact_rows`)."""
    if C.ctr[C_CSR_DIRTY]:
        build_csr(raw(C), nb)


def plan_moments(laws):
    """Whether a law of the functor set ``laws`` (the static first item of a law table) writes contact moments
    (the history group "moment", :data:`granum.core.contacts.F_MOMENT`): a constant of the compiled code, so
    that the force gather of a plan without such a law compiles to what it was before moments existed.
    Compiled code only."""
    raise TypeError("plan_moments is called from compiled kernels only")


@overload(plan_moments, inline="always")
def _plan_moments(laws):
    value = static_value(laws, "functors")
    registered = functors("law")
    if value is not None and any("moment" in registered[k].history for k in value[2]):
        return lambda laws: True
    return lambda laws: False


@jit(inline="always")  # per contact end: no call
def contact_load(c, second, xi, S, C, laws):
    """``(f, t)``: the force and torque [N], [N m] of contact ``c`` on its body 2 (``second``) or body 1, whose
    centre is ``xi`` [m]; with a law of ``laws`` writing moments (:func:`plan_moments`), the torque holds the
    contact's moment (on body 2, the opposite on body 1). The one formula of the force gather
    (:func:`gather_body`) and of the update's scatter (:func:`scatter_contact`): both add the same numbers."""
    f = add(load3_row(C.con_f, c, F_FN), load3_row(C.con_f, c, F_FS))  # force on body 2
    if C.con_i[c, I_FLAGS] & FLAG_RADIAL_ARMS:
        # YADE's sphericalBodies: lever arm (R_i - delta/2) along the normal
        half = 0.5 * C.con_f[c, F_PEN]
        arm_len = half - C.con_f[c, F_R2] if second else C.con_f[c, F_R1] - half
        arm = scale(load3_row(C.con_f, c, F_NORMAL), arm_len)
    elif second:
        shift, _ = contact_shift(c, S, C)
        arm = sub(load3_row(C.con_f, c, F_POINT), add(xi, shift))
    else:
        arm = sub(load3_row(C.con_f, c, F_POINT), xi)
    if not second:
        f = (-f[0], -f[1], -f[2])
    t = cross(arm, f)
    if plan_moments(laws):
        m = load3_row(C.con_f, c, F_MOMENT)
        t = add(t, m) if second else sub(t, m)
    return f, t


@jit
def gather_body(i, S, C, laws):
    """Add the forces and torques of body ``i``'s contacts to it, in increasing contact order
    (:func:`contact_load`). ``laws`` is a static value, no array: a call per body counts no reference."""
    a = C.csr_start[i]
    b = C.csr_start[i + 1]
    if a == b:
        return
    fx = S.force[i, 0]
    fy = S.force[i, 1]
    fz = S.force[i, 2]
    tx = S.torque[i, 0]
    ty = S.torque[i, 1]
    tz = S.torque[i, 2]
    xi = load3(S.pos, i)
    for k in range(a, b):
        c = C.csr_con[k]
        f, t = contact_load(c, C.con_i[c, I_ID2] == i, xi, S, C, laws)
        fx += f[0]
        fy += f[1]
        fz += f[2]
        tx += t[0]
        ty += t[1]
        tz += t[2]
    S.force[i, 0] = fx
    S.force[i, 1] = fy
    S.force[i, 2] = fz
    S.torque[i, 0] = tx
    S.torque[i, 1] = ty
    S.torque[i, 2] = tz


@jit(inline="always")  # once per contact of a one-thread update: no call
def scatter_contact(c, S, C, laws):
    """Add contact ``c``'s force and torque to its body 1 and to its body 2 (:func:`contact_load`). Both are
    computed before either is stored: a store into a body's force could be the same memory as the contact's row
    for all the compiler knows, and would make it read the row again."""
    id1 = C.con_i[c, I_ID1]
    id2 = C.con_i[c, I_ID2]
    f1, t1 = contact_load(c, False, load3(S.pos, id1), S, C, laws)
    f2, t2 = contact_load(c, True, load3(S.pos, id2), S, C, laws)
    for k in range(3):
        S.force[id1, k] += f1[k]
        S.torque[id1, k] += t1[k]
    for k in range(3):
        S.force[id2, k] += f2[k]
        S.torque[id2, k] += t2[k]


@jit
def prefetch_contacts(i, C):
    """Ask for the ``con_f`` rows of body ``i``'s contacts (see :mod:`granum.kernels.prefetch`; their
    ``con_i`` rows, one line each, gained nothing measurable)."""
    for k in range(C.csr_start[i], C.csr_start[i + 1]):
        prefetch_row(C.con_f, C.csr_con[k])


@jit
def gather_block(b, S, C, nb, ahead, laws):
    """Bodies of block ``b``; with ``ahead`` > 0, each while the rows of the body ``ahead`` later are on
    their way."""
    end = min(nb, (b + 1) * BLOCK)
    if C.csr_start[b * BLOCK] == C.csr_start[end]:
        return   # no contact in the block (the index is cumulative): a falling or resting cluster's blocks, mostly
    for i in range(b * BLOCK, end):
        if ahead and i + ahead < end:
            prefetch_contacts(i + ahead, C)
        gather_body(i, S, C, laws)


def _gather(S, C, nb, ahead, laws):
    queue = block_queue((nb + BLOCK - 1) // BLOCK)
    for w in prange(queue_workers(queue)):
        b = next_block(queue, w, -1)
        while b >= 0:
            gather_block(b, S, C, nb, ahead, laws)
            b = next_block(queue, w, b)


gather, gather_par = kernel(_gather, over="bodies")


@jit
def incident_velocity(S, C, c, ratchet):
    """Velocity of body 2 relative to body 1 at the point of contact ``c`` [m/s] (ScGeom.incidentVel), with
    the periodic image's shift; ``ratchet``: YADE's avoidGranularRatcheting."""
    shift, shift_vel = contact_shift(c, S, C)
    return scgeom_incident_vel(c, C.con_i[c, I_ID1], C.con_i[c, I_ID2], S, C, shift, shift_vel, ratchet)


@jit
def load3_row(a, c, col):
    return (a[c, col], a[c, col + 1], a[c, col + 2])


@jit
def contact_energy(S, C):
    """Add the contacts' elastic energy (instantaneous) and friction dissipation (cumulative)."""
    elast = 0.0
    dissip = 0.0
    live = False
    for c in range(C.ctr[C_CONTACTS]):
        if C.con_i[c, I_FLAGS] & FLAG_ALIVE:
            live = True
            elast += C.con_f[c, F_E_ELAST]
            dissip += C.con_f[c, F_E_DISSIP]
    # like YADE, a term appears in O.energy once something contributed to it
    if live or S.energy_set[E_ELAST_POT]:
        S.energy[E_ELAST_POT] = elast
        S.energy_set[E_ELAST_POT] = 1
    if dissip != 0.0:
        S.energy[E_PLAST_DISSIP] += dissip
        S.energy_set[E_PLAST_DISSIP] = 1


@jit
def interaction_stage(S, C, P):
    """Engine stage of InteractionLoop.

    ``P``: :class:`InteractionParams`. ``P.width``: the ``con_f`` columns the loop's functors use, and the
    energy columns when O.trackEnergy (:meth:`granum.engines.pipeline.InteractionLoop.params`); a narrower
    pool is widened first.
    """
    geom_code, geom_swap, geom_tab, geom_type = P.geom_code, P.geom_swap, P.geom_tab, P.geom_type
    phys_code, phys_swap, phys_tab, phys_type = P.phys_code, P.phys_swap, P.phys_tab, P.phys_type
    law_code, law_tab, pair_ok = P.law_code, P.law_tab, P.pair_ok
    widen_contacts(C, P.width)
    nb = S.iscal[SI_NBODIES]
    pair_blocks = (C.ctr[C_PAIRS] + BLOCK - 1) // BLOCK
    workers = thread_count()
    # the temporaries of detection, then those of the update, from the work area (granum.kernels.scratch)
    w = area(C, motion_words(nb) + pair_blocks * 3 + words_i4(workers * BLOCK))
    R = raw(S)  # hot loops read the records through raw views (see granum.core.records)
    V = raw(C)
    motion, spread, at = take_motions(w, nb)
    hits, at = take_i8(w, at, pair_blocks * 3)
    hits = rows_of(hits, 3)  # detection writes every block's row
    lists, at = take_i4(w, at, workers * BLOCK)
    lists = rows_of(lists, BLOCK)
    # the motions the collider's check left when it ran as the stage just before (granum.kernels.collider), else
    # computed here
    left_by = V.ctr[C_MOTIONS_STAGE]
    V.ctr[C_MOTIONS_STAGE] = 0
    if not (left_by > 0 and left_by == V.ctr[C_STAGE] - 1):
        if nb < PARALLEL_THRESHOLD:
            body_motions(R, nb, motion, spread)
        else:
            body_motions_par(R, nb, motion, spread)
    extent, turn = motion_bound(R, spread)
    bound = quick_bound(S, extent, turn)
    if V.ctr[C_PAIRS] < PARALLEL_THRESHOLD:
        detect(R, V, geom_code, geom_swap, geom_tab, pair_ok, motion, bound, hits, lists)
    else:
        detect_par(R, V, geom_code, geom_swap, geom_tab, pair_ok, motion, bound, hits, lists)
    new = passed = 0
    for b in range(pair_blocks):
        new += hits[b, 0]
        passed += hits[b, 2]
    if S.iscal[SI_PERIODIC] == 0 and REORIGIN_ONE_IN * passed > V.ctr[C_PAIRS]:
        reorigin(R, V, nb, motion)
    if new > 0:
        create_contacts(S, C, geom_code, geom_swap, geom_type, phys_code, phys_swap, phys_type, law_code, hits, new)
        if C.ctr[C_STATUS] != 0:
            return
    n = C.ctr[C_CONTACTS]
    contact_blocks = (n + BLOCK - 1) // BLOCK
    nended = C.ended.shape[0]
    w = area(C, words_i4(contact_blocks) + contact_blocks * nended)
    V = raw(C)  # the storage may have grown
    died, at = take_i4(w, 0, contact_blocks)
    died[:] = 0
    totals, at = take_f8(w, at, contact_blocks * nended)
    totals = rows_of(totals, nended)
    totals[:] = 0.0
    # one thread updates the contacts in order: it adds their forces as it goes, the gather's sums term for term
    scattered = n < PARALLEL_THRESHOLD_CONTACTS or thread_count() == 1
    if scattered:
        update_scatter(R, V, geom_tab, phys_tab, law_tab, died, P.law_totals, totals)
    else:
        update_par(R, V, geom_tab, phys_tab, law_tab, died, P.law_totals, totals)
    count_dead(V, died, totals)
    dirty = V.ctr[C_CSR_DIRTY] != 0
    compacting = dirty and 4 * V.ctr[C_DEAD] > V.ctr[C_CONTACTS]
    if not scattered:
        if dirty:
            build_csr(V, nb)
        # a pool that caches cannot hold is read from memory: prefetch (in cache, it would only cost instructions)
        big = V.ctr[C_CONTACTS] * V.con_f.shape[1] * V.con_f.itemsize >= GATHER_PREFETCH_BYTES
        ahead = GATHER_AHEAD if big else 0
        if nb < PARALLEL_THRESHOLD:
            gather(R, V, nb, ahead, law_tab[0])
        else:
            gather_par(R, V, nb, ahead, law_tab[0])
    # the pool is compacted after the forces are added (a compaction may sort it: the sums above follow the
    # order the contacts were updated in, with or without the scatter)
    if compacting:
        compact(V)
    # the per-body index is left stale here: its readers build it when they need it (the gather above, the stages
    # that read a body's contacts, Python's b.intrs(): index_contacts). Where the update scatters the forces no
    # stage needs it, and a falling ball's contacts begin and end at every step after its impact (a build reads
    # every body: 2.8 us a step for its 4,428 bodies)
    if S.iscal[SI_TRACK_ENERGY]:
        contact_energy(R, V)
