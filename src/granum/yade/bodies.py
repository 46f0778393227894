"""``Body``, ``State``, the shapes and ``O.bodies``: views onto the body storage.

None of these objects holds data. A :class:`Body` is a handle ``(store, id)`` onto a
row of a :class:`~granum.core.scene.BodyStore`; ``b.state`` and ``b.shape`` are views
through that handle, and vectors they return (``b.state.pos``) are views onto the
storage rows, so ``b.state.vel[2] = 1`` writes into the scene's arrays. A body
created by ``utils.sphere(...)`` lives in the store of detached bodies (:class:`_Nursery`) until
``O.bodies.append`` copies it into the scene and re-points the handle.
"""

from __future__ import annotations

import numpy as np

from granum.core import validate
from granum.core.bodies import (
    CPM_EPS_VOLUMETRIC,
    CPM_IS_STATE,
    CPM_NORM_DMG,
    CPM_NUM_CONTACTS,
    CPM_STRESS,
    DOF_ALL,
    dofs_from_string,
    dofs_to_string,
)
from granum.core.contacts import C_CONTACTS, FLAG_ALIVE, I_FLAGS, I_ID1, I_ID2
from granum.core.scene import BodyStore, Scene
from granum.core.shapes import ShapeKind, shape_type
from granum.mathtypes import Matrix3, Quaternion, Vector3, as_quat_wxyz, as_vec3
from granum.yade._pausing import pauses_the_run
from granum.yade.interactions import end_law_contact, interactions_of


class _Nursery(BodyStore):
    """The storage of the bodies, states and shapes that are not in a simulation (yet).

    ``utils.sphere()`` and its kin make many small bodies that ``O.bodies.append`` then copies
    into the scene. They all live as rows of this one store -- a few hundred bytes each -- rather
    than in a store of their own (6 kB and 100 us each, which made building a million-sphere
    scene take 13 GB). When no detached body is left (all appended or garbage-collected), tables
    longer than :data:`KEEP_ROWS` are dropped, so that the memory of a large scene's building
    does not outlast it; shorter ones are kept for the next bodies: a script appending its spheres
    one at a time (``O.bodies.append(sphere(...))`` in a loop) made new tables for each sphere,
    257.6 us a sphere against YADE's 20.9.
    """

    #: rows given their defaults at once when the nursery has none ready (one NumPy call a column for all)
    BLOCK = 256
    #: the longest tables kept when the last detached body is gone [rows] (each body adds a row to its shape's
    #: table, which rows released are not taken back from: 2 MB at most)
    KEEP_ROWS = 4096

    def __init__(self):
        super().__init__(capacity=64)
        self.live = 0
        self.ready: list[int] = []      # rows holding the defaults, the next one last
        self.released: list[int] = []   # rows given back (shapes and states made on the way), reset when needed

    def new_row(self) -> int:
        if not self.ready:
            if self.released:
                rows, self.released = self.released, []
                self.bodies.reset_rows(np.array(rows))
            else:
                first = self.bodies.append_rows(self.BLOCK)
                rows = range(first, first + self.BLOCK)
            self.ready = list(reversed(rows))
        row = self.ready.pop()
        self.bodies.alive[row] = True
        self.live += 1
        return row

    def release(self, *rows: int) -> None:
        """Body rows ``rows`` are free again (their bodies were appended or dropped)."""
        self.live -= len(rows)
        if self.live == 0 and self.longest_table() > self.KEEP_ROWS:
            self.__init__()
        else:
            self.released.extend(rows)

    def longest_table(self) -> int:
        """The row count of the longest of the nursery's tables."""
        return max(self.bodies.count, self.clump_members.count, *(t.count for t in self.shapes.values()))


_NURSERY = _Nursery()
_new_object = object.__new__  # handles made without a Python call (walks over O.bodies)


def _detached_handle() -> Body:
    """A handle on a new row of the nursery (its defaults), made without ``Body.__init__``."""
    body = _new_object(_DetachedBody)
    object.__setattr__(body, "_store", _NURSERY)
    object.__setattr__(body, "_row", _NURSERY.new_row())
    return body


def _all_detached(bodies) -> bool:
    """Whether ``bodies`` are all bodies of the nursery (a ``_DetachedBody`` is one), each once (then they may be
    appended together)."""
    return all([type(x) is _DetachedBody for x in bodies]) and len({x._row for x in bodies}) == len(bodies)


def _finite3(view, name: str, value) -> np.ndarray:
    """``value`` as a 3-vector of finite components, for attribute ``name`` of ``view`` (named in the error)."""
    a = as_vec3(value)
    validate.FINITE_VECTOR.check(a, lambda: f"{view._owner()}.{name}")
    return a


class Body:
    """A particle: shape, material and state (YADE ``Body``). ``id`` is -1 until appended."""

    __slots__ = ("_store", "_row")
    ID_NONE = -1

    def __init__(self, shape=None, state=None, material=None, mask: int = 1, dynamic=None):
        if type(self) is Body:
            self.__class__ = _DetachedBody   # until appended (see _DetachedBody)
        object.__setattr__(self, "_store", _NURSERY)
        object.__setattr__(self, "_row", _NURSERY.new_row())
        if state is not None:
            self.state = state
        if shape is not None:
            self.shape = shape
        if material is not None:
            self.material = material
        self.mask = mask
        if dynamic is not None:
            self.dynamic = dynamic

    # ---- identity -----------------------------------------------------------------
    @property
    def id(self) -> int:
        return self._row if isinstance(self._store, Scene) else Body.ID_NONE

    def _col(self, name: str):
        return getattr(self._store.bodies, name)

    def _attached(self) -> bool:
        return isinstance(self._store, Scene)

    def __eq__(self, other):
        return isinstance(other, Body) and other._store is self._store and other._row == self._row

    def __hash__(self):
        return hash((id(self._store), self._row))

    def __repr__(self):
        return f"<Body instance at {hex(id(self))}, id {self.id}>"

    # ---- parts ----------------------------------------------------------------------
    @property
    def state(self) -> State:
        cpm = vars(self._store.bodies).get("cpm_state")  # Table.stored without its empty array for a lazy column
        cpm_state = cpm is not None and self._row < cpm.shape[0] and cpm[self._row, CPM_IS_STATE] != 0.0
        st = _new_object(CpmState if cpm_state else State)  # State._view, inlined
        st._body = self
        return st

    @state.setter
    def state(self, st: State) -> None:
        if not isinstance(st, State):
            raise TypeError(f"Body.state must be a State, got {st!r}")
        src = st._body
        for name in type(st)._columns:
            self._col(name)[self._row] = src._col(name)[src._row]
        if not isinstance(st, CpmState) and self._store.bodies.allocated("cpm_state"):
            self._col("cpm_state")[self._row] = 0.0   # a plain State now

    @property
    def shape(self):
        kind = ShapeKind(int(self._col("shape_kind")[self._row]))
        cls = SHAPE_CLASSES.get(kind)
        return None if cls is None else cls._view(self)

    @shape.setter
    def shape(self, sh) -> None:
        if not isinstance(sh, Shape):
            names = ", ".join(c.__name__ for c in SHAPE_CLASSES.values())
            raise TypeError(f"Body.shape must be a Shape ({names}), got {sh!r}")
        src = sh._body
        kind, table, row = src._store.shape_table(src._row)
        dst = self._store.shapes[kind]
        new_row = dst.append_copy(table, row)
        b = self._store.bodies
        b.shape_kind[self._row] = int(kind)
        b.shape_row[self._row] = new_row
        for name in ("color", "wire", "highlight"):
            getattr(b, name)[self._row] = src._col(name)[src._row]
        b.aspherical[self._row] = shape_type(kind).aspherical
        self._sync_ang_mom()
        self._touch()

    @property
    def material(self):
        k = int(self._col("material")[self._row])
        return None if k < 0 else self._store.materials[k]

    @material.setter
    def material(self, m) -> None:
        from granum.yade.materials import Material

        if not isinstance(m, Material):
            raise TypeError(f"Body.material must be a Material, got {m!r}")
        self._col("material")[self._row] = self._store.material_index(m)

    mat = material

    @property
    def bound(self):
        b = self._store.bodies
        if not self._attached() or not b.bound_min[self._row, 0] <= b.bound_max[self._row, 0]:
            return None
        return Aabb(self)

    # ---- flags ----------------------------------------------------------------------
    @property
    def mask(self) -> int:
        return int(self._col("mask")[self._row])

    @mask.setter
    def mask(self, value: int) -> None:
        self._col("mask")[self._row] = int(value)
        self._touch()

    groupMask = mask

    @property
    def dynamic(self) -> bool:
        return int(self._col("blocked")[self._row]) != DOF_ALL

    @dynamic.setter
    def dynamic(self, value: bool) -> None:
        self._col("blocked")[self._row] = 0 if value else DOF_ALL
        if not value:
            self._col("vel")[self._row] = 0.0
            self._col("ang_vel")[self._row] = 0.0

    @property
    def aspherical(self) -> bool:
        return bool(self._col("aspherical")[self._row])

    @aspherical.setter
    def aspherical(self, value: bool) -> None:
        self._col("aspherical")[self._row] = bool(value)
        self._sync_ang_mom()

    def _sync_ang_mom(self) -> None:
        """An aspherical body is integrated through its angular momentum L = R I R^T w (R: its
        orientation): set L from the angular velocity (only such bodies use the column)."""
        if self._col("aspherical")[self._row]:
            r = np.asarray(Quaternion._wrap(self._col("ori")[self._row]).toRotationMatrix()._a)
            w = self._col("ang_vel")[self._row]
            self._col("ang_mom")[self._row] = r @ (self._col("inertia")[self._row] * (r.T @ w))

    @property
    def iterBorn(self) -> int:
        """Step (``O.iter``) at which the body was appended; -1 for a body not in a simulation."""
        return int(self._store.born.iter[self._row]) if self._attached() else -1

    @property
    def timeBorn(self) -> float:
        """Simulated time (``O.time``) at which the body was appended [s]; -1 for a body not in a simulation."""
        return float(self._store.born.time[self._row]) if self._attached() else -1.0

    @property
    def clumpId(self) -> int:
        return int(self._col("clump_id")[self._row])

    @property
    def isClump(self) -> bool:
        return int(self._col("shape_kind")[self._row]) == ShapeKind.CLUMP

    @property
    def bounded(self) -> bool:
        """Whether the body has a bound the collider sees: every body but a clump (whose members have theirs)."""
        return not self.isClump

    @property
    def isClumpMember(self) -> bool:
        return self.clumpId >= 0 and not self.isClump

    @property
    def isStandalone(self) -> bool:
        return self.clumpId < 0

    def intrs(self) -> list:
        """Real interactions of this body, in row order."""
        return interactions_of(self._store, self._row) if self._attached() else []

    def _touch(self) -> None:
        """The body's geometry changed: make the collider run again."""
        if self._attached():
            self._store.needs_collider()



class _DetachedBody(Body):
    """A body not in a simulation (yet): a row of the nursery, given back when the body is dropped.
    ``O.bodies.append`` makes it a plain :class:`Body` (it assigns the class), so that the handles of the bodies
    in a scene, made by the thousand in walks over ``O.bodies``, have no finalizer to run (80 ns each)."""

    __slots__ = ()

    def __del__(self):
        store = getattr(self, "_store", None)
        if store is _NURSERY:
            store.release(self._row)


_DetachedBody.__name__ = _DetachedBody.__qualname__ = "Body"   # it prints and reports as a Body


class _View:
    """A view through a body handle; unknown attribute names raise AttributeError (the classes have slots and no
    ``__dict__``; like ``Body``, they define no ``__setattr__``, which would disable CPython's fast attribute
    paths in walks over ``O.bodies``)."""

    __slots__ = ("_body",)

    def _col(self, name: str):
        return self._body._col(name)

    @property
    def _row(self) -> int:
        return self._body._row

    def _owner(self) -> str:
        i = self._body.id
        return type(self).__name__ if i < 0 else f"{type(self).__name__} of body {i}"


def _vec_property(column: str, doc: str, touch: bool = False):
    def get(self):
        body = self._body
        value = _new_object(Vector3)   # Vector3._new, inlined: walks over O.bodies read positions by the thousand
        value._a = getattr(body._store.bodies, column)[body._row]   # float64 (n, 3): no check needed
        return value

    def set(self, value):
        self._col(column)[self._row] = _finite3(self, column, value)
        if touch:
            self._body._touch()

    return property(get, set, doc=doc)


def _quat_property(column: str, doc: str):
    def get(self):
        return Quaternion._wrap(self._col(column)[self._row])

    def set(self, value):
        q = as_quat_wxyz(value)
        validate.QUATERNION.check(q, lambda: f"{self._owner()}.{column}")
        self._col(column)[self._row] = q / np.linalg.norm(q)

    return property(get, set, doc=doc)


class State(_View):
    """Kinematic state and mass properties of a body (YADE ``State``)."""

    __slots__ = ()
    _columns = ("pos", "vel", "ori", "ang_vel", "ang_mom", "mass", "inertia", "blocked", "is_damped",
                "ref_pos", "ref_ori")

    def __init__(self, **kw):
        object.__setattr__(self, "_body", _detached_handle())
        for k, v in kw.items():
            setattr(self, k, v)

    @classmethod
    def _view(cls, body: Body) -> State:
        st = object.__new__(cls)
        object.__setattr__(st, "_body", body)
        return st

    pos = _vec_property("pos", "Position of the centre of mass [m]", touch=False)
    vel = _vec_property("vel", "Linear velocity [m/s]")
    refPos = _vec_property("ref_pos", "Reference position [m]")
    angMom = _vec_property("ang_mom", "Angular momentum [kg m^2/s]")
    inertia = _vec_property("inertia", "Principal moments of inertia [kg m^2]")
    ori = _quat_property("ori", "Orientation")
    refOri = _quat_property("ref_ori", "Reference orientation")

    @property
    def angVel(self):
        """Angular velocity [rad/s]."""
        return Vector3._wrap(self._col("ang_vel")[self._row])

    @angVel.setter
    def angVel(self, value) -> None:
        w = _finite3(self, "angVel", value)
        self._col("ang_vel")[self._row] = w
        self._body._sync_ang_mom()

    @property
    def mass(self) -> float:
        """Mass [kg]."""
        return float(self._col("mass")[self._row])

    @mass.setter
    def mass(self, value: float) -> None:
        x = float(value)
        validate.NON_NEGATIVE_FINITE.check(x, lambda: f"{self._owner()}.mass")
        self._col("mass")[self._row] = x

    @property
    def blockedDOFs(self) -> str:
        """Blocked degrees of freedom, a subset of ``'xyzXYZ'``."""
        return dofs_to_string(int(self._col("blocked")[self._row]))

    @blockedDOFs.setter
    def blockedDOFs(self, value: str) -> None:
        self._col("blocked")[self._row] = dofs_from_string(value)

    @property
    def isDamped(self) -> bool:
        return bool(self._col("is_damped")[self._row])

    @isDamped.setter
    def isDamped(self, value: bool) -> None:
        self._col("is_damped")[self._row] = bool(value)

    @property
    def se3(self):
        return (self.pos, self.ori)

    def displ(self):
        """Displacement from the reference position [m]."""
        return self.pos - self.refPos

    def rot(self):
        """Rotation vector from the reference orientation [rad]."""
        q = self.ori * self.refOri.conjugate()
        axis, angle = q.toAxisAngle()
        return axis * angle

    def __repr__(self):
        return f"<State instance at {hex(id(self))}>"


class CpmState(State):
    """State of a body of the concrete model (YADE ``CpmState``, the state a CpmMat asks for): the per-body
    values CpmStateUpdater computes (post-processing only; no physics reads them). numBrokenCohesive is
    counted by Law2_ScGeom_CpmPhys_Cpm as contacts end."""

    __slots__ = ()
    _columns = State._columns + ("cpm_state", "cpm_broken")

    def __init__(self, **kw):
        super().__init__()
        self._col("cpm_state")[self._row, CPM_IS_STATE] = 1.0
        for k, v in kw.items():
            setattr(self, k, v)

    def _slot(self, k: int) -> float:
        return float(self._col("cpm_state")[self._row, k])

    def _set_slot(self, k: int, value) -> None:
        self._col("cpm_state")[self._row, k] = float(value)

    normDmg = property(lambda self: self._slot(CPM_NORM_DMG), lambda self, v: self._set_slot(CPM_NORM_DMG, v),
                       doc="Average damage including the contacts already ended: 1 - relative residual strength [-]")
    epsVolumetric = property(lambda self: self._slot(CPM_EPS_VOLUMETRIC),
                             lambda self, v: self._set_slot(CPM_EPS_VOLUMETRIC, v),
                             doc="Volumetric strain around the body (YADE leaves it as set) [-]")
    numContacts = property(lambda self: int(self._slot(CPM_NUM_CONTACTS)),
                           lambda self, v: self._set_slot(CPM_NUM_CONTACTS, int(v)),
                           doc="Number of contacts (YADE's CpmStateUpdater leaves it as set) [-]")

    @property
    def numBrokenCohesive(self) -> int:
        """Number of the body's contacts that the concrete law ended (broken bonds) [-]."""
        return int(self._col("cpm_broken")[self._row])

    @numBrokenCohesive.setter
    def numBrokenCohesive(self, value) -> None:
        self._col("cpm_broken")[self._row] = int(value)

    @property
    def stress(self):
        """Stress of the spherical particle, for a packing fraction 0.62 (CpmStateUpdater) [Pa]."""
        return Matrix3._wrap(self._col("cpm_state")[self._row, CPM_STRESS:CPM_STRESS + 9].reshape(3, 3))

    @stress.setter
    def stress(self, value) -> None:
        self._col("cpm_state")[self._row, CPM_STRESS:CPM_STRESS + 9] = np.asarray(value, float).reshape(9)

    @property
    def damageTensor(self):
        """YADE's microplane damage tensor: not computed by granum (YADE 2023.02a's values are not
        reproducible)."""
        raise NotImplementedError("CpmState.damageTensor is not implemented in granum")

    def __repr__(self):
        return f"<CpmState instance at {hex(id(self))}>"


class Aabb(_View):
    """Axis-aligned bound of a body (read-only view; includes the Verlet enlargement)."""

    __slots__ = ()

    def __init__(self, body: Body | None = None):
        """The bound of ``body``; ``Aabb()`` is the bound of a new detached body (as YADE's bare ``Aabb()``)."""
        object.__setattr__(self, "_body", Body() if body is None else body)

    @property
    def min(self):
        return Vector3(*self._col("bound_min")[self._row])

    @property
    def max(self):
        return Vector3(*self._col("bound_max")[self._row])


#: The view class of each shape kind, by kind (filled by :meth:`Shape.__init_subclass__`).
SHAPE_CLASSES: dict = {}


class Shape(_View):
    """Base of shapes: ``color``, ``wire``, ``highlight`` (YADE ``Shape``).

    A subclass is the view of the shape kind declared under its class name (the YADE class name,
    :data:`granum.core.shapes.SHAPES`): defining it sets its ``kind`` and makes it the class of
    ``b.shape`` for bodies of that kind and a name of the YADE namespace. Its class attributes say
    how output treats the kind: ``vtk``, the ``VTKRecorder`` base recorder and file part that
    writes these bodies (None: not written; shapes with ``faces`` are written as polygons), and
    ``vtk_coord_number``, whether that file has ``coordNumber`` cell data.
    """

    __slots__ = ()
    kind = ShapeKind.NONE
    vtk: str | None = None
    vtk_coord_number = False

    def __init_subclass__(cls, **kw):
        super().__init_subclass__(**kw)
        if cls.__name__.upper() not in ShapeKind.__members__:
            raise TypeError(f"shape view {cls.__name__}: no shape kind of that name is declared in "
                            f"granum.core.shapes.SHAPES")
        cls.kind = ShapeKind[cls.__name__.upper()]
        SHAPE_CLASSES[cls.kind] = cls

    def __init__(self, color=None, wire: bool = False, highlight: bool = False, **kw):
        object.__setattr__(self, "_body", _detached_handle())
        self._fill(color, wire, highlight, kw)

    def _fill(self, color, wire: bool, highlight: bool, values: dict) -> None:
        """Give the body row this view looks through a new row of the kind's shape table, and set ``color``,
        ``wire``, ``highlight`` and the kind's attributes ``values`` (name -> value) through their setters."""
        body = self._body
        store, row = body._store, body._row
        store.bodies.shape_kind[row] = int(self.kind)
        store.bodies.shape_row[row] = store.shapes[self.kind].append_rows(1) if self.kind in store.shapes else -1
        if color is not None:
            self.color = color
        self.wire = wire
        self.highlight = highlight
        for k, v in values.items():
            setattr(self, k, v)

    @classmethod
    def new_body(cls, color=None, wire: bool = False, highlight: bool = False, **values) -> Body:
        """A new detached body of this shape, as ``Body(shape=cls(color=color, ...))`` makes (the utils factories'
        bodies), with the shape written straight into the body's rows rather than into rows of its own first and
        copied."""
        body = _detached_handle()   # Body() without its setters: a new row holds Body()'s defaults
        cls._view(body)._fill(color, wire, highlight, values)
        body._store.bodies.aspherical[body._row] = shape_type(cls.kind).aspherical
        body._sync_ang_mom()
        return body

    @classmethod
    def _view(cls, body: Body):
        sh = object.__new__(cls)
        object.__setattr__(sh, "_body", body)
        return sh

    def _table(self):
        b = self._body
        return b._store.shapes[self.kind], int(b._col("shape_row")[b._row])

    def _check(self, column: str, value) -> None:
        """Raise ValueError unless ``value`` obeys the rule the kind declares for ``column``."""
        shape_type(self.kind).rules[column].check(value, lambda: f"{self._owner()}.{column}")

    color = _vec_property("color", "Display colour, RGB in [0, 1]")

    @property
    def wire(self) -> bool:
        return bool(self._col("wire")[self._row])

    @wire.setter
    def wire(self, value: bool) -> None:
        self._col("wire")[self._row] = bool(value)

    @property
    def highlight(self) -> bool:
        return bool(self._col("highlight")[self._row])

    @highlight.setter
    def highlight(self, value: bool) -> None:
        self._col("highlight")[self._row] = bool(value)

    def __repr__(self):
        return f"<{type(self).__name__} instance at {hex(id(self))}>"


class Sphere(Shape):
    """Sphere of radius ``radius`` [m]."""

    __slots__ = ()
    vtk = "spheres"

    @property
    def radius(self) -> float:
        t, row = self._table()
        return float(t.radius[row])

    @radius.setter
    def radius(self, value: float) -> None:
        r = float(value)
        self._check("radius", r)
        t, row = self._table()
        t.radius[row] = r
        self._body._touch()


class Facet(Shape):
    """Triangle given by three vertices relative to the body position [m] (local frame)."""

    __slots__ = ()
    vtk = "facets"
    vtk_coord_number = True

    @property
    def vertices(self) -> list:
        t, row = self._table()
        return [Vector3._wrap(t.vertices[row, k]) for k in range(3)]

    @vertices.setter
    def vertices(self, value) -> None:
        if len(value) != 3:
            raise ValueError(f"{self._owner()}.vertices {shape_type(self.kind).rules['vertices'].says}, "
                             f"got {len(value)} vectors")
        v = np.array([as_vec3(x) for x in value])
        self._check("vertices", v)
        n = np.cross(v[1] - v[0], v[2] - v[0])
        area2 = np.linalg.norm(n)
        t, row = self._table()
        t.vertices[row] = v
        t.normal[row] = n / area2
        self._body._touch()

    @property
    def normal(self):
        t, row = self._table()
        return Vector3(*t.normal[row])

    @property
    def area(self) -> float:
        t, row = self._table()
        v = t.vertices[row]
        return 0.5 * float(np.linalg.norm(np.cross(v[1] - v[0], v[2] - v[0])))


class Wall(Shape):
    """Infinite plane normal to ``axis`` (0, 1, 2); ``sense`` -1, 0, +1 selects the active side."""

    __slots__ = ()

    @property
    def axis(self) -> int:
        t, row = self._table()
        return int(t.axis[row])

    @axis.setter
    def axis(self, value: int) -> None:
        self._check("axis", value)
        t, row = self._table()
        t.axis[row] = value
        self._body._touch()

    @property
    def sense(self) -> int:
        t, row = self._table()
        return int(t.sense[row])

    @sense.setter
    def sense(self, value: int) -> None:
        self._check("sense", value)
        t, row = self._table()
        t.sense[row] = value
        self._body._touch()   # the sides it acts on: the detection's budgets measured the old ones


class Box(Shape):
    """Cuboid with half-sizes ``extents`` [m] along its local axes."""

    __slots__ = ()
    vtk = "boxes"

    @property
    def extents(self):
        t, row = self._table()
        return Vector3._wrap(t.extents[row])

    @extents.setter
    def extents(self, value) -> None:
        e = as_vec3(value)
        self._check("extents", e)
        t, row = self._table()
        t.extents[row] = e
        self._body._touch()


class Clump(Shape):
    """Shape of a clump body: a rigid aggregate of member bodies (see ``O.bodies.clump``)."""

    __slots__ = ()

    @property
    def members(self) -> dict:
        """Member ids and their offsets in the clump frame: ``{id: (Vector3, Quaternion)}``, by increasing id
        (YADE keeps members in a map by id)."""
        from granum.yade.clumps import clump_members

        b = self._body
        if not b._attached():
            return {}
        bt = b._store.bodies
        return {i: (Vector3(*bt.clump_rel_pos[i]), Quaternion(*bt.clump_rel_ori[i]))
                for i in sorted(clump_members(b._store, b._row))}

    @property
    def ids(self) -> list:
        return list(self.members)


def _body_of(scene: Scene, i: int) -> Body:
    """The handle of body ``i`` (a Python int) of ``scene``."""
    b = _new_object(Body)
    b._store = scene
    b._row = i
    return b


class BodyContainer:
    """``O.bodies``: bodies by id; appending copies a body into the scene's storage."""

    __slots__ = ("_omega",)

    def __init__(self, omega):
        self._omega = omega

    @property
    def _scene(self) -> Scene:
        return self._omega._scene

    def __len__(self) -> int:
        return self._scene.body_count

    def _check(self, i: int) -> int:
        n = self._scene.body_count
        if not isinstance(i, int | np.integer):
            raise TypeError(f"body id must be an integer, got {i!r}")
        i = int(i)
        if i < 0:
            i += n
        if not 0 <= i < n:
            raise IndexError(f"Body id out of range: {i} (there are {n} bodies)")
        return i

    def __getitem__(self, i):
        i = self._check(i)
        if not self._scene.bodies.alive[i]:
            return None
        return _body_of(self._scene, i)

    def __iter__(self):
        scene = self._scene
        new = _new_object
        for i in np.flatnonzero(scene.bodies.alive[:scene.body_count]).tolist():
            b = new(Body)  # _body_of, inlined
            b._store = scene
            b._row = i
            yield b

    #: ``arrays()`` names: YADE's State attribute (or O.forces quantity) -> body column
    ARRAY_COLUMNS = {"pos": "pos", "vel": "vel", "angVel": "ang_vel", "ori": "ori", "angMom": "ang_mom",
                     "inertia": "inertia", "mass": "mass", "refPos": "ref_pos", "refOri": "ref_ori",
                     "force": "force", "torque": "torque"}

    def arrays(self, *names: str) -> dict[str, np.ndarray]:
        """granum's bulk access (not in YADE): the quantities ``names`` of every existing body as NumPy arrays,
        one row per body in the order of ``ids``, copied (later steps do not change them).

        ``ids`` (n,) int64 is always included. Names are YADE's: ``pos``, ``vel``, ``angVel``, ``angMom``,
        ``inertia``, ``refPos`` (n, 3) [m, m/s, rad/s, kg m²/s, kg m², m]; ``ori``, ``refOri`` (n, 4), quaternions
        as (w, x, y, z); ``mass`` (n,) [kg]; ``force`` (n, 3) [N] and ``torque`` (n, 3) [N m], those of
        ``O.forces`` (the last step's). Example: ``z = O.bodies.arrays("pos")["pos"][:, 2]``."""
        unknown = [n for n in names if n not in self.ARRAY_COLUMNS]
        if unknown:
            raise ValueError(f"O.bodies.arrays: unknown quantities {unknown}; known: {sorted(self.ARRAY_COLUMNS)}")
        bodies = self._scene.bodies
        ids = np.flatnonzero(bodies.alive[:self._scene.body_count])
        out = {"ids": ids}
        for name in names:
            column = bodies.stored(self.ARRAY_COLUMNS[name])
            out[name] = column[ids] if len(column) else np.zeros((ids.size,) + column.shape[1:])
        return out

    @pauses_the_run
    def append(self, b):
        """Add a body (return its id) or a list of bodies (return the list of ids)."""
        if isinstance(b, list | tuple):
            if len(b) > 1 and _all_detached(b):
                return self._append_detached(b)
            return [self.append(x) for x in b]   # in order: an error leaves the bodies before it appended
        if not isinstance(b, Body):
            raise TypeError(f"O.bodies.append: expected a Body, got {b!r}")
        scene = self._scene
        if isinstance(b._store, Scene):
            raise ValueError(f"O.bodies.append: this body is already in a simulation (id {b._row}); "
                             f"create a new body instead of appending it twice")
        src, row = b._store, b._row
        i = scene.add_body_rows(1, src.bodies, row)
        kind, table, srow = src.shape_table(row)
        if table is not None:
            scene.bodies.shape_row[i] = scene.shapes[kind].append_copy(table, srow)
        mat = b.material
        if mat is None:
            mat = self._omega.default_material()
        scene.bodies.material[i] = scene.material_index(mat)
        scene.bodies.alive[i] = True
        scene.bodies.clump_id[i] = -1
        if type(b) is _DetachedBody:
            object.__setattr__(b, "__class__", Body)
        object.__setattr__(b, "_store", scene)
        object.__setattr__(b, "_row", i)
        src.release(row)
        return i

    def _append_detached(self, bodies: list) -> list[int]:
        """Append ``bodies``, detached bodies that are distinct rows of the nursery, as appending them one by one
        would (the same ids, shape rows and materials), copying each column once for all of them: 1 us a
        body where one by one took 34."""
        scene, nursery = self._scene, _NURSERY
        rows = np.array([x._row for x in bodies], np.int64)
        first = scene.add_body_rows(len(rows), nursery.bodies, rows)
        new = slice(first, first + len(rows))
        by_kind: dict = {}   # a shape table per kind: the positions in ``bodies`` of each kind, in their order
        for j, kind in enumerate(nursery.bodies.shape_kind[rows].tolist()):
            by_kind.setdefault(kind, []).append(j)
        for kind, of_kind in by_kind.items():
            table = nursery.shapes.get(ShapeKind(kind))
            if table is None:
                continue
            dst = scene.shapes[ShapeKind(kind)]
            of_kind = np.array(of_kind)
            start = dst.append_copy(table, nursery.bodies.shape_row[rows[of_kind]], len(of_kind))
            scene.bodies.shape_row[first + of_kind] = np.arange(start, dst.count)
        materials = nursery.bodies.material[rows].tolist()   # -1: none given, the default material
        in_scene: dict = {}
        for k in materials:   # added to the scene in the order they first appear
            if k not in in_scene:
                in_scene[k] = scene.material_index(nursery.materials[k] if k >= 0 else self._omega.default_material())
        scene.bodies.material[new] = [in_scene[k] for k in materials]
        scene.bodies.alive[new] = True
        scene.bodies.clump_id[new] = -1
        set_attribute = object.__setattr__
        out = list(range(first, first + len(rows)))
        for x, i in zip(bodies, out, strict=True):
            set_attribute(x, "__class__", Body)   # all are _DetachedBody (_all_detached)
            set_attribute(x, "_store", scene)
            set_attribute(x, "_row", i)
        nursery.release(*rows.tolist())
        return out

    @pauses_the_run
    def erase(self, i: int, eraseClumpMembers: bool = False) -> bool:
        """Remove body ``i`` and its interactions (its id is not reused). A clump's members become
        standalone, or are erased too with ``eraseClumpMembers``; an erased member leaves its clump,
        whose mass properties are computed again (granum.yade.clump_edits)."""
        i = self._check(i)
        scene = self._scene
        if not scene.bodies.alive[i]:
            return False
        if scene.bodies.shape_kind[i] == ShapeKind.CLUMP:
            from granum.yade.clump_edits import dissolve

            for m in dissolve(scene, i):
                if eraseClumpMembers:
                    self.erase(m)
        elif scene.bodies.clump_id[i] >= 0:
            from granum.yade.clump_edits import erase_member

            erase_member(scene, i)
        scene.bodies.alive[i] = False
        C = scene.contacts
        n = int(C.ctr[C_CONTACTS])
        for c in np.nonzero((C.con_i[:n, I_ID1] == i) | (C.con_i[:n, I_ID2] == i))[0]:
            if C.con_i[c, I_FLAGS] & FLAG_ALIVE:
                end_law_contact(C, c)
        scene.needs_collider()
        return True

    @pauses_the_run
    def clump(self, ids, discretization: int = 0) -> int:
        """Make the listed bodies one rigid clump; return the id of the new clump body.

        Mass, centre and principal inertia come from the members (parallel-axis sum, or a
        grid integration of overlapping spheres with ``discretization`` > 0).
        """
        from granum.yade.clumps import make_clump

        return make_clump(self._scene, [self._check(i) for i in ids], int(discretization))

    @pauses_the_run
    def appendClumped(self, bodies, discretization: int = 0):
        """Append ``bodies`` and clump them: ``(clumpId, [member ids])``."""
        ids = self.append(list(bodies))
        return self.clump(ids, discretization), ids

    @pauses_the_run
    def addToClump(self, ids, clumpId: int, discretization: int = 0) -> None:
        """Add bodies ``ids`` (a list; a clump or a member of one brings all that clump's members)
        to clump ``clumpId`` and compute its mass properties again."""
        from granum.yade.clump_edits import add_to_clump

        add_to_clump(self._scene, ids, clumpId, int(discretization))

    @pauses_the_run
    def releaseFromClump(self, bid: int, cid: int, discretization: int = 0) -> None:
        """Make member ``bid`` of clump ``cid`` standalone and compute the clump again (a clump of
        two members is left alone, with a warning)."""
        from granum.yade.clump_edits import release_from_clump

        release_from_clump(self._scene, bid, cid, int(discretization))

    @pauses_the_run
    def updateClumpProperties(self, excludeList=[], discretization: int = 5) -> None:  # noqa: B006 (YADE's default)
        """Compute the mass properties of every clump not in ``excludeList`` again."""
        from granum.yade.clump_edits import update_clump_properties

        update_clump_properties(self._scene, excludeList, int(discretization))

    @pauses_the_run
    def deleteClumpMember(self, clumpBody, memberBody) -> None:
        """Erase clump member ``memberBody`` of ``clumpBody``; the clump is computed again."""
        from granum.yade.clump_edits import delete_clump_member

        delete_clump_member(self, clumpBody, memberBody)

    @pauses_the_run
    def deleteClumpBody(self, clumpBody) -> None:
        """Erase clump ``clumpBody`` and its members."""
        from granum.yade.clump_edits import delete_clump_body

        delete_clump_body(self, clumpBody)

    def getRoundness(self, excludeList=[]) -> float:  # noqa: B006 (YADE's default)
        """Mean roundness R1/R2 of the clumps and standalone spheres not in ``excludeList``."""
        from granum.yade.clump_edits import roundness

        return roundness(self._scene, excludeList)

    @pauses_the_run
    def replaceByClumps(self, templates, amounts, discretization: int = 0) -> list:
        """Replace fractions ``amounts`` of the standalone spheres by clumps shaped as ``templates``
        (``utils.clumpTemplate``), each with the volume of the sphere it replaces;
        returns ``[(clumpId, [memberIds]), ...]`` (YADE's rules: granum.yade.clump_tools)."""
        from granum.yade.clump_tools import replace_by_clumps

        return replace_by_clumps(self, templates, amounts, discretization)

    @pauses_the_run
    def clear(self) -> None:
        """Remove all bodies and interactions."""
        self._scene.clear_bodies()

    @pauses_the_run
    def replace(self, bodies) -> list:
        self.clear()
        return self.append(list(bodies))
