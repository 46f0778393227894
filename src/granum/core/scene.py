"""The scene: all storage of one simulation, independent of the YADE scripting layer.

A :class:`BodyStore` holds the body table, the per-kind shape tables and the
materials the bodies refer to; a :class:`Scene` adds the interaction storage, the
clock, the energy accumulators, the periodic cell and the engine list. Detached
YADE objects (a ``Body`` built by ``utils.sphere`` before it is appended) keep their
values in rows of a :class:`BodyStore` shared by them (``granum.yade.bodies._Nursery``), so the same code
reads and writes attached and detached objects.
"""

from __future__ import annotations

import hashlib
import weakref

import numpy as np

from granum.core import validate
from granum.core.arrays import (
    MATERIAL_COLUMNS,
    MATERIAL_KINDS,
    NENERGY,
    NSCAL,
    NSISCAL,
    S_DT,
    S_TIME,
    SCENE,
    SI_HOMO_DEFORM,
    SI_ITER,
    SI_NBODIES,
    SI_PERIODIC,
    SI_TRACK_ENERGY,
)
from granum.core.bodies import BORN_COLUMNS, new_body_table
from granum.core.contacts import (
    C_COLLIDE,
    C_CONTACTS,
    C_REPLACED,
    COLLIDE_APPENDED,
    COLLIDE_FULL,
    CONTACTS,
    FLAG_ALIVE,
    I_FLAGS,
    I_GEOM,
    I_LAW,
    I_PHYS,
    new_contact_arrays,
    resize_for_bodies,
    with_images,
)
from granum.core.shapes import ASPHERICAL_KINDS, CLUMP_MEMBER_COLUMNS, ShapeKind, new_shape_tables, shape_type
from granum.core.table import Table


class BodyStore:
    """Body table, shape tables and the materials referred to by ``body.material``.

    ``materials`` holds material objects (anything with ``kind`` - a material class name
    of :data:`~granum.core.arrays.MATERIAL_KINDS` - and ``column_values()`` - a dict of
    material-table column values); ``body.material`` is an index into it.
    """

    def __init__(self, capacity: int = 8):
        self.bodies = new_body_table(capacity)
        self.shapes = new_shape_tables(capacity)
        self.clump_members = Table(CLUMP_MEMBER_COLUMNS, capacity)
        self.materials: list = []

    def material_index(self, material) -> int:
        """Index of ``material`` in :attr:`materials`, appending it if new."""
        for k, m in enumerate(self.materials):
            if m is material:
                return k
        self.materials.append(material)
        return len(self.materials) - 1

    def shape_table(self, i: int):
        """``(kind, table, row)`` of the shape of body ``i``."""
        kind = ShapeKind(int(self.bodies.shape_kind[i]))
        return kind, self.shapes.get(kind), int(self.bodies.shape_row[i])


def default_tags() -> dict:
    """YADE's predefined scene tags: ``id`` (date-time-pid, unique per run), ``d.id``, ``id.d``,
    ``isoTime`` and ``author``."""
    import datetime
    import getpass
    import os
    import socket

    now = datetime.datetime.now()
    sid = now.strftime("%Y%m%dT%H%M%S") + f"p{os.getpid()}"
    try:
        author = f"{getpass.getuser()}@{socket.gethostname()}"
    except (KeyError, OSError):
        author = "unknown"
    return {"author": author, "isoTime": now.strftime("%Y%m%dT%H%M%S"), "id": sid, "d.id": sid, "id.d": sid}


def _forgetter(scene):
    """A function that calls ``scene.forget_record()`` while the scene exists (it keeps no reference to it)."""
    ref = weakref.ref(scene)

    def forget() -> None:
        alive = ref()
        if alive is not None:
            alive.forget_record()

    return forget


class ContactsGeneration:
    """The life of one :attr:`Scene.contacts` object: ``replaced`` becomes True when the scene's contacts are next
    assigned (a step took them back from compiled code, which may have moved rows; another storage). Python-side
    caches of contact rows hold it: one attribute read tells them whether their rows are still in place, where
    comparing with the scene's attribute cost a walk of ``O.interactions`` a tenth of its time."""

    __slots__ = ("replaced",)

    def __init__(self):
        self.replaced = False


class Scene(BodyStore):
    """Storage, clock and engines of one simulation (what YADE's ``O`` refers to)."""

    def __init__(self):
        super().__init__(capacity=64)
        self._record = None   # (ids of the arrays, the record made of them): see arrays()
        self._contacts_record = None   # (contacts, the record they came from, its C_REPLACED): see take_contacts()
        self._forget = _forgetter(self)   # see arrays()
        self._generation = ContactsGeneration()   # renewed with each contacts object (__setattr__)
        self.contacts = new_contact_arrays(0)
        self.scal = np.zeros(NSCAL)
        self.iscal = np.zeros(NSISCAL, np.int64)
        self.scal[S_DT] = 1e-8
        self.energy = np.zeros(NENERGY)
        self.energy_set = np.zeros(NENERGY, np.uint8)
        self.cell_hsize = np.eye(3)
        self.cell_velgrad = np.zeros((3, 3))
        self.cell_prev_velgrad = np.zeros((3, 3))
        self.cell_trsf = np.eye(3)
        self.cell_ref_hsize = np.eye(3)
        self.cell_bound_hsize = np.eye(3)
        self.cell_prev_hsize = np.eye(3)
        self.iscal[SI_HOMO_DEFORM] = 2
        self.born = Table(BORN_COLUMNS, 64)  # per body id, beside the body table (not a kernel input)
        self.engines: list = []
        self.tags: dict = default_tags()
        self.stop_at_iter = 0
        self.stop_at_time = 0.0
        #: digest of the geometry functors and parameters the pairs' detection budgets were computed with
        self.detection_key = ""
        self._mat_cache = None
        self._contact_functors: dict = {}   # see contact_functors()

    def __setattr__(self, name: str, value) -> None:
        if name == "contacts":   # other contacts: the record kept of the last ones would keep their arrays alive
            kept = self._contacts_record   # not self.__dict__: reading that makes CPython keep a dict for the
            # scene, and every attribute read of it then costs 26 ns instead of 11 (a walk reads several an item)
            if kept is not None and kept[0] is not value:
                object.__setattr__(self, "_contacts_record", None)
            self._generation.replaced = True
            object.__setattr__(self, "_generation", ContactsGeneration())
        object.__setattr__(self, name, value)

    @property
    def contacts_generation(self) -> ContactsGeneration:
        """The :class:`ContactsGeneration` of :attr:`contacts` now."""
        return self._generation

    # ---- clock ----------------------------------------------------------------------
    @property
    def dt(self) -> float:
        return float(self.scal[S_DT])

    @dt.setter
    def dt(self, value: float) -> None:
        value = float(value)
        validate.TIME_STEP.check(value, "O.dt")
        self.scal[S_DT] = value

    @property
    def time(self) -> float:
        return float(self.scal[S_TIME])

    @time.setter
    def time(self, value: float) -> None:
        self.scal[S_TIME] = float(value)

    @property
    def iter(self) -> int:
        return int(self.iscal[SI_ITER])

    @iter.setter
    def iter(self, value: int) -> None:
        self.iscal[SI_ITER] = int(value)

    @property
    def track_energy(self) -> bool:
        return bool(self.iscal[SI_TRACK_ENERGY])

    @track_energy.setter
    def track_energy(self, on: bool) -> None:
        self.iscal[SI_TRACK_ENERGY] = int(bool(on))

    @property
    def periodic(self) -> bool:
        return bool(self.iscal[SI_PERIODIC])

    @periodic.setter
    def periodic(self, on: bool) -> None:
        self.iscal[SI_PERIODIC] = int(bool(on))
        if on:
            self.contacts = with_images(self.contacts)
        self.needs_collider()

    @property
    def body_count(self) -> int:
        return self.bodies.count

    # ---- changes ----------------------------------------------------------------------
    def note_contact_functors(self) -> None:
        """Record the functor codes of the live contacts (when a new engine list takes over: see
        :meth:`contact_functors`)."""
        C = self.contacts
        n = int(C.ctr[C_CONTACTS])
        live = C.con_i[:n][(C.con_i[:n, I_FLAGS] & FLAG_ALIVE) != 0]
        # a law code -1 (a contact createInteraction made without a law) names no functor
        self._contact_functors = {role: tuple(int(c) for c in np.unique(live[:, col]) if c >= 0)
                                  for role, col in (("geom", I_GEOM), ("phys", I_PHYS), ("law", I_LAW))}

    def contact_functors(self, role: str) -> tuple:
        """Codes of the ``role`` functors that live contacts used when the engine list last changed. A contact
        keeps the functors it was created with, so the dispatch compiled for a plan includes them; contacts
        created since came from the listed functors."""
        return self._contact_functors.get(role, ())

    def needs_collider(self) -> None:
        """Make the collider run at the next step (bodies or shapes changed): bound every body again and rebuild
        the pair list."""
        self.contacts.ctr[C_COLLIDE] = COLLIDE_FULL

    def bodies_appended(self) -> None:
        """Make the collider run at the next step after bodies were appended, and nothing else changed: unless a
        full run is due anyway, it bounds and pairs only the new bodies (:mod:`granum.kernels.collider_append`)."""
        if self.contacts.ctr[C_COLLIDE] == 0:
            self.contacts.ctr[C_COLLIDE] = COLLIDE_APPENDED

    def detection_uses(self, functors: bytes) -> None:
        """The interaction loop detects contacts with the geometry functors and parameters ``functors``
        (their bytes); if they changed, the collider runs again, which drops every pair's budget (a full run, after
        an edit, carries none over)."""
        key = hashlib.blake2b(functors, digest_size=16).hexdigest()
        if key != self.detection_key:
            self.detection_key = key
            self.needs_collider()

    def clear_bodies(self) -> None:
        """Remove all bodies and interactions; keep engines, materials and the clock."""
        self.bodies.clear()
        self.born.clear()
        self.clump_members.clear()
        for t in self.shapes.values():
            t.clear()
        self.contacts = new_contact_arrays(0, periodic=self.periodic)

    def add_body_rows(self, count: int = 1, src: Table | None = None, src_rows=None) -> int:
        """Append ``count`` body rows, all defaults or copies of ``src[src_rows]`` (:meth:`Table.append_copy`);
        return the id of the first."""
        i = self.bodies.append_rows(count) if src is None else self.bodies.append_copy(src, src_rows, count)
        k = self.born.append_rows(count)
        self.born.iter[k:k + count], self.born.time[k:k + count] = self.iter, self.time
        self.needs_collider()
        return i

    # ---- compiled view -------------------------------------------------------------------
    def material_arrays(self) -> tuple[np.ndarray, np.ndarray]:
        """``(mat_kind (M,) int32, mat (M, ncol) float64)`` compiled from :attr:`materials`."""
        key = tuple([(id(m), m.version) for m in self.materials])
        if self._mat_cache is not None and self._mat_cache[0] == key:
            return self._mat_cache[1]
        cols = MATERIAL_COLUMNS
        mat = np.full((max(len(self.materials), 1), len(cols)), np.nan)
        kind = np.zeros(max(len(self.materials), 1), np.int32)
        for k, m in enumerate(self.materials):
            kind[k] = MATERIAL_KINDS.index(m.kind)
            for name, value in m.column_values().items():
                mat[k, cols.index(name)] = value
        self._mat_cache = (key, (kind, mat))
        return kind, mat

    def arrays(self):
        """Record of all scene arrays for the kernels (cheap; call again after any edit).

        The record is kept while it is made of the same arrays (compiled code never replaces the
        scene's arrays), so a run with a Python engine every few steps, or a loop of ``O.step()``, does not
        rebuild it at every chunk; a table whose column is replaced drops it (:meth:`forget_record`, through
        ``Table.on_replace``), so that it keeps no replaced array alive. The tables say whether their arrays
        are the same (:attr:`Table.generation`); the other arrays are identified by their ids, which stay
        theirs while the record holds them."""
        b = self.bodies
        self.iscal[SI_NBODIES] = b.count
        C = resize_for_bodies(self.contacts, b.count)
        if C is not self.contacts:   # (assigning contacts makes a new ContactsGeneration: only when they change)
            self.contacts = C
        mat_kind, mat = self.material_arrays()
        # lazy columns the kernels follow without looking (clump members, aspherical bodies)
        if self.shapes[ShapeKind.CLUMP].count:
            b.allocate("clump_rel_pos", "clump_rel_ori")
        if any([self.shapes[kind].count for kind in ASPHERICAL_KINDS]):
            b.allocate("ang_mom")
        tables = (b, self.clump_members, *self.shapes.values())
        others = (mat_kind, mat, self.cell_hsize, self.cell_velgrad, self.cell_prev_velgrad, self.cell_trsf,
                  self.cell_bound_hsize, self.cell_prev_hsize, self.scal, self.iscal, self.energy, self.energy_set)
        # the tables themselves (compared by identity), so that a table dropped meanwhile cannot pass for a new one
        key = (tuple(self.shapes), tables, tuple([t.generation for t in tables]), tuple(map(id, others)))
        if self._record is None or self._record[0] != key:
            values = {c.name: b.stored(c.name) for c in b.columns}
            for kind, table in self.shapes.items():
                values.update({shape_type(kind).record_field(c.name): table.stored(c.name) for c in table.columns})
            values.update(mat_kind=mat_kind, mat=mat, cell_hsize=self.cell_hsize, cell_velgrad=self.cell_velgrad,
                          cell_prev_velgrad=self.cell_prev_velgrad, cell_trsf=self.cell_trsf,
                          cell_bound_hsize=self.cell_bound_hsize, cell_prev_hsize=self.cell_prev_hsize,
                          clump_members=self.clump_members.id,
                          scal=self.scal, iscal=self.iscal, energy=self.energy, energy_set=self.energy_set)
            self._record = (key, SCENE.to_record([values[n] for n in SCENE.names]))
            for table in tables:   # a column replaced (growth, a lazy column's first use) drops the record
                table.on_replace = self._forget
        return self._record[1]

    def contacts_record(self):
        """Record of :attr:`contacts` for the kernels: the one they came back in (:meth:`take_contacts`), while
        they are still those (assigning others drops it), or a new one."""
        kept = self._contacts_record
        if kept is not None and kept[0] is self.contacts:
            return kept[1]
        return CONTACTS.to_record(self.contacts)

    def take_contacts(self, record) -> None:
        """Take :attr:`contacts` back from a kernels' record: the arrays in it when compiled code replaced one since
        they were taken (``ctr[C_REPLACED]`` changed: converting the record makes a NumPy array of each of them,
        7 of the 37 microseconds of an ``O.step()``), else the same arrays. Either way in a new named tuple:
        compiled code may have moved rows within them, and Python's interaction handles take a new
        :attr:`contacts` object for the sign of that (:class:`granum.yade.interactions._Rows`)."""
        kept = self._contacts_record
        C = self.contacts
        if kept is not None and kept[1] is record and kept[0] is C and C.ctr.item(C_REPLACED) == kept[2]:
            C = tuple.__new__(type(C), C)
        else:
            C = CONTACTS.from_record(record)
        self.contacts = C
        self._contacts_record = (C, record, C.ctr.item(C_REPLACED))

    def forget_record(self) -> None:
        """Drop the record kept by :meth:`arrays` (a table's column was replaced: the record would keep the old
        array alive)."""
        self._record = None
