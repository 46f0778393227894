"""``yade.math``: the math functions and numeric traits of Real, as YADE's double build has them.

granum has one Real type, the IEEE double (Python's ``float``); in YADE's terms ``RealHP<1>`` is the
only precision level (no long double, float128 or MPFR levels, no mpmath), so the scope ``HP1`` is all
there is and :class:`RealHPConfig` says so. The functions follow C's ``<cmath>`` and ``<complex>``
(see :mod:`granum.yade._realfunctions`). YADE's CGAL number traits (``CGAL_*``) are absent, as in a YADE
built without CGAL (``testCgalNumTraits`` is False).
"""

from __future__ import annotations

import math as _math
import sys as _sys
import types as _types

import numpy as _np

from granum.yade import _realfunctions
from granum.yade._realfunctions import *  # noqa: F403 - the functions of the scope HP1, also global here
from granum.yade._realfunctions import DIGITS2 as _DIGITS2
from granum.yade._realfunctions import DIGITS10 as _DIGITS10

#: Eigen's cost estimates of operations on Real and on complex Real
ReadCost, AddCost, MulCost = 1, 1, 1
ComplexReadCost, ComplexAddCost, ComplexMulCost = 2, 2, 6
#: Eigen's NumTraits flags of Real
IsInteger, IsSigned, IsComplex, RequireInitialization = 0, 1, 0, 0
#: significand bits and the largest binary exponent of Real
defprec = _DIGITS2
max_exp2 = _sys.float_info.max_exp
hasInfinityNan = True
#: whether CGAL's number traits of Real are there to test: granum has no CGAL
testCgalNumTraits = False


class RealHPConfig:
    """The precision levels ``RealHP<N>`` there are: granum has N = 1 (double) only."""

    #: decimal digits added when a Real is written as text (granum prints 19 significant digits)
    extraStringDigits10 = 4
    isEnabledRealHP = False
    isFloat128Present = False
    isFloat128Broken = False
    workaroundSlowBoostBinFloat = 1

    @staticmethod
    def getSupportedByEigenCgal() -> tuple:
        """The levels N available to the compiled code: (1,)."""
        return (1,)

    @staticmethod
    def getSupportedByMinieigen() -> tuple:
        """The levels N available to scripts: (1,)."""
        return (1,)

    @staticmethod
    def getDigits10(N: int) -> int:
        """Decimal digits of ``RealHP<N>``."""
        _check_level(N)
        return _DIGITS10

    @staticmethod
    def getDigits2(N: int) -> int:
        """Significand bits of ``RealHP<N>``."""
        _check_level(N)
        return _DIGITS2


def _check_level(N: int) -> None:
    if N != 1:
        raise NotImplementedError(f"RealHP<{N}>: granum has only RealHP<1> (double precision)")


getDigits10 = RealHPConfig.getDigits10
getDigits2 = RealHPConfig.getDigits2


def needsMpmathAtN(N: int) -> bool:
    """Whether ``RealHP<N>`` needs mpmath on the Python side: never (only N = 1, a double, exists)."""
    _check_level(N)
    return False


def usesHP() -> bool:
    """Whether Real is wider than a double: no."""
    return False


def getRealHPCppDigits10() -> tuple:
    """Decimal digits of each precision level of the compiled code."""
    return tuple(getDigits10(n) for n in RealHPConfig.getSupportedByEigenCgal())


def getRealHPPythonDigits10() -> tuple:
    """Decimal digits of each precision level scripts can use."""
    return tuple(getDigits10(n) for n in RealHPConfig.getSupportedByMinieigen())


def toHP1(x):
    """x as a Real (a number or a decimal string, e.g. ``toHP1("-9.81")``)."""
    return float(x)


Real = Real1 = toHP1


def radians(degrees_value):
    """Degrees to radians, as a Real."""
    return _math.radians(float(degrees_value))


def degrees(radians_value):
    """Radians to degrees, as a Real."""
    return _math.degrees(float(radians_value))


radiansHP1, degreesHP1 = radians, degrees


def linspace(a, b, num):
    """``num`` evenly spaced Reals from a to b (``numpy.linspace``)."""
    return _np.linspace(a, b, num)


def eig(a):
    """Eigenvalues and eigenvectors of a square matrix (``numpy.linalg.eig``)."""
    return _np.linalg.eig(_np.asarray(a, dtype=float))


def isThisSystemLittleEndian() -> bool:
    """Whether the processor stores the least significant byte first."""
    return _sys.byteorder == "little"


class Var:
    """A Real and a complex Real held by an object, to check conversions both ways (YADE's test helper)."""

    def __init__(self):
        self._val = -71.23
        self._cpl = complex(-71.23, 33.23)

    @property
    def val(self):
        """The Real (starts at -71.23); only numbers are accepted."""
        return self._val

    @val.setter
    def val(self, value):
        if isinstance(value, (str, bytes, complex)):
            raise TypeError(f"Var.val takes a Real, not {type(value).__name__}")
        self._val = float(value)

    @property
    def cpl(self):
        """The complex Real (starts at -71.23+33.23j); only numbers are accepted."""
        return self._cpl

    @cpl.setter
    def cpl(self, value):
        if isinstance(value, (str, bytes)):
            raise TypeError(f"Var.cpl takes a complex Real, not {type(value).__name__}")
        self._cpl = complex(value)


#: independent values of the constants, to check Pi(), Euler(), Log2(), Catalan() against
_CONSTANTS_TEXT = {"Pi": "3.14159265358979323846264338327950288", "Euler": "0.57721566490153286060651209008240243",
                   "Log2": "0.69314718055994530941723212145817657", "Catalan": "0.91596559417721901505460351493238411"}


def testConstants() -> None:
    """Check that the constants are their 36-digit decimal values rounded to a Real.

    :raises AssertionError: naming the constant that is not.
    """
    for name, text in _CONSTANTS_TEXT.items():
        value = getattr(_realfunctions, name)()
        if value != float(text):
            raise AssertionError(f"{name}() = {value!r}, expected {float(text)!r}")


def testArray() -> None:
    """Check that an array of Reals (granum's float64 columns) keeps every bit of the Reals put in it.

    :raises AssertionError: if one comes back changed.
    """
    values = [Pi(), -Euler(), smallest_positive(), highest(), lowest(), epsilon(), _math.inf, -0.0]  # noqa: F405
    column = _np.array(values, dtype=_np.float64)
    if _np.finfo(column.dtype).nmant + 1 != _DIGITS2 or column.tolist() != values:
        raise AssertionError("an array of Reals does not hold the Reals put in it")


def testLoopRealHP() -> None:
    """:func:`testConstants` and :func:`testArray` at every precision level (only N = 1)."""
    for _level in RealHPConfig.getSupportedByMinieigen():
        testConstants()
        testArray()


def getRealHPErrors(testLevelsHP, testCount=10, minX=-10.0, maxX=10.0, useRandomArgs=False, printEveryNth=1000,
                    collectArgs=False, extraChecks=False):
    """YADE compares each function against a higher precision level; granum has none to compare with."""
    raise NotImplementedError("yade.math.getRealHPErrors: granum has only RealHP<1>, no higher precision to "
                              "measure errors against")


def getEigenFlags():
    """Eigen's storage flags of the math types: granum's types are NumPy arrays, not Eigen objects."""
    raise NotImplementedError("yade.math.getEigenFlags: granum's math types are NumPy arrays, not Eigen types")


def getEigenStorageOrders():
    """Eigen's storage orders of the math types: granum's types are NumPy arrays, not Eigen objects."""
    raise NotImplementedError("yade.math.getEigenStorageOrders: granum's math types are NumPy arrays, "
                              "not Eigen types")


def _scope() -> _types.ModuleType:
    """The scope ``HP1``: every function and trait of ``RealHP<1>`` (the same objects as at module level)."""
    scope = _types.ModuleType(f"{__name__}.HP1", "The functions and traits of RealHP<1> (double).")
    for name in _realfunctions.__all__:
        setattr(scope, name, getattr(_realfunctions, name))
    for name in ("ReadCost", "AddCost", "MulCost", "ComplexReadCost", "ComplexAddCost", "ComplexMulCost",
                 "IsInteger", "IsSigned", "IsComplex", "RequireInitialization", "defprec", "max_exp2",
                 "hasInfinityNan", "testCgalNumTraits", "Var", "testConstants", "testArray", "toHP1"):
        setattr(scope, name, globals()[name])
    return scope


HP1 = _scope()
