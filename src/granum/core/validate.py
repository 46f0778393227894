"""The value rules of the scene, in one place: the attribute setters of the YADE layer (``O.dt``,
``Body.state.pos``, ``Sphere.radius``, ``Cell.hSize``, ...) check one value with them, and
:mod:`granum.io.checkpoint` checks whole loaded columns with the same rules, so a crafted checkpoint
cannot hold a value the setters refuse.

A :class:`Rule` tests values item by item: a scalar, or the last ``item_ndim`` axes of an array
(3-vectors, quaternions, 3x3 matrices); an array of items is checked at once.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import NamedTuple

import numpy as np


class Rule(NamedTuple):
    """A constraint on values.

    ``says``: what it requires, as the end of a sentence naming the value ("must be positive and
    finite"); ``holds(a)``: for an array ``a`` of items, a boolean array over its leading axes, True
    where the item obeys the rule; ``item_ndim``: the number of trailing axes one item has.
    """

    says: str
    holds: Callable[[np.ndarray], np.ndarray]
    item_ndim: int = 0
    #: optional: whether one item, given as the list of its components (floats), obeys the rule; the same answer
    #: as ``holds`` for it, in a fraction of its time (NumPy's calls on a 3-vector took 3.6 us, building a sphere
    #: checked three of them)
    item_holds: Callable[[list], bool] | None = None

    def check(self, value, name: str | Callable[[], str], error: type[Exception] = ValueError) -> None:
        """Raise ``error`` (a ValueError by default) naming ``name`` unless the single item ``value``
        obeys the rule. ``name`` may be a function that makes the name, called only for the error (a setter
        checking values in a loop need not format a name each time)."""
        # a float goes to the rule as it is (0-d arrays and np.all cost several microseconds a value)
        if self.item_holds is not None:
            ok = self.item_holds([value] if type(value) is float else np.asarray(value, dtype=float).ravel().tolist())
        elif type(value) is float:
            ok = self.holds(value)
        else:
            ok = self.holds(np.asarray(value, dtype=float)).all()
        if not ok:
            shown = value if np.ndim(value) == 0 else tuple(np.asarray(value).ravel().tolist())
            raise error(f"{name if isinstance(name, str) else name()} {self.says}, got {shown!r}")

    def check_items(self, values: np.ndarray, name: str, ids=None) -> None:
        """Raise ValueError unless every item of ``values`` (items along the leading axes) obeys the
        rule. The error names the first offending item and its value: ``name`` with ``{}`` replaced
        by its identifier, ``ids[k]`` for item ``k`` (``k`` itself when ``ids`` is None)."""
        values = np.asarray(values)
        bad = np.flatnonzero(~self.holds(values.astype(float, copy=False)))
        if bad.size:
            k = int(bad[0])
            lead = values.shape[: values.ndim - self.item_ndim]
            item = values[np.unravel_index(k, lead)] if lead else values
            shown = item.item() if item.ndim == 0 else tuple(item.ravel().tolist())
            label = name.format(k if ids is None else int(ids[k]))
            raise ValueError(f"{label} {self.says}, got {shown!r}" + (f" ({bad.size} such)" if bad.size > 1 else ""))


def _all_finite(components: list) -> bool:
    return all(map(math.isfinite, components))


def _finite_not_negative(components: list) -> bool:
    return all(math.isfinite(x) and x >= 0 for x in components)


def _finite_positive(components: list) -> bool:
    return all(math.isfinite(x) and x > 0 for x in components)


def _finite_items(item_ndim: int) -> Callable[[np.ndarray], np.ndarray]:
    axes = tuple(range(-item_ndim, 0))
    return lambda a: np.isfinite(a).all(axis=axes) if item_ndim else np.isfinite(a)


def _one_of(choices: tuple) -> Callable[[np.ndarray], np.ndarray]:
    return lambda a: np.isin(a, choices)


def _triangle_area2(v: np.ndarray) -> np.ndarray:
    """Twice the area of triangles ``v[..., 3, 3]`` (vertices as rows) [m^2]."""
    return np.linalg.norm(np.cross(v[..., 1, :] - v[..., 0, :], v[..., 2, :] - v[..., 0, :]), axis=-1)


def _positive_volume(h: np.ndarray) -> np.ndarray:
    finite = np.isfinite(h).all(axis=(-2, -1))
    return finite & (np.linalg.det(np.where(np.isfinite(h), h, 0.0)) > 0)


#: A time step [s]: finite, not negative (0 is allowed, as in YADE: its periodic-cell tests step with dt = 0).
TIME_STEP = Rule("must be a finite time step in seconds, not negative", lambda a: np.isfinite(a) & (a >= 0),
                 item_holds=_finite_not_negative)
#: A length that must be positive, such as a sphere radius [m].
POSITIVE_FINITE = Rule("must be positive and finite", lambda a: np.isfinite(a) & (a > 0), item_holds=_finite_positive)
#: A mass [kg].
NON_NEGATIVE_FINITE = Rule("must be a finite non-negative number", lambda a: np.isfinite(a) & (a >= 0),
                           item_holds=_finite_not_negative)
#: A 3-vector of finite components (position, velocity, ...).
FINITE_VECTOR = Rule("must be finite", _finite_items(1), 1, _all_finite)
#: A 3x3 matrix of finite components (velocity gradient, facet vertices).
FINITE_MATRIX = Rule("must be finite", _finite_items(2), 2, _all_finite)
#: An orientation (w, x, y, z) that can be normalised.
QUATERNION = Rule("must be a finite non-zero quaternion",
                  lambda a: np.isfinite(a).all(axis=-1) & (np.abs(np.where(np.isfinite(a), a, 0)).sum(axis=-1) > 0), 1)
#: Half-sizes of a box [m]: finite and not negative.
EXTENTS = Rule("must be finite and non-negative", lambda a: (np.isfinite(a) & (a >= 0)).all(axis=-1), 1,
               _finite_not_negative)
#: The three vertices of a facet (rows) [m]: finite and not collinear.
TRIANGLE = Rule("must be three finite 3-vectors that are not collinear (the facet needs an area)",
                lambda v: np.isfinite(v).all(axis=(-2, -1)) & (_triangle_area2(np.where(np.isfinite(v), v, 0)) > 0), 2)
#: Base vectors of a periodic cell (columns) [m]: finite, spanning a positive volume.
CELL_BASE = Rule("must be finite with a positive volume", _positive_volume, 2)
#: The normal axis of a wall.
WALL_AXIS = Rule("must be 0, 1 or 2", _one_of((0, 1, 2)))
#: The active side of a wall.
WALL_SENSE = Rule("must be -1, 0 or 1", _one_of((-1, 0, 1)))
#: YADE's ``Cell.homoDeform``.
HOMO_DEFORM = Rule("must be 0, 1 or 2", _one_of((0, 1, 2)))
