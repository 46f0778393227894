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


class Functor(Attributed):
    """Base of all functors (YADE ``Functor``)."""

    _attrs = {"label": Attr("", "Name under which the functor is reachable from scripts", to_str("label"))}
    spec: registry.Functor

    @property
    def code(self) -> int:
        return code_of(self.spec.yade_name)

    def numeric_params(self) -> list[float]:
        """The functor's numeric parameters in registry order (booleans as 0/1)."""
        compiled = self.spec.compiled_params()
        for p in self.spec.params:
            value = getattr(self, p.name)
            if not p.supported and not _same(value, p.default):
                raise NotImplementedError(f"{type(self).__name__}.{p.name}={value!r} is not supported by granum "
                                          f"yet (only the default {p.default!r})")
        return [float(getattr(self, p.name)) for p in compiled]

    def prepare(self, scene) -> None:
        """Called by the engine listing the functor when it builds its parameters, before a run of ``scene``
        (a functor's mixin, ``registry.Functor.python``, may act on the scene then); nothing by default."""


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


def _convert_like(default):
    if isinstance(default, bool):
        return lambda o, v: bool(v)
    if isinstance(default, int):
        return lambda o, v: int(v)
    if isinstance(default, float):
        return lambda o, v: float(v)
    return None


def make_class(spec: registry.Functor) -> type:
    """The YADE-named class of a registered functor."""
    attrs = {p.name: Attr(p.default, p.doc, _convert_like(p.default)) for p in spec.params}
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
    width = max([len(s.params) for s in specs] + [1])
    prm = np.zeros((len(specs), width))
    for code in more_codes:   # with their default parameters
        values = CLASSES[specs[code].yade_name]().numeric_params()
        prm[code, : len(values)] = values
    for f in instances:
        values = f.numeric_params()
        prm[f.code, : len(values)] = values
    return functor_set(role, [f.code for f in instances] + list(more_codes)), prm


def check_role(f, role: str, where: str) -> None:
    """Raise a TypeError if ``f`` is not a functor of ``role``."""
    if not isinstance(f, _BASES[role]):
        raise TypeError(f"{where}: expected {_BASES[role].__name__.replace('Functor', '')} functors "
                        f"({_BASES[role].__name__}), got {f!r}")
