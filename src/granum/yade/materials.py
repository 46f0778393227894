"""Material classes (``Material``, ``ElastMat``, ``FrictMat``, ...) and ``O.materials``.

One class per material kind of the registry, named as in YADE and with the same
inheritance, so ``isinstance(m, FrictMat)`` works for a ``ViscElMat``. A material
object keeps its own attribute values; the scene compiles the materials its bodies
use into the material table before each run (``version`` tells it what changed).
Changing a material affects contacts created afterwards only, as in YADE.
"""

from __future__ import annotations

from granum.core.attrs import Attr, Attributed, one_of, only_default, to_float, to_int, to_str
from granum.physics import registry


class Material(Attributed):
    """Base material (YADE ``Material``): density, label and id in ``O.materials``."""

    kind = "Material"
    _attrs = {
        "label": Attr("", "Name to find the material by in O.materials", to_str("label")),
        "id": Attr(-1, "Index in O.materials (-1: not shared)", to_int("id")),
    }

    def __init__(self, **kw):
        object.__setattr__(self, "version", 0)
        super().__init__(**kw)

    def _changed(self, name: str) -> None:
        object.__setattr__(self, "version", self.version + 1)

    def state_class(self) -> type:
        """The class of state bodies of this material need: CpmState for a CpmMat, else State."""
        from granum.yade.bodies import CpmState, State

        return CpmState if "CpmMat" in registry.material_ancestry(self.kind) else State

    def newAssocState(self):
        """A new state of the class bodies of this material need (:meth:`state_class`)."""
        return self.state_class()()

    def stateTypeOk(self, state) -> bool:
        """Whether ``state`` is of the class :meth:`newAssocState` makes."""
        return type(state) is self.state_class()

    def column_values(self) -> dict:
        """Material-table columns of this material (see :meth:`granum.core.scene.Scene.material_arrays`)."""
        out = {}
        for k in registry.material_ancestry(self.kind):
            kind = registry.MATERIALS[k]
            for p in kind.params:
                if isinstance(p.default, int | float):
                    out[kind.columns.get(p.name, p.name)] = float(getattr(self, p.name))
        return out


def _converter(p: registry.Param):
    if not p.supported:
        return only_default(p.name, p.default)
    if p.name == "mRtype":
        return one_of(p.name, (1, 2))
    if isinstance(p.default, bool):
        return lambda o, v: bool(v)
    if isinstance(p.default, float) or isinstance(p.default, int) and p.valid is not None:
        conv = to_float(p.name) if isinstance(p.default, float) else to_int(p.name)

        def check(owner, value):
            x = conv(owner, value)
            p.check(type(owner).__name__, float(x))
            return x

        return check
    if isinstance(p.default, int):
        return to_int(p.name)
    return None


def _make(kind: registry.MaterialKind, base: type) -> type:
    attrs = {p.name: Attr(p.default, p.doc, _converter(p)) for p in kind.params}
    return type(kind.name, (base,), {"_attrs": attrs, "kind": kind.name, "__doc__": kind.doc,
                                     "__module__": __name__})


CLASSES: dict[str, type] = {"Material": None}


def add_class(kind: registry.MaterialKind) -> type:
    """Make (or make again, for a changed declaration) the class of a registered material kind."""
    if kind.name == "Material":
        Material._attrs.update({p.name: Attr(p.default, p.doc, _converter(p)) for p in kind.params})
        CLASSES["Material"] = Material
    else:
        CLASSES[kind.name] = _make(kind, CLASSES[kind.parent])
    return CLASSES[kind.name]


for _kind in registry.MATERIALS.values():
    add_class(_kind)
#: the materials granum itself declares (a user's material may not take their names)
BUILT_IN = frozenset(CLASSES)


def default_material():
    """YADE's default material: FrictMat(density=1e3, young=1e7, poisson=.3, frictionAngle=.5)."""
    return CLASSES["FrictMat"](density=1e3, young=1e7, poisson=0.3, frictionAngle=0.5, label="defaultMat")


class MaterialContainer:
    """``O.materials``: the shared materials, addressed by index or label."""

    def __init__(self):
        self._items: list = []

    def append(self, m):
        """Add a material (or a list of them); return its id (or the list of ids)."""
        if isinstance(m, list | tuple):
            return [self.append(x) for x in m]
        if not isinstance(m, Material):
            raise TypeError(f"O.materials.append: expected a Material, got {m!r}")
        if any(x is m for x in self._items):
            raise ValueError("O.materials.append: this material is already in O.materials "
                             f"(id {m.id})")
        m.id = len(self._items)
        self._items.append(m)
        return m.id

    def __getitem__(self, key):
        if isinstance(key, str):
            for m in self._items:
                if m.label == key:
                    return m
            raise KeyError(f"No material labeled {key!r}")
        try:
            return self._items[key]
        except IndexError:
            raise IndexError(f"Material id {key} out of range (there are {len(self._items)} materials)") from None

    def index(self, label: str) -> int:
        return self[label].id

    def __len__(self):
        return len(self._items)

    def __iter__(self):
        return iter(self._items)

    def clear(self) -> None:
        self._items.clear()


