"""YADE's ``yade.linterpolation``: piecewise-linear functions given as two lists ``x``, ``y``.

The ``x`` list is increasing. A periodic function wraps from the last x to the first,
which should then be 0 (:func:`xFromIntegral`). Units are those of the data: the
integral of y [y-unit] over x [x-unit] is in [y-unit x-unit].
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["integral", "revIntegrateLinear", "xFractionalFromIntegral", "xFromIntegral", "sanitizeInterpolation"]


def integral(x, y) -> float:
    """Integral of the piecewise-linear function through (x_i, y_i) (trapezoids); 0 for one point."""
    x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    return float(np.sum(0.5 * (y[1:] + y[:-1]) * np.diff(x)))


def revIntegrateLinear(I, x0, y0, x1, y1) -> float:
    """The x in [x0, x1] with int_x0^x f = ``I``, f the line through (x0, y0) and (x1, y1).

    Raises ValueError when no such x exists in the interval, or when two do.
    """
    slope = (y1 - y0) / (x1 - x0)
    span = x1 - x0
    # f = y0 + slope t with t = x - x0:  slope/2 t^2 + y0 t - I = 0
    if slope == 0:
        roots = [I / y0] if y0 != 0 else []
    else:
        disc = y0 * y0 + 2.0 * slope * I
        roots = [] if disc < 0 else sorted({(-y0 + s * math.sqrt(disc)) / slope for s in (1.0, -1.0)})
    inside = [t for t in roots if 0.0 <= t <= span]
    if not inside:
        raise ValueError(f"revIntegrateLinear: no x in [{x0}, {x1}] where the integral reaches {I}")
    if len(inside) > 1:
        raise ValueError(f"revIntegrateLinear: the integral reaches {I} twice in [{x0}, {x1}]")
    return x0 + inside[0]


def xFractionalFromIntegral(integral, x, y) -> float:
    """The x in [x_0, x_n] where int_x0^x f reaches ``integral``; ValueError if it never does."""
    done = 0.0
    for i in range(len(x) - 1):
        piece = 0.5 * (y[i] + y[i + 1]) * (x[i + 1] - x[i])
        if done + piece >= integral:
            return revIntegrateLinear(integral - done, x[i], y[i], x[i + 1], y[i + 1])
        done += piece
    if integral == done == 0.0:
        return x[0]
    raise ValueError(f"xFractionalFromIntegral: the integral {integral} is not reached within the range "
                     f"(it reaches {done})")


def xFromIntegral(integralValue, x, y) -> float:
    """The x where int_x0^x f reaches ``integralValue``, f repeated with period x_n (x_0 should be 0)."""
    period = integral(x, y)
    whole = math.floor(integralValue / period)
    return whole * x[-1] + xFractionalFromIntegral(integralValue - whole * period, x, y)


def sanitizeInterpolation(x, y, x0, x1) -> tuple[list, list]:
    """(x, y) padded so that it spans at least [x0, x1]: (x0, y_0) in front, (x1, y_n) behind, as needed."""
    x, y = list(x), list(y)
    if x0 < x[0]:
        x, y = [x0] + x, [y[0]] + y
    if x1 > x[-1]:
        x, y = x + [x1], y + [y[-1]]
    return x, y
