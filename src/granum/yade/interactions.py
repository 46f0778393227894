"""``Interaction``, its ``geom``/``phys`` views and ``O.interactions``.

An :class:`Interaction` is a handle ``(scene, id1, id2)``; it finds its row in the
interaction storage when accessed (rows move when dead contacts are compacted) and
reads and writes the columns of that row. The classes of ``i.geom`` and ``i.phys``
(``ScGeom``, ``FrictPhys``, ...) are generated from the types of the registry,
with the attributes their physics modules expose. A vector, quaternion or matrix
field (``i.phys.normalForce``) is bound to its interaction, as YADE's: it reads and
writes that contact's columns wherever compaction moves its row.

Walking ``O.interactions`` costs O(1) per item, and little: the iterator hands every
handle its row and the shared :class:`_Rows` of the storage it was found in, and the
views read the columns through memoryviews (a NumPy index or slice costs several
times more than the Python-level work of the walk).
"""

from __future__ import annotations

import operator
from bisect import bisect_left
from math import sqrt

import numpy as np

from granum._jit import call
from granum.core.contacts import (
    C_CONTACTS,
    C_CSR_DIRTY,
    C_DEAD,
    C_PAIRS,
    FLAG_ALIVE,
    I_BORN,
    I_CELL,
    I_FLAGS,
    I_GEOM,
    I_ID1,
    I_ID2,
    I_LAW,
    I_PAIR,
    I_PHYS,
    end_contact,
)
from granum.core.scene import ContactsGeneration
from granum.kernels.dispatch import functors
from granum.kernels.interaction import index_contacts
from granum.mathtypes import Matrix3, Quaternion, Vector3, Vector3i, _index
from granum.physics import registry
from granum.yade._pausing import pauses_the_run


def find_pair(C, a: int, b: int) -> int:
    """Index of the potential pair (a, b) in the sorted pair list, or -1 (O(log n)). The binary searches run over
    memoryviews of the strided columns (``bisect`` in C, each probe a Python int: 4.5 -> 1.4 us a lookup at 50,000
    pairs, where NumPy's indexing made each probe an object); NumPy's searchsorted would first copy the whole
    column (O(n) for one lookup)."""
    if a > b:
        a, b = b, a
    n = int(C.ctr[C_PAIRS])
    first, second = memoryview(C.pair_ids[:n, 0]), memoryview(C.pair_ids[:n, 1])
    lo = bisect_left(first, a)
    hi = bisect_left(first, a + 1, lo)
    k = bisect_left(second, b, lo, hi)
    return k if k < hi and second[k] == b else -1


def end_law_contact(C, c: int) -> None:
    """End live contact ``c`` from Python, keeping the running totals of its law (``end_contact``)."""
    law = int(C.con_i[c, I_LAW])
    end_contact(C, c, functors("law")[law].history if 0 <= law < len(functors("law")) else ())


def find_contact(scene, a: int, b: int) -> int:
    """Row of the live contact between bodies a and b of ``scene``, or -1 (O(log n))."""
    C = scene.contacts
    p = find_pair(C, a, b)
    if p >= 0:
        return int(C.pair_con[p])
    row = _unpaired_contacts(C, scene.iter).get((a, b) if a < b else (b, a), -1)
    return row if row >= 0 and _holds(C, row, a, b) else -1


_unpaired_index: dict = {}


def _unpaired_contacts(C, iteration: int) -> dict:
    """{(smaller id, larger id): row} of the live contacts that outlived their pair (bounds apart), rebuilt
    when the contact rows may have moved: at another step, with another row count or other arrays. (Between
    steps rows are only ended, never moved: ``find_contact`` checks that the row still holds the pair.)"""
    key = (iteration, int(C.ctr[C_CONTACTS]), int(C.ctr[C_PAIRS]))   # the arrays: C's, checked by identity below
    cached = _unpaired_index.get(id(C))
    if cached is not None and cached[0] == key and cached[1] is C:
        return cached[2]
    n = key[1]
    rows = np.nonzero((C.con_i[:n, I_PAIR] < 0) & (C.con_i[:n, I_FLAGS] & FLAG_ALIVE != 0))[0]
    ids = np.sort(C.con_i[rows, I_ID1:I_ID2 + 1], axis=1).tolist()
    index = {(a, b): int(r) for (a, b), r in zip(ids, rows, strict=True)}
    _unpaired_index.clear()  # one scene's index at a time: the lookups come in runs over one scene
    _unpaired_index[id(C)] = (key, C, index)
    return index


def _holds(C, row: int, a: int, b: int) -> bool:
    """Whether contact row ``row`` is the live contact of bodies a and b (in either order); O(1)."""
    if row >= C.ctr.item(C_CONTACTS):  # beyond the rows in use: a copy left by compaction
        return False
    id1, id2, _, flags = C.con_i[row, I_ID1:I_FLAGS + 1].tolist()
    return bool(flags & FLAG_ALIVE) and ((id1 == a and id2 == b) or (id1 == b and id2 == a))


class _Rows:
    """Where contact rows were found: the ``scene``, its storage ``C`` of that moment, its count of ended rows
    ``dead`` and flat memoryviews of its columns, shared by every handle found in it: ``f[row * fw + column]``
    is ``con_f[row, column]``, ``i[row * iw + column]`` is ``con_i[row, column]`` (the storage is allocated
    C-contiguous; a memoryview reads a number several times faster than NumPy's indexing), ``ctr`` the
    counters, ``geom``/``phys`` the functor codes by row; ``geom_class``/``phys_class``, once a walk has found
    that all the live contacts have the same one, their view class (else None: read by row).

    Rows move and are reused only inside compiled code, after which the runner (or ``createInteraction``) stores
    new arrays in the scene; from Python they only end, through ``end_contact``, which counts them and leaves
    their values in place. So while ``C`` is the scene's (``gen.replaced`` is False: two attribute reads, where
    ``C is scene.contacts`` took four), a row found in it holds the same contact's values (the
    last ones, if it has ended since: what YADE's phys object shows once erased): the value reads check only
    that (``_Bound``, ``_field_property``). While, besides, its count of ended rows is still ``dead``, the
    contact is as real as it was (``Interaction._row``)."""

    __slots__ = ("scene", "C", "gen", "dead", "f", "fw", "i", "iw", "ctr", "geom", "phys", "geom_class",
                 "phys_class")

    def __init__(self, scene, C=None):
        """The rows of ``C``, the scene's storage now (``gen`` its :class:`ContactsGeneration`: ``C`` is the
        scene's while ``gen.replaced`` is False), or (``C`` None) of nothing yet: never current."""
        self.scene, self.C = scene, C
        if C is None:  # nothing found yet: never current, so nothing else is read
            self.gen, self.dead = _NO_GENERATION, -1
            return
        self.gen = scene.contacts_generation
        self.f, self.fw = memoryview(C.con_f).cast("B").cast("d"), C.con_f.shape[1]
        self.i, self.iw = memoryview(C.con_i).cast("B").cast("i"), C.con_i.shape[1]
        self.geom, self.phys = memoryview(C.con_i[:, I_GEOM]), memoryview(C.con_i[:, I_PHYS])  # functor codes
        self.ctr = memoryview(C.ctr)
        self.dead = self.ctr[C_DEAD]
        self.geom_class = self.phys_class = None

    def find_classes(self, rows: np.ndarray) -> None:
        """Set ``geom_class``/``phys_class`` where the functors of all the live contacts ``rows`` (the codes from
        the least to the largest) make views of one class (rows are only made in compiled code, in a new storage,
        so this holds for every handle of this one)."""
        for role, column in (("geom", I_GEOM), ("phys", I_PHYS)):
            codes = self.C.con_i[rows, column]
            if codes.size:
                classes = {_view_class(role, c) for c in range(int(codes.min()), int(codes.max()) + 1)}
                setattr(self, f"{role}_class", classes.pop() if len(classes) == 1 else None)


_NO_GENERATION = ContactsGeneration()
_NO_GENERATION.replaced = True
_rows_cache = [_Rows(None)]


def _rows_of(scene) -> _Rows:
    """The :class:`_Rows` of the scene's storage now (one object per storage and count of ended rows)."""
    at = _rows_cache[0]
    if at.scene is not scene or at.gen.replaced or at.ctr[C_DEAD] != at.dead:
        at = _rows_cache[0] = _Rows(scene, scene.contacts)
    return at


class _ContactView:
    """Attributes mapped onto float columns of one contact row (see TypeInfo.fields): a float (width 1; a
    ``(column, 1, "bool")`` field reads as a bool, ``(column, 1, "int")`` as an int), a Vector3 (3), a Quaternion
    (4, w x y z) or a Matrix3 (9). Each field is a property of the generated class (``add_views``): reading one
    costs O(1). Other names raise AttributeError (the class has slots and no ``__dict__``).

    ``i.geom`` and ``i.phys`` make the view with its interaction ``_intr`` and the row ``_row`` it had in the
    storage ``_at`` (:class:`_Rows`). Its values are read there while that storage is the scene's (from Python,
    rows only end and keep their values: an erased interaction's view shows its last values, as YADE's); after
    a step has replaced it, the view finds its interaction's row again (``_moved``), and raises if the
    interaction is no longer real. The class defines no ``__init__``, ``__getattr__`` or ``__setattr__``: each
    would cost the walks a Python call per view or disable CPython's fast attribute paths. A view made by
    calling its class (``FrictPhys()``) belongs to no interaction: reading its fields raises AttributeError."""

    __slots__ = ("_intr", "_at", "_row")
    _fields: dict = {}

    def _moved(self) -> int:
        """The row of the interaction in the scene's storage now (RuntimeError if the interaction has ended)."""
        intr = self._intr
        self._row = row = intr._row_or_raise()
        self._at = intr._at
        return row

    def _value_row(self) -> int:
        """The row to read and write the values in."""
        at = self._at
        return self._moved() if at.gen.replaced else self._row

    def __dir__(self):
        return list(type(self)._fields)

    def __repr__(self):
        return f"<{type(self).__name__} instance at {hex(id(self))}>"


class _Bound:
    """A vector, quaternion or matrix field of a geometry or physics view ``_view``, bound to it as YADE's
    (``i.phys.normalForce[0] = 1`` writes the contact; ``fn = i.phys.normalForce`` shows the values of later
    steps): its array ``_a`` is the columns from ``_col`` in the view's row of the moment, looked up at each use
    (``_ContactView``), so the value stays with its contact when compaction moves the rows. Results of
    operations are plain values (``_new``); a copy or pickle too (``__reduce__``)."""

    __slots__ = ()
    __init__ = object.__init__  # made by the field getters only; construction without a Python frame
    _plain: type  # the unbound class
    _width: int

    def _columns(self) -> np.ndarray:
        view = self._view
        row = view._value_row()
        return view._at.C.con_f[row, self._col:self._col + self._width]

    def _store(self, value) -> None:
        """``self._a = value`` (what ``v *= 2`` does after writing in place): the values go to the contact."""
        self._columns()[:] = np.reshape(value, -1)

    _a = property(_columns, _store)

    @classmethod
    def _new(cls, a: np.ndarray):
        return cls._plain._new(a)

    def __reduce__(self):
        return (self._plain, tuple(self._a.ravel().tolist()))


class _BoundVector3(_Bound, Vector3):
    __slots__ = ("_view", "_col")
    _plain, _width = Vector3, 3

    def _xyz(self) -> tuple[float, float, float]:
        """The three components, read through the memoryview of the row (no NumPy object made)."""
        view = self._view
        at = view._at
        if at.gen.replaced:
            view._moved()
            at = view._at
        f, k = at.f, view._row * at.fw + self._col
        return f[k], f[k + 1], f[k + 2]

    def squaredNorm(self):
        x, y, z = self._xyz()
        return x * x + (y * y + z * z)  # x² + (y² + z²), YADE's order, as Vector3.squaredNorm

    def norm(self):  # the walks' hot path: _xyz inlined
        view = self._view
        at = view._at
        if at.gen.replaced:
            view._moved()
            at = view._at
        f, k = at.f, view._row * at.fw + self._col
        x, y, z = f[k], f[k + 1], f[k + 2]
        return sqrt(x * x + (y * y + z * z))

    __abs__ = norm

    def __getitem__(self, i):
        return self._xyz()[_index(i, 3)]

    def __iter__(self):
        return iter(self._xyz())


class _BoundQuaternion(_Bound, Quaternion):
    __slots__ = ("_view", "_col")
    _plain, _width = Quaternion, 4


class _BoundMatrix3(_Bound, Matrix3):
    __slots__ = ("_view", "_col")
    _plain, _width = Matrix3, 9

    _a = property(lambda self: self._columns().reshape(3, 3), _Bound._store)


for _cls in (_BoundVector3, _BoundQuaternion, _BoundMatrix3):  # they print and report as the plain types
    _cls.__name__ = _cls.__qualname__ = _cls._plain.__name__


def _field_property(name: str, field: tuple) -> property:
    """The property reading and writing ``field`` = (column, width[, "bool" or "int"]) of the view's contact
    row: a number, or a value bound to the view (:class:`_Bound`)."""
    col, width = field[:2]
    end = col + width
    scalar = {"bool": bool, "int": int}.get(field[2] if len(field) > 2 else "float", float)
    bound = {3: _BoundVector3, 4: _BoundQuaternion, 9: _BoundMatrix3}.get(width)

    if width == 1:
        def get(view):
            at = view._at
            if at.gen.replaced:  # _value_row, inlined
                view._moved()
                at = view._at
            return scalar(at.f[view._row * at.fw + col])
    else:
        def get(view):
            value = bound()
            value._view, value._col = view, col
            return value

    def put(view, value):
        row = view._value_row()
        a = view._at.C.con_f
        if width == 1:
            a[row, col] = float(value)
        else:
            a[row, col:end] = Quaternion(value)._a if width == 4 else np.asarray(value, dtype=float).reshape(width)

    return property(get, put, doc=f"{name}: contact column {col}" + (f"..{end - 1}" if width > 1 else ""))


def add_views(table: dict, views: dict) -> dict:
    """Add to ``views`` a view class for each type of ``table`` (GEOM_TYPES or PHYS_TYPES) it lacks."""
    for name in table:
        if name in views:
            continue
        parent = table[name].parent
        base = views[parent] if parent else _ContactView
        fields = registry.type_fields(table, name)
        namespace = {"__slots__": (), "_fields": fields, "__module__": __name__}
        namespace.update({k: _field_property(k, f) for k, f in fields.items() if base._fields.get(k) != f})
        views[name] = type(name, (base,), namespace)
    return views


GEOM_VIEWS = add_views(registry.GEOM_TYPES, {})


def _incident_vel(self, i=None, avoidGranularRatcheting: bool = True) -> Vector3:
    """Velocity of body 2 relative to body 1 at the contact point [m/s] (YADE's ``ScGeom.incidentVel``).

    With ``avoidGranularRatcheting`` the lever arms are the reference radii and the centres' relative
    velocity is scaled by (r1 + r2) / (r1 + r2 - penetrationDepth); otherwise the arms run from the centres
    to the contact point. ``i``, the interaction, is accepted as in YADE (it is this geometry's own)."""
    from granum._jit import call
    from granum.core.contacts import CONTACTS
    from granum.kernels.interaction import incident_velocity

    row = self._value_row()
    s = self._at.scene
    return Vector3(*call(incident_velocity, s.arrays(), CONTACTS.to_record(s.contacts), row,
                         bool(avoidGranularRatcheting)))


GEOM_VIEWS["ScGeom"].incidentVel = _incident_vel
PHYS_VIEWS = add_views(registry.PHYS_TYPES, {})


_GEOM_CLASSES: list = []
_PHYS_CLASSES: list = []
_view_classes: dict = {"geom": _GEOM_CLASSES, "phys": _PHYS_CLASSES}
_WALK_BLOCK = 2048  # interactions made per block of ids converted to Python ints (InteractionContainer.__iter__)


def _view_class(role: str, code: int):
    """The view class of the output of the ``role`` functor of this code. Codes follow registration order and
    a functor keeps its code, so the list is only extended, when a functor registered later (a user's law)
    shows up."""
    classes = _view_classes[role]
    if code >= len(classes):
        views = GEOM_VIEWS if role == "geom" else PHYS_VIEWS
        classes[:] = [views[f.produces] for f in functors(role)]
    return classes[code]


def _pack(id1, id2):
    """Body ids (Python ints or int64 arrays; below 2³¹, or -1) as one integer: id1 in the high 32 bits."""
    return (id1 << 32) | (id2 & 0xFFFFFFFF)


def body_contact_rows(scene, i: int) -> np.ndarray:
    """Rows of the live contacts of body ``i`` (none for an id outside the scene), in increasing order: from the
    per-body index (the CSR of :mod:`granum.core.contacts`), built first if a contact began or ended since
    (:func:`granum.kernels.interaction.index_contacts`), in the time of the body's own contacts (a loop of
    ``len(b.intrs())`` over the bodies, YADE's way to the coordination numbers, had taken time quadratic in their
    count); for a body appended since the last step, which the index does not cover yet, found among all rows."""
    C = scene.contacts
    start = C.csr_start
    if not 0 <= i < scene.body_count:
        return np.zeros(0, np.int64)
    if start.shape[0] == scene.body_count + 1:
        if C.ctr[C_CSR_DIRTY]:
            call(index_contacts, scene.contacts_record(), scene.body_count)
        return C.csr_con[start[i]:start[i + 1]]
    ids = C.con_i[:int(C.ctr[C_CONTACTS])]
    return np.nonzero(((ids[:, I_ID1] == i) | (ids[:, I_ID2] == i)) & (ids[:, I_FLAGS] & FLAG_ALIVE != 0))[0]


def interactions_of(scene, i: int) -> list:
    """The real interactions of body ``i`` (handles), in row order (:func:`body_contact_rows`)."""
    rows = body_contact_rows(scene, i)
    ids = scene.contacts.con_i[rows, I_ID1:I_ID2 + 1]
    return [Interaction._found(scene, a, b, row) for (a, b), row in zip(ids.tolist(), rows.tolist(), strict=True)]


class Interaction:
    """A pair of bodies: potential (bounds overlap) or real (``geom`` and ``phys`` exist)."""

    __slots__ = ("_ids", "_hint", "_at")  # _ids: the two body ids in one int (_pack), one store fewer per walked item

    def __init__(self, scene=None, id1: int = -1, id2: int = -1):
        """A view of the pair (``id1``, ``id2``) of ``scene``; ``Interaction()`` is a detached one that is
        never real, as YADE's bare ``Interaction()``."""
        if scene is None:
            from granum.core.scene import Scene

            scene = Scene()
        self._ids, self._hint, self._at = _pack(int(id1), int(id2)), -1, _Rows(scene)

    @staticmethod
    def _found(scene, id1: int, id2: int, row: int) -> Interaction:
        """The interaction of bodies ``id1``, ``id2`` (Python ints), whose contact row in the scene's storage
        of now is ``row`` (-1: none): a :class:`_Found`, as walks make."""
        intr = _Found()
        intr._ids, intr._hint, intr._at = _pack(id1, id2), row, _rows_of(scene)
        return intr

    @property
    def _id1(self) -> int:
        return self._ids >> 32

    @property
    def _id2(self) -> int:
        return ((self._ids & 0xFFFFFFFF) ^ 0x80000000) - 0x80000000  # the low 32 bits, signed

    @property
    def _scene(self):
        return self._at.scene

    def _row(self) -> int:
        """The contact row, or -1 when not real; O(1).

        The row found last is kept with the :class:`_Rows` of the storage it was found in: while those are
        current, the row is right. Otherwise the row found last is checked, and looked up again (O(log n)) if it
        moved."""
        at = self._at
        if not at.gen.replaced and at.ctr[C_DEAD] == at.dead:
            return self._hint
        row, scene = self._hint, at.scene
        if not (row >= 0 and _holds(scene.contacts, row, self._id1, self._id2)):
            row = find_contact(scene, self._id1, self._id2)
        self._hint, self._at = row, _rows_of(scene)
        return row

    def _row_or_raise(self) -> int:
        row = self._row()
        if row < 0:
            raise RuntimeError(f"interaction ({self._id1}, {self._id2}) is no longer real")
        return row

    @property
    def id1(self) -> int:
        row = self._row()
        return self._at.i[row * self._at.iw + I_ID1] if row >= 0 else self._id1

    @property
    def id2(self) -> int:
        row = self._row()
        return self._at.i[row * self._at.iw + I_ID2] if row >= 0 else self._id2

    @property
    def isReal(self) -> bool:
        return self._row() >= 0

    @property
    def isActive(self) -> bool:
        return True

    @property
    def geom(self):
        at, row = self._at, self._hint
        if at.gen.replaced or at.ctr[C_DEAD] != at.dead:  # _row, inlined
            row, at = self._row(), self._at
        if row < 0:
            return None
        cls = at.geom_class
        if cls is None:  # contacts of several functors
            try:
                cls = _GEOM_CLASSES[at.geom[row]]
            except IndexError:  # a functor registered since (a user's law)
                cls = _view_class("geom", at.geom[row])
        view = cls()
        view._intr = self
        view._at = at
        view._row = row
        return view

    @property
    def phys(self):
        # written out as geom is, not through a shared helper: one Python call more per walked item costs about
        # a tenth of the walk (python_walk.py), which is still slower than YADE's
        at, row = self._at, self._hint
        if at.gen.replaced or at.ctr[C_DEAD] != at.dead:  # _row, inlined
            row, at = self._row(), self._at
        if row < 0:
            return None
        cls = at.phys_class
        if cls is None:  # contacts of several functors
            try:
                cls = _PHYS_CLASSES[at.phys[row]]
            except IndexError:  # a functor registered since (a user's law)
                cls = _view_class("phys", at.phys[row])
        view = cls()
        view._intr = self
        view._at = at
        view._row = row
        return view

    @property
    def cellDist(self):
        row = self._row()
        con_i = self._scene.contacts.con_i
        if row < 0 or con_i.shape[1] <= I_CELL:  # aperiodic scenes store no images
            return Vector3i(0, 0, 0)
        return Vector3i(*con_i[row, I_CELL:I_CELL + 3])

    @property
    def iterMadeReal(self) -> int:
        row = self._row()
        return int(self._scene.contacts.con_i[row, I_BORN]) if row >= 0 else -1

    @property
    def iterBorn(self) -> int:
        """Step at which the interaction was created. granum keeps a step for real interactions only, the one
        at which they became real (``iterMadeReal``); YADE's collider may have created the pair earlier, when
        the bounds began to overlap. A potential interaction raises."""
        if self._row() < 0:
            raise NotImplementedError(f"Interaction({self.id1}, {self.id2}).iterBorn: granum records the step of "
                                      f"real interactions only, and this one is potential")
        return self.iterMadeReal

    def __repr__(self):
        return f"<Interaction instance at {hex(id(self))}, between bodies #{self.id1} and #{self.id2}>"


class _Found(Interaction):
    """The interactions that walks and lookups hand out: calling this class runs object's ``__init__``, not a
    Python one, and makes a handle in 52 ns where ``object.__new__(Interaction)`` took 73 (its argument checks),
    of the about 700 ns of each item walked (``benchmarks/python_walk.py``). It reports itself as ``Interaction``."""

    __slots__ = ()
    __init__ = object.__init__


_Found.__name__ = _Found.__qualname__ = "Interaction"


class InteractionContainer:
    """``O.interactions``: interactions by body pair; iteration yields the real ones."""

    __slots__ = ("_omega",)

    def __init__(self, omega):
        self._omega = omega

    @property
    def _scene(self):
        return self._omega._scene

    def _ids(self, key) -> tuple[int, int]:
        if not (isinstance(key, tuple) and len(key) == 2):
            raise TypeError("O.interactions[id1, id2]: give two body ids")
        n = self._scene.body_count
        a, b = (int(k) for k in key)
        for i in (a, b):
            if not 0 <= i < n:
                raise IndexError(f"Body id out of range: {i} (there are {n} bodies)")
        return a, b

    def _potential(self, a: int, b: int) -> bool:
        """Whether (a, b) is a potential pair (bounds overlap); erased bodies have none."""
        alive = self._scene.bodies.alive
        return bool(alive[a] and alive[b]) and find_pair(self._scene.contacts, a, b) >= 0

    def _live_pairs(self) -> np.ndarray:
        """Indices of the potential pairs whose two bodies exist."""
        C = self._scene.contacts
        n = int(C.ctr[C_PAIRS])
        alive = self._scene.bodies.alive
        return np.nonzero(alive[C.pair_ids[:n, 0]] & alive[C.pair_ids[:n, 1]])[0]

    def __getitem__(self, key) -> Interaction:
        a, b = self._ids(key)
        row = find_contact(self._scene, a, b)
        if row < 0 and not self._potential(a, b):
            raise ValueError(f"No such interaction: ({a}, {b})")
        return Interaction._found(self._scene, a, b, row)

    def has(self, id1: int, id2: int, onlyReal: bool = False) -> bool:
        a, b = self._ids((id1, id2))
        return find_contact(self._scene, a, b) >= 0 or (not onlyReal and self._potential(a, b))

    def _live_rows(self) -> np.ndarray:
        C = self._scene.contacts
        n = int(C.ctr[C_CONTACTS])
        return np.nonzero(C.con_i[:n, I_FLAGS] & FLAG_ALIVE)[0]

    def __iter__(self):
        """The real interactions, in row order. The rows and body ids are read at the start (the handles hold
        them, and a handle finds its contact again if a step moves the rows meanwhile); they become Python
        numbers a block at a time, which keeps the walk's working set in cache."""
        scene = self._scene
        C = scene.contacts
        rows = self._live_rows()
        ids = _pack(*C.con_i[rows, I_ID1:I_ID2 + 1].astype(np.int64).T)
        at, new = _rows_of(scene), _Found
        if at.phys_class is None:
            at.find_classes(rows)
        for start in range(0, rows.size, _WALK_BLOCK):
            block = slice(start, start + _WALK_BLOCK)
            for pair, row in zip(ids[block].tolist(), rows[block].tolist(), strict=True):
                intr = new()
                intr._ids = pair
                intr._hint = row
                intr._at = at
                yield intr

    def all(self, onlyReal: bool = False) -> list:
        out = list(self)
        if not onlyReal:
            C = self._scene.contacts
            for p in self._live_pairs():
                if C.pair_con[p] < 0:
                    out.append(Interaction(self._scene, int(C.pair_ids[p, 0]), int(C.pair_ids[p, 1])))
        return out

    def __len__(self) -> int:
        """The potential pairs of live bodies and the real interactions without a pair (YADE counts both). With
        every body alive, the pairs are their count, not looked at (32,768 spheres: 1.9 -> 0.12 ms)."""
        scene = self._scene
        C = scene.contacts
        pairs = int(C.ctr[C_PAIRS]) if scene.bodies.alive[:scene.body_count].all() else self._live_pairs().size
        con = C.con_i[:int(C.ctr[C_CONTACTS])]
        return pairs + int(np.count_nonzero((con[:, I_FLAGS] & FLAG_ALIVE != 0) & (con[:, I_PAIR] < 0)))

    def arrays(self, *names: str) -> dict[str, np.ndarray]:
        """granum's bulk access (not in YADE): fields of every real interaction as NumPy arrays, one row per
        interaction in iteration order, copied (later steps do not change them).

        ``id1`` and ``id2`` (k,) int64 are always included. ``names`` are fields of ``i.geom`` or ``i.phys``
        (``normalForce``, ``shearForce`` (k, 3) [N], ``penetrationDepth`` (k,) [m], ``contactPoint``,
        ``normal`` (k, 3), ``kn`` (k,) [N/m]...): a float field gives (k,), a vector (k, 3), a quaternion (k, 4),
        a matrix (k, 3, 3). A field that one of the real interactions' geometry or physics lacks is refused,
        naming the type. Example: ``fn = O.interactions.arrays("normalForce")["normalForce"]``."""
        C = self._scene.contacts
        rows = self._live_rows()
        out = {"id1": C.con_i[rows, I_ID1].astype(np.int64), "id2": C.con_i[rows, I_ID2].astype(np.int64)}
        for name in names:
            values = None
            for role, code_column in (("geom", I_GEOM), ("phys", I_PHYS)):
                codes = C.con_i[rows, code_column]
                classes = {int(c): _view_class(role, int(c)) for c in np.unique(codes)}
                if not any(name in cls._fields for cls in classes.values()):
                    continue
                for code, cls in classes.items():
                    field = cls._fields.get(name)
                    if field is None:
                        raise ValueError(f"O.interactions.arrays: {cls.__name__} has no field {name!r}")
                    col, width = field[:2]
                    mine = codes == code
                    if values is None:
                        values = np.zeros((rows.size, width))
                    values[mine] = C.con_f[rows[mine], col:col + width]
                break
            if values is None:
                widths = {cls._fields[name][1] for views in (GEOM_VIEWS, PHYS_VIEWS) for cls in views.values()
                          if name in cls._fields}
                if rows.size or len(widths) != 1:  # with no real interaction: empty, if the name is a field
                    raise ValueError(f"O.interactions.arrays: no geometry or physics of the real interactions has "
                                     f"a field {name!r}")
                values = np.zeros((0, widths.pop()))
            width = values.shape[1]
            out[name] = values[:, 0] if width == 1 else values.reshape(-1, 3, 3) if width == 9 else values
        return out

    def countReal(self) -> int:
        return int(self._live_rows().size)

    def nth(self, n: int) -> Interaction:
        return list(self)[n]

    def withBody(self, id: int) -> list:
        """Real interactions of body ``id``, in row order (none for an id outside the scene, where YADE 2023.02a
        crashes; a float or a string is refused, as YADE's argument check does)."""
        return interactions_of(self._scene, operator.index(id))

    def withBodyAll(self, id: int) -> list:
        """Real and potential interactions of body ``id``."""
        return [i for i in self.all() if id in (i._id1, i._id2)]

    @pauses_the_run
    def erase(self, id1: int, id2: int) -> bool:
        """End the real interaction between two bodies (it may form again if they still touch)."""
        a, b = self._ids((id1, id2))
        C = self._scene.contacts
        c = find_contact(self._scene, a, b)
        if c < 0:
            return False
        end_law_contact(C, c)
        return True

    @pauses_the_run
    def clear(self) -> None:
        """Remove all interactions (the collider finds the potential ones again)."""
        for i in list(self):
            self.erase(i._id1, i._id2)
        self._scene.contacts.ctr[C_PAIRS] = 0
        self._scene.needs_collider()

    @pauses_the_run
    def eraseNonReal(self) -> None:
        self._scene.needs_collider()
