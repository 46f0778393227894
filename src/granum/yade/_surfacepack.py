"""The surface part of ``yade.pack``: predicates bounded by a triangulated surface (``inGtsSurface``) or by
planes (``inConvexPolyhedron``), and the builders of surfaces (``sweptPolylines2gtsSurface``,
``revolutionSurfaceMeridians``) and of facets from them (``gtsSurface2Facets``).

Behaviour measured on YADE 2023.02a: ``inGtsSurface(surf)(pt, pad)`` is True when the point and the six
points ``pt +- pad`` along the axes are inside (``noPad=True``: the point only), and refuses an open
surface (ValueError); ``inConvexPolyhedron(planes)`` takes ``(point, normal)`` pairs with the normals
pointing inside and keeps points strictly more than ``pad`` inside every plane (normals normalised);
a revolution meridian point ``(x, y)`` at angle a is ``origin + orientation * (x cos a, x sin a, y)``;
a swept quad between polylines A and B, points j and j+1, is the triangles (A_j, A_j+1, B_j+1) and
(A_j, B_j+1, B_j); a cap is a fan from the polyline's first point p0, (p_j, p0, p_j+1) at the start and
(p0, p_j, p_j+1) at the end, and both caps of a single polyline are one set of faces (the start cap's).
"""

from __future__ import annotations

import math

import numpy as np

from granum.mathtypes import Matrix3, Quaternion, Vector3, as_vec3
from granum.yade import _surface, gts
from granum.yade.pack import Predicate

__all__ = ["gtsSurface2Facets", "inConvexPolyhedron", "inGtsSurface", "revolutionSurfaceMeridians",
           "sweptPolylines2gtsSurface"]

#: the defaults YADE gives (never modified)
_ORIGIN = Vector3(0, 0, 0)
_NO_ROTATION = Quaternion((1, 0, 0), 0)


class inGtsSurface(Predicate):
    """Inside the closed gts surface ``surf``. The surface is read once, when the predicate is made (later
    changes to ``surf`` are not seen, as in YADE). ``noPad``: ignore the padding."""

    def __init__(self, surf, noPad=False):
        if not isinstance(surf, gts.Surface):
            raise TypeError(f"inGtsSurface needs a gts.Surface, not {type(surf).__name__}")
        if not surf.is_closed():
            _, use = surf._edge_use() if surf.Nfaces else (None, np.zeros(0, int))
            raise ValueError(f"Surface is not closed. (inGtsSurface needs a closed surface: of its {len(use)} edges, "
                             f"{int(np.sum(use == 1))} belong to one face only and {int(np.sum(use > 2))} to more "
                             f"than two)")
        self.surf, self.noPad = surf, bool(noPad)
        self._grid = _surface.SurfaceGrid(surf.triangles())

    def _inside(self, pts, pad):
        return self._grid.inside(pts, 0.0 if self.noPad else float(pad))

    def _box(self):
        return self._grid.lo.copy(), self._grid.hi.copy()


class inConvexPolyhedron(Predicate):
    """The intersection of the half-spaces ``(x - point) . normal > 0`` of ``planes``, a list of
    ``(point, normal)`` pairs (normals pointing inside, any length). The polyhedron must be bounded."""

    def __init__(self, planes):
        pts = np.array([as_vec3(p) for p, _ in planes], dtype=np.float64).reshape(-1, 3)
        nrm = np.array([as_vec3(n) for _, n in planes], dtype=np.float64).reshape(-1, 3)
        length = np.linalg.norm(nrm, axis=1)
        if len(planes) < 4 or np.any(length == 0):
            raise ValueError("inConvexPolyhedron: give at least 4 (point, normal) planes with non-zero normals")
        self.n = nrm / length[:, None]
        self.d = np.einsum("ij,ij->i", self.n, pts)
        self._lo, self._hi = self._vertex_box()

    def _vertex_box(self):
        n = self.n
        # unbounded iff a direction v != 0 has n_i . v >= 0 for all planes: such a recession direction is an
        # extreme ray of the cone {n_i . v >= 0} (on two of its planes) or a line in it (normal to all n_i)
        cand = [np.cross(n[i], n[j]) for i in range(len(n)) for j in range(i + 1, len(n))]
        cand += [np.cross(n[0], e) for e in np.eye(3)]
        for v in cand:
            size = np.linalg.norm(v)
            for w in (v / size, -v / size) if size > 1e-12 else ():
                if np.all(n @ w >= -1e-12):
                    raise ValueError(f"inConvexPolyhedron: the planes do not bound a finite volume (unbounded "
                                     f"along {w.round(6).tolist()})")
        corners = []
        for i in range(len(n)):
            for j in range(i + 1, len(n)):
                for k in range(j + 1, len(n)):
                    A = n[[i, j, k]]
                    if abs(np.linalg.det(A)) < 1e-12:
                        continue
                    x = np.linalg.solve(A, self.d[[i, j, k]])
                    if np.all(n @ x >= self.d - 1e-9 * (1 + np.abs(self.d))):
                        corners.append(x)
        if not corners:
            raise ValueError("inConvexPolyhedron: the planes enclose no volume")
        corners = np.array(corners)
        return corners.min(axis=0), corners.max(axis=0)

    def _inside(self, pts, pad):
        return np.all(pts @ self.n.T - self.d > pad, axis=1)

    def _box(self):
        return self._lo.copy(), self._hi.copy()


def gtsSurface2Facets(surf, **kw):
    """One facet per face of the gts surface (``utils.facet(face vertices, **kw)``), in the surface's order."""
    from granum.yade import utils  # lazy: the scene code imports this module

    return [utils.facet([Vector3(*v.coords()) for v in f.vertices()], **kw) for f in surf.faces()]


def sweptPolylines2gtsSurface(pts, threshold=0, capStart=False, capEnd=False):
    """The surface swept between same-length polylines ``pts`` (a list of lists of 3-vectors): each quad between
    polylines i, i+1 and points j, j+1 gives two triangles (a single polyline gives only its caps). With
    ``threshold`` > 0 triangles with an edge shorter than it are left out and vertices closer than it merged
    (``Surface.cleanup``), which closes polylines whose last point is their first. ``capStart``/``capEnd`` close
    the first/last polyline by a fan of triangles from its first point (fine for convex sections)."""
    lines = [[as_vec3(p) for p in line] for line in pts]
    if not lines or len({len(line) for line in lines}) != 1 or len(lines[0]) < 2:
        raise ValueError("sweptPolylines2gtsSurface: give polylines of the same length (>= 2 points)")
    m = len(lines[0])
    xyz = np.array(lines, dtype=np.float64).reshape(-1, 3)
    idx = np.arange(len(xyz)).reshape(len(lines), m)
    tri = []
    for i in range(len(lines) - 1):
        for j in range(m - 1):
            a, a1, b, b1 = idx[i, j], idx[i, j + 1], idx[i + 1, j], idx[i + 1, j + 1]
            tri += [(a, a1, b1), (a, b1, b)]
    if capStart:
        tri += [(idx[0, j], idx[0, 0], idx[0, j + 1]) for j in range(1, m - 1)]
    if capEnd:
        tri += [(idx[-1, 0], idx[-1, j], idx[-1, j + 1]) for j in range(1, m - 1)]
    tri = np.array(tri, dtype=np.int64).reshape(-1, 3)
    # a face made twice (both caps of a single polyline) is kept once, as first made
    _, first = np.unique(np.sort(tri, axis=1), axis=0, return_index=True)
    tri = tri[np.sort(first)]
    if threshold > 0:
        t = xyz[tri]
        shortest = np.min([np.linalg.norm(t[:, k] - t[:, (k + 1) % 3], axis=1) for k in range(3)], axis=0)
        tri = tri[shortest >= threshold]
    surf = gts.Surface()
    surf._set_arrays(xyz, tri)
    if threshold > 0:
        surf.cleanup(threshold)
    return surf


def revolutionSurfaceMeridians(sects, angles, origin=_ORIGIN, orientation=_NO_ROTATION):
    """Meridians of a surface of revolution about z: section k (2D points ``(x, y)``) turned by ``angles[k]``
    [rad] becomes the 3D points ``origin + orientation * (x cos a, x sin a, y)``; a list of lists of Vector3,
    ready for :func:`sweptPolylines2gtsSurface`."""
    if len(sects) != len(angles):
        raise ValueError(f"revolutionSurfaceMeridians: {len(sects)} sections but {len(angles)} angles")
    R = np.asarray(Matrix3(orientation if isinstance(orientation, Quaternion) else Quaternion(orientation)))
    o = as_vec3(origin)
    out = []
    for sect, a in zip(sects, angles, strict=True):
        xy = np.array([(float(p[0]), float(p[1])) for p in sect], dtype=np.float64).reshape(-1, 2)
        local = np.column_stack([xy[:, 0] * math.cos(a), xy[:, 0] * math.sin(a), xy[:, 1]])
        out.append([Vector3(*map(float, p)) for p in o + local @ R.T])
    return out
