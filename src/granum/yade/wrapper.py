"""``yade.wrapper``: every class of YADE's object model that granum has (engines, functors, dispatchers,
materials, shapes, states, interaction geometry and physics, ``Body``, ``Interaction``, ``Cell``,
``Omega``), and ``O``. YADE scripts write ``from yade.wrapper import *``.

The math types are in :mod:`granum.yade.minieigenHP`, as in YADE.
"""

from __future__ import annotations

import inspect

import granum.yade as _yade
from granum import mathtypes as _mathtypes

#: modules whose classes are not part of the object model: the math types (yade.minieigenHP) and the packing
#: classes and predicates (yade.pack)
_NOT_MODEL = (_mathtypes.__name__, "granum.yade.pack", "granum.yade._packing", "granum.yade._surfacepack")


def _is_model_class(value) -> bool:
    """A class of YADE's object model: not a math type, not an exception, not a granum-only class."""
    return (inspect.isclass(value) and not issubclass(value, BaseException)
            and value.__module__ not in _NOT_MODEL and not value.__module__.startswith("granum.idem")
            and value.__name__ != "clumpTemplate")


#: name -> class, every class of the object model
CLASSES: dict[str, type] = {name: value for name, value in _yade.namespace().items()
                            if _is_model_class(value) and name == value.__name__}

globals().update(CLASSES)
O = _yade.O
__all__ = sorted(CLASSES) + ["O"]
