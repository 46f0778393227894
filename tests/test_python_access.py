"""O.interactions and O.bodies from Python: every handle reads the row it names, through steps that end,
create and compact contact rows and through erasures, checked against a brute-force reading of the contact
arrays; walking them makes no per-item search (the cost is O(1) per item)."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import frict_engines

from granum.core.contacts import C_CONTACTS, C_CSR_DIRTY, C_PAIRS, F_FN, FLAG_ALIVE, I_FLAGS, I_ID1, I_ID2, I_PAIR
from granum.yade import interactions as intr_module


def _pile(y, n=4):
    """n³ unit-spaced spheres of radius 0.55 (each touches its neighbours), thrown apart by their velocities."""
    y.O.engines = frict_engines(y, gravity=(0, 0, -10), damping=0)
    y.O.dt = 1e-4
    y.O.bodies.append([y.sphere((i, j, k), 0.55) for k in range(n) for j in range(n) for i in range(n)])
    for b in y.O.bodies:  # spread the spheres so that contacts end and rows are compacted
        b.state.vel = (0.3 * (b.id % 3 - 1), 0.2 * (b.id % 5 - 2), 0.1 * (b.id % 7 - 3))


def _brute_force(y):
    """{(id1, id2): normal force} of the live contacts, read from the arrays without the lookups under test."""
    C = y.O._scene.contacts
    n = int(C.ctr[1])
    out = {}
    for row in range(n):
        if C.con_i[row, I_FLAGS] & FLAG_ALIVE:
            out[(int(C.con_i[row, I_ID1]), int(C.con_i[row, I_ID2]))] = tuple(C.con_f[row, F_FN:F_FN + 3])
    return out


def test_handles_follow_their_contact_through_steps_and_erasures(yade):
    y = yade
    _pile(y)
    y.O.step()
    held = {(i.id1, i.id2): i for i in y.O.interactions}
    assert len(held) == 144  # 3 n² (n - 1) neighbour pairs of the 4³ lattice
    ended = 0
    for _ in range(40):
        y.O.run(25, True)
        truth = _brute_force(y)
        walked = {(i.id1, i.id2): tuple(i.phys.normalForce) for i in y.O.interactions}
        assert walked == truth
        for key, i in held.items():  # handles made steps ago: real exactly when the pair still touches
            assert i.isReal == (key in truth)
            if i.isReal:
                assert tuple(i.phys.normalForce) == truth[key]
                assert y.O.interactions[key[1], key[0]].phys.normalForce == i.phys.normalForce
            else:
                assert i.phys is None and not y.O.interactions.has(*key, onlyReal=True)
        ended = len(held) - len(truth)
        if truth:  # erase one from Python: its handles see it at once
            key = min(truth)
            y.O.interactions.erase(*key)
            assert not held[key].isReal if key in held else True
            assert (key not in _brute_force(y)) and not y.O.interactions.has(*key, onlyReal=True)
    assert ended > 100  # the pile came apart: rows were ended and compacted many times


def test_walking_makes_no_search(yade, monkeypatch):
    """Iterating O.interactions and reading i.phys / i.geom fields, and iterating O.bodies, never looks a
    contact up: the rows come with the iteration."""
    y = yade
    _pile(y)
    y.O.run(3, True)
    calls = []
    monkeypatch.setattr(intr_module, "find_contact", lambda *a: calls.append(a) or -1)
    total = sum(i.phys.normalForce.norm() + i.geom.penetrationDepth + i.phys.kn for i in y.O.interactions)
    assert calls == [] and total > 0
    assert [b.id for b in y.O.bodies] == list(range(64))


def test_withBody_and_lookups_agree_with_brute_force(yade):
    y = yade
    _pile(y, 3)
    y.O.run(5, True)
    truth = _brute_force(y)
    for b in range(27):
        mine = sorted((i.id1, i.id2) for i in y.O.interactions.withBody(b))
        assert mine == sorted(k for k in truth if b in k)
    for a in range(27):
        for b in range(27):
            expected = (a, b) in truth or (b, a) in truth
            assert y.O.interactions.has(a, b, onlyReal=True) == expected


def _rows_with(y, b):
    """[(id1, id2)] of the live contacts of body b in row order, read from the arrays."""
    C = y.O._scene.contacts
    ids = C.con_i[:int(C.ctr[1])]
    return [(int(r[I_ID1]), int(r[I_ID2])) for r in ids if r[I_FLAGS] & FLAG_ALIVE and b in (r[I_ID1], r[I_ID2])]


def test_intrs_and_withBody_in_row_order_through_steps_erasures_and_appends(yade):
    """b.intrs() and O.interactions.withBody(b) list the body's live contacts in row order, read from the per-body
    index (a view of it: no scan of all rows), which the first lookup builds when a contact began or ended since it
    was built, else (a body appended since the last step) from a scan: through steps that begin, end and compact
    contacts, an erased interaction and an appended body."""
    y = yade
    _pile(y, 3)
    C_used = stale = 0
    for step in range(40):
        y.O.step()
        if step == 20:
            i = next(iter(y.O.interactions))
            y.O.interactions.erase(i.id1, i.id2)   # the index is out of date
        if step == 30:
            y.O.bodies.append(y.sphere((10, 10, 10), 0.5))   # a body the index does not cover until the next step
        scene = y.O._scene
        C = scene.contacts
        covered = C.csr_start.shape[0] == scene.body_count + 1
        stale += C.ctr[C_CSR_DIRTY] != 0
        for b in range(len(y.O.bodies)):
            want = _rows_with(y, b)
            assert [(i.id1, i.id2) for i in y.O.bodies[b].intrs()] == want
            assert [(i.id1, i.id2) for i in y.O.interactions.withBody(b)] == want
            if covered:
                assert intr_module.body_contact_rows(scene, b).base is C.csr_con
                assert not C.ctr[C_CSR_DIRTY]
        C_used += covered
    assert C_used == 39 and stale > 0
    assert y.O.interactions.withBody(-1) == y.O.interactions.withBody(10 ** 6) == []   # YADE 2023.02a crashes
    pairs = [[(i.id1, i.id2) for i in y.O.interactions.withBody(k)] for k in (True, 1)]
    assert pairs[0] == pairs[1] != []   # as YADE: True is body 1
    for bad in (1.0, "1"):   # YADE: ArgumentError, a TypeError
        with pytest.raises(TypeError):
            y.O.interactions.withBody(bad)


def test_len_counts_the_pairs_of_live_bodies_and_the_unpaired_contacts(yade):
    """len(O.interactions), YADE's count of potential and real interactions, against the arrays read directly:
    with every body alive (the pairs' count taken as it is) and after an erased body (its pairs left out)."""
    y = yade
    _pile(y, 3)
    y.O.run(5, True)
    y.O.interactions.erase(*next((i.id1, i.id2) for i in y.O.interactions))   # a real one made potential again

    def brute():
        scene = y.O._scene
        C, alive = scene.contacts, scene.bodies.alive
        live_pairs = sum(1 for a, b in C.pair_ids[:int(C.ctr[C_PAIRS])] if alive[a] and alive[b])
        rows = C.con_i[:int(C.ctr[C_CONTACTS])]
        unpaired = sum(1 for r in rows if r[I_FLAGS] & FLAG_ALIVE and r[I_PAIR] < 0)
        return live_pairs + unpaired

    assert len(y.O.interactions) == brute() > 0
    y.O.bodies.erase(13)   # the middle sphere: its pairs stay listed until the collider runs again
    assert len(y.O.interactions) == brute()
    assert len(y.O.interactions) < int(y.O._scene.contacts.ctr[C_PAIRS])


@pytest.mark.parametrize("n", [1, 2, 7, 100])
def test_pair_search_against_a_scan(n):
    """find_pair's binary search over the sorted pair list, against a scan of it, for present and absent pairs."""
    rng = np.random.default_rng(n)
    pairs = sorted({tuple(sorted(rng.choice(30, 2, replace=False).tolist())) for _ in range(n)})

    class C:
        pair_ids = np.array(pairs + [(99, 99)] * 5, dtype=np.int32)  # rows past the count are garbage
        ctr = np.array([len(pairs)], dtype=np.int32)

    for a in range(31):
        for b in range(31):
            expected = pairs.index((min(a, b), max(a, b))) if (min(a, b), max(a, b)) in pairs else -1
            assert intr_module.find_pair(C, a, b) == expected


def test_bulk_arrays_equal_the_per_item_values(yade):
    y = yade
    assert y.O.interactions.arrays("normalForce")["normalForce"].shape == (0, 3)
    _pile(y, 3)
    y.O.bodies.append(y.wall(-0.6, axis=2))  # a wall contact: ScGeom and FrictPhys too, another geometry functor
    y.O.run(5, True)
    walked = list(y.O.interactions)
    got = y.O.interactions.arrays("normalForce", "penetrationDepth", "kn", "contactPoint")
    assert got["id1"].tolist() == [i.id1 for i in walked] and got["id2"].tolist() == [i.id2 for i in walked]
    assert np.array_equal(got["normalForce"], [list(i.phys.normalForce) for i in walked])
    assert np.array_equal(got["kn"], [i.phys.kn for i in walked])
    assert np.array_equal(got["penetrationDepth"], [i.geom.penetrationDepth for i in walked])
    assert np.array_equal(got["contactPoint"], [list(i.geom.contactPoint) for i in walked])
    with pytest.raises(ValueError, match="'normalForse'"):
        y.O.interactions.arrays("normalForse")
    bodies = y.O.bodies.arrays("pos", "angVel", "mass", "force", "ori")
    assert bodies["ids"].tolist() == [b.id for b in y.O.bodies]
    assert np.array_equal(bodies["pos"], [list(b.state.pos) for b in y.O.bodies])
    assert np.array_equal(bodies["angVel"], [list(b.state.angVel) for b in y.O.bodies])
    assert np.array_equal(bodies["mass"], [b.state.mass for b in y.O.bodies])
    assert np.array_equal(bodies["force"], [list(y.O.forces.f(b.id)) for b in y.O.bodies])
    assert np.array_equal(bodies["ori"][:, 0], [b.state.ori[3] for b in y.O.bodies])  # (w, x, y, z); YADE's w is [3]
    y.O.bodies.erase(4)
    assert 4 not in y.O.bodies.arrays()["ids"].tolist()
    with pytest.raises(ValueError, match="'position'"):
        y.O.bodies.arrays("position")


def test_walked_norms_equal_the_bulk_arrays(yade):
    """The walk of the benchmark (python_walk.py): each ``i.phys.normalForce.norm()`` is sqrt(x² + (y² + z²)) (YADE's
    order) of its own contact's force, read from the bulk array of the same forces (same bits), and so is the sum."""
    y = yade
    _pile(y)
    y.O.run(3, True)
    walked = [(i.id1, i.id2, i.phys.normalForce.norm(), tuple(i.phys.normalForce)) for i in y.O.interactions]
    bulk = y.O.interactions.arrays("normalForce")
    fn = bulk["normalForce"]
    norms = np.sqrt(fn[:, 0] * fn[:, 0] + (fn[:, 1] * fn[:, 1] + fn[:, 2] * fn[:, 2]))
    assert [w[:2] for w in walked] == list(zip(bulk["id1"].tolist(), bulk["id2"].tolist(), strict=True))
    assert [w[2] for w in walked] == norms.tolist() and [w[3] for w in walked] == [tuple(f) for f in fn.tolist()]
    assert sum(w[2] for w in walked) == pytest.approx(norms.sum(), rel=1e-13) and norms.min() > 0
    assert [w[2] for w in walked] == [y.Vector3(*w[3]).norm() for w in walked]  # as a plain Vector3's


def test_held_values_follow_their_contact_through_compaction(yade):
    """``fn = i.phys.normalForce`` and ``ph = i.phys`` are bound to their interaction, as YADE's: after steps that
    end contacts and compact the rows (the others move), each still reads and writes its own contact's columns."""
    y = yade
    _pile(y)
    y.O.step()
    held = {(i.id1, i.id2): (i, i.phys, i.phys.normalForce, i.geom) for i in y.O.interactions}
    first_rows = {key: intr_module.find_contact(y.O._scene, *key) for key in held}
    moved, wrote = set(), False
    for _ in range(30):
        y.O.run(25, True)
        truth = _brute_force(y)
        for key, (i, ph, fn, geom) in held.items():
            if key not in truth:
                assert not i.isReal and i.phys is None
                with pytest.raises(RuntimeError, match="no longer real"):
                    fn.norm()
                continue
            if intr_module.find_contact(y.O._scene, *key) != first_rows[key]:
                moved.add(key)
            assert tuple(fn) == truth[key] == tuple(ph.normalForce) and fn.norm() == y.Vector3(*truth[key]).norm()
            assert ph.kn == i.phys.kn and geom.penetrationDepth == i.geom.penetrationDepth > 0
        if moved and not wrote:  # writes go to the contact's own row, wherever it moved
            key, wrote = min(moved), True
            i, ph, fn, _ = held[key]
            fn[0] = 1.5
            assert _brute_force(y)[key][0] == 1.5 and i.phys.normalForce[0] == 1.5
            ph.normalForce = (1.0, 2.0, 3.0)
            fn += (1.0, 0.0, 0.0)
            assert _brute_force(y)[key] == (2.0, 2.0, 3.0) == tuple(i.phys.normalForce)
    assert len(moved) > 5 and wrote  # rows moved under the held values (compaction), which followed their contacts


def test_held_values_of_an_erased_interaction(yade):
    """As in YADE: once erased, the interaction is not real and has no phys, while the values taken from it
    before show its last values; after a step they follow the pair's contact if it formed again, and raise if
    not."""
    y = yade
    _pile(y)
    y.O.run(3, True)
    i = next(iter(y.O.interactions))
    ph, fn, last = i.phys, i.phys.normalForce, tuple(i.phys.normalForce)
    y.O.interactions.erase(i.id1, i.id2)
    assert not i.isReal and i.phys is None and i.geom is None
    assert tuple(fn) == last and ph.normalForce.norm() == y.Vector3(*last).norm()
    y.O.run(50, True)
    key = (i._id1, i._id2)
    if key in _brute_force(y):
        assert tuple(fn) == _brute_force(y)[key]
    else:
        with pytest.raises(RuntimeError, match="no longer real"):
            _ = ph.kn


def test_field_values_are_plain_values_when_copied_or_computed(yade):
    """A bound vector, quaternion or matrix reports and prints as its plain type; arithmetic, copies and pickles
    give plain values that later steps do not change."""
    import copy
    import pickle

    y = yade
    _pile(y, 2)
    y.O.run(2, True)
    i = next(iter(y.O.interactions))
    fn = i.phys.normalForce
    assert isinstance(fn, y.Vector3) and type(fn).__name__ == "Vector3" and repr(fn).startswith("Vector3(")
    plain = [copy.copy(fn), copy.deepcopy(fn), pickle.loads(pickle.dumps(fn)), fn * 1.0, fn + (0, 0, 0), -fn * -1.0]
    assert all(type(v) is y.Vector3 and v == fn for v in plain)
    before = tuple(fn)
    fn[0] = before[0] + 1.0
    assert [tuple(v) for v in plain] == [before] * len(plain) and fn[0] == before[0] + 1.0
    assert np.asarray(fn).tolist() == list(fn) and fn.dot((1, 0, 0)) == fn[0] and abs(fn) == fn.norm()


def test_in_place_operations_on_held_values_write_their_contact(yade):
    """``fn *= 2``, ``fn /= 2``, ``fn.normalize()``, ``fn -= v`` on a held field change its contact's row."""
    y = yade
    _pile(y, 2)
    y.O.run(2, True)
    i = next(iter(y.O.interactions))
    key, fn = (i.id1, i.id2), i.phys.normalForce
    x0 = _brute_force(y)[key]
    fn *= 2.0
    assert _brute_force(y)[key] == tuple(2.0 * x for x in x0)
    fn /= 2.0
    fn -= (x0[0], 0.0, 0.0)
    assert _brute_force(y)[key] == (0.0, x0[1], x0[2])
    fn[1], fn[2] = 3.0, 4.0
    fn.normalize()
    assert _brute_force(y)[key] == (0.0, 0.6, 0.8) and fn.norm() == 1.0


def test_held_values_read_the_storage_assigned_to_the_scene(yade):
    """Any assignment of ``scene.contacts`` (a step's, ``createInteraction``'s, or here a plain one) tells the held
    handles that their rows may be elsewhere (``ContactsGeneration``): they read the new arrays, not the old."""
    y = yade
    _pile(y)
    y.O.step()
    i = next(iter(y.O.interactions))
    fn, ph = i.phys.normalForce, i.phys
    scene = y.O._scene
    generation = scene.contacts_generation
    C = scene.contacts
    con_f = C.con_f.copy()
    con_f[:, F_FN:F_FN + 3] *= 2.0
    scene.contacts = C._replace(con_f=con_f)
    assert generation.replaced and not scene.contacts_generation.replaced
    key = (i.id1, i.id2)
    row = intr_module.find_contact(scene, *key)
    assert tuple(fn) == _brute_force(y)[key] == tuple(2.0 * C.con_f[row, F_FN:F_FN + 3])
    assert ph.normalForce.norm() == fn.norm() == y.Vector3(*_brute_force(y)[key]).norm()
    assert type(i).__name__ == "Interaction" and isinstance(i, intr_module.Interaction)
