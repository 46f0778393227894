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


def find_pair(C, a: int, b: int) -> int:
    """Index of the potential pair (a, b) in the sorted pair list, or -1."""
    if a > b:
        a, b = b, a
    n = int(C.ctr[C_PAIRS])
    keys = C.pair_ids[:n]
    lo = np.searchsorted(keys[:, 0], a, side="left")
    hi = np.searchsorted(keys[:, 0], a, side="right")
    k = lo + np.searchsorted(keys[lo:hi, 1], b)
    return int(k) if k < hi and keys[k, 1] == b else -1


def find_contact(C, a: int, b: int) -> int:
    """Row of the live contact between bodies a and b, or -1."""
    p = find_pair(C, a, b)
    if p >= 0:
        return int(C.pair_con[p])
    n = int(C.ctr[C_CONTACTS])  # contacts that outlived their pair (bounds apart)
    rows = np.nonzero(((C.con_i[:n, I_ID1] == a) & (C.con_i[:n, I_ID2] == b)
                       | (C.con_i[:n, I_ID1] == b) & (C.con_i[:n, I_ID2] == a))
                      & (C.con_i[:n, I_FLAGS] & FLAG_ALIVE != 0))[0]
    return int(rows[0]) if rows.size else -1


class _ContactView:
    """Attributes mapped onto float columns of one contact row (see TypeInfo.fields): a float (width 1; a
    ``(column, 1, "bool")`` field reads as a bool, ``(column, 1, "int")`` as an int), a Vector3 (3), a Quaternion
    (4, w x y z) or a Matrix3 (9)."""

    __slots__ = ("_intr",)
    _fields: dict = {}

    def __init__(self, intr=None):
        """The geometry or physics of ``intr``; with no interaction (``FrictPhys()``), of a detached one,
        whose attributes cannot be read (it is never real)."""
        object.__setattr__(self, "_intr", Interaction() if intr is None else intr)

    def __getattr__(self, name):
        f = type(self)._fields.get(name)
        if f is None:
            raise AttributeError(f"{type(self).__name__} has no attribute {name!r}")
        col, width = f[:2]
        row = self._intr._row_or_raise()
        a = self._intr._scene.contacts.con_f
        if width == 1:
            kind = {("bool",): bool, ("int",): int}.get(tuple(f[2:]), float)
            return kind(a[row, col])
        if width == 9:
            return Matrix3._wrap(a[row, col:col + 9].reshape(3, 3))
        if width == 4:
            return Quaternion._wrap(a[row, col:col + 4])
        return Vector3._wrap(a[row, col:col + 3])

    def __setattr__(self, name, value):
        f = type(self)._fields.get(name)
        if f is None:
            raise AttributeError(f"{type(self).__name__} has no attribute {name!r}")
        col, width = f[:2]
        row = self._intr._row_or_raise()
        a = self._intr._scene.contacts.con_f
        if width == 1:
            a[row, col] = float(value)
        elif width == 4:
            a[row, col:col + 4] = Quaternion(value)._a
        else:
            a[row, col:col + width] = np.asarray(value, dtype=float).reshape(width)

    def __dir__(self):
        return list(type(self)._fields)

    def __repr__(self):
        return f"<{type(self).__name__} instance at {hex(id(self))}>"


def add_views(table: dict, views: dict) -> dict:
    """Add to ``views`` a view class for each type of ``table`` (GEOM_TYPES or PHYS_TYPES) it lacks."""
    for name in table:
        if name in views:
            continue
        parent = table[name].parent
        base = views[parent] if parent else _ContactView
        views[name] = type(name, (base,), {"__slots__": (), "_fields": registry.type_fields(table, name),
                                           "__module__": __name__})
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


class Interaction:
    """A pair of bodies: potential (bounds overlap) or real (``geom`` and ``phys`` exist)."""

    __slots__ = ("_scene", "_id1", "_id2", "_cache")

    def __init__(self, scene=None, id1: int = -1, id2: int = -1):
        """A view of the pair (``id1``, ``id2``) of ``scene``; ``Interaction()`` is a detached one that is
        never real, as YADE's bare ``Interaction()``."""
        if scene is None:
            from granum.core.scene import Scene

            scene = Scene()
        self._scene = scene
        self._id1, self._id2 = int(id1), int(id2)
        self._cache = None

    def _row(self) -> int:
        key = (id(self._scene.contacts), self._scene.iter)
        if self._cache is not None and self._cache[0] == key:
            return self._cache[1]
        row = find_contact(self._scene.contacts, self._id1, self._id2)
        self._cache = (key, row)
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
        spec = functors("geom")[int(self._scene.contacts.con_i[row, I_GEOM])]
        return GEOM_VIEWS[spec.produces](self)

    @property
    def phys(self):
        row = self._row()
        if row < 0:
            return None
        spec = functors("phys")[int(self._scene.contacts.con_i[row, I_PHYS])]
        return PHYS_VIEWS[spec.produces](self)

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
        C = self._scene.contacts
        if find_contact(C, a, b) < 0 and not self._potential(a, b):
            raise ValueError(f"No such interaction: ({a}, {b})")
        return Interaction(self._scene, a, b)

    def has(self, id1: int, id2: int, onlyReal: bool = False) -> bool:
        a, b = self._ids((id1, id2))
        return find_contact(self._scene.contacts, a, b) >= 0 or (not onlyReal and self._potential(a, b))

    def _live_rows(self) -> np.ndarray:
        C = self._scene.contacts
        n = int(C.ctr[C_CONTACTS])
        return np.nonzero(C.con_i[:n, I_FLAGS] & FLAG_ALIVE)[0]

    def __iter__(self):
        C = self._scene.contacts
        for c in self._live_rows():
            yield Interaction(self._scene, int(C.con_i[c, I_ID1]), int(C.con_i[c, I_ID2]))

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

    def countReal(self) -> int:
        return int(self._live_rows().size)

    def nth(self, n: int) -> Interaction:
        return list(self)[n]

    def withBody(self, id: int) -> list:
        """Real interactions of body ``id``."""
        return [i for i in self if id in (i._id1, i._id2)]

    def withBodyAll(self, id: int) -> list:
        """Real and potential interactions of body ``id``."""
        return [i for i in self.all() if id in (i._id1, i._id2)]

    @pauses_the_run
    def erase(self, id1: int, id2: int) -> bool:
        """End the real interaction between two bodies (it may form again if they still touch)."""
        a, b = self._ids((id1, id2))
        C = self._scene.contacts
        c = find_contact(C, a, b)
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
