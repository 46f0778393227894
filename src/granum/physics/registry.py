"""Registration of materials and contact functors.

A contact model in granum is a set of pure compiled functions plus a record saying
which types they handle. Registering them here is all it takes to make them usable:
the YADE classes (``Ig2_*``, ``Ip2_*``, ``Law2_*``, materials) are generated from
these records in :mod:`granum.yade`, and the compiled dispatch is generated from
them in :mod:`granum.kernels.dispatch`. Functors are registered by the modules of
:mod:`granum.physics` (imported by its ``__init__``), before the kernels are imported.

Type hierarchies (materials, geometry and physics types) follow YADE's class
hierarchy, because YADE resolves a functor by the smallest distance in that
hierarchy (an ``Ip2_FrictMat_FrictMat_FrictPhys`` also serves two ``ViscElMat``).

Calling conventions of the registered compiled functions (``S``: scene arrays,
``C``: contact arrays, ``prm``: float64 parameters of the functor instance):

``geom(c, id1, id2, shift, S, C, prm) -> float``
    With ``c < 0`` (detection), without writing anything: the *separation* of the
    potential pair (id1, id2) [m]. It is <= 0 when they are in contact now; otherwise
    it must be a lower bound of the relative displacement (of centres, plus rotation
    times the reach of shapes that turn) that would bring them into contact, because
    the interaction loop skips the pair until its bodies have moved that far
    (``pair_gap`` in :mod:`granum.core.contacts`). With ``c >= 0``: update the geometry
    columns of the real contact ``c`` and return 0.
``phys(c, id1, id2, S, C, prm)``
    Compute the constant physical parameters of a new contact ``c`` from materials.
``law(c, id1, id2, S, C, prm) -> bool``
    Compute the normal and shear forces on body 2 (``F_FN``, ``F_FS``) and the
    energy columns; return False to end the contact.
``bound(i, S, prm, out)``
    Write the axis-aligned bound of body ``i`` into ``out`` (min x, y, z, max x, y, z).
"""

from __future__ import annotations

import hashlib
import inspect
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np

from granum.core.arrays import MATERIAL_COLUMNS, MATERIAL_KINDS, declare_material


@dataclass(frozen=True)
class TypeInfo:
    """A named type in a YADE class hierarchy (IGeom or IPhys).

    ``fields`` maps the YADE attribute names the type adds to its parent to
    ``(first float column of the contact pool, width)``, width 1 (a float; ``(column, 1, "bool")``: a flag
    stored as 0/1; ``(column, 1, "int")``: an integer), 3 (a Vector3), 4 (a Quaternion, w x y z) or 9 (a
    Matrix3, row by row); the YADE views of interactions (``i.geom``, ``i.phys``) are generated from them.
    """

    name: str
    parent: str | None
    code: int
    fields: dict = field(default_factory=dict)


@dataclass(frozen=True)
class Range:
    """The values a float parameter may take for its law to stay physical.

    A value must be finite and lie between ``low`` and ``high`` (excluded when ``low_open`` /
    ``high_open``), or be one of the values ``also`` (a sentinel such as YADE's -1 for "none"); ``why``
    says, for the error message, what goes wrong outside.
    """

    low: float = -math.inf
    high: float = math.inf
    low_open: bool = False
    high_open: bool = False
    why: str = ""
    also: tuple[float, ...] = ()

    def holds(self, x: float) -> bool:
        """Whether ``x`` lies in the range or is one of ``also`` (NaN and infinities never do)."""
        above = x > self.low if self.low_open else x >= self.low
        below = x < self.high if self.high_open else x <= self.high
        return math.isfinite(x) and (above and below or x in self.also)

    def says(self) -> str:
        """The requirement, as the end of a sentence naming the value ("must be finite and >= 0")."""
        parts = []
        if self.low > -math.inf:
            parts.append(f"{'>' if self.low_open else '>='} {self.low:g}")
        if self.high < math.inf:
            parts.append(f"{'<' if self.high_open else '<='} {self.high:g}")
        others = "".join(f" or {v:g}" for v in self.also)
        return "must be finite" + (" and " + " and ".join(parts) if parts else "") + others


@dataclass(frozen=True)
class Param:
    """A functor or material parameter: YADE attribute name, default, meaning and units.

    ``supported=False`` marks a YADE attribute granum accepts for compatibility but
    does not implement: any value other than the default is refused when the scene runs.
    ``valid`` is the :class:`Range` a float value must lie in (None: any float); a parameter
    whose default is NaN is optional and NaN stands for "not given". ``matchmaker`` marks a functor parameter
    that is YADE's MatchMaker (:mod:`granum.physics.matchmaker`; default None): ``"values"`` when the
    compiled function supplies the two values its algorithm combines, ``"bare"`` when it supplies none (as
    YADE); ``valid`` then applies to each value it holds.
    """

    name: str
    default: object
    doc: str = ""
    supported: bool = True
    valid: Range | None = None
    matchmaker: str = ""

    def check(self, owner: str, value: float) -> None:
        """Raise ValueError naming ``owner.name``, the valid range and ``value`` unless ``value`` (a float)
        is valid for this parameter. The material classes check every assignment with it."""
        optional = isinstance(self.default, float) and math.isnan(self.default)
        if self.valid is None or (optional and math.isnan(value)) or self.valid.holds(value):
            return
        why = f" ({self.valid.why})" if self.valid.why and math.isfinite(value) else ""
        raise ValueError(f"{owner}.{self.name} {self.valid.says()}{why}, got {value!r}")


@dataclass(frozen=True)
class MaterialKind:
    """A material class: its YADE name, parent class and the parameters it adds.

    ``columns`` maps each parameter to the column of the material table holding it.
    """

    name: str
    parent: str | None
    params: tuple[Param, ...]
    columns: dict = field(default_factory=dict)
    doc: str = ""


@dataclass(frozen=True)
class Functor:
    """A registered functor.

    Attributes:
        yade_name: YADE class name, e.g. ``"Ig2_Sphere_Sphere_ScGeom"``.
        role: ``"bound"``, ``"geom"``, ``"phys"`` or ``"law"``.
        types: the dispatch types: shape kinds (bound, geom), material names (phys),
            (geometry type, physics type) names (law).
        produces: the IGeom (geom) or IPhys (phys) type name created.
        func: ``"module:function"`` of the compiled function.
        params: instance parameters, in the order of the ``prm`` array.
        doc: description with formula and reference.
        history: the contact column groups the function reads or writes beyond the core ones
            (:func:`granum.core.contacts.register_history`); the pool is made that wide.
        function: a law written outside granum (:mod:`granum.yade.userlaws`): the plain Python function,
            compiled into the dispatch like the built-in ones; None for granum's functors, which ``func``
            names.
        digest: for such a function, :func:`code_digest` of it: the compiled code is cached under it.
        python: ``"module:Class"`` of a mixin the generated YADE class derives from, for a functor whose
            Python side does more than hold parameters: its ``prepare(scene)`` runs when an engine builds
            its parameters before a run, and it may override ``numeric_params`` (e.g.
            ``Ip2_CohFrictMat_CohFrictMat_CohFrictPhys.setCohesionNow`` acts at one step). Empty: none.
    """

    yade_name: str
    role: str
    types: tuple
    produces: str | None
    func: str
    params: tuple[Param, ...] = ()
    doc: str = ""
    history: tuple[str, ...] = ()
    function: Callable | None = field(default=None, compare=False, repr=False)
    digest: str = ""
    python: str = ""

    def compiled_params(self) -> tuple[Param, ...]:
        """The parameters compiled code receives in its row ``prm``, in this order: the supported ones
        whose value is a number (booleans as 0/1), and the MatchMakers (the offset of their table in ``prm``,
        :mod:`granum.physics.matchmaker`). The others (unsupported attributes) only exist in Python."""
        return tuple(p for p in self.params
                     if p.supported and (p.matchmaker or isinstance(p.default, bool | int | float)))

    def slot(self, name: str) -> int:
        """Index of the parameter ``name`` in the functor's row ``prm``: compiled functions read
        ``prm[slot]`` through a module constant made with this, never a bare number."""
        for k, p in enumerate(self.compiled_params()):
            if p.name == name:
                return k
        raise KeyError(f"{self.yade_name} has no compiled parameter {name!r} (numeric and supported)")


MATERIALS: dict[str, MaterialKind] = {}
GEOM_TYPES: dict[str, TypeInfo] = {}
PHYS_TYPES: dict[str, TypeInfo] = {}
FUNCTORS: dict[str, Functor] = {}


def _add_type(table: dict, name: str, parent: str | None, fields: dict | None) -> None:
    if parent is not None and parent not in table:
        raise KeyError(f"parent type {parent!r} of {name!r} is not registered")
    old = table.get(name)
    info = TypeInfo(name, parent, old.code if old else len(table), dict(fields or {}))
    if old is not None and old != info:   # the same declaration again (a script run twice) is no change
        raise ValueError(f"type {name!r} is already declared with parent {old.parent!r} and fields "
                         f"{sorted(old.fields)}; choose another name")
    table[name] = info


def register_geom_type(name: str, parent: str | None = None, fields: dict | None = None) -> None:
    """Declare an IGeom type (e.g. ``ScGeom``), its parent and the contact columns it exposes."""
    _add_type(GEOM_TYPES, name, parent, fields)


def register_phys_type(name: str, parent: str | None = None, fields: dict | None = None) -> None:
    """Declare an IPhys type (e.g. ``FrictPhys``), its parent and the contact columns it exposes."""
    _add_type(PHYS_TYPES, name, parent, fields)


def type_fields(table: dict, name: str) -> dict:
    """All fields of a type, base types first."""
    out = {}
    for n in reversed(_type_ancestry(table, name)):
        out.update(table[n].fields)
    return out


def register_material(kind: MaterialKind) -> None:
    """Declare a material class with the parameters it adds to its parent."""
    if kind.parent is not None and kind.parent not in MATERIALS:
        raise KeyError(f"parent material {kind.parent!r} of {kind.name!r} is not registered")
    MATERIALS[kind.name] = kind
    _ANCESTRY.clear()
    declare_material(kind.name, [kind.columns.get(p.name, p.name) for p in kind.params])


_sealed = False

#: Bumped by every registration of a functor: what caches of the functors by role compare
#: (:func:`granum.kernels.dispatch.functors`).
functor_generation = 0


def seal() -> None:
    """Refuse further functors: the dispatch has been generated from these (granum.kernels.dispatch)."""
    global _sealed
    _sealed = True


def register_functor(f: Functor) -> None:
    """Declare a functor (see the module docstring for the compiled calling conventions).

    granum's own functors name their function (``func``) in a module of granum.physics, registered
    before the kernels are imported: the kernel cache is keyed by granum's sources. A functor defined
    elsewhere (a script, a user's module: :mod:`granum.yade.userlaws`) hands over the function itself
    with its :func:`code_digest`, which keys the compiled code instead; it may be registered at any
    time and registered again (a script run twice, an edited law) for the same role and types, keeping
    its code."""
    old = FUNCTORS.get(f.yade_name)
    if f.function is None:
        if old is not None:
            raise ValueError(f"functor {f.yade_name} is registered twice")
        if not f.func.startswith("granum.physics."):
            raise ValueError(f"functor {f.yade_name}: its function {f.func!r} must be in a module of granum.physics "
                             f"(see ARCHITECTURE.md, 'How to add a contact law'), or be handed over as a function "
                             f"(granum.yade.userlaws)")
        if _sealed:
            raise RuntimeError(f"functor {f.yade_name} is registered after the kernels were compiled; register it "
                               f"in a granum.physics module imported by granum/physics/__init__.py")
    elif old is not None and (old.function is None or (old.role, old.types, old.produces) != (f.role, f.types,
                                                                                               f.produces)):
        what = "granum's own functor" if old.function is None else \
            f"the {old.role} functor for {old.types} registered before"
        raise ValueError(f"functor {f.yade_name} is already {what}; choose another name")
    global functor_generation
    FUNCTORS[f.yade_name] = f
    functor_generation += 1


def code_digest(func: Callable) -> str:
    """A hash of what a law's compiled code is made of: its Python bytecode, constants and names, and,
    through the globals it reads, the functions it calls (recursively) and the values of the constants
    it reads, which Numba freezes into the machine code (16 hex digits).

    Line numbers and file names are left out, so moving a law in its script keeps its cached code.
    Functions of granum itself are represented by their name: the kernel cache is keyed by granum's
    sources already. A global that is a module is not followed (``math.sqrt`` is stable); attributes of
    a user's own module read as ``mod.X`` inside the law are therefore not part of the hash: import
    them by name.
    """
    h = hashlib.sha256()
    seen: set[int] = set()

    def value(v) -> None:
        if isinstance(v, bool | int | float | complex | str | bytes | type(None)):
            h.update(repr(v).encode())
        elif isinstance(v, tuple):
            for x in v:
                value(x)
        elif isinstance(v, np.ndarray):
            h.update(f"{v.dtype}{v.shape}".encode() + np.ascontiguousarray(v).tobytes())
        elif hasattr(v, "py_func") or inspect.isfunction(v):
            function(v)

    def function(fn) -> None:
        fn = getattr(fn, "py_func", fn)
        if id(fn) in seen:
            return
        seen.add(id(fn))
        if (getattr(fn, "__module__", None) or "").startswith("granum."):
            h.update(f"{fn.__module__}:{fn.__qualname__}".encode())
            return
        code(fn.__code__, fn.__globals__)
        for cell in fn.__closure__ or ():   # the variables of an enclosing function, frozen like globals
            value(cell.cell_contents)

    def code(co, globs: dict) -> None:
        h.update(co.co_code + repr((co.co_names, co.co_varnames, co.co_argcount)).encode())
        for const in co.co_consts:
            if inspect.iscode(const):
                code(const, globs)
            else:
                value(const)
        for name in co.co_names:
            if name in globs and not inspect.ismodule(globs[name]):
                h.update(name.encode())
                value(globs[name])

    function(func)
    return h.hexdigest()[:16]


def material_code(name: str) -> int:
    """Code of the material class ``name`` (its value in the scene's ``mat_kind``)."""
    return MATERIAL_KINDS.index(name)


#: material_ancestry's answers since the last registration (``utils.sphere()`` asks for every body)
_ANCESTRY: dict[str, tuple[str, ...]] = {}


def material_ancestry(name: str) -> tuple[str, ...]:
    """``(name, parent, grandparent, ...)`` of a material class."""
    out = _ANCESTRY.get(name)
    if out is None:
        chain = []
        kind = name
        while kind is not None:
            chain.append(kind)
            kind = MATERIALS[kind].parent
        out = _ANCESTRY[name] = tuple(chain)
    return out


def material_params(name: str) -> list[Param]:
    """All parameters of a material class, base classes first."""
    return [p for n in reversed(material_ancestry(name)) for p in MATERIALS[n].params]


def material_columns() -> list[str]:
    """Columns of the compiled material table, in a fixed order (declared to the storage as the
    materials are registered, :func:`granum.core.arrays.declare_material`)."""
    return list(MATERIAL_COLUMNS)


def _type_ancestry(table: dict, name: str) -> list[str]:
    out = []
    while name is not None:
        out.append(name)
        name = table[name].parent
    return out


def best_match(candidates: list[Functor], chain_a: Sequence[str],
               chain_b: Sequence[str]) -> tuple[Functor | None, bool]:
    """The functor whose two dispatch types are closest to (a, b) in the hierarchy.

    ``chain_a``/``chain_b`` are the ancestries of the two actual types. Returns
    ``(functor, swapped)``; ``swapped`` tells that the functor is declared for (b, a).
    Raises ``ValueError`` on a tie between different functors (ambiguous dispatch).
    """
    best, best_d, swapped, tie = None, None, False, False
    for f in candidates:
        t1, t2 = f.types
        for sw, (x, y) in ((False, (chain_a, chain_b)), (True, (chain_b, chain_a))):
            if t1 in x and t2 in y:
                d = x.index(t1) + y.index(t2)
                if best_d is None or d < best_d:
                    best, best_d, swapped, tie = f, d, sw, False
                elif d == best_d and f is not best:
                    tie = True
    if tie:
        raise ValueError(f"ambiguous dispatch for {chain_a[0]}+{chain_b[0]}")
    return best, swapped


def geom_ancestry(name: str) -> list[str]:
    return _type_ancestry(GEOM_TYPES, name)


def phys_ancestry(name: str) -> list[str]:
    return _type_ancestry(PHYS_TYPES, name)


#: The reach of each shape kind that turns with its body, by kind (see :func:`register_reach`).
REACH: dict[int, str] = {}


def register_reach(kind: int, func: str) -> None:
    """Declare the reach of the shape kind ``kind``: ``func``, ``"module:function"`` of a compiled
    ``reach(row, S) -> float``, is the largest distance from the body position to a point of the shape in
    row ``row`` of the kind's table [m]. The collider allows a body that turned by an angle a since its
    bound was computed a motion of a times its reach (:mod:`granum.kernels.collider`); a kind without a
    reach (sphere, wall) does not move by turning."""
    if _sealed:
        raise RuntimeError(f"the reach of shape kind {kind} is registered after the kernels were compiled")
    REACH[int(kind)] = func
