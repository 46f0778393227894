"""``yade.system``: questions about the class hierarchy of YADE's object model (``childClasses``...).

The hierarchy is the Python class hierarchy of the classes in :mod:`granum.yade.wrapper`; YADE's root
``Serializable`` stands for all of them.
"""

from __future__ import annotations

import sys

from granum.yade import wrapper
from granum.yade.omega import O

#: YADE's root class, of which every class of the object model derives
ROOT = "Serializable"


def _check_base(base: str) -> None:
    if not isinstance(base, str):
        raise TypeError(f"childClasses: the base is a class name (str), got {base!r}")


def _ancestors(cls: type) -> list[str]:
    """Names of the object-model classes ``cls`` derives from in YADE, nearest first, then ``Serializable``
    (``Omega`` is no Serializable). A class whose YADE parent is not its Python base (the dispatchers are
    engines in YADE, the display functors functors) names it in ``yade_parent``."""
    if cls is O.__class__:
        return []
    names = [k.__name__ for k in cls.__mro__[1:] if wrapper.CLASSES.get(k.__name__) is k]
    parent = getattr(cls, "yade_parent", None)
    if parent and parent not in names:
        names += [parent] + [n for n in _ancestors(wrapper.CLASSES[parent])[:-1] if n not in names]
    return names + [ROOT]


def childClasses(base: str, recurse: bool = True, includeBase: bool = False) -> set:
    """Names of the classes deriving from the class named ``base`` (all descendants, or only the direct
    ones with ``recurse=False``); ``base`` itself with ``includeBase``. An unknown name gives an empty
    set, as in YADE."""
    _check_base(base)
    found = set()
    for name, cls in wrapper.CLASSES.items():
        parents = _ancestors(cls)
        if (base in parents) if recurse else parents[:1] == [base]:
            found.add(name)
    if includeBase and (base in wrapper.CLASSES or base == ROOT):
        found.add(base)
    return found


def isChildClassOf(child: str, base: str) -> bool:
    """Whether the class named ``child`` derives from the class named ``base`` (``O.isChildClassOf``)."""
    cls = wrapper.CLASSES.get(child)
    return cls is not None and base in _ancestors(cls)


def cxxCtorsDict(proxyNamespace=None) -> dict:
    """Class name -> class of every class of the object model (YADE: to update a namespace with)."""
    return dict(wrapper.CLASSES)


__all__ = ["O", "childClasses", "cxxCtorsDict", "isChildClassOf", "sys", "wrapper"]
