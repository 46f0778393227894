"""Contact laws, physics and materials written in a user's own script or module.

A law is a plain Python function with the calling convention of granum's own laws
(:mod:`granum.physics.registry`); the decorator registers it and returns the YADE functor
class of the function's name, which goes into ``O.engines`` like any YADE functor::

    from granum.yade.userlaws import law, F_FN, F_KN, F_NORMAL, F_PEN

    @law(types=("ScGeom", "FrictPhys"), params={"neverErase": False})
    def Law2_ScGeom_FrictPhys_Spring(c, id1, id2, S, C, prm):
        '''Normal spring only: F_N = k_n delta n on body 2.'''
        f = C.con_f
        if f[c, F_PEN] < 0.0 and prm[0] == 0.0:
            return False          # the contact ends
        for k in range(3):
            f[c, F_FN + k] = f[c, F_KN] * f[c, F_PEN] * f[c, F_NORMAL + k]
        return True

    O.engines = [..., InteractionLoop([Ig2_Sphere_Sphere_ScGeom()], [Ip2_FrictMat_FrictMat_FrictPhys()],
                                      [Law2_ScGeom_FrictPhys_Spring(neverErase=True)]), ...]

The function is compiled into the interaction loop's dispatch and inlined there, as granum's
own laws are, so it runs at their speed. The compiled code is cached on disk under a digest of
the function's code (:func:`granum.physics.registry.code_digest`: its bytecode, the helpers it
calls and the constants it reads), so a second run loads it and an edited law compiles again;
nothing else is recompiled. Helpers a law calls must be compiled functions (decorate them with
:func:`jit`) imported or defined by name. Checkpoints store the functor by its name: a script
that loads a checkpoint with contacts of a user's law defines the law before ``O.load``.

Arguments of a law ``(c, id1, id2, S, C, prm)``: ``c`` the contact's row in the pool ``C.con_f``
(float columns ``F_*``) and ``C.con_i`` (integer columns ``I_*``), ``id1``/``id2`` the bodies
(body arrays ``S.pos[id]``, ``S.vel[id]``..., material row ``S.mat[S.material[id]]``), ``prm`` the
functor's numeric parameters in the order declared (booleans as 0/1). Write the normal and shear
force on body 2 into ``F_FN``/``F_FS`` (and, for a law with moments -- rolling, twisting, bending --, the
moment on body 2 into ``F_MOMENT`` at every step, naming ``"moment"`` in its history: the force gather adds
it to body 2's torque and its opposite to body 1's); return False to end the contact. A physics functor
``(c, id1, id2, S, C, prm)`` computes the constants of a new contact (``F_KN``, ``F_KS``, ``F_TANPHI``, its
own columns).
"""

from __future__ import annotations

import inspect
from collections import namedtuple

import granum.yade as _yade
from granum import _jit
from granum.core.arrays import S_DT, S_TIME, SI_ITER, SI_TRACK_ENERGY
from granum.core.contacts import (
    F_E_DISSIP,
    F_E_ELAST,
    F_FN,
    F_FS,
    F_KN,
    F_KS,
    F_MOMENT,
    F_NORMAL,
    F_PEN,
    F_POINT,
    F_R1,
    F_R2,
    F_TANPHI,
    FLAG_RADIAL_ARMS,
    HISTORY_COLUMNS,
    I_FLAGS,
    register_history,
)
from granum.engines import functors as _functors
from granum.physics import registry
from granum.physics.materials import column as material_column
from granum.physics.registry import Param, Range
from granum.physics.scgeom import contact_shift, scgeom_incident_vel, scgeom_ratchet, scgeom_rotate_shear, tangential
from granum.physics.vec import add, cross, dot, norm, scale, sub
from granum.yade import interactions as _interactions
from granum.yade import materials as _materials

__all__ = [
    "law", "phys", "phys_type", "material", "jit", "Param", "Range", "material_column",
    "F_NORMAL", "F_PEN", "F_POINT", "F_R1", "F_R2", "F_KN", "F_KS", "F_TANPHI", "F_FN", "F_FS",
    "F_MOMENT", "F_E_ELAST", "F_E_DISSIP", "I_FLAGS", "FLAG_RADIAL_ARMS",
    "S_DT", "S_TIME", "SI_ITER", "SI_TRACK_ENERGY",
    "contact_shift", "scgeom_incident_vel", "scgeom_ratchet", "scgeom_rotate_shear", "tangential",
    "add", "cross", "dot", "norm", "scale", "sub",
]

#: the contact column groups of the physics types declared here (type name -> group names)
_TYPE_GROUPS: dict[str, tuple[str, ...]] = {}
#: the calling convention every law and physics functor has
_ARGS = ("c", "id1", "id2", "S", "C", "prm")
#: what a functor's name starts with, per role (YADE's convention, which its class hierarchy follows)
_PREFIX = {"law": "Law2_", "phys": "Ip2_"}


def jit(fn=None, **options):
    """Compile a helper that a user's law calls (granum's ``jit``, see :func:`granum._jit.jit`). The helper is
    not cached on its own: its code is part of the law's kernel, which is cached under the law's digest
    (scripts run with ``exec`` have no file Numba could key a cache on)."""
    return _jit.jit(fn, **{"cache": False, **options})


def _publish(name: str, obj) -> None:
    """Give scripts (``from yade import *`` after this) and checkpoints (which rebuild objects by class
    name from the YADE namespace) the class ``name``."""
    _yade._namespace[name] = obj
    setattr(_yade, name, obj)
    if name not in _yade.__all__:
        _yade.__all__.append(name)


def _params(owner: str, params) -> tuple[Param, ...]:
    """``params`` ({name: default} or Param records) as Param records with numeric defaults."""
    items = [Param(n, d) for n, d in params.items()] if isinstance(params, dict) else list(params)
    for p in items:
        if not isinstance(p, Param):
            raise TypeError(f"{owner}: a parameter is a Param or a name: default item of a dict, got {p!r}")
        if not isinstance(p.default, bool | int | float):
            raise TypeError(f"{owner}.{p.name}: a parameter's default must be a number or a bool (compiled code "
                            f"reads it as a float), got {p.default!r}")
    return tuple(items)


def _groups_of_phys(name: str) -> tuple[str, ...]:
    """The contact column groups the physics type ``name`` and its parents keep: those declared here,
    and those granum's physics functors producing them use."""
    out: list[str] = []
    chain = registry.phys_ancestry(name)
    for t in chain:
        out += _TYPE_GROUPS.get(t, ())
    for f in registry.FUNCTORS.values():
        if f.role == "phys" and f.function is None and f.produces in chain:
            out += f.history
    return tuple(dict.fromkeys(out))


def _register(role: str, func, types: tuple, produces: str | None, params, history) -> type:
    name = getattr(func, "__name__", None)
    if not inspect.isfunction(getattr(func, "py_func", func)):
        raise TypeError(f"a {role} functor is a Python function, got {func!r}")
    if not name.startswith(_PREFIX[role]):
        raise ValueError(f"{name}: a {role} functor's name starts with {_PREFIX[role]!r} (it is the YADE class "
                         f"name scripts use, e.g. {_PREFIX[role]}ScGeom_MyPhys_MyLaw)")
    args = tuple(inspect.signature(getattr(func, "py_func", func)).parameters)
    if len(args) != len(_ARGS):
        raise TypeError(f"{name}{inspect.signature(func)}: a {role} functor takes (c, id1, id2, S, C, prm)")
    if len(types) != 2 or not all(isinstance(t, str) for t in types):
        raise TypeError(f"{name}: types is a pair of type names, got {types!r}")
    if role == "phys":
        for t in types:
            if t not in registry.MATERIALS:
                raise ValueError(f"{name}: unknown material {t!r} (declared: {', '.join(registry.MATERIALS)})")
        if produces not in registry.PHYS_TYPES:
            raise ValueError(f"{name}: unknown physics type {produces!r}; declare it with phys_type()")
    else:
        if types[0] not in registry.GEOM_TYPES:
            raise ValueError(f"{name}: unknown geometry type {types[0]!r} (declared: {', '.join(registry.GEOM_TYPES)})")
        if types[1] not in registry.PHYS_TYPES:
            raise ValueError(f"{name}: unknown physics type {types[1]!r}; declare it with phys_type()")
    history = tuple(dict.fromkeys(_groups_of_phys(produces if role == "phys" else types[1]) + tuple(history)))
    for g in history:
        if g not in HISTORY_COLUMNS:
            raise ValueError(f"{name}: unknown contact column group {g!r} (declared: {', '.join(HISTORY_COLUMNS)})")
    spec = registry.Functor(name, role, types, produces, f"{func.__module__}:{func.__qualname__}",
                            _params(name, params), inspect.getdoc(func) or "", tuple(history),
                            function=func, digest=registry.code_digest(func))
    registry.register_functor(spec)
    cls = _functors.make_class(spec)
    _functors.CLASSES[name] = cls
    _publish(name, cls)
    return cls


def law(types, params=(), history=()):
    """Decorator: register the function as the law functor of its name for the contacts of geometry
    ``types[0]`` and physics ``types[1]``, with numeric ``params`` ({name: default}, in the order of
    ``prm``) and the contact column groups it reads or writes besides those of its physics type
    (``history``; ``("moment",)`` for a law that writes the contact moment ``F_MOMENT``). Returns the
    functor class (``Law2_...``)."""
    return lambda func: _register("law", func, tuple(types), None, params, history)


def phys(materials, produces: str, params=(), history=()):
    """Decorator: register the function as the physics functor of its name, making contacts of type
    ``produces`` between bodies of the two ``materials``. Returns the functor class (``Ip2_...``)."""
    return lambda func: _register("phys", func, tuple(materials), produces, params, history)


def phys_type(name: str, parent: str = "FrictPhys", fields: dict | None = None) -> tuple:
    """Declare a physics type (an ``IPhys`` class) with extra per-contact float ``fields`` ({YADE attribute:
    width}: 1 a float, 3 a Vector3, 9 a Matrix3), kept in a contact column group named after the type.
    ``i.phys.<attribute>`` reads and writes them. Returns the first column of each field in ``C.con_f``
    as a named tuple, which compiled code reads as constants (``MyPhys = phys_type(...); f[c, MyPhys.kr]``)."""
    fields = dict(fields or {})
    for attr, width in fields.items():
        if width not in (1, 3, 9):
            raise ValueError(f"{name}.{attr}: a field's width is 1, 3 or 9, got {width!r}")
    columns, groups = {}, ()
    if fields:
        offset = register_history(name, sum(fields.values()))
        groups = (name,)
        for attr, width in fields.items():
            columns[attr] = (offset, width)
            offset += width
    registry.register_phys_type(name, parent, columns)
    _TYPE_GROUPS[name] = groups
    _interactions.add_views(registry.PHYS_TYPES, _interactions.PHYS_VIEWS)
    _publish(name, _interactions.PHYS_VIEWS[name])
    return namedtuple(f"{name}Columns", list(columns))(*(col for col, _ in columns.values()))


def material(name: str, parent: str = "FrictMat", params=(), doc: str = "") -> type:
    """Declare a material class ``name`` deriving from ``parent`` with numeric ``params`` ({name: default}
    or Param records). Compiled physics functors read a parameter from the material table as
    ``S.mat[S.material[id1], material_column("name")]`` (take the column as a module constant). Returns
    the class."""
    old = registry.MATERIALS.get(name)
    if old is not None and name in _materials.BUILT_IN:
        raise ValueError(f"{name} is one of granum's materials; choose another name")
    if parent not in registry.MATERIALS:
        raise ValueError(f"{name}: unknown parent material {parent!r} (declared: {', '.join(registry.MATERIALS)})")
    kind = registry.MaterialKind(name, parent, _params(name, params), doc=doc)
    if old is not None and (old.parent, old.params) != (kind.parent, kind.params):
        raise ValueError(f"material {name} is already declared with other parameters; choose another name")
    registry.register_material(kind)
    cls = _materials.add_class(kind)
    _publish(name, cls)
    return cls
