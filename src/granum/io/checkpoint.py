"""``O.save`` / ``O.load`` checkpoints: the whole scene as plain metadata plus NumPy arrays.

Loading a checkpoint and running on gives a trajectory bitwise identical to the run that was
never interrupted, because the storage is saved exactly as it is, not reconstructed:

* every NumPy array of the :class:`~granum.core.scene.Scene` (scalars and clock, energies,
  cell), every column of its tables (bodies, per-kind shapes, clump members) at full capacity
  with its row count, and every array of the interaction storage (potential pairs, the contact
  pool in its order with the laws' history columns such as the shear force, the per-body
  index, counters). These are found generically -- any array, :class:`~granum.core.table.Table`,
  dict of tables or named tuple of arrays in ``vars(scene)`` -- so a new column or scene array
  is saved without touching this module;
* the other public scene attributes (``tags``, ``stop_at_iter``, ...) as plain values;
* engines, functors and materials (``O.materials`` and the materials bodies refer to) as
  objects: class name, every declared attribute (``label``, ``dead``, periods and counters of
  ``PyRunner``, functor lists of ``InteractionLoop`` and the collider, ...) and the private
  instance state made of plain values and arrays (``PeriTriaxController``'s servo output,
  ``VTKRecorder``'s file series). Other private objects are caches their engine rebuilds on
  demand (``SnapshotEngine``'s default camera view) and are not saved. An object shared by
  several places (a material in ``O.materials`` and used by bodies) is stored once and shared
  again after loading.

Objects are rebuilt through the classes of a namespace the caller passes (``O.save``/``O.load``
pass the one ``granum.yade`` exports; this module sits below the YADE layer), by name, with
their declared attributes as constructor keywords (read-only ones and private state set
afterwards): no class, function or pickle is taken from a file. Loading runs no code, but the
engines loaded run with the scene, and a ``PyRunner``'s ``command`` is Python code executed at
``O.run``: a checkpoint is to be trusted as a script is. A value that cannot be represented without
code -- a Python callable, an object of a class defined in a script -- makes saving fail with
a :class:`~granum.io.checkpoint_formats.CheckpointError` naming the engine and attribute,
before anything is written.

Values are encoded as JSON: ``None``, booleans, integers, finite floats (exact: ``repr``
round-trips), strings and lists as themselves; anything else as a one-key object:
``{"tuple": [...]}``, ``{"dict": {...}}`` (string keys), ``{"float": "nan"}`` (non-finite),
``{"math": ["Vector3", [...]]}``, ``{"array": name}``, ``{"ref": k}`` (object ``k`` of the
object list, always earlier in it), ``{"dispatcher": [refs]}`` (a functor list). Scene fields
use ``{"table": {"count", "columns"}}``, ``{"tables": {kind: table}}`` and ``{"record": {field:
array}}``.

On loading, everything is checked before the scene is used: the container's checksums (see
:mod:`granum.io.checkpoint_formats`), every array's dtype and shape against a fresh scene, the
types of the plain fields, the indices compiled kernels follow without bounds checks (body
shapes, materials, clumps, pairs, contacts, per-body contact index, functor codes), and the
values with the rules the setters apply (:mod:`granum.core.validate`: ``O.dt``, the cell, the
state and shape of every body), so a bad file gives an error instead of a crash. Contacts
store functor codes; the checkpoint records the functor names of each code, and codes are
translated if this granum registers its functors in another order. Saving from inside an
engine (a ``PyRunner`` calling ``O.save``) stores the state in the
middle of the step; loading it resumes at the start of that step, as in YADE.
"""

from __future__ import annotations

import io
import os

import numpy as np

from granum import mathtypes
from granum.core import validate
from granum.core.arrays import ENERGY_NAMES, S_DT, SI_HOMO_DEFORM, SI_HOOK
from granum.core.attrs import Attributed
from granum.core.contacts import (
    C_CONTACTS,
    C_CSR_DIRTY,
    C_PAIRS,
    FLAG_ALIVE,
    HISTORY_COLUMNS,
    I_FLAGS,
    I_GEOM,
    I_ID1,
    I_ID2,
    I_LAW,
    I_PAIR,
    I_PHYS,
    NF_CORE,
    NI,
    NI_CORE,
    nf,
)
from granum.core.scene import Scene
from granum.core.shapes import ShapeKind, shape_type
from granum.core.table import Table
from granum.engines.pipeline import Dispatcher
from granum.io.atomic import atomic_path
from granum.io.checkpoint_formats import (
    CheckpointError,
    CheckpointNotFoundError,
    container_read,
    container_write,
    format_of_path,
)

__all__ = ["CheckpointError", "CheckpointNotFoundError", "checkpoint_bytes", "checkpoint_from_bytes",
           "checkpoint_read", "checkpoint_write"]

#: The minieigen types, by name.
MATH_TYPES = {n: getattr(mathtypes, n) for n in mathtypes.__all__ if hasattr(getattr(mathtypes, n), "_wrap")}
#: Roles whose functor codes contacts store, and the contact column holding each.
_CODE_COLUMNS = {"geom": I_GEOM, "phys": I_PHYS, "law": I_LAW}
#: How scene fields are called in error messages.
_FIELD_NAMES = {"tags": "O.tags", "engines": "O.engines", "materials": "the materials of O.bodies"}
_ARRAY_KINDS = "biuf"
_MISSING = object()
#: what a class or functor missing on load may be
_USER_DEFINED = " (a law, physics or material written in a script, granum.yade.userlaws, is defined before O.load)"


def _classes(namespace: dict) -> dict[str, type]:
    """The classes of ``namespace`` (name -> object, e.g. the YADE namespace) that objects are saved as
    and rebuilt with: its engines, functors and materials, all :class:`~granum.core.attrs.Attributed`."""
    return {n: c for n, c in namespace.items() if isinstance(c, type) and issubclass(c, Attributed)}


def layout() -> dict:
    """What the meaning of saved arrays depends on besides their shapes: shape kinds, the functor
    names of the codes contacts store, the laws' history columns and the energy slots."""
    from granum.kernels.dispatch import functors

    return {"shapes": {k.name: int(k) for k in ShapeKind},
            "functors": {role: [f.yade_name for f in functors(role)] for role in _CODE_COLUMNS},
            "contact_history": {n: list(ow) for n, ow in HISTORY_COLUMNS.items()},
            "energy": list(ENERGY_NAMES)}


def _plain(v) -> bool:
    """Whether ``v`` is made of plain values and arrays only (private state that is saved)."""
    if v is None or isinstance(v, bool | int | float | str | np.integer | np.floating | np.bool_):
        return True
    if isinstance(v, np.ndarray):
        return v.dtype.kind in _ARRAY_KINDS
    if isinstance(v, tuple(MATH_TYPES.values())):
        return True
    if isinstance(v, list | tuple):
        return all(_plain(x) for x in v)
    if isinstance(v, dict):
        return all(isinstance(k, str) and _plain(x) for k, x in v.items())
    return False


# ---- encoding ---------------------------------------------------------------------------------
class _Encoder:
    """Turns scene values into JSON values, collecting arrays and objects on the way."""

    def __init__(self, classes: dict[str, type]):
        self.classes = classes
        self.arrays: dict[str, np.ndarray] = {}
        self.objects: list[dict] = []
        self._index: dict[int, int] = {}   # id(object) -> its index in objects
        self._open: set[int] = set()       # objects being encoded (a cycle is an error)
        self._keep: list = []              # the encoded objects, alive so their ids stay unique

    def array(self, name: str, a: np.ndarray) -> dict:
        self.arrays[name] = a
        return {"array": name}

    def value(self, v, where: str):
        if v is None or isinstance(v, bool | str):
            return v
        if isinstance(v, np.bool_):
            return bool(v)
        if isinstance(v, int | np.integer):
            return int(v)
        if isinstance(v, float | np.floating):
            return float(v) if np.isfinite(v) else {"float": repr(float(v))}
        if isinstance(v, np.ndarray) and v.dtype.kind in _ARRAY_KINDS:
            return self.array(f"values/{len(self.arrays)}", v)
        if isinstance(v, tuple(MATH_TYPES.values())):
            return {"math": [type(v).__name__, [self.value(x, where) for x in v._a.ravel().tolist()]]}
        if isinstance(v, list):
            return [self.value(x, f"{where}[{k}]") for k, x in enumerate(v)]
        if isinstance(v, tuple):
            return {"tuple": [self.value(x, f"{where}[{k}]") for k, x in enumerate(v)]}
        if isinstance(v, dict):
            bad = [k for k in v if not isinstance(k, str)]
            if bad:
                raise CheckpointError(f"O.save: {where} has the key {bad[0]!r}; checkpoints store dicts with "
                                      f"string keys only")
            return {"dict": {k: self.value(x, f"{where}[{k!r}]") for k, x in v.items()}}
        if isinstance(v, Dispatcher):
            return {"dispatcher": [self.value(f, f"{where}.functors[{k}]") for k, f in enumerate(v.functors)]}
        if isinstance(v, Attributed):
            return {"ref": self.obj(v, where)}
        if callable(v):
            raise CheckpointError(f"O.save: {where} holds a Python callable ({v!r}); a checkpoint stores no code, "
                                  f"so it cannot be saved")
        raise CheckpointError(f"O.save: {where} holds a {type(v).__name__} ({v!r:.80}), which a checkpoint "
                              f"cannot store")

    def obj(self, o: Attributed, where: str) -> int:
        """Index of ``o`` in :attr:`objects`, encoding it (after what it refers to) when first met."""
        key = id(o)
        if key in self._index:
            return self._index[key]
        cls = type(o)
        label = getattr(o, "label", "")
        where = f"{where} ({cls.__name__}" + (f" {label!r})" if label else ")")
        if self.classes.get(cls.__name__) is not cls:
            raise CheckpointError(f"O.save: {where}: class {cls.__module__}.{cls.__qualname__} is not one of "
                                  f"granum's YADE classes; a checkpoint stores no code, so it cannot be saved")
        if key in self._open:
            raise CheckpointError(f"O.save: {where} refers to itself; a checkpoint cannot store cycles")
        self._open.add(key)
        attrs = {n: self.value(getattr(o, n), f"{where}.{n}") for n in cls._attrs}
        state = {n: self.value(v, f"{where}.{n}") for n, v in vars(o).items() if n not in cls._attrs and _plain(v)}
        self._open.discard(key)
        self.objects.append({"class": cls.__name__, "attrs": attrs, "state": state})
        self._keep.append(o)
        self._index[key] = len(self.objects) - 1
        return self._index[key]

    def field(self, name: str, v):
        """A scene field: arrays, tables and records by name, anything else as a value."""
        if isinstance(v, np.ndarray):
            return self.array(f"scene/{name}", v)
        if isinstance(v, Table):
            return {"table": self.table(f"scene/{name}", v)}
        if isinstance(v, dict) and v and all(isinstance(t, Table) for t in v.values()):
            return {"tables": {k.name: self.table(f"scene/{name}/{k.name}", t) for k, t in v.items()}}
        if isinstance(v, tuple) and hasattr(v, "_fields") and all(isinstance(a, np.ndarray) for a in v):
            skip = getattr(v, "_transient", ())  # work areas: no state
            return {"record": {f: self.array(f"scene/{name}/{f}", a) for f, a in zip(v._fields, v, strict=True)
                               if f not in skip}}
        return self.value(v, _FIELD_NAMES.get(name, f"scene.{name}"))

    def table(self, name: str, t: Table) -> dict:
        # lazy columns never used are not stored: they load as their defaults
        return {"count": t.count, "columns": {c.name: self.array(f"{name}/{c.name}", getattr(t, c.name))
                                              for c in t.columns if t.allocated(c.name)}}


def scene_encode(scene: Scene, materials, namespace: dict) -> tuple[dict, dict[str, np.ndarray]]:
    """``(meta, arrays)`` of ``scene`` and ``O.materials`` (see the module docstring); objects must be of
    the classes of ``namespace`` (name -> class, e.g. the YADE namespace).

    Raises :class:`CheckpointError` for a value a checkpoint cannot store.
    """
    enc = _Encoder(_classes(namespace))
    fields = {n: enc.field(n, v) for n, v in vars(scene).items() if not n.startswith("_")}  # _*: caches
    mats = enc.value(list(materials), "O.materials")
    return {"layout": layout(), "scene": fields, "materials": mats, "objects": enc.objects}, enc.arrays


# ---- decoding ---------------------------------------------------------------------------------
class _Decoder:
    """Turns the JSON values of a checkpoint back into scene values."""

    def __init__(self, arrays: dict[str, np.ndarray], source: str):
        self.arrays = arrays
        self.source = source
        self.objects: list = []

    def fail(self, what: str) -> CheckpointError:
        return CheckpointError(f"{self.source}: {what}")

    def array(self, node) -> np.ndarray:
        if not (isinstance(node, dict) and set(node) == {"array"} and node["array"] in self.arrays):
            raise self.fail(f"corrupt checkpoint (expected an array, found {str(node)[:80]})")
        return self.arrays[node["array"]]

    def value(self, node):
        if node is None or isinstance(node, bool | int | float | str):
            return node
        if isinstance(node, list):
            return [self.value(x) for x in node]
        if not (isinstance(node, dict) and len(node) == 1):
            raise self.fail(f"corrupt checkpoint (unexpected value {str(node)[:80]})")
        tag, body = next(iter(node.items()))
        if tag == "tuple" and isinstance(body, list):
            return tuple(self.value(x) for x in body)
        if tag == "dict" and isinstance(body, dict):
            return {k: self.value(x) for k, x in body.items()}
        if tag == "float" and body in ("nan", "inf", "-inf"):
            return float(body)
        if tag == "array":
            return self.array(node)
        if tag == "ref" and isinstance(body, int) and 0 <= body < len(self.objects):
            return self.objects[body]
        if tag == "math" and isinstance(body, list) and len(body) == 2 and body[0] in MATH_TYPES:
            cls = MATH_TYPES[body[0]]
            a = np.array([self.value(x) for x in body[1]], dtype=cls._dtype)
            if a.size == int(np.prod(cls._shape)):
                return cls._wrap(a.reshape(cls._shape))
        raise self.fail(f"corrupt checkpoint (unexpected value {str(node)[:80]})")

    def obj(self, node, classes: dict) -> Attributed:
        """An object rebuilt from its node (the objects it refers to are already rebuilt)."""
        if not (isinstance(node, dict) and set(node) == {"class", "attrs", "state"}
                and isinstance(node["attrs"], dict) and isinstance(node["state"], dict)):
            raise self.fail("corrupt checkpoint (malformed object)")
        name = node["class"]
        cls = classes.get(name)
        if cls is None:
            raise self.fail(f"the checkpoint holds an object of class {name!r}, which this granum does not have"
                            f"{_USER_DEFINED}")
        kwargs, readonly, functor_lists = {}, {}, {}
        for n, v in node["attrs"].items():
            a = cls._attrs.get(n)
            if a is None:
                raise self.fail(f"{name} has no attribute {n!r} in this granum")
            if isinstance(v, dict) and set(v) == {"dispatcher"} and isinstance(v["dispatcher"], list):
                functor_lists[n] = [self.value(f) for f in v["dispatcher"]]
            else:
                (readonly if a.readonly else kwargs)[n] = self.value(v)
        try:
            o = cls(**kwargs)
            for n, v in functor_lists.items():
                getattr(o, n).functors = v
        except (TypeError, ValueError, NotImplementedError, AttributeError) as e:
            raise self.fail(f"cannot rebuild {name}: {e}") from e
        for n, v in readonly.items():
            object.__setattr__(o, n, v)
        for n, v in node["state"].items():
            fresh = vars(o).get(n, getattr(cls, n, _MISSING))  # instance state or a class default (_plan_index)
            if fresh is _MISSING or callable(fresh):
                raise self.fail(f"{name} has no state {n!r} in this granum")
            v = self.value(v)
            if isinstance(fresh, np.ndarray) and not (isinstance(v, np.ndarray) and v.dtype == fresh.dtype
                                                      and v.shape == fresh.shape):
                raise self.fail(f"{name}.{n} must be a {fresh.dtype} array of shape {fresh.shape}")
            object.__setattr__(o, n, v)
        return o

    def table(self, node, columns, where: str) -> Table:
        """A table of ``columns`` from its node: all columns of one capacity, declared dtypes and row shapes;
        columns the checkpoint lacks (added to granum since) hold their defaults."""
        if not (isinstance(node, dict) and isinstance(node.get("count"), int)
                and isinstance(node.get("columns"), dict)):
            raise self.fail(f"corrupt checkpoint (malformed table {where})")
        saved = {n: self.array(a) for n, a in node["columns"].items()}
        declared = {c.name: c for c in columns}
        unknown = set(saved) - set(declared)
        if unknown:
            raise self.fail(f"table {where} has column {sorted(unknown)[0]!r}, which this granum does not have")
        capacity = len(next(iter(saved.values()))) if saved else 1
        count = node["count"]
        if not 0 <= count <= capacity or capacity < 1:
            raise self.fail(f"corrupt checkpoint (table {where}: {count} rows in a capacity of {capacity})")
        t = Table(columns, capacity)
        t.append_rows(count)
        for n, a in saved.items():
            c = declared[n]
            if a.dtype != np.dtype(c.dtype) or a.shape != (capacity,) + c.tail:
                raise self.fail(f"column {where}.{n} is {a.dtype} {a.shape}; this granum needs {np.dtype(c.dtype)} "
                                f"{(capacity,) + c.tail}")
            getattr(t, n)[:] = a
        return t

    def field(self, name: str, fresh, node):
        """Scene field ``name`` from its node, checked against the value of a fresh scene."""
        if isinstance(fresh, np.ndarray):
            a = self.array(node)
            if a.dtype != fresh.dtype or a.shape != fresh.shape:
                raise self.fail(f"scene array {name} is {a.dtype} {a.shape}; this granum needs {fresh.dtype} "
                                f"{fresh.shape}")
            return a
        if isinstance(fresh, Table):
            return self.table(_tagged(node, "table"), fresh.columns, name)
        if isinstance(fresh, dict) and fresh and all(isinstance(t, Table) for t in fresh.values()):
            saved = _tagged(node, "tables")
            if set(saved) != {k.name for k in fresh}:
                raise self.fail(f"the checkpoint has the {name} tables {sorted(saved)}; this granum has "
                                f"{sorted(k.name for k in fresh)}")
            return {k: self.table(saved[k.name], t.columns, f"{name}.{k.name}") for k, t in fresh.items()}
        if isinstance(fresh, tuple) and hasattr(fresh, "_fields"):
            saved = _tagged(node, "record")
            transient = getattr(fresh, "_transient", frozenset())
            kept = [f for f in fresh._fields if f not in transient]
            if set(saved) != set(kept):
                raise self.fail(f"the checkpoint's {name} has the arrays {sorted(saved)}; this granum has "
                                f"{sorted(kept)}")
            out = {f: getattr(fresh, f) for f in transient}
            for f in kept:
                ref = getattr(fresh, f)
                a = self.array(saved[f])
                tail_ok = a.shape[1:] == ref.shape[1:] or (  # the contact pool is as wide as its laws need
                    f == "con_f" and a.ndim == 2 and NF_CORE <= a.shape[1] <= nf()) or (
                    f == "con_i" and a.ndim == 2 and a.shape[1] in (NI_CORE, NI))  # images: periodic only
                if a.dtype != ref.dtype or a.ndim != ref.ndim or not tail_ok:
                    raise self.fail(f"{name}.{f} is {a.dtype} {a.shape}; this granum needs {ref.dtype} "
                                    f"(n,{''.join(f' {k},' for k in ref.shape[1:])[:-1]})")
                if f == "ctr" and len(a) != len(ref):   # the kernels read every counter without bounds checks
                    if len(a) > len(ref):
                        raise self.fail(f"{name}.ctr holds {len(a)} counters; this granum has {len(ref)}")
                    a = np.concatenate([a, np.zeros(len(ref) - len(a), a.dtype)])   # earlier versions had fewer
                out[f] = a
            return type(fresh)(**out)
        v = self.value(node)
        if type(v) is not type(fresh):
            raise self.fail(f"scene field {name} is a {type(v).__name__}; this granum needs a {type(fresh).__name__}")
        return v


def _tagged(node, tag: str):
    if not (isinstance(node, dict) and set(node) == {tag} and isinstance(node[tag], dict)):
        raise CheckpointError(f"corrupt checkpoint (expected a {tag})")
    return node[tag]


def _codes_translate(contacts, saved: dict, source: str) -> None:
    """Map the functor codes of the contact pool from the saved registry order to this granum's. Only the
    functors its contacts use must exist here (a script's own law registered when the file was written, which
    none of its contacts uses, does not matter)."""
    now = layout()["functors"]
    k = int(contacts.ctr[C_CONTACTS])
    for role, col in _CODE_COLUMNS.items():
        names = saved.get(role)
        if names == now[role]:
            continue
        codes = contacts.con_i[:k, col]
        if np.any((codes < -1) | (codes >= len(names))):
            raise CheckpointError(f"{source}: corrupt checkpoint (contact functor code out of range)")
        used = {names[c] for c in np.unique(codes) if c >= 0}
        missing = sorted(n for n in used if n not in now[role])
        if missing:
            raise CheckpointError(f"{source}: contacts use the functor {missing[0]}, which this granum does not have"
                                  f"{_USER_DEFINED}")
        lut = np.array([now[role].index(n) if n in now[role] else -1 for n in names] + [-1], np.int32)
        contacts.con_i[:k, col] = lut[codes]  # code -1 stays -1


def _layout_check(saved, source: str) -> None:
    now = layout()
    if not isinstance(saved, dict) or set(saved) != set(now):
        raise CheckpointError(f"{source}: corrupt checkpoint (no valid layout record)")
    for key in ("shapes", "energy"):
        if saved[key] != now[key]:
            raise CheckpointError(f"{source} was written by a granum with other {key.replace('_', ' ')} "
                                  f"({saved[key]}; this granum: {now[key]}); it cannot be resumed here")
    if not isinstance(saved["contact_history"], dict):
        raise CheckpointError(f"{source}: corrupt checkpoint (no contact history record)")
    if not isinstance(saved["functors"], dict) or not all(
            isinstance(saved["functors"].get(r), list) for r in _CODE_COLUMNS):
        raise CheckpointError(f"{source}: corrupt checkpoint (no functor table)")


def _history_check(saved: dict, width: int, source: str) -> None:
    """The contact history columns the saved pool holds (its ``width`` first ``con_f`` columns) must mean here
    what they meant when the file was written: every group that has one of them, in the file's registry or in
    this granum's, has the same columns in both. Groups beyond the pool (a script's own law registered then,
    which none of the saved contacts used) do not matter."""
    now = layout()["contact_history"]
    for name in sorted(set(saved) | set(now)):
        ranges = [r for r in (saved.get(name), now.get(name)) if r is not None]
        if any(not (isinstance(r, list) and len(r) == 2 and all(type(x) is int for x in r)) for r in ranges):
            raise CheckpointError(f"{source}: corrupt checkpoint (contact history record of {name})")
        if any(r[0] < width for r in ranges) and saved.get(name) != now.get(name):
            raise CheckpointError(f"{source} was written by a granum with other contact history ({name}: "
                                  f"{saved.get(name)}; this granum: {now.get(name)}); it cannot be resumed here")


def _range(a: np.ndarray, lo: int, hi: int, what: str, source: str) -> None:
    """Raise unless every value of ``a`` lies in [lo, hi)."""
    if a.size and (a.min() < lo or a.max() >= hi):
        raise CheckpointError(f"{source}: corrupt checkpoint ({what} out of range)")


#: Body columns and the rule their setters (``Body.state``) apply, checked for the bodies in use.
_BODY_RULES = {"pos": validate.FINITE_VECTOR, "vel": validate.FINITE_VECTOR, "ang_vel": validate.FINITE_VECTOR,
               "ang_mom": validate.FINITE_VECTOR, "inertia": validate.FINITE_VECTOR,
               "ref_pos": validate.FINITE_VECTOR, "color": validate.FINITE_VECTOR,
               "mass": validate.NON_NEGATIVE_FINITE, "ori": validate.QUATERNION}


def _obeys(rule: validate.Rule, values, name: str, source: str, ids=None) -> None:
    """Raise :class:`CheckpointError` unless ``values`` obey ``rule`` (see :meth:`validate.Rule.check_items`)."""
    try:
        rule.check_items(values, name, ids)
    except ValueError as e:
        raise CheckpointError(f"{source}: invalid checkpoint ({e})") from e


def scene_values_check(scene: Scene, source: str) -> None:
    """The loaded values must obey the rules the setters enforce (:mod:`granum.core.validate`): time
    step, cell, and the state and shape of every body in use. Call after :func:`scene_check`."""
    _obeys(validate.TIME_STEP, scene.scal[S_DT], "O.dt", source)
    _obeys(validate.HOMO_DEFORM, scene.iscal[SI_HOMO_DEFORM], "O.cell.homoDeform", source)
    _obeys(validate.CELL_BASE, scene.cell_hsize, "O.cell.hSize", source)
    _obeys(validate.CELL_BASE, scene.cell_ref_hsize, "O.cell.refHSize", source)
    _obeys(validate.FINITE_MATRIX, scene.cell_velgrad, "O.cell.velGrad", source)
    b = scene.bodies
    ids = np.flatnonzero(b.alive[: b.count])
    for column, rule in _BODY_RULES.items():
        if b.allocated(column):
            _obeys(rule, getattr(b, column)[ids], f"O.bodies[{{}}].state.{column}", source, ids)
    kind = b.shape_kind[ids]
    for k, table in scene.shapes.items():   # the rules their setters (Sphere.radius, ...) apply
        of_kind = ids[kind == k]
        rows = b.shape_row[of_kind]
        for column, rule in shape_type(k).rules.items():
            _obeys(rule, getattr(table, column)[rows], f"O.bodies[{{}}].shape.{column}", source, of_kind)


def scene_check(scene: Scene, source: str) -> None:
    """The indices compiled kernels follow without bounds checks must point inside their arrays; the pairs'
    detection state is made what the interaction loop takes for granted."""
    from granum.kernels.dispatch import functors

    b = scene.bodies
    n = b.count
    alive = b.alive[:n]
    kind = b.shape_kind[:n]
    _range(kind, 0, len(ShapeKind), "body shape kind", source)
    for k, t in scene.shapes.items():
        _range(b.shape_row[:n][alive & (kind == k)], 0, t.count, f"{k.name.lower()} shape row", source)
    _range(b.material[:n][alive], -1, len(scene.materials), "body material", source)
    _range(b.clump_id[:n], -1, n, "clump id", source)
    _range(scene.iscal[SI_HOOK:SI_HOOK + 1], 0, len(scene.engines) + 1, "engine hook index", source)
    members = scene.clump_members
    _range(members.id[: members.count], 0, n, "clump member id", source)
    clumps = scene.shapes[ShapeKind.CLUMP]
    first, count = clumps.member_first[: clumps.count], clumps.member_count[: clumps.count]
    _range(first, 0, members.count + 1, "clump member range", source)
    _range(first + count, 0, members.count + 1, "clump member range", source)
    C = scene.contacts
    npair, ncon = int(C.ctr[C_PAIRS]), int(C.ctr[C_CONTACTS])
    images_ok = (len(C.pair_cell) >= npair or (not scene.periodic and len(C.pair_cell) == 0)) and (  # aperiodic: none
        C.con_i.shape[1] == NI or not scene.periodic)
    if not (images_ok and 0 <= npair <= min(len(C.pair_ids), len(C.pair_con), len(C.pair_gap), len(C.pair_hit))
            and 0 <= ncon <= len(C.con_i) == len(C.con_f)):
        raise CheckpointError(f"{source}: corrupt checkpoint (interaction counters exceed their arrays)")
    _range(C.pair_ids[:npair], 0, n, "pair body id", source)
    _range(C.pair_con[:npair], -1, ncon, "pair contact", source)
    # what the detection takes for granted (granum.core.contacts): no hit outside a step (earlier versions left
    # the last step's), an infinite budget for a pair with a contact
    C.pair_hit[:] = 0
    C.pair_gap[:npair][C.pair_con[:npair] >= 0] = np.inf
    live = (C.con_i[:ncon, I_FLAGS] & FLAG_ALIVE) != 0
    _range(C.con_i[:ncon][live][:, [I_ID1, I_ID2]], 0, n, "contact body id", source)
    _range(C.con_i[:ncon, I_PAIR], -1, npair, "contact pair", source)
    for role, col in _CODE_COLUMNS.items():
        _range(C.con_i[:ncon, col], -1, len(functors(role)), f"contact {role} functor code", source)
    if len(C.csr_con) < 2 * len(C.con_i):   # the per-body index is built in place (granum.kernels.interaction)
        raise CheckpointError(f"{source}: corrupt checkpoint (per-body contact index shorter than the contacts)")
    if not C.ctr[C_CSR_DIRTY] and len(C.csr_start) == n + 1:
        start = C.csr_start
        if np.any(np.diff(start) < 0) or start[0] < 0 or start[-1] > len(C.csr_con):
            raise CheckpointError(f"{source}: corrupt checkpoint (per-body contact index out of range)")
        _range(C.csr_con[: start[-1]], 0, ncon, "per-body contact index", source)


def scene_decode(meta, arrays: dict[str, np.ndarray], source: str, namespace: dict):
    """``(scene, [materials of O.materials])`` rebuilt from ``(meta, arrays)`` with the classes of
    ``namespace`` (name -> class, holding ``Material``, the base of the materials); raises
    :class:`CheckpointError`."""
    from granum.engines.base import Engine

    if not (isinstance(meta, dict) and set(meta) == {"layout", "scene", "materials", "objects"}
            and isinstance(meta["scene"], dict) and isinstance(meta["objects"], list)):
        raise CheckpointError(f"{source}: corrupt checkpoint (malformed manifest)")
    _layout_check(meta["layout"], source)
    dec = _Decoder(arrays, source)
    classes = _classes(namespace)
    material = classes["Material"]
    for node in meta["objects"]:
        dec.objects.append(dec.obj(node, classes))
    scene = Scene()
    expected = {n for n in vars(scene) if not n.startswith("_")}
    if set(meta["scene"]) != expected:
        odd = sorted(set(meta["scene"]) ^ expected)
        raise CheckpointError(f"{source}: the checkpoint's scene fields differ from this granum's ({odd})")
    for name, node in meta["scene"].items():
        setattr(scene, name, dec.field(name, getattr(scene, name), node))
    materials = dec.value(meta["materials"])
    if not (isinstance(materials, list)
            and all(isinstance(m, material) for m in materials + scene.materials)
            and all(isinstance(e, Engine) for e in scene.engines)):
        raise CheckpointError(f"{source}: corrupt checkpoint (materials or engines of the wrong type)")
    _history_check(meta["layout"]["contact_history"], scene.contacts.con_f.shape[1], source)
    _codes_translate(scene.contacts, meta["layout"]["functors"], source)
    scene_check(scene, source)
    scene_values_check(scene, source)
    return scene, materials


# ---- files and bytes ----------------------------------------------------------------------------
def checkpoint_write(path, scene: Scene, materials, namespace: dict) -> None:
    """Save ``scene`` and ``O.materials`` to ``path`` atomically, in the format its extension names
    (objects of the classes of ``namespace``, see :func:`scene_encode`).

    Everything is encoded before the file is touched; the data go to a temporary file in the same
    directory, flushed to disk, which then replaces ``path``. On any error the temporary file is
    removed and an existing ``path`` is left as it was.
    """
    path = os.fspath(path)
    fmt, compression = format_of_path(path)
    meta, arrays = scene_encode(scene, materials, namespace)
    try:
        with atomic_path(path) as tmp, open(tmp, "w+b") as f:
            container_write(f, fmt, compression, meta, arrays)
            f.flush()
            os.fsync(f.fileno())
    except OSError as e:
        raise type(e)(e.errno, f"O.save: cannot write {path!r}: {e.strerror}") from e


def checkpoint_read(path, namespace: dict):
    """``(scene, [materials of O.materials])`` from the checkpoint ``path`` (any format, detected from the
    content), objects rebuilt with the classes of ``namespace`` (see :func:`scene_decode`)."""
    path = os.fspath(path)
    if not os.path.exists(path):
        raise CheckpointNotFoundError(2, f"O.load: checkpoint file {path!r} does not exist")
    with open(path, "rb") as f:
        meta, arrays = container_read(f, path)
    return scene_decode(meta, arrays, path, namespace)


def checkpoint_bytes(scene: Scene, materials, namespace: dict) -> bytes:
    """The checkpoint of ``scene`` and ``O.materials`` in memory (``.yade`` format; ``O.saveTmp``), objects of
    the classes of ``namespace``."""
    meta, arrays = scene_encode(scene, materials, namespace)
    buf = io.BytesIO()
    container_write(buf, "yade", None, meta, arrays)
    return buf.getvalue()


def checkpoint_from_bytes(data: bytes, namespace: dict, source: str = "checkpoint in memory"):
    """``(scene, [materials of O.materials])`` from :func:`checkpoint_bytes` output, objects rebuilt with the
    classes of ``namespace``."""
    meta, arrays = container_read(io.BytesIO(data), source)
    return scene_decode(meta, arrays, source, namespace)
