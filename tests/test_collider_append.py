"""The collider's run after bodies were only appended (a factory's): it bounds and pairs the new bodies and keeps
the others' bounds, pairs and detection budgets (granum.kernels.collider_append).

What must hold is the broad phase's promise, whatever it costs: the same contacts at the same steps, hence the
same bits, as a full run at every such step; a pair list sorted, listing every two bodies whose bounds overlap, its
contacts linked both ways; and a full run wherever the shortcut would not be exact."""

from __future__ import annotations

import numpy as np
from conftest import factory_in_box

from granum.core.arrays import S_VERLET
from granum.core.contacts import C_CONTACTS, C_PAIRS, FLAG_ALIVE, I_FLAGS, I_ID1, I_ID2, I_PAIR


def _state(O):
    a = O.bodies.arrays("pos", "vel", "angVel")
    return a, O.interactions.countReal()


def _bound_changes(y, steps):
    """How many of ``steps`` single steps changed the bound of the newest sphere the collider has bounded (it falls
    all the while)."""
    O = y.O
    first = max((b for b in O.bodies if isinstance(b.shape, y.Sphere) and b.bound is not None), key=lambda b: b.id)
    changes = 0
    before = tuple(first.bound.min)
    for _ in range(steps):
        O.run(1, True)
        now = tuple(first.bound.min)
        changes += now != before
        before = now
    return changes


def test_same_bits_as_full_runs(yade):
    """The spheres made, their contacts and every state bit after 1,000 steps equal those of the same seeded run
    with a full collider run at every step; and the run did take the shortcut (the bounds of the spheres made
    before stay put while new ones come)."""
    O = yade.O
    factory_in_box(yade)
    O.run(1000, True)
    appended, contacts = _state(O)
    changes = _bound_changes(yade, 30)
    O.reset()
    factory_in_box(yade, force_full_runs=True)
    O.run(1000, True)
    full, contacts_full = _state(O)
    assert contacts > 50 and contacts == contacts_full   # spheres have landed and touch
    assert len(appended["ids"]) > 1000
    for k in ("ids", "pos", "vel", "angVel"):
        assert np.array_equal(appended[k], full[k]), k
    # the falling sphere's bound is taken anew at every full run only: about every 10 steps here (0.5 rMin of
    # Verlet distance, 2 mm, at 1.5-3 m/s), against every step when each step runs in full
    assert changes <= 10
    assert _bound_changes(yade, 30) == 30


def _check_pairs(s):
    """The pairs are sorted by (id1, id2) without repeats, they are exactly the pairs of live bodies whose (stored)
    bounds overlap and whose masks share a bit (brute force), and each live contact and its pair point at each
    other; the number of live contacts."""
    C, b = s.contacts, s.bodies
    n = b.count
    pairs = C.pair_ids[:C.ctr[C_PAIRS]].astype(np.int64)
    keys = pairs[:, 0] * n + pairs[:, 1]
    assert (pairs[:, 0] < pairs[:, 1]).all() and (np.diff(keys) > 0).all()
    lo, hi = b.bound_min[:n], b.bound_max[:n]
    live = b.alive[:n] & (lo[:, 0] <= hi[:, 0])
    i, j = np.triu_indices(n, 1)
    keep = live[i] & live[j] & ((b.mask[i] & b.mask[j]) != 0)
    i, j = i[keep], j[keep]
    overlap = ((lo[i] <= hi[j]) & (lo[j] <= hi[i])).all(axis=1)
    assert np.array_equal(np.sort(i[overlap] * n + j[overlap]), keys)
    rows = np.flatnonzero(C.con_i[:C.ctr[C_CONTACTS], I_FLAGS] & FLAG_ALIVE)
    p = C.con_i[rows, I_PAIR]
    assert (p >= 0).all() and np.array_equal(C.pair_con[p], rows)
    ends = np.sort(C.con_i[rows][:, [I_ID1, I_ID2]], axis=1)
    assert np.array_equal(C.pair_ids[p], ends)
    linked = np.flatnonzero(C.pair_con[:C.ctr[C_PAIRS]] >= 0)
    assert np.array_equal(np.sort(linked), np.sort(p))
    return rows.size


def test_pair_list_stays_exact_and_linked(yade):
    """After every one of 30 steps following 1,000 steps of appends, the pair list is exact and linked to the
    contacts (:func:`_check_pairs`). The factory's region reaches the walls: new spheres pair with the facets,
    whose ids come first, so the pairs of the contacts move down the list."""
    O = yade.O
    factory_in_box(yade, half_width=0.093)
    O.run(1000, True)
    contacts = []
    for _ in range(30):
        O.run(1, True)
        contacts.append(_check_pairs(O._scene))
    assert min(contacts) > 10


def test_a_smaller_sphere_takes_a_full_run(yade):
    """With verletDist < 0 the Verlet distance is that fraction of the smallest radius: a new sphere smaller than
    all before lowers it, which only a full run may do. After every step it is what a full run would set for the
    spheres the collider has seen (the factory appends after it)."""
    O = yade.O
    factory_in_box(yade, rate_per_step=0.5, r_min=0.004, r_max=0.012)
    smallest = []
    for _ in range(150):
        O.run(1, True)
        radii = [b.shape.radius for b in O.bodies if isinstance(b.shape, yade.Sphere) and b.bound is not None]
        if radii:
            assert O._scene.scal[S_VERLET] == 0.5 * min(radii)
            smallest.append(min(radii))
    assert len(set(smallest)) > 3   # the smallest radius did fall during the run


def test_many_new_bodies_take_a_full_run(yade):
    """More bodies than the shortcut takes (APPEND_MAX) appended in one step: the collider runs in full, and the
    falling sphere's bound is taken anew at every step."""
    O = yade.O
    factory_in_box(yade, rate_per_step=60.0, r_min=0.003, r_max=0.004)
    O.run(5, True)
    assert _bound_changes(yade, 10) == 10
