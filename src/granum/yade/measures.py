"""More global measures of ``yade.utils``: momenta, boxes, forces across planes, size distribution.

Vectorised NumPy over the scene's arrays, like the measures of :mod:`granum.yade.utils`,
whose selection helpers they call. Vectors are returned as Vector3 [SI units].
"""

from __future__ import annotations

import math

import numpy as np

from granum.core.contacts import C_PAIRS, F_FN, F_FS, F_KN, F_KS, F_PEN, I_ID1, I_ID2
from granum.core.shapes import ShapeKind
from granum.mathtypes import Vector3, as_vec3
from granum.yade.formulas import rotate
from granum.yade.omega import O
from granum.yade.utils import _live_contacts, _not_member, _spheres, aabbExtrema, getStress

__all__ = [
    "momentum", "angularMomentum", "aabbDim", "fractionalBox", "perpendicularArea", "sumFacetNormalForces",
    "forcesOnPlane", "forcesOnCoordPlane", "maxOverlapRatio", "psd", "sumTorques", "numIntrsOfEachBody",
    "getBodyIdsContacts", "negPosExtremeIds", "getSpheresVolume2D", "totalForceInVolume", "voxelPorosity",
    "stressTensorOfPeriodicCell", "flipCell", "approxSectionArea", "uniaxialTestFeatures",
]


def _standalone_live():
    """Ids of live bodies that move on their own (standalone bodies and clumps, not members)."""
    b = O._scene.bodies
    n = b.count
    return np.nonzero(b.alive[:n] & _not_member(b, n))[0]


def momentum():
    """Linear momentum sum m v of all bodies, fixed ones included (as YADE) [kg m/s]."""
    b = O._scene.bodies
    ids = _standalone_live()
    return Vector3(*(b.mass[ids, None] * b.vel[ids]).sum(axis=0))


def angularMomentum(origin=(0.0, 0.0, 0.0)):
    """Angular momentum about ``origin`` [kg m^2/s]: sum (x - origin) x m v + State.angMom.

    As in YADE, spheres count by their orbital term only: State.angMom is kept for
    aspherical bodies (0 for the others).
    """
    b = O._scene.bodies
    ids = _standalone_live()
    orbital = np.cross(b.pos[ids] - as_vec3(origin), b.mass[ids, None] * b.vel[ids]).sum(axis=0)
    spin = b.stored("ang_mom")
    if spin.shape[0]:
        orbital = orbital + spin[ids].sum(axis=0)
    return Vector3(*orbital)


def aabbDim(cutoff=0.0, centers=False):
    """Sizes of the spheres' bounding box, ``cutoff`` (relative) cut away on each side [m]."""
    lo, hi = aabbExtrema(cutoff, centers)
    return Vector3(*(np.asarray(hi._a) - np.asarray(lo._a)))


def fractionalBox(fraction=1.0, minMax=None):
    """``minMax`` (default: the spheres' bounding box) scaled by ``fraction`` about its centre [m]."""
    lo, hi = (np.asarray(as_vec3(x)) for x in (minMax or aabbExtrema()))
    c, half = 0.5 * (lo + hi), 0.5 * fraction * (hi - lo)
    return Vector3(*(c - half)), Vector3(*(c + half))


def perpendicularArea(axis):
    """Area of the spheres' bounding box seen along ``axis`` (0, 1, 2) [m^2]."""
    d = np.asarray(aabbDim()._a)
    return float(np.prod(np.delete(d, axis)))


def _global_facet_normals(ids: np.ndarray) -> np.ndarray:
    s = O._scene
    b = s.bodies
    return rotate(b.ori[ids], s.shapes[ShapeKind.FACET].normal[b.shape_row[ids]])


def sumFacetNormalForces(ids, axis=-1) -> float:
    """Sum over facets ``ids`` of the force on each projected on its normal [N].

    With ``axis`` >= 0, that component of each normal is dropped first: what YADE
    2023.02a computes, although its documentation says the axis replaces the normal.
    """
    ids = np.asarray(list(ids), dtype=np.int64)
    b = O._scene.bodies
    wrong = ids[b.shape_kind[ids] != ShapeKind.FACET]
    if wrong.size:
        raise TypeError(f"sumFacetNormalForces: body {int(wrong[0])} is not a Facet")
    n = _global_facet_normals(ids)
    if axis >= 0:
        n[:, axis] = 0.0
    return float(np.einsum("ki,ki->", b.force[ids], n))


def forcesOnPlane(planePt, normal):
    """Sum of the contact forces (normal + shear) of the contacts whose two bodies lie on opposite
    sides of the plane through ``planePt`` with ``normal``: the force on the body on the positive side [N]."""
    n = as_vec3(normal)
    n = n / np.linalg.norm(n)
    b = O._scene.bodies
    C, rows = _live_contacts()
    side1 = (b.pos[C.con_i[rows, I_ID1]] - as_vec3(planePt)) @ n
    side2 = (b.pos[C.con_i[rows, I_ID2]] - as_vec3(planePt)) @ n
    cross = np.sign(side1) * np.sign(side2) < 0
    f = C.con_f[rows, F_FN:F_FN + 3] + C.con_f[rows, F_FS:F_FS + 3]  # on body 2
    return Vector3(*(np.sign(side2[cross])[:, None] * f[cross]).sum(axis=0))


def forcesOnCoordPlane(coord, axis):
    """:func:`forcesOnPlane` for the plane x[axis] = ``coord`` with normal along +axis [N]."""
    pt, n = np.zeros(3), np.zeros(3)
    pt[axis], n[axis] = coord, 1.0
    return forcesOnPlane(pt, n)


def maxOverlapRatio() -> float:
    """Largest u_N / (2 r1 r2 / (r1 + r2)) over sphere-sphere contacts [-] (0 without any)."""
    s = O._scene
    b = s.bodies
    C, rows = _live_contacts()
    id1, id2 = C.con_i[rows, I_ID1], C.con_i[rows, I_ID2]
    both = (b.shape_kind[id1] == ShapeKind.SPHERE) & (b.shape_kind[id2] == ShapeKind.SPHERE)
    if not both.any():
        return 0.0
    radius = s.shapes[ShapeKind.SPHERE].radius
    r1, r2 = radius[b.shape_row[id1[both]]], radius[b.shape_row[id2[both]]]
    return float(np.max(C.con_f[rows[both], F_PEN] * (r1 + r2) / (2.0 * r1 * r2)))


def psd(bins=5, mass=True, mask=-1):
    """Cumulative particle size distribution of the spheres over ``bins`` equal diameter bins.

    Returns ``(binsSizes, binsProc, binsSumCum)``, arrays (bins+1,): the bin edges
    [m] from the smallest to the largest diameter, the cumulative fraction [-] and the
    cumulative mass [kg] (or count, ``mass=False``). A sphere of diameter d counts in
    edge k >= (d - dmin)/h + 1 (the first edge holds nothing). With no spheres or a
    single diameter, prints so and returns False, as YADE.
    """
    ids, r = _spheres(mask)
    d = 2.0 * r
    if ids.size == 0 or d.min() == d.max():
        print("Monodisperse packing with diameter =", float(d.max()) if ids.size else 0.0, ". Not computing psd")
        return False
    dmin, dmax = d.min(), d.max()
    h = (dmax - dmin) / bins
    which = np.minimum(np.floor((d - dmin) / h).astype(np.int64) + 1, bins)
    weight = O._scene.bodies.mass[ids] if mass else np.ones(ids.size)
    cum = np.cumsum(np.bincount(which, weights=weight, minlength=bins + 1))
    return dmin + h * np.arange(bins + 1), cum / cum[-1], cum


def sumTorques(ids, axis, axisPt) -> float:
    """Sum over bodies ``ids`` of ((x - axisPt) x f + t) . axis [N m]; ``axis`` is not normalised."""
    ids = np.asarray(list(ids), dtype=np.int64)
    b = O._scene.bodies
    m = np.cross(b.pos[ids] - as_vec3(axisPt), b.force[ids]) + b.torque[ids]
    return float((m @ as_vec3(axis)).sum())


def _contact_ends():
    C, rows = _live_contacts()
    return C.con_i[rows, I_ID1], C.con_i[rows, I_ID2]


def numIntrsOfEachBody() -> list:
    """Number of real interactions of each body id, a list (N,)."""
    id1, id2 = _contact_ends()
    return np.bincount(np.concatenate([id1, id2]), minlength=O._scene.bodies.count).tolist()


def getBodyIdsContacts(bodyID=0) -> list:
    """Sorted ids of the bodies sharing an interaction (real or potential) with ``bodyID``."""
    s = O._scene
    id1, id2 = _contact_ends()
    C = s.contacts
    pairs = C.pair_ids[:int(C.ctr[C_PAIRS])]
    a = np.concatenate([id1, id2, pairs[:, 0], pairs[:, 1]])
    b = np.concatenate([id2, id1, pairs[:, 1], pairs[:, 0]])
    other = np.unique(b[a == bodyID])
    return other[s.bodies.alive[other]].tolist()


def negPosExtremeIds(axis, distFactor) -> tuple[list, list]:
    """Ids of the spheres at the two ends along ``axis``: those whose x -/+ distFactor r reaches
    the spheres' bounding box (lower end, upper end)."""
    ids, r = _spheres()
    x = O._scene.bodies.pos[ids, axis]
    lo, hi = (x - r).min(), (x + r).max()
    return ids[x - distFactor * r <= lo].tolist(), ids[x + distFactor * r >= hi].tolist()


#: approxSectionArea's outline of a sphere of radius r about its centre, in the plane's coordinates
#: (u, v) = (x[axis + 1], x[axis + 2]) (indices mod 3), in units of r: the hexagon (cos k pi/3, 2 sin k pi/3),
#: twice as tall along v as wide (area 3 sqrt(3) r^2), whatever the sphere's distance to the plane. What YADE
#: 2023.02a's convex hull encloses, measured point by point (tests/reference/yade/section_area.py); its
#: documentation warns that the function is approximate.
SECTION_OUTLINE = np.array([[math.cos(k * math.pi / 3), 2.0 * math.sin(k * math.pi / 3)] for k in range(6)])
#: uniaxialTestFeatures' sections: the interior points of UNIAXIAL_SECTIONS equally spaced points from one end
#: of the spheres' bounding box to the other along the axis (YADE 2023.02a's, whatever its ``areaSections``)
UNIAXIAL_SECTIONS = 10


def _coord_axis(axis, fn) -> int:
    if isinstance(axis, bool) or axis not in (0, 1, 2):
        raise ValueError(f"{fn}: axis must be 0, 1 or 2, got {axis!r}")
    return int(axis)


def _convex_hull_area(p: np.ndarray) -> float:
    """Area of the convex hull of the points ``p`` (n, 2) [m^2] (Andrew's monotone chain; 0 below 3 points)."""
    p = np.unique(p, axis=0)  # sorted by u, then v
    if p.shape[0] < 3:
        return 0.0
    pts = [tuple(q) for q in p]

    def chain(points):
        h = []
        for q in points:
            while len(h) >= 2 and ((h[-1][0] - h[-2][0]) * (q[1] - h[-2][1])
                                   - (h[-1][1] - h[-2][1]) * (q[0] - h[-2][0])) <= 0:
                h.pop()
            h.append(q)
        return h[:-1]

    hull = np.array(chain(pts) + chain(pts[::-1]))
    u, v = hull[:, 0], hull[:, 1]
    return float(0.5 * abs(u @ np.roll(v, -1) - v @ np.roll(u, -1)))


def approxSectionArea(coord, axis) -> float:
    """Approximate area [m^2] of the section of the packing by the plane x[axis] = ``coord``: the convex hull of
    the spheres that reach the plane (x[axis] - r <= coord <= x[axis] + r), each taken as the hexagon
    :data:`SECTION_OUTLINE` of its full radius about its centre (YADE's approximation, as measured)."""
    axis = _coord_axis(axis, "approxSectionArea")
    c = float(coord)
    if not math.isfinite(c):
        raise ValueError(f"approxSectionArea: coord must be finite, got {coord!r}")
    ids, r = _spheres()
    x = O._scene.bodies.pos[ids]
    cut = (x[:, axis] - r <= c) & (x[:, axis] + r >= c)
    uv = x[cut][:, [(axis + 1) % 3, (axis + 2) % 3]]
    return _convex_hull_area((uv[:, None, :] + r[cut, None, None] * SECTION_OUTLINE).reshape(-1, 2))


def uniaxialTestFeatures(filename=None, areaSections=10, axis=-1, distFactor=2.2, **kw) -> dict:
    """What a uniaxial test needs from the spheres in the scene: ``{"negIds", "posIds", "axis", "area"}``.

    ``axis``: the given one, or (-1) the longest side of the spheres' bounding box (the first of equal ones);
    ``negIds``/``posIds``: :func:`negPosExtremeIds` (``axis``, ``distFactor``); ``area``: the smallest
    :func:`approxSectionArea` [m^2] over the sections at the interior points of UNIAXIAL_SECTIONS equally spaced
    points along the box (YADE 2023.02a samples these 8 whatever ``areaSections`` says, so granum refuses another
    value). Loading the spheres from ``filename`` (with ``kw``) is refused: YADE 2023.02a's fails too
    (NameError: spheresFromFile).
    """
    if filename is not None or kw:
        raise NotImplementedError(f"uniaxialTestFeatures(filename={filename!r}, **{kw!r}): loading spheres from a "
                                  "file is not implemented (YADE 2023.02a's spheresFromFile no longer exists)")
    if areaSections != UNIAXIAL_SECTIONS:
        raise ValueError(f"uniaxialTestFeatures: areaSections={areaSections!r} is not supported: YADE 2023.02a "
                         f"always samples the {UNIAXIAL_SECTIONS - 2} sections of the default 10")
    ids, _ = _spheres()
    lo, hi = (np.asarray(v._a) for v in aabbExtrema())
    axis = int(np.argmax(hi - lo)) if axis == -1 else _coord_axis(axis, "uniaxialTestFeatures")
    if ids.size == 0:
        return {"negIds": [], "posIds": [], "axis": axis, "area": 0.0}
    neg, pos = negPosExtremeIds(axis, distFactor)
    coords = np.linspace(lo[axis], hi[axis], UNIAXIAL_SECTIONS)[1:-1]
    return {"negIds": neg, "posIds": pos, "axis": axis, "area": min(approxSectionArea(c, axis) for c in coords)}


def getSpheresVolume2D(mask=-1) -> float:
    """Total area of the spheres taken as discs, sum pi r^2 [m^2]."""
    _, r = _spheres(mask)
    return float(math.pi * (r ** 2).sum())


def totalForceInVolume():
    """``(Vector3 F, K)``: F_k the sum over live contacts of |f_k|, f = fn + fs [N] (PeriIsoCompressor's
    measure), and K the mean of kn/3 + 2 ks/3 over them [N/m] (-1 without contacts)."""
    C, rows = _live_contacts()
    f = C.con_f[rows, F_FN:F_FN + 3] + C.con_f[rows, F_FS:F_FS + 3]
    k = C.con_f[rows, F_KN] / 3.0 + 2.0 * C.con_f[rows, F_KS] / 3.0
    return Vector3(*np.abs(f).sum(axis=0)), float(k.mean()) if rows.size else -1.0


def stressTensorOfPeriodicCell(volume=0):
    """The Love-Weber stress tensor [Pa], as :func:`getStress` (YADE's deprecated name)."""
    return getStress(volume)


def flipCell():
    """``O.cell.flipCell()`` (YADE's deprecated utils function, which takes no argument)."""
    import warnings

    warnings.warn("flipCell from utils module is deprecated, use O.cell.flipCell() or O.cell.flipFlippable=True "
                  "instead", DeprecationWarning, stacklevel=2)
    return O.cell.flipCell()


def voxelPorosity(resolution=200, start=(0.0, 0.0, 0.0), end=(0.0, 0.0, 0.0)) -> float:
    """Porosity of the box ``start``..``end`` [-]: the fraction of the resolution³ grid points
    start + (i, j, k)·(end − start)/resolution (i, j, k in 0..resolution−1) lying strictly inside no sphere
    (YADE's voxel count, measured on its results); parts of spheres outside the box do not count."""
    res = int(resolution)
    if res < 50:
        raise ValueError("utils.voxelPorosity: it doesn't make sense to calculate porosity with voxel resolution "
                         f"below 50 (got {res}).")
    lo, hi = as_vec3(start), as_vec3(end)
    if (lo == hi).all():
        raise ValueError("utils.voxelPorosity: cannot calculate porosity when start==end of the volume box.")
    h = (hi - lo) / res
    solid = np.zeros((res, res, res), bool)
    ids, radii = _spheres()
    for c, r in zip(O._scene.bodies.pos[ids], radii, strict=True):
        first = np.maximum(np.ceil((c - r - lo) / h), 0).astype(int)
        last = np.minimum(np.floor((c + r - lo) / h), res - 1).astype(int)
        if (last < first).any():
            continue
        axes = [lo[a] + h[a] * np.arange(first[a], last[a] + 1) - c[a] for a in range(3)]
        d2 = axes[0][:, None, None] ** 2 + axes[1][None, :, None] ** 2 + axes[2][None, None, :] ** 2
        solid[first[0]:last[0] + 1, first[1]:last[1] + 1, first[2]:last[2] + 1] |= d2 < r * r
    return float(1.0 - solid.sum() / res ** 3)
