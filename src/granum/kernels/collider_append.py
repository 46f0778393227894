"""Bodies appended between collider runs: their bounds and their pairs, merged into the pair list.

A factory appends a few spheres at every step (YADE's ``SpheresFactory``). A full run of the broad phase
(:func:`granum.kernels.collider.collider_stage`) bounds every body again and rebuilds the whole pair list: about
1 ms a step at 5,000 falling spheres, half of such a step. When bodies were only appended since the collider
last ran (:data:`granum.core.contacts.COLLIDE_APPENDED`), the bodies listed before keep their bounds, their pairs
and their pairs' detection budgets; only the new bodies are bounded, each is tested against every bound, and
their pairs are merged into the sorted list.

The pair list keeps the broad phase's promise. Every body listed before stays within its Verlet-enlarged bound
until the collider runs again (the trigger is unchanged), and so does a new body, bounded now with the same
Verlet distance. So two bodies that may touch before that run have overlapping bounds, and their pair is listed.
The contacts found are therefore those a full run would let the interaction loop find, at the same steps and in
the same pair order: the same bits (``tests/test_collider_append.py``). The other pairs may differ: a full run
drops the pairs of bodies whose fresh bounds no longer overlap, which never become contacts.

The appended bodies are those alive without a bound yet (NaN: the collider never saw them).
"""

from __future__ import annotations

import math

import numpy as np

from granum._jit import jit
from granum.core.arrays import S_VERLET
from granum.core.contacts import C_COLLIDE, C_COLLIDER_RUNS, C_PAIRS, C_REPLACED, I_PAIR
from granum.core.shapes import ShapeKind
from granum.kernels.bounds import bound_body, bounds_overlap
from granum.kernels.copy import copy_rows
from granum.kernels.motion import any_body_moved
from granum.kernels.pairing import may_collide
from granum.kernels.sorting import argsort_keys

#: The most appended bodies bounded and paired here: testing each against every bound (a few ns a test) costs
#: less than a full run (about 200 ns a body) only for a few dozen of them.
APPEND_MAX = 32


@jit
def appended_bodies(S, nb):
    """Ids of the live bodies without a bound (appended since the collider last ran), int64; at most
    :data:`APPEND_MAX` + 1 of them (one more says: too many)."""
    out = np.empty(APPEND_MAX + 1, np.int64)
    n = 0
    for i in range(nb):
        if S.alive[i] and not S.bound_min[i, 0] == S.bound_min[i, 0]:
            out[n] = i
            n += 1
            if n > APPEND_MAX:
                break
    return out[:n]


@jit
def same_verlet(S, new, verlet_dist):
    """Whether a full run would enlarge the bounds by the Verlet distance in use (``scal[S_VERLET]``) with the
    bodies ``new`` added: ``verlet_dist`` [m] itself, or, negative, that fraction of the smallest sphere radius,
    which a new sphere smaller than the others would lower."""
    verlet = S.scal[S_VERLET]
    if verlet_dist >= 0.0:
        return verlet_dist == verlet
    if not verlet > 0.0:  # no sphere before: a new one would set the distance
        return False
    for i in new:
        if S.shape_kind[i] == ShapeKind.SPHERE and -verlet_dist * S.sphere_radius[S.shape_row[i]] < verlet:
            return False
    return True


@jit
def new_pairs(S, nb, new, avoid_self):
    """The pairs (id1 < id2) of the bounded bodies ``new`` with every body whose bound overlaps theirs and whose
    masks allow, sorted, (K, 2) int32."""
    is_new = np.zeros(nb, np.bool_)
    for a in new:
        is_new[a] = True
    found = np.empty((16, 2), np.int32)
    k = 0
    for a in new:
        for j in range(nb):
            if j == a or (is_new[j] and j < a):  # a pair of two new bodies is found once, from its smaller id
                continue
            if bounds_overlap(S, a, j) and may_collide(S, min(a, j), max(a, j), avoid_self):
                if k == found.shape[0]:
                    grown = np.empty((2 * k, 2), np.int32)
                    copy_rows(grown, found, k)
                    found = grown
                found[k, 0] = min(a, j)
                found[k, 1] = max(a, j)
                k += 1
    keys = np.empty(k, np.int64)
    for t in range(k):
        keys[t] = np.int64(found[t, 0]) * nb + found[t, 1]
    order = argsort_keys(keys)
    pairs = np.empty((k, 2), np.int32)
    for t in range(k):
        pairs[t, 0] = found[order[t], 0]
        pairs[t, 1] = found[order[t], 1]
    return pairs


@jit
def merge_pairs(C, added):
    """Merge the sorted pairs ``added`` (K, 2), none of them listed, into the sorted pair list of ``C``: the listed
    pairs keep their contact, budget and reference motion, the added ones start with none (evaluated at the next
    step); the contacts' pair indices follow their pairs."""
    n = C.ctr[C_PAIRS]
    k = added.shape[0]
    ids = np.empty((n + k, 2), np.int32)
    con = np.empty(n + k, np.int32)
    gap = np.empty(n + k, np.float32)
    ref = np.zeros((n + k, 3), np.int16)
    hit = np.zeros(n + k, np.uint8)
    p = 0
    q = 0
    for t in range(n + k):
        take_old = q == k or (p < n and (C.pair_ids[p, 0] < added[q, 0] or (
            C.pair_ids[p, 0] == added[q, 0] and C.pair_ids[p, 1] < added[q, 1])))
        if take_old:
            ids[t, 0] = C.pair_ids[p, 0]
            ids[t, 1] = C.pair_ids[p, 1]
            con[t] = C.pair_con[p]
            gap[t] = C.pair_gap[p]
            for d in range(3):
                ref[t, d] = C.pair_ref[p, d]
            hit[t] = C.pair_hit[p]
            if con[t] >= 0:
                C.con_i[con[t], I_PAIR] = t
            p += 1
        else:
            ids[t, 0] = added[q, 0]
            ids[t, 1] = added[q, 1]
            con[t] = -1
            gap[t] = -math.inf
            q += 1
    C.pair_ids = ids
    C.pair_con = con
    C.pair_gap = gap
    C.pair_ref = ref
    C.pair_hit = hit
    C.ctr[C_PAIRS] = n + k
    C.ctr[C_REPLACED] += 1


@jit
def append_bodies(S, C, nb, bound_code, bound_tab, verlet_dist, avoid_self, motion, spread):
    """The collider's run when bodies were only appended since the last one (aperiodic scenes): bound the new
    bodies, merge their pairs into the list and return True; or change nothing and return False when a full run
    is due anyway: no body or more than :data:`APPEND_MAX` to add, another Verlet distance, or a listed body that
    left its bound. ``S``: a raw view of the scene; ``verlet_dist``, ``avoid_self``: the collider's
    (:class:`granum.kernels.collider.ColliderParams`); ``motion``, ``spread``: the pieces of
    :func:`granum.kernels.motion.any_body_moved`."""
    new = appended_bodies(S, nb)
    if new.shape[0] == 0 or new.shape[0] > APPEND_MAX or not same_verlet(S, new, verlet_dist):
        return False
    out = np.empty(6)
    for i in new:
        bound_body(i, S, bound_code, bound_tab, S.scal[S_VERLET], out)
    if any_body_moved(S, nb, motion, spread):   # the new bodies have not moved since: only the others count
        return False
    merge_pairs(C, new_pairs(S, nb, new, avoid_self))
    C.ctr[C_COLLIDE] = 0
    C.ctr[C_COLLIDER_RUNS] += 1
    return True
