"""The functions of ``yade.math`` for granum's one Real type, the IEEE double.

They follow C (``<cmath>``, ``<complex>``) as YADE's double build does: an overflow gives ``inf``, a
pole ``±inf``, a domain error ``nan``, where Python's :mod:`math` would raise. A function that YADE
overloads for complex numbers takes a Python ``complex`` as well and then returns a complex.
"""

from __future__ import annotations

import builtins
import cmath
import math
import random as _random
import struct
import sys
from fractions import Fraction

import numpy as np

#: digits of the one Real type: significand bits and the decimal digits it always keeps
DIGITS2 = sys.float_info.mant_dig
DIGITS10 = sys.float_info.dig


def _numpy_c(ufunc, complex_function=None):
    """A real function with C's results at the edges (numpy's ufunc, warnings off), complex through
    ``complex_function`` where YADE has a complex overload."""

    def call(x):
        if complex_function is not None and isinstance(x, complex):
            return complex_function(x)
        with np.errstate(all="ignore"):
            return float(ufunc(float(x)))

    call.__name__ = ufunc.__name__
    call.__doc__ = f"C's {ufunc.__name__} of a Real" + (" or a complex." if complex_function else ".")
    return call


sin = _numpy_c(np.sin, cmath.sin)
sinh = _numpy_c(np.sinh, cmath.sinh)
cos = _numpy_c(np.cos, cmath.cos)
cosh = _numpy_c(np.cosh, cmath.cosh)
tan = _numpy_c(np.tan, cmath.tan)
tanh = _numpy_c(np.tanh, cmath.tanh)
asin = _numpy_c(np.arcsin, cmath.asin)
asinh = _numpy_c(np.arcsinh, cmath.asinh)
acos = _numpy_c(np.arccos, cmath.acos)
acosh = _numpy_c(np.arccosh, cmath.acosh)
atan = _numpy_c(np.arctan, cmath.atan)
atanh = _numpy_c(np.arctanh, cmath.atanh)
exp = _numpy_c(np.exp, cmath.exp)
log = _numpy_c(np.log, cmath.log)
log10 = _numpy_c(np.log10, cmath.log10)
sqrt = _numpy_c(np.sqrt, cmath.sqrt)
cbrt = _numpy_c(np.cbrt)
exp2 = _numpy_c(np.exp2)
expm1 = _numpy_c(np.expm1)
log1p = _numpy_c(np.log1p)
log2 = _numpy_c(np.log2)
ceil = _numpy_c(np.ceil)
floor = _numpy_c(np.floor)
trunc = _numpy_c(np.trunc)
rint = _numpy_c(np.rint)
fabs = _numpy_c(np.fabs)
erf = _numpy_c(math.erf)
erfc = _numpy_c(math.erfc)


def _two(ufunc):
    def call(a, b):
        with np.errstate(all="ignore"):
            return float(ufunc(float(a), float(b)))

    call.__name__ = ufunc.__name__
    call.__doc__ = f"C's {ufunc.__name__} of two Reals."
    return call


atan2 = _two(np.arctan2)
fmod = _two(np.fmod)
hypot = _two(np.hypot)
remainder = _two(math.remainder)


def abs(x):  # noqa: A001 - YADE's name
    """|x| of a Real or the modulus of a complex (a Real)."""
    return float(x.__abs__()) if isinstance(x, complex) else math.fabs(x)


def pow(x, y):  # noqa: A001 - YADE's name
    """x to the power y: C's pow for Reals, the principal value for complex numbers."""
    if isinstance(x, complex) or isinstance(y, complex):
        return complex(x) ** complex(y)
    with np.errstate(all="ignore"):
        return float(np.power(float(x), float(y)))


def max(a, b):  # noqa: A001 - YADE's name
    """The larger of two Reals (C's fmax: a NaN loses)."""
    return float(np.fmax(float(a), float(b)))


def min(a, b):  # noqa: A001 - YADE's name
    """The smaller of two Reals (C's fmin: a NaN loses)."""
    return float(np.fmin(float(a), float(b)))


def round(x):  # noqa: A001 - YADE's name
    """C's round: the nearest integer, halves away from zero (a Real)."""
    x = float(x)
    whole = math.trunc(x) if math.isfinite(x) else x
    if math.isfinite(x) and math.fabs(x - whole) >= 0.5:  # x - trunc(x) is exact
        whole += math.copysign(1, x)
    return float(whole)


def lgamma(x):
    """log|Γ(x)|; ``inf`` at the poles (0, -1, -2...)."""
    try:
        return math.lgamma(x)
    except (ValueError, OverflowError):
        return math.inf


def tgamma(x):
    """Γ(x): ``±inf`` at 0 and on overflow, ``nan`` at the negative integers."""
    try:
        return math.gamma(x)
    except OverflowError:
        return math.inf
    except ValueError:
        return math.copysign(math.inf, x) if x == 0 else math.nan


def fma(a, b, c):
    """a·b + c with one rounding (exact product and sum, then rounded to a Real)."""
    a, b, c = float(a), float(b), float(c)
    if not (math.isfinite(a) and math.isfinite(b) and math.isfinite(c)):
        return a * b + c
    return float(Fraction(a) * Fraction(b) + Fraction(c))


def remquo(a, b):
    """``(remainder(a, b), q)``: q is the quotient a/b rounded to the nearest integer (C guarantees only its
    sign and lowest 3 bits; granum gives all of it)."""
    a, b = float(a), float(b)
    rest = math.remainder(a, b)
    return rest, int((Fraction(a) - Fraction(rest)) / Fraction(b))


def frexp(x):
    """``(m, e)`` with x = m·2^e and 0.5 ≤ |m| < 1."""
    return math.frexp(float(x))


def modf(x):
    """``(fractional part, integral part)`` of x, both with the sign of x."""
    return math.modf(float(x))


def ldexp(x, e):
    """x·2^e."""
    with np.errstate(all="ignore"):
        return float(np.ldexp(float(x), int(e)))


_ILOGB_ZERO_OR_NAN = -(2**31)
_ILOGB_INF = 2**31 - 1


def ilogb(x):
    """The binary exponent of x (as a Real, as YADE returns it); C's sentinels for 0, inf and NaN."""
    x = float(x)
    if x == 0 or x != x:
        return float(_ILOGB_ZERO_OR_NAN)
    if math.isinf(x):
        return float(_ILOGB_INF)
    return float(math.frexp(x)[1] - 1)


def logb(x):
    """The binary exponent of x as a Real: ``-inf`` for 0, ``inf`` for ±inf."""
    x = float(x)
    if x == 0:
        return -math.inf
    if not math.isfinite(x):
        return math.fabs(x)
    return float(math.frexp(x)[1] - 1)


def sgn(x) -> int:
    """-1, 0 or 1."""
    return (x > 0) - (x < 0)


sign = sgn


def isinf(x) -> bool:
    """Whether x is ±inf."""
    return math.isinf(x)


def isnan(x) -> bool:
    """Whether x is NaN."""
    return math.isnan(x)


def isfinite(x) -> bool:
    """Whether x is neither inf nor NaN."""
    return math.isfinite(x)


def factorial(n):
    """n! as a Real."""
    return float(math.factorial(int(n)))


# complex-only functions of <complex>

def conj(z):
    """The complex conjugate."""
    return complex(z).conjugate()


def real(z):
    """The real part."""
    return complex(z).real


def imag(z):
    """The imaginary part."""
    return complex(z).imag


def arg(z):
    """The phase angle (C++ std::arg)."""
    return cmath.phase(complex(z))


def squaredNorm(z):
    """|z|² (C++ std::norm)."""
    z = complex(z)
    return z.real * z.real + z.imag * z.imag


def polar(rho, theta):
    """The complex number of modulus rho and phase theta."""
    return cmath.rect(float(rho), float(theta))


def proj(z):
    """The projection onto the Riemann sphere: z, or (inf, ±0) when a part of z is infinite."""
    z = complex(z)
    if math.isinf(z.real) or math.isinf(z.imag):
        return complex(math.inf, math.copysign(0.0, z.imag))
    return z


# special functions (Boost.Math's in YADE)

def cylBesselJ(n, x):
    """The Bessel function of the first kind J_n(x) of integer order n (Bessel's integral, summed with the
    trapezoidal rule, which is exact to rounding for this periodic integrand).

    YADE 2023.02a's double build returns NaN for most arguments here (only some small x come out); granum
    returns the value."""
    n, x = int(n), float(x)
    points = 64 + 2 * int(math.fabs(x) + math.fabs(n))
    tau = np.pi * (np.arange(points) + 0.5) / points
    return float(np.mean(np.cos(n * tau - x * np.sin(tau))))


def laguerre(n, m, x):
    """The associated Laguerre polynomial L_n^m(x) (three-term recurrence)."""
    n, m, x = int(n), int(m), float(x)
    previous, current = 1.0, 1.0 + m - x
    if n == 0:
        return previous
    for k in range(1, n):
        previous, current = current, ((2 * k + 1 + m - x) * current - (k + m) * previous) / (k + 1)
    return current


def _legendre(n: int, m: int, x: float) -> float:
    """The associated Legendre function P_n^m(x), 0 ≤ m ≤ n, with the Condon-Shortley phase."""
    pmm = 1.0
    root = math.sqrt(builtins.max(0.0, (1 - x) * (1 + x)))
    for i in range(1, m + 1):
        pmm *= -(2 * i - 1) * root
    if n == m:
        return pmm
    pm1 = x * (2 * m + 1) * pmm
    for k in range(m + 2, n + 1):
        pmm, pm1 = pm1, ((2 * k - 1) * x * pm1 - (k + m - 1) * pmm) / (k - m)
    return pm1


def sphericalHarmonic(n, m, theta, phi):
    """The spherical harmonic Y_n^m(θ, φ) (complex; Condon-Shortley phase, orthonormal as Boost.Math's)."""
    n, m, theta, phi = int(n), int(m), float(theta), float(phi)
    if builtins.abs(m) > n:
        return 0j
    k = -m if m < 0 else m
    norm = math.sqrt((2 * n + 1) / (4 * math.pi) * math.factorial(n - k) / math.factorial(n + k))
    value = norm * _legendre(n, k, math.cos(theta)) * cmath.exp(1j * k * phi)
    return (-1) ** k * value.conjugate() if m < 0 else value


# Eigen's NumTraits and fuzzy comparisons

def epsilon():
    """The gap between 1 and the next Real."""
    return sys.float_info.epsilon


def dummy_precision():
    """Eigen's default precision of fuzzy comparisons of doubles."""
    return 1e-12


def smallest_positive():
    """The smallest positive normal Real."""
    return sys.float_info.min


def highest():
    """The largest finite Real."""
    return sys.float_info.max


def lowest():
    """The most negative finite Real."""
    return -sys.float_info.max


def Pi():
    """π."""
    return math.pi


def Euler():
    """The Euler–Mascheroni constant γ."""
    return 0.5772156649015329


def Log2():
    """ln 2."""
    return math.log(2)


def Catalan():
    """Catalan's constant G."""
    return 0.915965594177219


def random(a=None, b=None):
    """A uniform random Real in (-1, 1), or in (a, b)."""
    if a is None:
        return _random.uniform(-1.0, 1.0)
    return _random.uniform(float(a), float(b))


def isMuchSmallerThan(a, b, eps):
    """Eigen's |a| ≤ |b|·eps."""
    return math.fabs(a) <= math.fabs(b) * eps


def isApprox(a, b, eps):
    """Eigen's |a - b| ≤ min(|a|, |b|)·eps."""
    return math.fabs(a - b) <= builtins.min(math.fabs(a), math.fabs(b)) * eps


isEqualFuzzy = isApprox


def isApproxOrLessThan(a, b, eps):
    """a ≤ b, or a approximately b."""
    return a <= b or isApprox(a, b, eps)


# conversions and diagnostics of the binary representation

def roundTrip(x):
    """x as a Real."""
    return float(x)


def toInt(x) -> int:
    """x truncated to an integer."""
    return int(x)


toLong = toInt
toDouble = roundTrip
toLongDouble = roundTrip  # granum has no long double; a Real converted to it keeps its value


def fromBits(bits: str, exp: int = 0, sign: int = 1):
    """The Real with significand bits ``b0.b1b2...`` (a string of '0'/'1'), times 2^exp, times sign."""
    value = Fraction(0)
    for position, bit in enumerate(bits):
        if bit not in "01":
            raise ValueError(f"fromBits: {bit!r} is not a bit")
        value += Fraction(int(bit), 2**position)
    return float(value * Fraction(2) ** int(exp) * sign)


def getRawBits(x) -> str:
    """The 64 bits of x in memory order of significance: sign, exponent, significand."""
    return format(struct.unpack(">Q", struct.pack(">d", float(x)))[0], "064b")


_FP_NAN, _FP_INFINITE, _FP_ZERO, _FP_SUBNORMAL, _FP_NORMAL = 0, 1, 2, 3, 4


def getDecomposedReal(x) -> dict:
    """How x is made: sign, binary exponent, the 53 significand bits (leading one shown), C's fpclassify."""
    x = float(x)
    mantissa, exponent = math.frexp(x) if math.isfinite(x) else (0.0, 0)
    scaled = int(Fraction(math.fabs(mantissa)) * 2**DIGITS2)
    bits = format(scaled, "b").rjust(DIGITS2, "0") if scaled else "0" * DIGITS2
    if x != x:
        kind = _FP_NAN
    elif math.isinf(x):
        kind = _FP_INFINITE
    elif x == 0:
        kind = _FP_ZERO
    elif math.fabs(x) < sys.float_info.min:
        kind = _FP_SUBNORMAL
    else:
        kind = _FP_NORMAL
    return {"reconstructed": x, "sign": sgn(x), "exp": exponent - 1, "bits": bits, "wrong": False,
            "fpInf": kind == _FP_INFINITE, "fpNan": kind == _FP_NAN, "fpNormal": kind == _FP_NORMAL,
            "fpSubNormal": kind == _FP_SUBNORMAL, "fpZero": kind == _FP_ZERO, "fpClassify": kind,
            "type": "double", "input": f"{x:.19g}"}


def _ordinal(x: float) -> int:
    """Doubles in order as integers (adjacent doubles differ by one, -0 and +0 coincide)."""
    raw = struct.unpack(">q", struct.pack(">d", x))[0]
    return raw if raw >= 0 else -(raw & 0x7FFFFFFFFFFFFFFF)


def getFloatDistanceULP(a, b):
    """The directed distance from a to b in units in the last place (negative when b < a), as a Real."""
    return float(_ordinal(float(b)) - _ordinal(float(a)))


def getDemangledName() -> str:
    """The C++ name of Real."""
    return "double"


def getDemangledNameComplex() -> str:
    """The C++ name of the complex Real."""
    return "std::complex<double>"


#: the functions of the scope HP1 (everything callable defined here)
__all__ = sorted(name for name, value in list(globals().items())
                 if callable(value) and not name.startswith("_") and getattr(value, "__module__", None) == __name__)
