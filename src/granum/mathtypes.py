"""YADE's minieigen math types as scripts see them: vectors, ``Matrix3`` and ``Quaternion``.

Every object holds exactly one NumPy array ``_a`` and all component reads and writes go to it.
``cls._wrap(view)`` binds an existing array (e.g. the row ``body_pos[i]`` of a scene's storage)
without copying, so ``v[0] = 1.0`` or ``v += (1, 0, 0)`` write straight into that storage; every
other constructor, operator and method returns an object owning a fresh array.

Storage: vectors ``(n,)``; ``Matrix3`` ``(3, 3)`` row-major (``M[i, j]`` is row i, column j);
``Quaternion`` ``(w, x, y, z)``, while ``q[0..3]``, iteration and ``np.asarray(q)`` follow YADE's
``x, y, z, w`` order. ``Vector3i``/``Vector2i`` hold int64, everything else float64.

Quirks of YADE 2023.02a mirrored on purpose (each checked against real YADE): negative indices
raise IndexError; ``Vector3 * Vector3`` is a TypeError; ``Vector3 * Matrix3`` gives
``Matrix3 * Vector3``; ``Quaternion(axis, angle)`` normalizes the quaternion, not the axis (so a
non-unit axis changes the angle); hashing is by identity although ``==`` compares values; class
constants (``Vector3.Zero`` ...) are a fresh object on every access, so they cannot be corrupted.

``as_vec3``/``as_mat3``/``as_quat_wxyz`` turn whatever YADE accepts for an attribute of that type
into a new NumPy array, raising TypeError/ValueError that name the expected form.
"""

from __future__ import annotations

import math
import numbers
import operator

import numpy as np

__all__ = ["Matrix3", "Quaternion", "Vector2", "Vector2i", "Vector3", "Vector3i", "Vector6", "Vector6i",
           "as_array", "as_mat3", "as_quat_wxyz", "as_vec3"]


def _fmt(x) -> str:
    """One component as YADE prints it: ints plainly, floats with 19 significant digits."""
    if isinstance(x, int):
        return str(x)
    if x != x:  # YADE (a C++ stream) shows the sign of a NaN, Python's format drops it
        return "-nan" if math.copysign(1.0, x) < 0 else "nan"
    return f"{x:.19g}"


def _index(i, n: int) -> int:
    i = operator.index(i)
    if not 0 <= i < n:  # YADE rejects negative indices too
        raise IndexError(f"Index {i} out of range 0..{n - 1}")
    return i


def as_array(cls, obj) -> np.ndarray:
    """``obj`` as an array of ``cls``'s shape and dtype, the way YADE converts an argument.

    Accepts an instance of a compatible type or any sequence/array of the right length (for
    ``Matrix3`` also 9 flat numbers). May return the instance's own array: copy before mutating.
    """
    what = cls._what
    if isinstance(obj, _Base):
        if isinstance(obj, Quaternion) != (cls is Quaternion):
            raise TypeError(f"expected a {what}, got {type(obj).__name__}")
        a = obj._a
    elif cls is Quaternion or isinstance(obj, str | bytes):
        raise TypeError(f"expected a {what}, got {type(obj).__name__}")
    else:
        try:
            a = np.asarray(obj)
        except (TypeError, ValueError):  # ragged nesting
            raise ValueError(f"expected a {what}, got an irregular sequence") from None
    if a.ndim == 0:
        raise TypeError(f"expected a {what}, got {type(obj).__name__}")
    if a.dtype.kind not in cls._kinds:
        raise TypeError(f"expected a {what}, got components of type {a.dtype}")
    if a.shape != cls._shape:
        if a.ndim == 1 and a.size == math.prod(cls._shape):  # Matrix3 from 9 flat numbers
            a = a.reshape(cls._shape)
        elif a.ndim == 1:
            raise ValueError(f"expected a {what}, got {a.size} components")
        else:
            raise ValueError(f"expected a {what}, got an array of shape {a.shape}")
    return a.astype(cls._dtype, copy=False)


#: as_vec3 converts floats and ints within int64 directly (as_array gives the same values); a larger int goes to
#: as_array, which NumPy makes an object array of (refused) or a float (2**63)
_INT64 = 1 << 63


def as_vec3(obj) -> np.ndarray:
    """New float64 array (3,) from a Vector3/Vector3i or a tuple, list or array of 3 numbers."""
    kind = type(obj)
    if kind is Vector3:   # the setters' usual arguments, without as_array's checks (1.2 -> 0.3-0.5 us)
        return obj._a.copy()
    if (kind is tuple or kind is list) and len(obj) == 3 and \
            all([type(x) is float or (type(x) is int and -_INT64 <= x < _INT64) for x in obj]):
        return np.array(obj, dtype=np.float64)
    return np.array(as_array(Vector3, obj), copy=True)


def as_mat3(obj) -> np.ndarray:
    """New float64 array (3, 3) from a Matrix3, 9 numbers (row by row) or 3 rows of 3 numbers."""
    return np.array(as_array(Matrix3, obj), copy=True)


def as_quat_wxyz(obj) -> np.ndarray:
    """New float64 ``(w, x, y, z)`` array from a Quaternion or an ``(axis, angle)`` pair.

    YADE accepts ``b.state.ori = ((0, 0, 1), 0.5)`` but rejects 4 plain numbers (their order
    would be ambiguous), and so does this function.
    """
    if isinstance(obj, Quaternion):
        return obj._a.copy()
    if isinstance(obj, tuple | list) and len(obj) == 2 and isinstance(obj[1], numbers.Real):
        return _axis_angle_wxyz(as_array(Vector3, obj[0]), obj[1])
    raise TypeError(f"expected a Quaternion or an (axis, angle) pair, got {type(obj).__name__}")


class _Const:
    """Class constant (``Vector3.Zero`` ...) made afresh on each access: in-place edits of the
    value a script got cannot corrupt the constant (YADE behaves the same)."""

    def __init__(self, make):
        self._make = make

    def __get__(self, obj, owner):
        return owner._new(self._make(owner))


def _unit(i: int) -> _Const:
    """Constant unit vector along axis i (``UnitX`` ...)."""
    return _Const(lambda c: np.eye(1, c._shape[0], i, dtype=c._dtype)[0])


class _Base:
    """The wrapped array, construction without copying, 1-D indexing, equality, NumPy interop."""

    __slots__ = ("_a",)
    _dtype, _kinds, _scalar, _noun = np.float64, "biuf", numbers.Real, "a number"
    _order = None  # storage position of YADE's index i, where the two differ (Quaternion)
    __hash__ = object.__hash__  # identity hash, as YADE's types (despite value equality)

    @classmethod
    def _new(cls, a: np.ndarray):
        obj = object.__new__(cls)
        obj._a = a
        return obj

    @classmethod
    def _wrap(cls, array: np.ndarray):
        """Bind ``array`` (not copied: writes go through to it); it must have cls's shape and dtype."""
        if not isinstance(array, np.ndarray) or array.shape != cls._shape or array.dtype != cls._dtype:
            raise TypeError(f"{cls.__name__}._wrap needs a {np.dtype(cls._dtype)} array, shape {cls._shape}")
        return cls._new(array)

    @classmethod
    def _coerce(cls, obj):
        """Operand as an array for cls, or None where YADE would not convert it (-> NotImplemented)."""
        try:
            return as_array(cls, obj)
        except (TypeError, ValueError):
            return None

    def _public(self) -> np.ndarray:
        """Components in YADE's index order."""
        return self._a

    def _coefficients(self) -> list:
        """The coefficients in the order Eigen stores them (YADE's reductions follow it): YADE's index order
        (a quaternion's x, y, z, w), but for matrices (:meth:`Matrix3._coefficients`)."""
        return self._public().ravel().tolist()

    def _pos(self, i) -> int:
        i = _index(i, self._shape[0])
        return i if self._order is None else self._order[i]

    def __getitem__(self, i):
        return self._a[self._pos(i)].item()

    def __setitem__(self, i, value):
        if not isinstance(value, self._scalar):
            raise TypeError(f"{type(self).__name__}[i] must be {self._noun}, got {type(value).__name__}")
        self._a[self._pos(i)] = value

    def __len__(self):
        return self._shape[0]

    def __iter__(self):
        return iter(self._public().tolist())

    def __array__(self, dtype=None, copy=None):
        return np.array(self._public(), dtype=dtype, copy=copy)

    def __eq__(self, other):
        o = self._coerce(other)
        return NotImplemented if o is None else bool(np.array_equal(self._a, o))

    def __reduce__(self):  # pickle and copy rebuild from the numbers: a copy never aliases storage
        return (type(self), tuple(self._a.ravel().tolist()))

    def __repr__(self):
        vals = [_fmt(x) for x in self._a.ravel().tolist()]
        groups = (",".join(vals[i : i + 3]) for i in range(0, len(vals), 3))  # Matrix3(1,0,0, 0,1,0, ...)
        return f"{type(self).__name__}({', '.join(groups)})"

    __str__ = __repr__


def eigen_reduce(values: list, op=operator.add) -> float:
    """``values`` combined by ``op`` in the order of Eigen's unrolled reductions, which YADE's minieigen types use:
    the first ``len // 2`` and the rest, each half combined the same way (x + (y + z) for three). Sums, products
    and dot products so combined have YADE's bits (``tests/reference/yade/norms.py``, ``reductions.py``); NumPy's
    reductions differ from them in the last bit about every fifth time."""
    n = len(values)
    if n == 1:
        return values[0]
    if n == 2:
        return op(values[0], values[1])
    half = n // 2
    return op(eigen_reduce(values[:half], op), eigen_reduce(values[half:], op))


def _dot3(r, c) -> float:
    """r . c for two sequences of three numbers, in Eigen's order (a matrix product's entry)."""
    return r[0] * c[0] + (r[1] * c[1] + r[2] * c[2])


class _Normed(_Base):
    """Euclidean (for Matrix3 Frobenius) norm and normalization."""

    __slots__ = ()

    def squaredNorm(self):
        return eigen_reduce([x * x for x in self._coefficients()])

    def norm(self):
        return math.sqrt(self.squaredNorm())

    __abs__ = norm  # YADE: abs(v) is the norm

    def normalized(self):
        n = self.norm()
        return self._new(self._a / n if n > 0 else self._a.copy())  # zero stays zero, as in YADE

    def normalize(self):
        n = self.norm()
        if n > 0:
            self._a /= n


class _Dense(_Base):
    """Vectors and matrices: coefficient-wise +, -, scaling by a number, reductions."""

    __slots__ = ()
    Zero = _Const(lambda c: np.zeros(c._shape, c._dtype))
    Ones = _Const(lambda c: np.ones(c._shape, c._dtype))

    # No __radd__/__rsub__: YADE has none either, so ``(1, 1, 1) + v`` is a tuple error there too.
    def __add__(self, other):
        o = self._coerce(other)
        return NotImplemented if o is None else self._new(self._a + o)

    def __sub__(self, other):
        o = self._coerce(other)
        return NotImplemented if o is None else self._new(self._a - o)

    def _inplace(self, other, op):
        o = self._coerce(other)
        if o is None:
            return NotImplemented
        op(self._a, o, out=self._a)  # in place, so it writes through a _wrap'ped view
        return self

    def __iadd__(self, other):
        return self._inplace(other, np.add)

    def __isub__(self, other):
        return self._inplace(other, np.subtract)

    def __neg__(self):
        return self._new(-self._a)

    def __mul__(self, other):
        return self._new(self._a * other) if isinstance(other, self._scalar) else NotImplemented

    __rmul__ = __mul__

    def __imul__(self, other):
        if not isinstance(other, self._scalar):
            return NotImplemented
        self._a *= other
        return self

    def sum(self):
        return eigen_reduce(self._coefficients())

    def prod(self):
        return eigen_reduce(self._coefficients(), operator.mul)

    def mean(self):
        s, n = self.sum(), self._a.size
        if self._dtype is np.int64:  # integer division truncating toward zero, as in C++
            return s // n if s >= 0 else -(-s // n)
        return s / n

    def maxCoeff(self):
        return self._a.max().item()

    def minCoeff(self):
        return self._a.min().item()

    def maxAbsCoeff(self):
        return np.abs(self._a).max().item()

    def isApprox(self, other, prec=1e-12):
        """Eigen's fuzzy equality: |a - b|^2 <= prec^2 * min(|a|^2, |b|^2)."""
        a, b = self._a.ravel().astype(float), as_array(type(self), other).ravel().astype(float)
        return bool((a - b) @ (a - b) <= prec * prec * min(a @ a, b @ b))


class _Real(_Dense, _Normed):
    """Float vectors and matrices: adds norms and division (YADE's integer vectors have neither)."""

    __slots__ = ()

    def __truediv__(self, other):
        if not isinstance(other, numbers.Real):
            return NotImplemented
        with np.errstate(divide="ignore", invalid="ignore"):  # x/0 is inf/nan silently, as in YADE
            return self._new(self._a / other)

    def __itruediv__(self, other):
        if not isinstance(other, numbers.Real):
            return NotImplemented
        with np.errstate(divide="ignore", invalid="ignore"):
            self._a /= other
        return self


class _Vector(_Dense):
    """Column vector; ``V(n numbers)``, ``V(sequence of n)`` or ``V()`` (zero)."""

    __slots__ = ()
    _padded = False  # YADE's Vector3(1, 2) means (1, 2, 0); other sizes need all components

    def __init__(self, *args):
        n, name = self._shape[0], type(self).__name__
        if len(args) == 1 and not isinstance(args[0], numbers.Number):
            self._a = as_array(type(self), args[0]).copy()
            return
        if len(args) > n or (0 < len(args) < n and not self._padded):
            raise TypeError(f"{name}() takes {n} numbers or one sequence of {n}, got {len(args)} arguments")
        for x in args:
            if not isinstance(x, self._scalar):
                raise TypeError(f"{name}(): expected {self._noun}, got {type(x).__name__}")
        self._a = np.zeros(n, self._dtype)
        self._a[: len(args)] = args

    Identity = _unit(0)  # YADE's Vector3.Identity is (1, 0, 0)

    def __getitem__(self, i):
        if type(i) is int and 0 <= i < self._shape[0]:  # the common case, without _index's checks
            return self._a.item(i)
        return self._a[_index(i, self._shape[0])].item()

    @classmethod
    def Unit(cls, i):
        return cls._new(np.eye(1, cls._shape[0], _index(i, cls._shape[0]), dtype=cls._dtype)[0])

    def dot(self, other):
        return eigen_reduce([x * y for x, y in zip(self._a.tolist(), as_array(type(self), other).tolist(),
                                                   strict=True)])


class Vector2(_Vector, _Real):
    """2D float vector; storage float64 ``(x, y)``."""

    __slots__ = ()
    _shape, _what = (2,), "2-vector"
    UnitX, UnitY = _unit(0), _unit(1)


class Vector2i(_Vector):
    """2D integer vector; storage int64 ``(x, y)``."""

    __slots__ = ()
    _shape, _what = (2,), "2-vector of integers"
    _dtype, _kinds, _scalar, _noun = np.int64, "biu", numbers.Integral, "an integer"
    UnitX, UnitY = _unit(0), _unit(1)


class _Vector3Base(_Vector):
    """What Vector3 and Vector3i share: default components, ``UnitX/Y/Z``, cross product."""

    __slots__ = ()
    _padded = True
    UnitX, UnitY, UnitZ = _unit(0), _unit(1), _unit(2)

    def squaredNorm(self):
        # eigen_reduce of the three squares, written out: scripts call it per body or contact in their loops
        x, y, z = self._a.tolist()
        return x * x + (y * y + z * z)

    def cross(self, other):
        (a0, a1, a2), (b0, b1, b2) = self._a.tolist(), as_array(type(self), other).tolist()
        return self._new(np.array([a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0], self._dtype))


class Vector3(_Vector3Base, _Real):
    """3D float vector; storage float64 ``(x, y, z)``.

    ``Vector3 * Vector3`` is a TypeError, as in YADE: use ``dot``, ``cross`` or ``outer``.
    """

    __slots__ = ()
    _shape, _what = (3,), "3-vector"

    def asDiagonal(self):
        return Matrix3._new(np.diag(self._a))

    def outer(self, other):
        return Matrix3._new(np.outer(self._a, as_array(Vector3, other)))


class Vector3i(_Vector3Base):
    """3D integer vector; storage int64 ``(x, y, z)`` (YADE's is int32)."""

    __slots__ = ()
    _shape, _what = (3,), "3-vector of integers"
    _dtype, _kinds, _scalar, _noun = np.int64, "biu", numbers.Integral, "an integer"


class Vector6(_Vector, _Real):
    """6D float vector; storage float64 ``(v0 .. v5)``. Also ``Vector6(head, tail)`` (two 3-vectors)."""

    __slots__ = ()
    _shape, _what = (6,), "6-vector"

    def __init__(self, *args):
        if len(args) == 2:
            self._a = np.concatenate([as_array(Vector3, args[0]), as_array(Vector3, args[1])])
        else:
            super().__init__(*args)

    def head(self):
        return Vector3._new(self._a[:3].copy())

    def tail(self):
        return Vector3._new(self._a[3:].copy())


class Vector6i(_Vector):
    """6D integer vector; storage int64 ``(v0 .. v5)``."""

    __slots__ = ()
    _shape, _what = (6,), "6-vector of integers"
    _dtype, _kinds, _scalar, _noun = np.int64, "biu", numbers.Integral, "an integer"


class Matrix3(_Real):
    """3x3 float matrix; storage float64 ``(3, 3)`` row-major: ``M[i, j]`` is row i, column j.

    Constructors, as in YADE: ``Matrix3()`` (zero); 9 numbers row by row; three row vectors
    (``cols=True``: columns); one Matrix3, sequence of 9 numbers or of 3 rows; a Vector3 (the
    diagonal); a Quaternion (its rotation matrix). ``M[i]`` is a copy of row i; iteration gives rows.
    """

    __slots__ = ()
    _shape, _what = (3, 3), "3x3 matrix (9 numbers or 3 rows of 3)"
    Identity = _Const(lambda c: np.eye(3))

    def _coefficients(self) -> list:
        return self._a.T.ravel().tolist()   # Eigen stores a matrix column by column

    def __init__(self, *args, cols=False):
        if len(args) == 4 and isinstance(args[3], bool):  # Matrix3(r0, r1, r2, True)
            args, cols = args[:3], args[3]
        if len(args) == 9:
            if not all(isinstance(x, numbers.Real) for x in args):
                raise TypeError("Matrix3(): expected 9 numbers")
            self._a = np.array(args, dtype=np.float64).reshape(3, 3)
        elif len(args) == 3:
            a = np.array([as_array(Vector3, r) for r in args])
            self._a = a.T.copy() if cols else a
        elif len(args) == 1 and isinstance(args[0], Quaternion):
            self._a = args[0].toRotationMatrix()._a
        elif len(args) == 1:
            m = self._coerce(args[0])  # else a 3-vector: the diagonal (anything else raises here)
            self._a = m.copy() if m is not None else np.diag(as_array(Vector3, args[0]))
        elif not args:
            self._a = np.zeros((3, 3))
        else:
            raise TypeError(f"Matrix3() takes 0, 1, 3 or 9 arguments, got {len(args)}")

    def __iter__(self):
        return (Vector3._new(r) for r in self._a.copy())

    def _ij(self, key):
        if not isinstance(key, tuple):
            return _index(key, 3)
        if len(key) != 2:
            raise IndexError("Index must be integer or a 2-tuple")
        return _index(key[0], 3), _index(key[1], 3)

    def __getitem__(self, key):
        ij = self._ij(key)
        return self._a[ij].item() if isinstance(ij, tuple) else Vector3._new(self._a[ij].copy())

    def __setitem__(self, key, value):
        ij = self._ij(key)
        if isinstance(ij, tuple) and not isinstance(value, numbers.Real):
            raise TypeError(f"Matrix3 component must be a number, not {type(value).__name__}")
        self._a[ij] = value if isinstance(ij, tuple) else as_array(Vector3, value)

    def __mul__(self, other):
        """``M * number``; ``M * Vector3`` (a Vector3); ``M * Matrix3`` (matrix product)."""
        if isinstance(other, numbers.Real):
            return Matrix3._new(self._a * other)
        if (v := Vector3._coerce(other)) is not None:
            return Vector3._new(self._times(v))
        if (m := self._coerce(other)) is not None:
            return Matrix3._new(self._times(m))
        return NotImplemented

    def _times(self, other: np.ndarray) -> np.ndarray:
        """This matrix times a (3,) vector or a (3, 3) matrix, each entry in Eigen's order (YADE's bits)."""
        rows = self._a.tolist()
        if other.ndim == 1:
            v = other.tolist()
            return np.array([_dot3(r, v) for r in rows])
        cols = other.T.tolist()
        return np.array([[_dot3(r, c) for c in cols] for r in rows])

    def __rmul__(self, other):
        if isinstance(other, numbers.Real):
            return Matrix3._new(self._a * other)
        # YADE quirk, mirrored: ``v * M`` returns ``M * v``, not the row-vector product.
        v = Vector3._coerce(other)
        return NotImplemented if v is None else Vector3._new(self._times(v))

    def __imul__(self, other):
        if isinstance(other, numbers.Real):
            self._a *= other
        elif (m := self._coerce(other)) is not None:
            self._a[...] = self._times(m)
        else:
            return NotImplemented
        return self

    def row(self, i):
        return Vector3._new(self._a[_index(i, 3)].copy())

    def col(self, i):
        return Vector3._new(self._a[:, _index(i, 3)].copy())

    @staticmethod
    def rows():
        """Number of rows (3), as minieigen's."""
        return 3

    @staticmethod
    def cols():
        """Number of columns (3), as minieigen's."""
        return 3

    def diagonal(self):
        return Vector3._new(self._a.diagonal().copy())

    def trace(self):
        return eigen_reduce(self._a.diagonal().tolist())

    def transpose(self):
        return Matrix3._new(self._a.T.copy())

    def _cofactors(self) -> np.ndarray:
        (a, b, c), (d, e, f), (g, h, i) = self._a.tolist()
        return np.array([[e * i - f * h, f * g - d * i, d * h - e * g],
                         [c * h - b * i, a * i - c * g, b * g - a * h],
                         [b * f - c * e, c * d - a * f, a * e - b * d]])

    def determinant(self):
        # expansion along the first row, the terms added left to right: YADE's bits (tests/reference/yade/
        # reductions.py); a singular matrix gives exactly 0
        (a, b, c), (d, e, f), (g, h, i) = self._a.tolist()
        return a * (e * i - h * f) - b * (d * i - g * f) + c * (d * h - g * e)

    def inverse(self):
        """Adjugate / determinant; a singular matrix gives inf/nan entries, no error (as YADE). The determinant is
        here the first column's expansion in Eigen's order (YADE's inverse has these bits, its determinant()
        others)."""
        cof = self._cofactors()
        det = _dot3(self._a[:, 0].tolist(), cof[:, 0].tolist())
        with np.errstate(divide="ignore", invalid="ignore"):
            return Matrix3._new(cof.T * (np.float64(1.0) / det))

    def spectralDecomposition(self):
        """(eigenvectors as columns, eigenvalues ascending) of this symmetric matrix."""
        w, v = np.linalg.eigh(self._a)
        return Matrix3._new(v), Vector3._new(w)

    selfAdjointEigenDecomposition = spectralDecomposition


def _axis_angle_wxyz(axis: np.ndarray, angle) -> np.ndarray:
    # YADE normalizes (cos(a/2), sin(a/2)*axis), not the axis: Quaternion((0,0,2), pi/2) is a
    # unit quaternion printed with angle 2.214297435588180818.
    s = math.sin(0.5 * angle)
    q = np.array([math.cos(0.5 * angle), s * axis[0], s * axis[1], s * axis[2]])
    return q / Quaternion._new(q).norm()


def _hamilton(p, q) -> np.ndarray:
    """Product of two quaternions given as (w, x, y, z) sequences."""
    pw, px, py, pz = p
    qw, qx, qy, qz = q
    return np.array([pw * qw - px * qx - py * qy - pz * qz,
                     pw * qx + px * qw + py * qz - pz * qy,
                     pw * qy + py * qw + pz * qx - px * qz,
                     pw * qz + pz * qw + px * qy - py * qx])


class Quaternion(_Normed):
    """Rotation quaternion; storage float64 ``(w, x, y, z)``.

    YADE's ``q[0], q[1], q[2], q[3]`` are x, y, z, w (so are iteration and ``np.asarray(q)``);
    it prints in axis-angle form, ``Quaternion((1,0,0),0)``. Constructors, as in YADE: ``()``
    (identity), ``(axis, angle)``, ``(angle, axis)``, either pair as one tuple, ``axis=..., angle=...``,
    ``(w, x, y, z)``, ``(Matrix3)``, ``(Quaternion)``, ``(u, v)`` (the rotation taking direction u to
    direction v).
    """

    __slots__ = ()
    _shape, _what, _order = (4,), "Quaternion", (1, 2, 3, 0)
    Identity = _Const(lambda c: np.array([1.0, 0.0, 0.0, 0.0]))

    def __init__(self, *args, axis=None, angle=None):
        if axis is not None or angle is not None:
            if args or axis is None or angle is None:
                raise TypeError("Quaternion(axis=..., angle=...) takes both keywords and nothing else")
            args = (axis, angle)
        if len(args) == 1 and isinstance(args[0], tuple) and len(args[0]) == 2:
            args = args[0]  # Quaternion((axis, angle)) and Quaternion((angle, axis))
        real = [isinstance(x, numbers.Real) for x in args]
        if not args:
            self._a = np.array([1.0, 0.0, 0.0, 0.0])
        elif len(args) == 4 and all(real):
            self._a = np.array(args, dtype=np.float64)
        elif len(args) == 1 and isinstance(args[0], Quaternion):
            self._a = args[0]._a.copy()
        elif len(args) == 1:
            self._a = self._from_matrix(as_array(Matrix3, args[0]))
        elif len(args) == 2 and real == [False, True]:
            self._a = _axis_angle_wxyz(as_array(Vector3, args[0]), args[1])
        elif len(args) == 2 and real == [True, False]:
            self._a = _axis_angle_wxyz(as_array(Vector3, args[1]), args[0])
        elif len(args) == 2 and real == [False, False]:
            self._a = np.empty(4)
            self.setFromTwoVectors(*args)
        else:
            raise TypeError("Quaternion() takes (axis, angle), (angle, axis), (w, x, y, z), "
                            "(Matrix3), (Quaternion) or (u, v)")

    @staticmethod
    def _from_matrix(m: np.ndarray) -> np.ndarray:
        """Shepperd's method: pivot on the largest of trace and diagonal, for accuracy."""
        t = m.trace()
        if t > 0:
            s = math.sqrt(t + 1.0)
            f = 0.5 / s
            return np.array([0.5 * s, (m[2, 1] - m[1, 2]) * f, (m[0, 2] - m[2, 0]) * f,
                             (m[1, 0] - m[0, 1]) * f])
        i = int(np.argmax(m.diagonal()))
        j, k = (i + 1) % 3, (i + 2) % 3
        s = math.sqrt(m[i, i] - m[j, j] - m[k, k] + 1.0)
        f = 0.5 / s
        q = np.empty(4)
        q[0], q[1 + i] = (m[k, j] - m[j, k]) * f, 0.5 * s
        q[1 + j], q[1 + k] = (m[j, i] + m[i, j]) * f, (m[k, i] + m[i, k]) * f
        return q

    def setFromTwoVectors(self, u, v):
        """Set (in place) to the shortest rotation taking direction ``u`` to direction ``v``."""
        a, b = as_array(Vector3, u), as_array(Vector3, v)
        a, b = a / np.linalg.norm(a), b / np.linalg.norm(b)
        c = (a @ b).item()
        if c < -1.0 + 1e-12:  # (nearly) opposite: about half a turn around an axis normal to both
            w2 = 0.5 * (1.0 + max(c, -1.0))
            self._a[0], self._a[1:] = math.sqrt(w2), np.linalg.svd(np.array([a, b]))[2][2] * math.sqrt(1 - w2)
        else:
            s = math.sqrt(2.0 * (1.0 + c))
            self._a[0], self._a[1:] = 0.5 * s, np.cross(a, b) / s

    @classmethod
    def _coerce(cls, obj):
        return obj._a if isinstance(obj, Quaternion) else None  # YADE compares only to Quaternions

    def _public(self) -> np.ndarray:
        return self._a[[1, 2, 3, 0]]

    def __array__(self, dtype=None, copy=None):
        if copy is False:
            raise ValueError("Quaternion is stored as (w,x,y,z): its (x,y,z,w) array needs a copy")
        return np.asarray(self._public(), dtype=dtype)

    def __mul__(self, other):
        """``q * q`` (composition: the right one acts first) or ``q * Vector3`` (rotated vector)."""
        if isinstance(other, Quaternion):
            return Quaternion._new(_hamilton(self._a.tolist(), other._a.tolist()))
        v = Vector3._coerce(other)
        return NotImplemented if v is None else self.Rotate(v)

    def __imul__(self, other):
        if not isinstance(other, Quaternion):
            return NotImplemented
        self._a[:] = _hamilton(self._a.tolist(), other._a.tolist())
        return self

    def Rotate(self, v):
        """``v`` rotated by this quaternion: v + w t + u x t with t = 2 u x v (u = (x, y, z))."""
        w, x, y, z = self._a.tolist()
        vx, vy, vz = as_array(Vector3, v).tolist()
        tx, ty, tz = 2 * (y * vz - z * vy), 2 * (z * vx - x * vz), 2 * (x * vy - y * vx)
        return Vector3._new(np.array([vx + w * tx + (y * tz - z * ty),
                                      vy + w * ty + (z * tx - x * tz),
                                      vz + w * tz + (x * ty - y * tx)]))

    def conjugate(self):
        return Quaternion._new(self._a * np.array([1.0, -1.0, -1.0, -1.0]))

    def inverse(self):
        """Conjugate / squared norm (zero for a zero quaternion, as in YADE)."""
        n2 = self.squaredNorm()
        return Quaternion._new(self.conjugate()._a / n2 if n2 > 0 else np.zeros(4))

    def toAxisAngle(self):
        """(unit axis as Vector3, angle in [0, pi]); a non-unit quaternion counts by its direction."""
        w, x, y, z = self._a.tolist()
        n = math.sqrt(eigen_reduce([x * x, y * y, z * z]))  # |(x, y, z)| added as YADE adds it: its bits
        if n < 1e-150:  # the squares may have underflowed: redo without underflow
            n = math.hypot(x, y, z)
        if n == 0:
            return Vector3._new(np.array([1.0, 0.0, 0.0])), 0.0
        axis = np.array([x, y, z]) / (-n if w < 0 else n)  # divide, don't multiply: YADE's digits
        return Vector3._new(axis), 2.0 * math.atan2(n, abs(w))

    def toAngleAxis(self):
        return self.toAxisAngle()[::-1]

    def toRotationVector(self):
        axis, angle = self.toAxisAngle()
        return axis * angle

    def toRotationMatrix(self):
        """Rotation matrix (a non-unit quaternion goes through the same formula, as in YADE)."""
        w, x, y, z = self._a.tolist()
        tx, ty, tz = 2 * x, 2 * y, 2 * z
        twx, twy, twz, txx, txy, txz = tx * w, ty * w, tz * w, tx * x, ty * x, tz * x
        tyy, tyz, tzz = ty * y, tz * y, tz * z
        return Matrix3._new(np.array([[1 - (tyy + tzz), txy - twz, txz + twy],
                                      [txy + twz, 1 - (txx + tzz), tyz - twx],
                                      [txz - twy, tyz + twx, 1 - (txx + tyy)]]))

    def angularDistance(self, other):
        """Angle in [0, pi] of the rotation between this quaternion and ``other``."""
        w, x, y, z = _hamilton(self._a.tolist(), other.conjugate()._a.tolist()).tolist()
        return 2.0 * math.atan2(math.hypot(x, y, z), abs(w))

    def __repr__(self):
        axis, angle = self.toAxisAngle()
        return f"Quaternion(({','.join(_fmt(c) for c in axis._a.tolist())}),{_fmt(angle)})"

    __str__ = __repr__
