"""Objects with declared attributes, constructed by keyword like YADE's classes.

YADE objects accept their attributes as constructor keywords (``NewtonIntegrator(
damping=.4)``), expose them for reading and writing, and list them with ``.dict()``.
:class:`Attributed` does the same for granum's engines, functors and materials and
rejects names it does not declare, so that a typo (``dampin=.4``) is an error
instead of a silently ignored setting.
"""

from __future__ import annotations

import difflib
import itertools
import math
import numbers

import numpy as np


class Attr:
    """Declaration of an attribute: default value, optional converter and documentation.

    ``convert(owner, value)`` validates/converts an assigned value and may raise
    ``ValueError``/``TypeError`` with a message naming the attribute.
    """

    def __init__(self, default=None, doc: str = "", convert=None, readonly: bool = False):
        self.default = default
        self.doc = doc
        self.convert = convert
        self.readonly = readonly


def _suggest(name: str, known) -> str:
    close = difflib.get_close_matches(name, list(known), n=1)
    return f" (did you mean {close[0]!r}?)" if close else ""


class Attributed:
    """Base of objects whose attributes are declared in the class-level ``_attrs`` dict.

    ``_attrs`` of a subclass extends those of its bases. Values are kept in the
    instance ``__dict__``; assigning an undeclared name raises ``AttributeError``.
    """

    _attrs: dict[str, Attr] = {}
    #: declared attributes assigned so far (:func:`edit_token`)
    _edits = 0

    def __init_subclass__(cls, **kw):
        super().__init_subclass__(**kw)
        merged = {}
        for base in reversed(cls.__mro__[1:]):
            merged.update(getattr(base, "_attrs", {}))
        merged.update(cls.__dict__.get("_attrs", {}))
        cls._attrs = merged

    def __init__(self, **kw):
        for name, a in self._attrs.items():
            object.__setattr__(self, name, _copy_default(a.default))
        for name, value in kw.items():
            if name not in self._attrs and not self._has_property(name):
                raise TypeError(f"{type(self).__name__}() got an unexpected keyword argument {name!r}"
                                f"{_suggest(name, self._known())}")
            setattr(self, name, value)

    @classmethod
    def _has_property(cls, name: str) -> bool:
        return isinstance(getattr(cls, name, None), property)

    @classmethod
    def _known(cls):
        return list(cls._attrs) + [n for n in dir(cls) if not n.startswith("_")]

    def __setattr__(self, name, value):
        a = self._attrs.get(name)
        if a is None:
            if name.startswith("_") or self._has_property(name):
                object.__setattr__(self, name, value)
                return
            raise AttributeError(f"{type(self).__name__} has no attribute {name!r}{_suggest(name, self._known())}")
        if a.readonly:
            raise AttributeError(f"{type(self).__name__}.{name} is read-only")
        if a.convert is not None:
            value = a.convert(self, value)
        object.__setattr__(self, name, value)
        object.__setattr__(self, "_edits", self._edits + 1)
        note_assignment()
        self._changed(name)

    def _changed(self, name: str) -> None:
        """Hook called after a declared attribute is assigned."""

    def dict(self) -> dict:
        """All declared attributes and their values (YADE's ``.dict()``)."""
        return {name: getattr(self, name) for name in self._attrs}

    def updateAttrs(self, values: dict) -> None:
        """Assign several attributes; unknown names raise."""
        for k, v in values.items():
            setattr(self, k, v)

    def updateExistingAttrs(self, values: dict) -> None:
        """Assign the attributes of ``values`` that exist; ignore the others."""
        for k, v in values.items():
            if k in self._attrs:
                setattr(self, k, v)

    def clone(self):
        """A new object of the same class with the same attribute values."""
        return type(self)(**{k: v for k, v in self.dict().items() if not self._attrs[k].readonly})

    def __repr__(self):
        return f"<{type(self).__name__} instance at {hex(id(self))}>"


def _copy_default(v):
    if isinstance(v, list):
        return list(v)
    if isinstance(v, dict):
        return dict(v)
    return v


def as_number(value, what: str) -> float:
    """``value`` as a float, or TypeError naming ``what`` ("Sphere.radius"). A bool is refused although
    ``float(True)`` is 1.0: a flag given where a quantity is expected is a mistake, not a value; so is a
    string, even ``"1"`` (YADE refuses strings for numbers too)."""
    if isinstance(value, bool | np.bool_ | str | bytes):
        raise TypeError(f"{what} must be a number, got {value!r}")
    try:
        return float(value)
    except (TypeError, ValueError):
        raise TypeError(f"{what} must be a number, got {value!r}") from None


def as_flag(value, what: str) -> bool:
    """``value`` as a bool, or TypeError naming ``what`` ("sphere: fixed"). Accepts True/False (also
    NumPy's) and the integers 0 and 1, as YADE's scripts write them; refuses anything else, such as the
    string ``'no'``, which Python would take as True."""
    if value is True or value is False:   # first: the body factories check several flags a body
        return value
    if isinstance(value, bool | np.bool_) or (isinstance(value, numbers.Integral) and value in (0, 1)):
        return bool(value)
    raise TypeError(f"{what} must be True or False, got {value!r}")


def to_float(name: str, positive: bool = False, allow_nan: bool = True):
    """Converter to float that names the attribute in its error messages."""

    def convert(owner, value):
        x = as_number(value, f"{type(owner).__name__}.{name}")
        if math.isnan(x) and not allow_nan:
            raise ValueError(f"{type(owner).__name__}.{name} must not be NaN")
        if positive and not x > 0:
            raise ValueError(f"{type(owner).__name__}.{name} must be positive, got {x!r}")
        return x

    return convert


def as_integer(value, what: str) -> int:
    """``value`` as an int (``2.0`` is 2), or TypeError naming ``what`` for a bool, a fraction or a non-number."""
    if isinstance(value, bool | np.bool_) or not float(as_number(value, what)).is_integer():
        raise TypeError(f"{what} must be an integer, got {value!r}")
    return int(value)


def to_int(name: str, minimum: int | None = None):
    """Converter to int that names the attribute in its error messages (see :func:`as_integer`); with
    ``minimum``, smaller values are refused (a number of steps: 1)."""

    def convert(owner, value):
        n = as_integer(value, f"{type(owner).__name__}.{name}")
        if minimum is not None and n < minimum:
            raise ValueError(f"{type(owner).__name__}.{name} must be at least {minimum}, got {n}")
        return n

    return convert


def to_bool(owner, value):
    return bool(value)


def instance_of(kind: type, noun: str, name: str):
    """Converter accepting only ``kind`` instances; its TypeError names the attribute and ``noun``."""

    def convert(owner, value):
        if not isinstance(value, kind):
            raise TypeError(f"{type(owner).__name__}.{name} must be {noun}, got {value!r}")
        return value

    return convert


def to_str(name: str):
    return instance_of(str, "a string", name)


def only_default(name: str, default):
    """Converter of an attribute granum does not implement yet: any value but ``default`` is refused by name
    (never accepted and ignored)."""

    def convert(owner, value):
        if value != default or isinstance(value, bool) != isinstance(default, bool):
            raise NotImplementedError(f"{type(owner).__name__}.{name}={value!r}: not implemented in granum yet "
                                      f"(only the default {default!r})")
        return default

    return convert


def one_of(name: str, allowed: tuple):
    """Converter to one of the integers ``allowed``, naming the attribute otherwise."""

    def convert(owner, value):
        if isinstance(value, bool) or value not in allowed:
            raise ValueError(f"{type(owner).__name__}.{name} must be one of {allowed}, got {value!r}")
        return int(value)

    return convert


#: a new value for every assignment to a declared attribute of any Attributed object (:func:`assignments`)
_ASSIGNMENT_STAMPS = itertools.count(1)
_assignments = 0


def note_assignment() -> None:
    """Take a new :func:`assignments` stamp: every assignment to a declared attribute does, and so must a setter
    that changes what an :func:`edit_token` would read without one (a dispatcher's functor list)."""
    global _assignments
    _assignments = next(_ASSIGNMENT_STAMPS)


def assignments() -> int:
    """The stamp of the last assignment to a declared attribute of any Attributed object: while it stays the same,
    no :func:`edit_token` has changed. Each assignment stores a value never stored before (``next`` of a counter is
    atomic; two threads assigning at once may store theirs out of order, but a stamp read after either store
    differs from every stamp read before it). A PeriodicEngine's schedule (``iterLast``, ``nDone``...) counts in
    its own edit count only: it is set at every step its engine may be due, and no parameters kept on this stamp
    read it (:attr:`granum.engines.base.Engine.key_from_edits`)."""
    return _assignments


def edit_token(obj: Attributed, held: list) -> tuple:
    """Edit counts of ``obj`` and of the Attributed objects its declared attributes hold (directly or in lists and
    tuples), depth first, with their ids; the objects are appended to ``held``, whose keeper keeps them alive (so
    that no new object takes an id of the token). Equal tokens of kept objects: the same attribute values, as
    long as values change by assignment (YADE hands out copies of its vectors and lists, so changing one in
    place changes nothing there either)."""
    held.append(obj)
    token = [id(obj), obj._edits]
    values = obj.__dict__
    for name in obj._attrs:
        v = values.get(name)
        for x in (v if isinstance(v, (list, tuple)) else (v,)):
            if isinstance(x, Attributed):
                token.append(edit_token(x, held))
    return tuple(token)
