"""YADE's ``yade.pack``: sphere packings (``SpherePack``), volume predicates, regular lattices.

Design
------
* :class:`SpherePack` is pure geometry: centres in a NumPy ``(N, 3)`` array and radii in an
  ``(N,)`` array (both float64, lengths in the scene's units), plus an optional periodic cell
  size. Scripts see YADE's sequence API (``sp[i]`` -> ``(Vector3, float)``, iteration,
  ``toList``...); bulk work (cloud generation, translation, scaling) runs on the arrays.
* ``makeCloud`` is random sequential insertion (spheres at random positions, rejected if
  they overlap, stop after 1000 failed positions for one sphere), compiled with numba
  in :mod:`granum.yade._packing` with a cell grid, so overlap tests cost O(1).
  The count/size logic (deterministic sizes when ``num`` is given, porosity retries, PSDs)
  follows what YADE 2023.02a does, observed as a black box: sizes with ``num`` sit at the
  quantiles ``1 - (i + 1/2)/(num + 1)`` of the size distribution, largest first; a failed
  ``num`` generation without ``rMean`` retries with ``porosity += 0.1 * (1 - porosity)``.
  Random numbers differ from YADE's, so counts agree statistically, not exactly.
* Predicates answer "is this point (with a padding distance) inside?". Each one has a
  vectorized ``_inside(points (N,3), pad) -> bool (N,)`` used by the lattice generators;
  Python subclasses of :class:`Predicate` that only define ``__call__``/``aabb`` still work.
  ``&``, ``|``, ``-`` and ``^`` combine predicates, as in YADE (which has no ``~``).
* ``regularOrtho``/``regularHexa`` reproduce YADE's lattices point for point (origin and
  layer offsets observed from YADE's output); the centres alone come from
  :func:`regularOrthoCenters`/:func:`regularHexaCenters`, which need no scene.
* Clumps: every sphere carries a clump id (``-1``: standalone). ``makeClumpCloud`` (in
  :mod:`granum.yade._clumpcloud`) adds rigid clumps made from template packs; ``sp[i]`` and
  ``toList()`` give ``(center, radius, clumpId)`` for clump members and ``(center, radius)``
  for standalone spheres, while iteration always gives pairs (all as YADE does).
  ``toSimulation`` appends all spheres in pack order, then makes one clump body per clump
  id in increasing order, and returns the sphere ids followed by the clump ids (YADE's ids).
* Scene-facing functions (``toSimulation``, lattice bodies, ``fromSimulation``) import
  ``utils``/``O`` when called, so this module imports without the scene code.
"""

from __future__ import annotations

import math
import secrets
import warnings

import numpy as np

from granum.mathtypes import Matrix3, Quaternion, Vector3, as_mat3, as_vec3
from granum.yade import _clumpcloud, _packing

__all__ = [
    "Predicate", "PredicateBoolean", "PredicateDifference", "PredicateIntersection",
    "PredicateSymmetricDifference", "PredicateUnion", "SpherePack", "inAlignedBox", "inCylinder",
    "inEllipsoid", "inHyperboloid", "inParallelepiped", "inSpace", "inSphere", "notInNotch",
    "regularHexa", "regularHexaCenters", "regularOrtho", "regularOrthoCenters",
]

#: Positions tried for one sphere before makeCloud gives up (YADE's value, from its warning).
MAX_TRY = 1000
_INF = np.full(3, np.inf)


def _V(a) -> Vector3:
    return Vector3(float(a[0]), float(a[1]), float(a[2]))


# ----------------------------------------------------------------------------- predicates
class Predicate:
    """Base of volume predicates: ``pred(pt, pad=0)`` is True if ``pt`` lies inside the volume
    at least ``pad`` away from its boundary (so a sphere of radius ``pad`` at ``pt`` fits).

    Subclasses implement ``_inside(pts, pad)`` on an ``(N, 3)`` array and ``_box()`` returning
    ``(min, max)`` arrays; a user subclass may instead override ``__call__`` and ``aabb``.
    """

    def __call__(self, pt, pad=0.0):
        if type(self)._inside is Predicate._inside:
            raise NotImplementedError(f"{type(self).__name__} must define __call__(pt, pad)")
        return bool(self._inside(as_vec3(pt)[None, :], float(pad))[0])

    def _inside(self, pts, pad):
        # fallback for Python subclasses that only define __call__
        return np.array([bool(self(_V(p), pad)) for p in pts], dtype=bool)

    def _box(self):
        if type(self).aabb is Predicate.aabb:
            raise NotImplementedError(f"{type(self).__name__} must define aabb()")
        mn, mx = self.aabb()
        return as_vec3(mn), as_vec3(mx)

    def aabb(self):
        """Axis-aligned bounding box ``(Vector3 min, Vector3 max)``."""
        mn, mx = self._box()
        return _V(mn), _V(mx)

    def center(self):
        """Centre of the bounding box (YADE's convention)."""
        mn, mx = self._box()
        with np.errstate(invalid="ignore"):
            return _V(0.5 * (mn + mx))

    def dim(self):
        """Size of the bounding box."""
        mn, mx = self._box()
        return _V(mx - mn)

    def __and__(self, other):
        return PredicateIntersection(self, other)

    def __or__(self, other):
        return PredicateUnion(self, other)

    def __sub__(self, other):
        return PredicateDifference(self, other)

    def __xor__(self, other):
        return PredicateSymmetricDifference(self, other)


class PredicateBoolean(Predicate):
    """Combination of two predicates ``A`` and ``B``."""

    def __init__(self, A, B):
        self.A, self.B = A, B


class PredicateUnion(PredicateBoolean):
    """Inside A or inside B; bounding box encloses both."""

    def _inside(self, pts, pad):
        return self.A._inside(pts, pad) | self.B._inside(pts, pad)

    def _box(self):
        (a0, a1), (b0, b1) = self.A._box(), self.B._box()
        return np.minimum(a0, b0), np.maximum(a1, b1)


class PredicateIntersection(PredicateBoolean):
    """Inside A and inside B; bounding box is the overlap of both boxes."""

    def _inside(self, pts, pad):
        return self.A._inside(pts, pad) & self.B._inside(pts, pad)

    def _box(self):
        (a0, a1), (b0, b1) = self.A._box(), self.B._box()
        return np.maximum(a0, b0), np.minimum(a1, b1)


class PredicateDifference(PredicateBoolean):
    """Inside A and not inside B; the point must also be ``pad`` away from B (B tested
    with ``-pad``, as YADE does). Bounding box of A."""

    def _inside(self, pts, pad):
        return self.A._inside(pts, pad) & ~self.B._inside(pts, -pad)

    def _box(self):
        return self.A._box()


class PredicateSymmetricDifference(PredicateBoolean):
    """Inside exactly one of A, B (both tested with the same pad). Box encloses both."""

    def _inside(self, pts, pad):
        return self.A._inside(pts, pad) != self.B._inside(pts, pad)

    def _box(self):
        return PredicateUnion._box(self)


class inAlignedBox(Predicate):
    """Axis-aligned box between corners ``minAABB`` and ``maxAABB`` (boundary inclusive)."""

    def __init__(self, minAABB, maxAABB):
        self.mn, self.mx = as_vec3(minAABB), as_vec3(maxAABB)

    def _inside(self, pts, pad):
        return np.all((pts >= self.mn + pad) & (pts <= self.mx - pad), axis=1)

    def _box(self):
        return self.mn.copy(), self.mx.copy()


class inSphere(Predicate):
    """Ball of ``radius`` around ``center``."""

    def __init__(self, center, radius):
        self.c, self.r = as_vec3(center), float(radius)

    def _inside(self, pts, pad):
        return np.linalg.norm(pts - self.c, axis=1) <= self.r - pad

    def _box(self):
        return self.c - self.r, self.c + self.r


class _Axial(Predicate):
    """Shared geometry of solids of revolution between two base centres ``c1``, ``c2``."""

    def __init__(self, centerBottom, centerTop, radius):
        self.c1, self.c2, self.r = as_vec3(centerBottom), as_vec3(centerTop), float(radius)
        axis = self.c2 - self.c1
        self.ht = float(np.linalg.norm(axis))
        self.n = axis / self.ht

    def _axial(self, pts, pad):
        """Axial coordinate t (from c1), radial distance, and the mask pad <= t <= ht - pad."""
        rel = pts - self.c1
        t = rel @ self.n
        # |rel x n| is exactly 0 on the axis (rel - t*n is not), which decides touching spheres
        rad = np.linalg.norm(np.cross(rel, self.n), axis=1)
        return t, rad, (t >= pad) & (t <= self.ht - pad)

    def _box(self):
        # exact AABB of a cylinder: each base disc extends r*sin(angle(axis, e_i)) along axis i,
        # written r*sqrt(ax_j^2 + ax_k^2)/|ax|, the rounding YADE's boxes have (lattices start there)
        ax = self.c2 - self.c1
        sq = ax * ax
        ext = self.r * np.sqrt(np.array([sq[1] + sq[2], sq[0] + sq[2], sq[0] + sq[1]])) / self.ht
        return np.minimum(self.c1, self.c2) - ext, np.maximum(self.c1, self.c2) + ext


class inCylinder(_Axial):
    """Cylinder with base centres ``centerBottom``, ``centerTop`` and ``radius``."""

    def _inside(self, pts, pad):
        _, rad, ok = self._axial(pts, pad)
        return ok & (rad <= self.r - pad)


class inHyperboloid(_Axial):
    """Hyperboloid of one sheet (dog-bone specimen): ``radius`` at both bases, ``skirt`` in
    the middle. Padding is applied radially and axially (an approximation, as in YADE)."""

    def __init__(self, centerBottom, centerTop, radius, skirt):
        super().__init__(centerBottom, centerTop, radius)
        self.skirt = float(skirt)
        # r(z) = skirt*sqrt(1 + (z/c)^2), z from the middle, r(+-ht/2) = radius
        self.c = 0.5 * self.ht / math.sqrt((self.r / self.skirt) ** 2 - 1.0)

    def _inside(self, pts, pad):
        t, rad, ok = self._axial(pts, pad)
        z = t - 0.5 * self.ht
        return ok & (rad <= self.skirt * np.sqrt(1.0 + (z / self.c) ** 2) - pad)


class inEllipsoid(Predicate):
    """Axis-aligned ellipsoid at ``centerPoint`` with semi-axes ``abc``; the padding shrinks
    every semi-axis by ``pad`` (approximate, as in YADE)."""

    def __init__(self, centerPoint, abc):
        self.c, self.abc = as_vec3(centerPoint), as_vec3(abc)

    def _inside(self, pts, pad):
        return np.sum(((pts - self.c) / (self.abc - pad)) ** 2, axis=1) <= 1.0

    def _box(self):
        return self.c - self.abc, self.c + self.abc


class inParallelepiped(Predicate):
    """Parallelepiped with vertex ``o`` and edges ``o->a``, ``o->b``, ``o->c``."""

    def __init__(self, o, a, b, c):
        self.o = as_vec3(o)
        self.e = np.array([as_vec3(a), as_vec3(b), as_vec3(c)]) - self.o
        # for each pair of opposite faces: unit normal pointing inside and the thickness
        self.nrm, self.thick = [], []
        for i in range(3):
            n = np.cross(self.e[(i + 1) % 3], self.e[(i + 2) % 3])
            n /= np.linalg.norm(n)
            if n @ self.e[i] < 0:
                n = -n
            self.nrm.append(n)
            self.thick.append(float(n @ self.e[i]))

    def _inside(self, pts, pad):
        rel = pts - self.o
        ok = np.ones(len(pts), dtype=bool)
        for n, h in zip(self.nrm, self.thick, strict=True):
            d = rel @ n
            ok &= (d >= pad) & (d <= h - pad)
        return ok

    def _box(self):
        corners = self.o + np.array([[i, j, k] for i in (0, 1) for j in (0, 1) for k in (0, 1)]) @ self.e
        return corners.min(axis=0), corners.max(axis=0)


class notInNotch(Predicate):
    """Everything except an infinite slot of width ``aperture``: the slot lies on the
    ``edge x normal`` side of the line through ``centerPoint`` along ``edge``, symmetric about
    the plane with ``normal``. Padding uses the exact distance to the slot. Infinite AABB."""

    def __init__(self, centerPoint, edge, normal, aperture):
        self.c = as_vec3(centerPoint)
        self.edge = as_vec3(edge) / np.linalg.norm(as_vec3(edge))
        n = as_vec3(normal)
        n = n - (n @ self.edge) * self.edge  # made perpendicular to the edge
        self.normal = n / np.linalg.norm(n)
        self.inside = np.cross(self.edge, self.normal)
        self.half = 0.5 * float(aperture)

    def _inside(self, pts, pad):
        rel = pts - self.c
        u = rel @ self.inside  # > 0: the notch's side of the edge
        v = np.abs(rel @ self.normal)
        beyond = np.maximum(v - self.half, 0.0)
        far = np.where(v <= self.half, -u >= pad, u * u + beyond * beyond >= pad * pad)
        return np.where(u > 0, v >= self.half + pad, far)

    def _box(self):
        return -_INF, _INF.copy()


class inSpace(Predicate):
    """Every point; infinite bounding box (its centre is the origin)."""

    def __init__(self, _center=(0, 0, 0)):
        self._c = as_vec3(_center)

    def _inside(self, pts, pad):
        return np.ones(len(pts), dtype=bool)

    def _box(self):
        return -_INF, _INF.copy()

    def center(self):
        return _V(self._c)


# ----------------------------------------------------------------------------- lattices
def _finite_box(predicate):
    mn, mx = predicate._box()
    if not (np.all(np.isfinite(mn)) and np.all(np.isfinite(mx))):
        raise ValueError("the predicate has an infinite bounding box; combine it with a finite one")
    return mn, mx


def regularOrthoCenters(predicate, radius, gap):
    """Centres (N, 3) of ``regularOrtho``: a simple cubic lattice of spacing ``2*radius + gap``
    starting at the predicate's AABB minimum + radius, x slowest, z fastest (YADE's order),
    kept where ``predicate(c, radius)`` holds."""
    mn, mx = _finite_box(predicate)
    a = 2.0 * radius + gap
    # same np.arange calls as YADE produces (end excluded), so boundary points match exactly
    axes = [np.arange(mn[d] + radius, mx[d] - radius, a) for d in range(3)]
    pts = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
    return pts[predicate._inside(pts, radius)] if len(pts) else pts


def regularHexaCenters(predicate, radius, gap):
    """Centres (N, 3) of ``regularHexa``: hexagonal close packing with spacing ``a = 2r + gap``.

    With h = a/2 and (x0, y0, z0) the predicate's AABB minimum, for i, j, k >= 0:
    x = x0 + (2i + (j+k) mod 2)*h, y = y0 + sqrt(3)*(j + (k mod 2)/3)*h, z = z0 + 2*sqrt(6)/3*k*h
    (rows a*sqrt(3)/2 apart, layers a*sqrt(6)/3 apart). The products are grouped exactly so,
    because YADE's lattice points come out bit for bit like that and a point that touches the
    boundary is kept or dropped on the last bit. Points are kept where ``predicate(c, radius)``
    holds, in YADE's order: x slowest, z fastest.
    """
    mn, mx = _finite_box(predicate)
    h = (2.0 * radius + gap) / 2.0
    s3, c6 = math.sqrt(3.0), 2.0 * math.sqrt(6.0) / 3.0
    size = mx - mn
    n = [int(math.ceil(size[0] / (2 * h))) + 2, int(math.ceil(size[1] / (s3 * h))) + 2,
         int(math.ceil(size[2] / (c6 * h))) + 2]
    i, j, k = np.meshgrid(*(np.arange(m) for m in n), indexing="ij")
    x = mn[0] + (2 * i + (j + k) % 2) * h
    y = mn[1] + (s3 * (j + (k % 2) / 3.0)) * h
    z = mn[2] + (c6 * k) * h
    pts = np.stack([x, y, z], axis=-1).reshape(-1, 3)
    pts = pts[np.all(pts <= mx, axis=1)]  # beyond the AABB nothing can be inside
    return pts[predicate._inside(pts, radius)]


def _bodies(centers, radius, kw):
    from granum.yade import utils  # lazy: the scene code imports this module

    return [utils.sphere(_V(c), radius, **kw) for c in centers]


def regularOrtho(predicate, radius, gap, **kw):
    """List of sphere Bodies (``utils.sphere(center, radius, **kw)``) on a cubic lattice
    clipped by ``predicate``; see :func:`regularOrthoCenters`."""
    return _bodies(regularOrthoCenters(predicate, radius, gap), radius, kw)


def regularHexa(predicate, radius, gap, **kw):
    """List of sphere Bodies on a hexagonal close-packed lattice clipped by ``predicate``;
    see :func:`regularHexaCenters`."""
    return _bodies(regularHexaCenters(predicate, radius, gap), radius, kw)


# ----------------------------------------------------------------------------- SpherePack
class _PackIndexError(IndexError, RuntimeError):
    """YADE raises RuntimeError for a bad index; Python's protocols expect IndexError."""


def _quantiles(num):
    """Cumulative fractions at which ``num`` deterministic sizes are taken, largest first."""
    return 1.0 - (np.arange(num) + 0.5) / (num + 1.0)


class SpherePack:
    """Set of spheres (centres ``(N, 3)``, radii ``(N,)``, clump ids ``(N,)``) with an optional
    periodic cell.

    ``SpherePack()``, ``SpherePack([((x, y, z), r), ...])`` or with ``((x, y, z), r, clumpId)``
    items. Sequence protocol: ``len(sp)``, ``sp[i] -> (Vector3 center, float radius)`` (plus
    the clump id for a clump member), ``for c, r in sp``.
    """

    def __init__(self, spheres=None):
        self._c = np.empty((16, 3))  # storage with spare capacity; rows [0, _n) are valid
        self._r = np.empty(16)
        self._cid = np.empty(16, dtype=np.int64)
        self._n = 0
        self._cell = np.zeros(3)
        self.isPeriodic = False
        #: factor applied to PSD sizes by the last ``makeCloud`` (1 if none)
        self.appliedPsdScaling = 1.0
        if spheres is not None:
            self.fromList(spheres)

    # -- storage
    @property
    def centers(self) -> np.ndarray:
        """Centres as a read-only ``(N, 3)`` array view (granum extension)."""
        v = self._c[: self._n]
        v.flags.writeable = False
        return v

    @property
    def radii(self) -> np.ndarray:
        """Radii as a read-only ``(N,)`` array view (granum extension)."""
        v = self._r[: self._n]
        v.flags.writeable = False
        return v

    @property
    def clumpIds(self) -> np.ndarray:
        """Clump id of each sphere, ``-1`` for standalone ones, as a read-only ``(N,)`` int64
        array view (granum extension)."""
        v = self._cid[: self._n]
        v.flags.writeable = False
        return v

    def _set(self, centers, radii, clump_ids=None):
        c = np.array(centers, dtype=np.float64).reshape(-1, 3)
        r = np.array(radii, dtype=np.float64).reshape(-1)
        if len(c) != len(r):
            raise ValueError(f"{len(c)} centers but {len(r)} radii")
        k = np.full(len(r), -1, np.int64) if clump_ids is None else np.array(clump_ids, dtype=np.int64).reshape(-1)
        if len(k) != len(r):
            raise ValueError(f"{len(r)} spheres but {len(k)} clump ids")
        self._c = np.concatenate([c, np.empty((16, 3))])
        self._r = np.concatenate([r, np.empty(16)])
        self._cid = np.concatenate([k, np.empty(16, np.int64)])
        self._n = len(r)

    def add(self, center, radius):
        """Append one standalone sphere (amortised O(1): storage grows geometrically)."""
        if self._n == len(self._r):
            self._c = np.concatenate([self._c, np.empty_like(self._c)])
            self._r = np.concatenate([self._r, np.empty_like(self._r)])
            self._cid = np.concatenate([self._cid, np.empty_like(self._cid)])
        self._c[self._n] = as_vec3(center)
        self._r[self._n] = float(radius)
        self._cid[self._n] = -1
        self._n += 1

    def __len__(self):
        return self._n

    def __getitem__(self, i):
        if not isinstance(i, int | np.integer):
            raise TypeError(f"SpherePack indices must be integers, not {type(i).__name__}")
        j = int(i) + self._n if i < 0 else int(i)
        if not 0 <= j < self._n:
            raise _PackIndexError(f"Index {i} out of range 0..{self._n - 1}")
        if self._cid[j] >= 0:
            return _V(self._c[j]), float(self._r[j]), int(self._cid[j])
        return _V(self._c[j]), float(self._r[j])

    def __iter__(self):
        # pairs even for clump members: YADE's iterator drops the clump id
        for j in range(self._n):
            yield _V(self._c[j]), float(self._r[j])

    def __repr__(self):
        return f"<SpherePack with {self._n} spheres{', periodic' if self.isPeriodic else ''}>"

    def toList(self):
        """``[(Vector3 center, float radius), ...]``; clump members as ``(center, radius, clumpId)``."""
        return [self[j] for j in range(self._n)]

    def fromList(self, *args):
        """Replace the content: ``fromList([((x, y, z), r), ...])`` (items may carry a third
        element, the clump id) or ``fromList(centers, radii)``."""
        ids = None
        if len(args) == 2:
            centers, radii = args
            centers = [as_vec3(c) for c in centers]
        elif len(args) == 1:
            items = [tuple(x) for x in args[0]]
            if any(len(x) not in (2, 3) for x in items):
                raise ValueError("fromList: items must be (center, radius) or (center, radius, clumpId)")
            centers = [as_vec3(x[0]) for x in items]
            radii = [float(x[1]) for x in items]
            ids = [int(x[2]) if len(x) == 3 else -1 for x in items]
        else:
            raise TypeError("fromList(list) or fromList(centers, radii)")
        self._set(np.reshape(centers, (-1, 3)), radii, ids)

    # -- clumps
    def hasClumps(self):
        """Whether some sphere belongs to a clump."""
        return bool(np.any(self._cid[: self._n] >= 0))

    def getClumps(self):
        """``(standalones, [clump1, clump2, ...])``: sphere indices of the standalone spheres,
        and for each clump id in increasing order the indices of its members (YADE's form)."""
        k = self._cid[: self._n]
        alone = [int(i) for i in np.flatnonzero(k < 0)]
        members = np.flatnonzero(k >= 0)
        order = members[np.argsort(k[members], kind="stable")]  # by id, sphere order within one
        groups = np.split(order, np.flatnonzero(np.diff(k[order])) + 1) if len(order) else []
        return alone, [[int(i) for i in g] for g in groups]

    # -- periodic cell
    @property
    def cellSize(self):
        """Periodic cell size (Vector3; zero if aperiodic). Setting it makes the pack periodic."""
        return _V(self._cell)

    @cellSize.setter
    def cellSize(self, value):
        self._cell = as_vec3(value)
        self.isPeriodic = bool(np.any(self._cell != 0))

    # -- geometry
    def aabb(self):
        """Bounding box of the spheres (radii included): ``(Vector3 min, Vector3 max)``;
        ``(inf, -inf)`` when empty, as YADE."""
        if self._n == 0:
            return _V(_INF), _V(-_INF)
        c, r = self._c[: self._n], self._r[: self._n, None]
        return _V((c - r).min(axis=0)), _V((c + r).max(axis=0))

    def dim(self):
        """Size of :meth:`aabb`."""
        mn, mx = self.aabb()
        return _V(np.asarray(mx) - np.asarray(mn))

    def center(self):
        """Middle of :meth:`aabb`."""
        mn, mx = self.aabb()
        with np.errstate(invalid="ignore"):
            return _V(0.5 * (np.asarray(mn) + np.asarray(mx)))

    def translate(self, shift):
        """Move all centres by ``shift``."""
        self._c[: self._n] += as_vec3(shift)

    def scale(self, scale):
        """Scale centres about :meth:`center`, radii and the cell size by ``scale``."""
        ctr = np.asarray(self.center())
        self._c[: self._n] = ctr + scale * (self._c[: self._n] - ctr)
        self._r[: self._n] *= scale
        self._cell = self._cell * scale

    def rotate(self, axis, angle):
        """Rotate all centres about :meth:`center` by ``angle`` (rad) around ``axis``."""
        R = np.asarray(Matrix3(Quaternion(_V(as_vec3(axis) / np.linalg.norm(as_vec3(axis))), angle)))
        ctr = np.asarray(self.center())
        self._c[: self._n] = ctr + (self._c[: self._n] - ctr) @ R.T

    # -- files (YADE's text format: optional "##PERIODIC:: a b c", then "x y z r clumpId")
    def save(self, fileName):
        """Write the packing to a text file."""
        with open(fileName, "w") as f:
            if self.isPeriodic:
                f.write("##PERIODIC:: {:.17g} {:.17g} {:.17g}\n".format(*self._cell))
            for c, r, k in zip(self._c[: self._n], self._r[: self._n], self._cid[: self._n], strict=True):
                f.write(f"{c[0]:.17g} {c[1]:.17g} {c[2]:.17g} {r:.17g} {k}\n")

    def load(self, fileName):
        """Replace the content with a file written by :meth:`save` (or by YADE)."""
        rows, cell = [], None
        with open(fileName) as f:
            for line in f:
                if line.startswith("##PERIODIC::"):
                    cell = [float(x) for x in line.split()[1:4]]
                elif line.strip() and not line.startswith("#"):
                    v = line.split()
                    rows.append([float(x) for x in v[:4]] + [float(v[4]) if len(v) > 4 else -1.0])
        a = np.array(rows, dtype=np.float64).reshape(-1, 5)
        self._set(a[:, :3], a[:, 3], a[:, 4].astype(np.int64))
        self._cell, self.isPeriodic = np.zeros(3), False
        if cell is not None:
            self.cellSize = cell

    # -- cloud generation
    def makeCloud(self, minCorner=(0, 0, 0), maxCorner=(0, 0, 0), rMean=-1, rRelFuzz=0, num=-1,
                  periodic=False, porosity=0.65, psdSizes=(), psdCumm=(), distributeMass=False,
                  seed=-1, hSize=None):
        """Random loose cloud of non-overlapping spheres in the box ``minCorner``..``maxCorner``,
        appended to the spheres already in the pack (new ones avoid them).

        Sizes: uniform in ``rMean*(1 +- rRelFuzz)``; or, with ``num`` and ``rMean < 0``,
        ``rMean`` from ``porosity`` (r = cbrt(V(1-porosity) / (4/3 pi (1+rRelFuzz^2) num)),
        retried with higher porosity until ``num`` spheres fit); or a particle size
        distribution ``psdSizes`` (diameters) / ``psdCumm`` (cumulative fractions, by number
        or, with ``distributeMass``, by mass). Without ``num`` spheres are inserted until
        one does not fit after 1000 tries; with ``num`` exactly ``num`` deterministic sizes
        are placed largest first. ``periodic``: centres anywhere in the box, no overlaps
        across its faces, and ``cellSize`` becomes the box size. A zero box extent along
        one axis makes a 2D packing. ``seed >= 0`` reproduces a cloud; negative (default)
        is random per call. ``hSize``: diagonal periodic cell (box from the origin).

        Returns the number of spheres generated without ``num``, else ``len(self)``.
        """
        mn, mx = as_vec3(minCorner), as_vec3(maxCorner)
        if hSize is not None and np.any(as_mat3(hSize) != 0):
            h = as_mat3(hSize)
            if np.any(h != np.diag(np.diag(h))):
                raise NotImplementedError("makeCloud: only a diagonal hSize is supported")
            mn, mx, periodic = np.zeros(3), np.diag(h).copy(), True
        length = mx - mn
        if np.any(length < 0):
            raise ValueError("makeCloud: maxCorner must not be below minCorner")
        flat = length == 0
        if flat.sum() == 1:
            warnings.warn("makeCloud: the box has zero volume, the packing is 2D", stacklevel=2)
        elif flat.sum() > 1:
            raise ValueError("makeCloud: the box is degenerate along more than one axis")
        if seed is None or seed < 0:
            seed = secrets.randbits(32)
        z, num = float(rRelFuzz), int(num)
        volume = float(np.prod(length[~flat]))
        # 3D: sphere volume 4/3 pi r^3; 2D: disc area pi r^2 (porosity is then an area fraction)
        dim_exp, unit = (2, math.pi) if flat.any() else (3, 4.0 / 3.0 * math.pi)

        def fill(radii=None, cdf=None, rtab=None, mass=False):
            """One insertion from the seed (YADE's retries with a higher porosity start the generator again)."""
            empty = np.empty(0)
            pos, rad, n = _packing.rsa_fill(
                self._c[: self._n].copy(), self._r[: self._n].copy(), mn, length, bool(periodic),
                empty if radii is None else np.ascontiguousarray(radii, dtype=np.float64),
                empty if cdf is None else cdf, empty if rtab is None else rtab,
                bool(mass), MAX_TRY, seed % (1 << 32))
            return pos[:n], rad[:n]

        n_old = self._n
        old_ids = self._cid[:n_old].copy()  # old spheres keep their clumps; new ones are standalone
        self.appliedPsdScaling = 1.0
        if len(psdSizes):
            cdf, rtab = _packing.psd_table(psdSizes, psdCumm, distributeMass)
            if num > 0:
                base = _packing.inverse_cdf_many(_quantiles(num), cdf, rtab, bool(distributeMass))
                scale = 1.0
                while True:
                    pos, rad = fill(radii=base * scale)
                    if len(rad) - n_old >= num:
                        break
                    # fewer than num fit: shrink all sizes as a porosity step 0.1*(1-p) would
                    new = porosity + 0.1 * (1.0 - porosity)
                    scale *= ((1.0 - new) / (1.0 - porosity)) ** (1.0 / dim_exp)
                    porosity = new
                if scale != 1.0:
                    warnings.warn(f"makeCloud: the size distribution was scaled down by {scale:g}",
                                  stacklevel=2)
                self.appliedPsdScaling = scale
            else:
                pos, rad = fill(cdf=cdf, rtab=rtab, mass=distributeMass)
        elif rMean > 0:
            rlo, rhi = rMean * (1.0 - z), rMean * (1.0 + z)
            if num > 0:
                pos, rad = fill(radii=rlo + _quantiles(num) * (rhi - rlo))
                if len(rad) - n_old < num:
                    warnings.warn(f"makeCloud: exceeded {MAX_TRY} tries to insert a non-overlapping sphere; "
                                  f"only {len(rad) - n_old} of {num} spheres were added", stacklevel=2)
            else:
                pos, rad = fill(cdf=np.array([0.0, 1.0]), rtab=np.array([rlo, rhi]))
        elif num > 0:
            while True:
                rm = (volume * (1.0 - porosity) / (unit * (1.0 + z * z) * num)) ** (1.0 / dim_exp)
                pos, rad = fill(radii=rm * (1.0 - z) + _quantiles(num) * (2.0 * z * rm))
                if len(rad) - n_old >= num:
                    break
                new = porosity + 0.1 * (1.0 - porosity)
                warnings.warn(f"makeCloud: only {len(rad) - n_old} of {num} spheres fit; "
                              f"trying again with porosity {new:g}", stacklevel=2)
                porosity = new
        else:
            raise ValueError("makeCloud: give rMean > 0, or num > 0, or psdSizes/psdCumm")
        self._set(pos, rad, np.concatenate([old_ids, np.full(len(rad) - n_old, -1, np.int64)]))
        self.isPeriodic = bool(periodic)
        if periodic:
            self._cell = length.copy()
        return self._n if num > 0 else self._n - n_old

    def makeClumpCloud(self, minCorner, maxCorner, clumps, periodic=False, num=-1, seed=-1):
        """Random loose cloud of clumps in the box ``minCorner``..``maxCorner``, appended to the
        spheres already in the pack (new clumps avoid them).

        ``clumps``: list of template SpherePacks; each clump copies a randomly chosen one,
        turned by a uniformly random rotation about its bounding-box centre, which lies
        uniformly in the box. A clump may not overlap any other sphere; without ``periodic``
        it must lie inside the box, with ``periodic`` overlaps count across the faces and
        ``cellSize`` becomes the box size (``isPeriodic`` is left unchanged, as in YADE).
        Stops after ``num`` clumps or when one clump fails 200 attempts (warning if ``num``
        was given). ``seed >= 0`` reproduces a cloud. Returns the number of clumps added.
        Details: :mod:`granum.yade._clumpcloud`.
        """
        n = self._n
        c, r, k, added = _clumpcloud.clump_cloud(self._c[:n], self._r[:n], self._cid[:n], as_vec3(minCorner),
                                                 as_vec3(maxCorner), clumps, periodic, num, seed)
        self._set(c, r, k)
        if periodic:
            self._cell = as_vec3(maxCorner) - as_vec3(minCorner)
        return added

    # -- scene
    def toSimulation(self, rot=None, **kw):
        """Add the spheres to the scene with ``utils.sphere(center, radius, **kw)``, then make
        each clump (clump ids in increasing order) a clump body with ``O.bodies.clump``;
        returns the sphere ids followed by the clump ids. ``rot`` (Matrix3 or Quaternion)
        rotates the packing about the origin. A periodic pack (``isPeriodic``) also makes the
        scene periodic with ``O.cell.hSize = rot * diag(cellSize)`` and ``O.cell.trsf = Identity``."""
        from granum.yade import omega, utils  # lazy: the scene code imports this module

        O = omega.O
        if rot is None:
            R = np.eye(3)
        else:
            R = np.asarray(Matrix3(rot)) if isinstance(rot, Quaternion) else as_mat3(rot)
        centers = self._c[: self._n] @ R.T
        if self.isPeriodic:
            O.periodic = True
            h = R @ np.diag(self._cell)
            O.cell.hSize = Matrix3(*(float(x) for x in h.ravel()))
            O.cell.trsf = Matrix3.Identity
        radii = self._r[: self._n]
        bodies = [utils.sphere(_V(c), float(r), **kw) for c, r in zip(centers, radii, strict=True)]
        ids = O.bodies.append(bodies)
        # all spheres first, then the clumps: the body ids YADE gives (not appendClumped's order)
        for members in self.getClumps()[1]:
            ids.append(O.bodies.clump([ids[m] for m in members]))
        return ids

    def fromSimulation(self):
        """Replace the content with the spheres of the current scene (and its periodic cell);
        clump members get the id of their clump body as clump id."""
        from granum.yade import omega  # lazy: the scene code imports this module

        O = omega.O
        centers, radii, ids = [], [], []
        for b in O.bodies:
            shape = getattr(b, "shape", None)
            if b is not None and type(shape).__name__ == "Sphere":
                centers.append(as_vec3(b.state.pos))
                radii.append(float(shape.radius))
                ids.append(int(b.clumpId) if b.isClumpMember else -1)  # YADE: the clump body's id
        self._set(np.reshape(centers, (-1, 3)), radii, ids)
        self._cell, self.isPeriodic = np.zeros(3), False
        if O.periodic:
            self.cellSize = np.diag(np.asarray(O.cell.hSize)).copy()


# the surface predicates and builders (their module imports Predicate from this one)
from granum.yade._surfacepack import (  # noqa: E402
    gtsSurface2Facets,
    inConvexPolyhedron,
    inGtsSurface,
    revolutionSurfaceMeridians,
    sweptPolylines2gtsSurface,
)

__all__ += ["gtsSurface2Facets", "inConvexPolyhedron", "inGtsSurface", "revolutionSurfaceMeridians",
            "sweptPolylines2gtsSurface"]
