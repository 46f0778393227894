"""``Interaction``, its ``geom``/``phys`` views and ``O.interactions``.

An :class:`Interaction` is a handle ``(scene, id1, id2)``; it finds its row in the
interaction storage when accessed (rows move when dead contacts are compacted) and
reads and writes the columns of that row. The classes of ``i.geom`` and ``i.phys``
(``ScGeom``, ``FrictPhys``, ...) are generated from the types of the registry,
with the attributes their physics modules expose.
"""

from __future__ import annotations

import numpy as np

from granum.core.contacts import (
    C_CONTACTS,
    C_DEAD,
    C_PAIRS,
    FLAG_ALIVE,
    I_BORN,
    I_CELL,
    I_FLAGS,
    I_GEOM,
    I_ID1,
    I_ID2,
    I_PAIR,
    I_PHYS,
    end_contact,
)
from granum.kernels.dispatch import functors
from granum.mathtypes import Matrix3, Quaternion, Vector3, Vector3i
from granum.physics import registry
from granum.yade._pausing import pauses_the_run


def _lower_bound(column, lo: int, hi: int, value: int) -> int:
    """First index in [lo, hi) of the sorted ``column`` whose value is not below ``value``. A loop over the
    strided column: NumPy's searchsorted would first copy the whole column (O(n) for one lookup)."""
    while lo < hi:
        mid = (lo + hi) >> 1
        if column[mid] < value:
            lo = mid + 1
        else:
            hi = mid
    return lo


def find_pair(C, a: int, b: int) -> int:
    """Index of the potential pair (a, b) in the sorted pair list, or -1 (O(log n))."""
    if a > b:
        a, b = b, a
    n = int(C.ctr[C_PAIRS])
    first, second = C.pair_ids[:n, 0], C.pair_ids[:n, 1]
    lo = _lower_bound(first, 0, n, a)
    hi = _lower_bound(first, lo, n, a + 1)
    k = _lower_bound(second, lo, hi, b)
    return k if k < hi and second[k] == b else -1


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
    key = (iteration, int(C.ctr[C_CONTACTS]), int(C.ctr[C_PAIRS]), C.con_i.__array_interface__["data"][0])
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


class _ContactView:
    """Attributes mapped onto float columns of one contact row (see TypeInfo.fields): a float (width 1; a
    ``(column, 1, "bool")`` field reads as a bool, ``(column, 1, "int")`` as an int), a Vector3 (3), a Quaternion
    (4, w x y z) or a Matrix3 (9). Each field is a property of the generated class (``add_views``): reading one
    costs O(1)."""

    __slots__ = ("_intr",)
    _fields: dict = {}

    def __init__(self, intr=None):
        """The geometry or physics of ``intr``; with no interaction (``FrictPhys()``), of a detached one,
        whose attributes cannot be read (it is never real)."""
        object.__setattr__(self, "_intr", Interaction() if intr is None else intr)

    @classmethod
    def _of(cls, intr: Interaction):
        view = object.__new__(cls)
        object.__setattr__(view, "_intr", intr)
        return view

    def __getattr__(self, name):  # only reached for names that are not fields
        raise AttributeError(f"{type(self).__name__} has no attribute {name!r}")

    def __setattr__(self, name, value):
        if name not in type(self)._fields:
            raise AttributeError(f"{type(self).__name__} has no attribute {name!r}")
        object.__setattr__(self, name, value)

    def __dir__(self):
        return list(type(self)._fields)

    def __repr__(self):
        return f"<{type(self).__name__} instance at {hex(id(self))}>"


def _field_property(name: str, field: tuple) -> property:
    """The property reading and writing ``field`` = (column, width[, "bool"]) of the view's contact row."""
    col, width = field[:2]
    end = col + width
    scalar = {"bool": bool, "int": int}.get(field[2] if len(field) > 2 else "float", float)
    kind = {1: scalar, 3: Vector3, 4: Quaternion, 9: Matrix3}[width]

    def get(view):
        intr = view._intr
        row = intr._row()
        if row < 0:
            intr._row_or_raise()
        a = intr._scene.contacts.con_f
        if width == 1:
            return scalar(a.item(row, col))
        return kind._new(a[row, col:end] if width != 9 else a[row, col:end].reshape(3, 3))

    def put(view, value):
        intr = view._intr
        row = intr._row_or_raise()
        a = intr._scene.contacts.con_f
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

    intr = self._intr
    row = intr._row_or_raise()
    s = intr._scene
    return Vector3(*call(incident_velocity, s.arrays(), CONTACTS.to_record(s.contacts), row,
                         bool(avoidGranularRatcheting)))


GEOM_VIEWS["ScGeom"].incidentVel = _incident_vel
PHYS_VIEWS = add_views(registry.PHYS_TYPES, {})


_view_classes: dict = {"geom": [], "phys": []}


def _view_class(role: str, code: int):
    """The view class of the output of the ``role`` functor of this code. Codes follow registration order and
    a functor keeps its code, so the list is only extended, when a functor registered later (a user's law)
    shows up."""
    classes = _view_classes[role]
    if code >= len(classes):
        views = GEOM_VIEWS if role == "geom" else PHYS_VIEWS
        classes[:] = [views[f.produces] for f in functors(role)]
    return classes[code]


class Interaction:
    """A pair of bodies: potential (bounds overlap) or real (``geom`` and ``phys`` exist)."""

    __slots__ = ("_scene", "_id1", "_id2", "_hint", "_seen", "_dead")

    def __init__(self, scene=None, id1: int = -1, id2: int = -1):
        """A view of the pair (``id1``, ``id2``) of ``scene``; ``Interaction()`` is a detached one that is
        never real, as YADE's bare ``Interaction()``."""
        if scene is None:
            from granum.core.scene import Scene

            scene = Scene()
        self._scene = scene
        self._id1, self._id2 = int(id1), int(id2)
        self._hint, self._seen, self._dead = -1, None, -1

    @classmethod
    def _at(cls, scene, id1: int, id2: int, row: int, contacts=None, dead: int = -1) -> Interaction:
        """The interaction of contact row ``row`` (bodies ``id1``, ``id2``, Python ints), known to hold them in
        ``contacts`` with ``dead`` ended rows (see ``_row``); with no ``contacts``, checked at first use."""
        intr = object.__new__(cls)
        intr._scene, intr._id1, intr._id2, intr._hint, intr._seen, intr._dead = scene, id1, id2, row, contacts, dead
        return intr

    def _row(self) -> int:
        """The contact row, or -1 when not real; O(1).

        The row found last is kept with the contact arrays it was found in and their count of ended rows.
        Contact rows move only inside compiled code, after which the runner stores new arrays in the scene,
        and end only through ``end_contact``, which counts them: while both are unchanged the row is still
        right. Otherwise the row found last is checked, and looked up again (O(log n)) if it moved."""
        C = self._scene.contacts
        if C is self._seen and C.ctr.item(C_DEAD) == self._dead:
            return self._hint
        row = self._hint
        if not (row >= 0 and _holds(C, row, self._id1, self._id2)):
            row = find_contact(self._scene, self._id1, self._id2)
        self._hint, self._seen, self._dead = row, C, C.ctr.item(C_DEAD)
        return row

    def _row_or_raise(self) -> int:
        row = self._row()
        if row < 0:
            raise RuntimeError(f"interaction ({self._id1}, {self._id2}) is no longer real")
        return row

    @property
    def id1(self) -> int:
        row = self._row()
        return int(self._scene.contacts.con_i[row, I_ID1]) if row >= 0 else self._id1

    @property
    def id2(self) -> int:
        row = self._row()
        return int(self._scene.contacts.con_i[row, I_ID2]) if row >= 0 else self._id2

    @property
    def isReal(self) -> bool:
        return self._row() >= 0

    @property
    def isActive(self) -> bool:
        return True

    @property
    def geom(self):
        row = self._row()
        if row < 0:
            return None
        return _view_class("geom", self._scene.contacts.con_i.item(row, I_GEOM))._of(self)

    @property
    def phys(self):
        row = self._row()
        if row < 0:
            return None
        return _view_class("phys", self._scene.contacts.con_i.item(row, I_PHYS))._of(self)

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
        return Interaction._at(self._scene, a, b, row)

    def has(self, id1: int, id2: int, onlyReal: bool = False) -> bool:
        a, b = self._ids((id1, id2))
        return find_contact(self._scene, a, b) >= 0 or (not onlyReal and self._potential(a, b))

    def _live_rows(self) -> np.ndarray:
        C = self._scene.contacts
        n = int(C.ctr[C_CONTACTS])
        return np.nonzero(C.con_i[:n, I_FLAGS] & FLAG_ALIVE)[0]

    def __iter__(self):
        scene = self._scene
        C = scene.contacts
        rows = self._live_rows()
        ids = C.con_i[rows, I_ID1:I_ID2 + 1].tolist()
        dead = C.ctr.item(C_DEAD)
        for (a, b), row in zip(ids, rows.tolist(), strict=True):
            yield Interaction._at(scene, a, b, row, C, dead)

    def all(self, onlyReal: bool = False) -> list:
        out = list(self)
        if not onlyReal:
            C = self._scene.contacts
            for p in self._live_pairs():
                if C.pair_con[p] < 0:
                    out.append(Interaction(self._scene, int(C.pair_ids[p, 0]), int(C.pair_ids[p, 1])))
        return out

    def __len__(self) -> int:
        C = self._scene.contacts
        rows = self._live_rows()
        return int(self._live_pairs().size) + int(np.count_nonzero(C.con_i[rows, I_PAIR] < 0))

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
        """Real interactions of body ``id``."""
        scene = self._scene
        rows = self._live_rows()
        ids = scene.contacts.con_i[rows, I_ID1:I_ID2 + 1]
        mine = np.nonzero((ids[:, 0] == id) | (ids[:, 1] == id))[0]
        return [Interaction._at(scene, a, b, row)
                for (a, b), row in zip(ids[mine].tolist(), rows[mine].tolist(), strict=True)]

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
        end_contact(C, c)
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
