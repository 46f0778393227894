"""The records the runner hands to compiled code are kept between runs (a loop of ``O.step()`` does not build them
anew at every call: core.scene.Scene.arrays, Scene.contacts_record), but never keep an array the scene no longer
holds alive: a table that grows, contacts that are replaced, each frees the old arrays at once (checked with weak
references and the garbage collector)."""

from __future__ import annotations

import gc
import weakref

import numba
import numpy as np
import pytest
from conftest import factory_in_box, frict_engines

from granum.core.contacts import C_COLLIDER_RUNS, C_REPLACED, CONTACTS


def _pile(yade, n=8):
    """``n`` spheres resting in a column on a fixed one: contacts from the first steps."""
    O = yade.O
    O.bodies.append([yade.sphere((0, 0, 2 * k * 0.099), 0.1, fixed=k == 0) for k in range(n)])
    O.engines = frict_engines(yade, gravity=(0, 0, -10), damping=0.3)
    O.dt = 0.5 * yade.PWaveTimeStep()


def test_a_grown_table_frees_its_old_columns(yade):
    """After steps, the body table grows (appended spheres): its old position column is freed at once, though no
    run has taken the scene's record since; the next steps move the new spheres."""
    O = yade.O
    _pile(yade)
    for _ in range(5):
        O.step()
    old = weakref.ref(O._scene.bodies.pos)
    capacity = len(O._scene.bodies.pos)
    O.bodies.append([yade.sphere((3, 0, k * 0.25), 0.1) for k in range(capacity)])
    assert len(O._scene.bodies.pos) > capacity
    gc.collect()
    assert old() is None
    z = O.bodies[len(O.bodies) - 1].state.pos[2]
    O.run(10, True)
    assert O.bodies[len(O.bodies) - 1].state.pos[2] < z


def test_replaced_contacts_are_freed(yade):
    """After steps with contacts, the bodies are cleared (new, empty contact arrays): the old contact pool is freed
    at once; a new pile then makes its own contacts."""
    O = yade.O
    _pile(yade)
    O.run(20, True)
    assert O.interactions.countReal() > 0
    old = weakref.ref(O._scene.contacts.con_f)
    O.bodies.clear()
    gc.collect()
    assert old() is None
    _pile(yade)
    O.run(20, True)
    assert O.interactions.countReal() > 0


def test_steps_one_by_one_equal_one_run(yade):
    """100 calls of O.step() (records kept from call to call) end in the same state, bit for bit, as O.run(100)."""
    O = yade.O
    _pile(yade)
    for _ in range(100):
        O.step()
    stepped = O.bodies.arrays("pos", "vel", "angVel")
    O.reset()
    _pile(yade)
    O.run(100, True)
    ran = O.bodies.arrays("pos", "vel", "angVel")
    for k in ("pos", "vel", "angVel"):
        assert np.array_equal(stepped[k], ran[k]), k


def _same_arrays(C, record) -> bool:
    """Whether the contact arrays ``C`` are the arrays held by the kernels' ``record`` (same memory)."""
    held = CONTACTS.from_record(record)
    return all(a.__array_interface__["data"][0] == b.__array_interface__["data"][0] and a.shape == b.shape
               for a, b in zip(C, held, strict=True))


def test_python_sees_every_array_compiled_code_replaced(yade):
    """Python takes the contact arrays back from the kernels' record only when compiled code replaced one (a step
    without a replacement keeps the same array objects). Step by step through a run in which the
    collider runs again and again, the contact pool and the work area grow, and a factory appends bodies (the
    collider's run for appended bodies), the scene's arrays are the record's after every step."""
    O = yade.O
    factory_in_box(yade, height=0.03)
    scene = O._scene
    kept = []
    for step in range(900):
        if step == 600:
            O.engines[-1].dead = True   # the factory: no more bodies: Python no longer replaces the per-body index
        before = scene.contacts
        O.step()
        assert _same_arrays(scene.contacts, scene._contacts_record[1]), O.iter
        kept.append(all(a is b for a, b in zip(scene.contacts, before, strict=True)))
    C = scene.contacts
    assert len(O.bodies) > 100 and O.interactions.countReal() > 50
    assert int(C.ctr[C_COLLIDER_RUNS]) > 100 and int(C.ctr[C_REPLACED]) > int(C.ctr[C_COLLIDER_RUNS])
    assert sum(kept[600:]) > 250   # once the factory stops, most steps replace nothing


@numba.njit
def _given_back(record):
    return record


def test_records_compiled_code_does_not_count_stay_held_by_python_alone(yade):
    """The scene's and the contacts' records are uncounted in compiled code (granum.core.records.UncountedRecordType):
    every function that takes them, from the step loop down, leaves their count alone. After runs with contacts
    that come and go, the collider running again and again and the work area growing, the two records the last run
    used (kept by the scene, read before anything could make new ones) are each held by one reference, their Python
    handles': a count taken and not given back (unboxing) would show as more, one dropped and not taken as fewer
    (and a freed record). A record that compiled code returns gets a reference of its own; a dropped handle frees
    the record's arrays at once; compiled code cannot make such a record."""
    O = yade.O
    factory_in_box(yade, height=0.03)
    scene = O._scene
    for _ in range(3):
        O.run(150, True)
        S, C = scene._record[1], scene._contacts_record[1]   # the run's, not new ones (arrays() may replace them)
        assert (S._meminfo.refcount, C._meminfo.refcount) == (1, 1)
        del S, C
    assert O.interactions.countReal() > 20 and int(scene.contacts.ctr[C_COLLIDER_RUNS]) > 20
    O.engines[-1].dead = True   # the factory: no more bodies, so the next run keeps the scene's records
    O.run(1, True)
    S, C = scene.arrays(), scene.contacts_record()
    O.run(20, True)
    assert S is scene.arrays() and C is scene.contacts_record()
    assert (S._meminfo.refcount, C._meminfo.refcount) == (1, 1)
    again = _given_back(C)   # returned to Python: a second handle, with a reference of its own
    assert again._meminfo.refcount == 2
    del again
    assert C._meminfo.refcount == 1
    del S, C
    arrays = CONTACTS.tuple(*(a.copy() for a in scene.contacts))
    record = CONTACTS.to_record(arrays)
    O.run(1, True)   # compiled code ran meanwhile, with the scene's records
    column = weakref.ref(arrays.con_f)
    del arrays
    gc.collect()
    assert column() is not None   # the record holds its arrays ...
    assert record._meminfo.refcount == 1
    del record
    gc.collect()
    assert column() is None   # ... and frees them with it
    with pytest.raises(TypeError, match="made by Python only"):
        CONTACTS.compiled_constructor()
