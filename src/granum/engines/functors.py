"""Functor classes (``Bo1_*``, ``Ig2_*``, ``Ip2_*``, ``Law2_*``) generated from the registry.

A functor object only carries its parameters; the physics is the registered
compiled function. One class is generated per registered functor, named as in YADE.
"""

from __future__ import annotations

import importlib
import math

import numpy as np

from granum.core.attrs import Attr, Attributed, to_str
from granum.kernels.dispatch import code_of, functor_set, functors
from granum.physics import registry
from granum.physics.matchmaker import as_matchmaker


class Functor(Attributed):
    """Base of all functors (YADE ``Functor``)."""

    _attrs = {"label": Attr("", "Name under which the functor is reachable from scripts", to_str("label"))}
    spec: registry.Functor

    @property
    def code(self) -> int:
        return code_of(self.spec.yade_name)

    #: the compiled tables of the MatchMaker parameters given, by name, for the scene's material rows
    #: (built by :meth:`prepare`)
    _pair_tables: dict = {}

    def numeric_params(self) -> list[float]:
        """The functor's numeric parameters in registry order (booleans as 0/1), a MatchMaker as the offset
        of its table (0: None), then the MatchMakers' tables (:mod:`granum.physics.matchmaker`)."""
        compiled = self.spec.compiled_params()
        for p in self.spec.params:
            value = getattr(self, p.name)
            if not p.supported and not _same(value, p.default):
                raise NotImplementedError(f"{type(self).__name__}.{p.name}={value!r} is not supported by granum "
                                          f"yet (only the default {p.default!r})")
        values = [0.0] * len(compiled)
        tables: list[float] = []
        for k, p in enumerate(compiled):
            if not p.matchmaker:
                values[k] = float(getattr(self, p.name))
            elif getattr(self, p.name) is None:
                values[k] = 0.0   # a table's offset is never 0: it follows the parameters
            else:
                values[k] = float(len(compiled) + len(tables))
                tables += self._pair_tables[p.name]
        return values + tables

    def prepare(self, scene) -> None:
        """Called by the engine listing the functor when it builds its parameters, before a run of ``scene``:
        checks the values of the MatchMaker parameters against their ranges and makes their tables for the
        scene's materials. A functor's mixin (``registry.Functor.python``) may act on the scene too, and calls
        this first."""
        tables = {}
        for p in self.spec.params:
            mm = getattr(self, p.name) if p.matchmaker else None
            if mm is None:
                continue
            owner = f"{type(self).__name__}.{p.name}"
            if mm.algo == "val" and mm.val != mm.val:
                raise ValueError(f"{owner}: MatchMaker(algo='val') needs val, got val=nan")
            if p.matchmaker == "bare" and mm.algo not in ("val", "zero") and not mm.matches:
                raise ValueError(f"{owner}: MatchMaker(algo={mm.algo!r}) without matches gives no value: "
                                 f"{type(self).__name__} supplies no values for the algorithm to combine (as in "
                                 f"YADE); give matches, or algo 'val' with val")
            if p.valid is not None:
                for x in mm.values():
                    p.check(type(self).__name__, x)
            tables[p.name] = mm.table([getattr(m, "id", -1) for m in scene.materials])
        self._pair_tables = tables

    def explain_pair(self, scene, id1: int, id2: int) -> str | None:
        """Why this functor has no value for the materials of bodies ``id1``, ``id2`` (the run stopped with
        ``STATUS_NO_PAIR_VALUE``), or None if it has one; a mixin may add reasons of its own."""
        mats = [scene.materials[scene.bodies.material[i]] for i in (id1, id2)]
        ids = [getattr(m, "id", -1) for m in mats]
        for p in self.spec.params:
            mm = getattr(self, p.name) if p.matchmaker == "bare" else None
            if mm is not None and mm.matched(*ids) is None and mm.algo not in ("val", "zero"):
                return (f"{type(self).__name__}.{p.name}: its MatchMaker has no match for the materials {ids[0]} "
                        f"and {ids[1]} of bodies {id1} and {id2}, and algo {mm.algo!r} needs values that "
                        f"{type(self).__name__} does not supply (YADE stops there too); add ({ids[0]}, {ids[1]}, "
                        f"value) to its matches, or use algo 'val'")
        return None


def _same(value, default) -> bool:
    """Whether an attribute still holds its default (NaN, which never equals itself, included)."""
    if value is default or value == default:
        return True
    return isinstance(value, float) and isinstance(default, float) and math.isnan(value) and math.isnan(default)


class BoundFunctor(Functor):
    """YADE ``BoundFunctor``."""


class IGeomFunctor(Functor):
    """YADE ``IGeomFunctor``."""


class IPhysFunctor(Functor):
    """YADE ``IPhysFunctor``."""


class LawFunctor(Functor):
    """YADE ``LawFunctor``."""


_BASES = {"bound": BoundFunctor, "geom": IGeomFunctor, "phys": IPhysFunctor, "law": LawFunctor}


def _convert_like(p: registry.Param):
    default = p.default
    if p.matchmaker:
        return as_matchmaker(p.name)
    if isinstance(default, bool):
        return lambda o, v: bool(v)
    if isinstance(default, int):
        return lambda o, v: int(v)
    if isinstance(default, float):
        return lambda o, v: float(v)
    return None


def make_class(spec: registry.Functor) -> type:
    """The YADE-named class of a registered functor."""
    attrs = {p.name: Attr(p.default, p.doc, _convert_like(p)) for p in spec.params}
    bases = (_BASES[spec.role],)
    if spec.python:   # a mixin with the functor's Python side (see registry.Functor.python)
        module, name = spec.python.split(":")
        bases = (getattr(importlib.import_module(module), name),) + bases
    return type(spec.yade_name, bases, {"_attrs": attrs, "spec": spec, "__doc__": spec.doc, "__module__": __name__})


CLASSES = {name: make_class(spec) for name, spec in registry.FUNCTORS.items()}


def functor_table(role: str, instances, more_codes=()) -> tuple:
    """The functor table of ``role`` that kernels dispatch through (:mod:`granum.kernels.dispatch`):
    the set of the given instances' codes and ``more_codes``, and their parameters (row = functor code;
    the functors of ``more_codes`` not among ``instances`` have their default parameters)."""
    specs = functors(role)
    rows = {f.code: f.numeric_params() for f in instances}
    rows.update({code: CLASSES[specs[code].yade_name]().numeric_params() for code in more_codes  # the defaults
                 if code not in rows})
    # a MatchMaker's table makes its row longer than the functor's parameters
    prm = np.zeros((len(specs), max([len(s.params) for s in specs] + [len(v) for v in rows.values()] + [1])))
    for code, values in rows.items():
        prm[code, : len(values)] = values
    return functor_set(role, [f.code for f in instances] + list(more_codes)), prm


def check_role(f, role: str, where: str) -> None:
    """Raise a TypeError if ``f`` is not a functor of ``role``."""
    if not isinstance(f, _BASES[role]):
        raise TypeError(f"{where}: expected {_BASES[role].__name__.replace('Functor', '')} functors "
                        f"({_BASES[role].__name__}), got {f!r}")
