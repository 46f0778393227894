"""Closed-form helpers of ``yade.utils``: triangle centres, boxes, spherical coordinates, 2d outlines.

:func:`rotate` (batches of quaternions) serves the other modules; it is not a YADE name.
"""

from __future__ import annotations

import math

import numpy as np

from granum.mathtypes import Vector3, as_vec3

__all__ = ["inscribedCircleCenter", "ptInAABB", "spher2cart", "cart2spher", "aabbExtrema2d", "xMirror",
           "getViscoelasticFromSpheresInteraction"]


def rotate(q: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Vectors ``v`` (K, 3) rotated by unit quaternions ``q`` (K, 4) in (w, x, y, z) order."""
    u = q[:, 1:]
    t = 2.0 * np.cross(u, v)
    return v + q[:, :1] * t + np.cross(u, t)


def inscribedCircleCenter(v1, v2, v3):
    """Centre of the circle inscribed in triangle (v1, v2, v3): the vertices weighted by the opposite
    edge lengths [m]."""
    v = np.array([as_vec3(v1), as_vec3(v2), as_vec3(v3)])
    w = np.linalg.norm(v[[1, 2, 0]] - v[[2, 0, 1]], axis=1)
    return Vector3(*(w @ v / w.sum()))


def ptInAABB(p, minPt, maxPt) -> bool:
    """Whether point ``p`` lies strictly inside the box (``minPt``, ``maxPt``)."""
    p, lo, hi = as_vec3(p), as_vec3(minPt), as_vec3(maxPt)
    return bool(np.all((lo < p) & (p < hi)))


def spher2cart(vec):
    """Cartesian (x, y, z) of spherical (r, theta from +z, phi from +x in the xy plane)."""
    r, theta, phi = as_vec3(vec)
    return Vector3(r * math.sin(theta) * math.cos(phi), r * math.sin(theta) * math.sin(phi), r * math.cos(theta))


def cart2spher(vec):
    """Spherical (r, theta in [0, pi] from +z, phi in [0, 2 pi) from +x) of a cartesian vector; 0 -> 0."""
    x, y, z = as_vec3(vec)
    r = math.sqrt(x * x + y * y + z * z)
    if r == 0:
        return Vector3(0, 0, 0)
    return Vector3(r, math.acos(z / r), math.atan2(y, x) % (2.0 * math.pi))


def aabbExtrema2d(pts):
    """((xmin, ymin), (xmax, ymax)) of a sequence of 2d points."""
    xs, ys = [p[0] for p in pts], [p[1] for p in pts]
    return (min(xs), min(ys)), (max(xs), max(ys))


def xMirror(half) -> list:
    """``half`` followed by its mirror image across the x axis, in reverse order (a closed outline).

    The last point is not repeated when it lies on the x axis (y = 0).
    """
    back = half[:-1] if half[-1][1] == 0 else half
    return list(half) + [(x, -y) for x, y in reversed(back)]


def getViscoelasticFromSpheresInteraction(tc, en, es):
    """Refused, as in YADE 2023.02a: set ``tc``, ``en``, ``es`` on ViscElMat instead."""
    raise RuntimeError("getViscoelasticFromSpheresInteraction is deprecated (as in YADE): set tc, en and es "
                       "directly on ViscElMat")
