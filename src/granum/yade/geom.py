"""YADE's ``yade.geom``: bodies made of facets.

Every surface is built in a local frame (axis along z), as triangles listed in YADE 2023.02a's order, then
placed by ``center`` and ``orientation`` and made into ``utils.facet`` bodies (other keywords go to
``utils.facet``). Most surfaces are strips of triangles between two polylines (:func:`_strip`): a
cylinder's side between its top and bottom circles, a cap between a circle and its centre or inner circle,
a helix between its inner and outer edges, a sphere's bands between two parallels. The vertex order of each
triangle (which decides its normal) is YADE's, measured on real YADE (``tests/reference/yade/geom.py``).
"""

from __future__ import annotations

import math

import numpy as np

from granum.mathtypes import Quaternion, as_quat_wxyz, as_vec3
from granum.yade import utils

__all__ = ["facetBox", "facetBunker", "facetCone", "facetCylinder", "facetCylinderConeGenerator", "facetHelix",
           "facetParallelepiped", "facetPolygon", "facetPolygonHelixGenerator", "facetSphere"]


class GeomError(ValueError, RuntimeError):
    """A refused argument of a ``geom`` function (YADE raises RuntimeError for these)."""


# Triangles of one segment of a strip, as (polyline, offset) per vertex: segment i uses points i and i + 1
# of each polyline. The names say where YADE uses each pattern.
_CAP_TOP = (((0, 0), (1, 1), (1, 0)),)                    # (centre, circle): centre, p[i+1], p[i]
_CAP_BOTTOM = (((0, 0), (1, 0), (1, 1)),)                 # (centre, circle): centre, p[i], p[i+1]
_CAP_RING = (((0, 0), (1, 1), (1, 0)), ((0, 0), (0, 1), (1, 1)))   # (outer, inner circle)
_SIDE = (((0, 1), (1, 1), (1, 0)), ((1, 0), (0, 0), (0, 1)))       # (top, bottom circle)
_HELIX_RING = (((0, 0), (1, 0), (1, 1)), ((0, 1), (0, 0), (1, 1)))  # (inner, outer edge)
_HELIX_FAN = (((0, 1), (1, 1), (1, 0)),)                  # (axis, outer edge)
_BAND_FIRST = (((0, 0), (0, 1), (1, 0)),)                 # sphere (upper, lower parallel)
_BAND_SECOND = (((1, 0), (1, 1), (0, 1)),)


def _strip(pattern, *lines) -> np.ndarray:
    """Triangles between polylines: ``lines`` are m + 1 points each, (m+1, 3) float, or m + 1 node indices,
    (m+1,) int; returns (m, len(pattern), 3, 3) points or (m, len(pattern), 3) indices, segment by segment."""
    m = len(lines[0]) - 1
    return np.stack([np.stack([lines[line][off:off + m] for line, off in tri], axis=1) for tri in pattern], axis=1)


def _axis_line(z, m: int) -> np.ndarray:
    """m + 1 points on the z axis at heights ``z`` (a number or (m+1,)), (m+1, 3)."""
    out = np.zeros((m + 1, 3))
    out[:, 2] = z
    return out


def _arc(radius: float, angles: np.ndarray, z) -> np.ndarray:
    """Points at ``angles`` [rad] on the circle of ``radius`` [m] about the z axis, at heights ``z``, (m+1, 3)."""
    return np.stack([radius * np.cos(angles), radius * np.sin(angles), np.broadcast_to(z, angles.shape)], axis=1)


def _check(fname: str, ok: bool, message: str) -> None:
    if not ok:
        raise GeomError(f"{fname}: {message}")


def _segments(fname: str, segmentsNumber, minimum: int = 3) -> int:
    n = int(segmentsNumber)
    _check(fname, n == segmentsNumber and n >= minimum, f"segmentsNumber must be an integer >= {minimum}, "
                                                         f"got {segmentsNumber!r}")
    return n


def _angles(fname: str, angleRange, n: int, helix: bool = False) -> np.ndarray:
    """The n + 1 angles [rad] of n equal segments of ``angleRange`` (None: a full turn), (n+1,). A cylinder's
    range increases and spans at most a turn; a helix's or polygon's may go either way and turn many times
    (YADE 2023.02a)."""
    a0, a1 = (0.0, 2 * math.pi) if angleRange is None else (float(angleRange[0]), float(angleRange[1]))
    if not helix:
        _check(fname, a1 >= a0, f"angleRange must be increasing, got {angleRange!r}")
        _check(fname, a1 - a0 <= 2 * math.pi, f"angleRange may span at most 2*pi, got {angleRange!r}")
    return a0 + np.arange(n + 1) * ((a1 - a0) / n)


def _place(triangles: np.ndarray, center, orientation) -> np.ndarray:
    """Local triangles (N, 3, 3) to global ones: center + orientation * vertex."""
    q = Quaternion(*as_quat_wxyz(orientation)) if orientation is not None else Quaternion(1, 0, 0, 0)
    rot = np.asarray(q.toRotationMatrix()._a)
    return triangles @ rot.T + as_vec3(center)


def _facets(triangles: np.ndarray, kw: dict) -> list:
    return [utils.facet([tuple(v) for v in tri], **kw) for tri in triangles]


def _cylinder_cone(radius_top: float, radius_bottom: float, height: float, angles: np.ndarray, wall_mask: int,
                   close_gap: bool, inner_top: float, inner_bottom: float, z_mid: float = 0.0) -> np.ndarray:
    """Local triangles (N, 3, 3) of a truncated cone about the z axis, from z_mid - height/2 (radius_bottom)
    to z_mid + height/2 (radius_top), in YADE's order: per segment its top cap (wall_mask bit 0), bottom cap
    (bit 1) and side (bit 2); a cap with an inner radius > 0 is a ring. ``close_gap`` then closes an open
    angle range: over less than pi by a wedge through the axis (with the side only), otherwise by the chord
    plane (with the side) and a triangle on each cap present. A flat one (height 0) is one disc with the
    top cap's vertex order, made if either cap is asked for."""
    m = len(angles) - 1
    zt, zb = z_mid + height / 2, z_mid - height / 2
    top, bottom = _arc(radius_top, angles, zt), _arc(radius_bottom, angles, zb)
    centre_top, centre_bottom = _axis_line(zt, m), _axis_line(zb, m)
    if height == 0:
        wall_mask = 1 if wall_mask & 3 else 0
    walls = []
    if wall_mask & 1:
        walls.append(_strip(_CAP_RING, top, _arc(inner_top, angles, zt)) if inner_top > 0
                     else _strip(_CAP_TOP, centre_top, top))
    if wall_mask & 2:
        walls.append(_strip(_CAP_RING, bottom, _arc(inner_bottom, angles, zb)) if inner_bottom > 0
                     else _strip(_CAP_BOTTOM, centre_bottom, bottom))
    if wall_mask & 4:
        walls.append(_strip(_SIDE, top, bottom))
    tris = [np.concatenate(walls, axis=1).reshape(-1, 3, 3)] if walls else []
    if close_gap:
        t0, tn, b0, bn, ct, cb = top[0], top[-1], bottom[0], bottom[-1], centre_top[0], centre_bottom[0]
        if angles[-1] - angles[0] >= math.pi:
            close = ([(t0, tn, ct)] if wall_mask & 1 else []) + ([(cb, bn, b0)] if wall_mask & 2 else []) \
                + ([(b0, bn, t0), (bn, tn, t0)] if wall_mask & 4 else [])
        else:
            close = [(b0, cb, t0), (cb, ct, t0), (cb, bn, ct), (bn, tn, ct)] if wall_mask & 4 else []
        tris.append(np.array(close).reshape(-1, 3, 3))
    return np.concatenate(tris) if tris else np.zeros((0, 3, 3))


def _positive(fname: str, name: str, value, zero_ok: bool = False) -> float:
    v = float(value)
    _check(fname, v >= 0 if zero_ok else v > 0,
           f"{name} must be {'>= 0' if zero_ok else 'positive'}, got {value!r}")
    return v


def _inner(fname: str, name: str, inner, outer: float) -> float:
    """An inner radius: -1 (YADE's default) or any negative value means none (0)."""
    v = float(inner)
    _check(fname, v <= outer, f"{name} ({inner!r}) must not exceed the outer radius ({outer!r})")
    return max(v, 0.0)


def facetCylinderConeGenerator(center, radiusTop, height, orientation=None, segmentsNumber=10, wallMask=7,
                               angleRange=None, closeGap=False, radiusBottom=-1, radiusTopInner=-1,
                               radiusBottomInner=-1, **kw):
    """Facets of a cylinder (``radiusBottom`` -1: radiusTop) or truncated cone about the local z axis,
    ``height`` [m] long and centred on ``center``; the base of :func:`facetCylinder` and :func:`facetCone`.

    ``wallMask``: bit 0 the top cap, 1 the bottom cap, 2 the side; ``angleRange`` (min, max) [rad] makes
    part of it (None: a full turn) and ``closeGap`` closes the rest; ``radiusTopInner``/``radiusBottomInner``
    [m] make the caps rings (-1: full discs). YADE's order and vertex order (see :func:`_cylinder_cone`).
    """
    fname = "facetCylinderConeGenerator"
    n = _segments(fname, segmentsNumber)
    r_top = _positive(fname, "radius", radiusTop)
    r_bottom = r_top if radiusBottom == -1 else _positive(fname, "radiusBottom", radiusBottom)
    h = _positive(fname, "height", height, zero_ok=True)
    angles = _angles(fname, angleRange, n)
    tris = _cylinder_cone(r_top, r_bottom, h, angles, int(wallMask), bool(closeGap),
                          _inner(fname, "radiusTopInner", radiusTopInner, r_top),
                          _inner(fname, "radiusBottomInner", radiusBottomInner, r_bottom))
    return _facets(_place(tris, center, orientation), kw)


def facetCylinder(center, radius, height, orientation=None, segmentsNumber=10, wallMask=7, angleRange=None,
                  closeGap=False, radiusTopInner=-1, radiusBottomInner=-1, **kw):
    """Facets of a cylinder of ``radius`` and ``height`` [m] centred on ``center``, axis along the local z
    (``orientation`` turns it); ``wallMask`` bit 0 top, 1 bottom, 2 side (7: all). See
    :func:`facetCylinderConeGenerator` for the other arguments."""
    return facetCylinderConeGenerator(center, radius, height, orientation, segmentsNumber, wallMask, angleRange,
                                      closeGap, radius, radiusTopInner, radiusBottomInner, **kw)


def facetCone(center, radiusTop, radiusBottom, height, orientation=None, segmentsNumber=10, wallMask=7,
              angleRange=None, closeGap=False, radiusTopInner=-1, radiusBottomInner=-1, **kw):
    """Facets of a truncated cone (radii [m] at z = +height/2 and -height/2 of the local frame); see
    :func:`facetCylinderConeGenerator`."""
    return facetCylinderConeGenerator(center, radiusTop, height, orientation, segmentsNumber, wallMask,
                                      angleRange, closeGap, radiusBottom, radiusTopInner, radiusBottomInner, **kw)


def facetBunker(center, dBunker, dOutput, hBunker, hOutput, hPipe=0.0, orientation=None, segmentsNumber=10,
                wallMask=4, angleRange=None, closeGap=False, **kw):
    """Facets of a bunker standing on ``center`` along the local z: a pipe of diameter ``dOutput`` and
    height ``hPipe``, a cone widening to ``dBunker`` over ``hOutput``, then a cylinder of diameter
    ``dBunker`` and height ``hBunker`` [m]. ``wallMask`` bit 2 makes the sides (the default), bit 1 the
    pipe's bottom, bit 0 the cylinder's top; a part of zero height is a flat disc if it has a cap, else nothing
    (YADE's construction: three :func:`facetCylinderConeGenerator` parts)."""
    fname = "facetBunker"
    n = _segments(fname, segmentsNumber)
    r_bunker = _positive(fname, "dBunker", dBunker) / 2
    r_output = _positive(fname, "dOutput", dOutput) / 2
    parts = [(_positive(fname, "hPipe", hPipe, zero_ok=True), r_output, r_output),
             (_positive(fname, "hOutput", hOutput, zero_ok=True), r_bunker, r_output),
             (_positive(fname, "hBunker", hBunker, zero_ok=True), r_bunker, r_bunker)]
    angles = _angles(fname, angleRange, n)
    mask, z, tris = int(wallMask), 0.0, []
    for (h, r_top, r_bottom), part_mask in zip(parts, (mask & 6, mask & 4, mask & 5), strict=True):
        tris.append(_cylinder_cone(r_top, r_bottom, h, angles, part_mask, bool(closeGap), 0.0, 0.0, z_mid=z + h / 2))
        z += h
    return _facets(_place(np.concatenate(tris), center, orientation), kw)


def facetPolygonHelixGenerator(center, radiusOuter, pitch=0, orientation=None, segmentsNumber=10,
                               angleRange=None, radiusInner=0, **kw):
    """Facets of a flat ring or disc (``pitch`` 0) or of a helical ramp rising ``pitch`` [m] per turn along
    the local z, from ``radiusInner`` (0: the axis) to ``radiusOuter`` [m], over ``angleRange`` (None: one
    turn); the base of :func:`facetPolygon` and :func:`facetHelix`."""
    fname = "facetPolygonHelixGenerator"
    return _facets(_place(_polygon_helix(fname, radiusOuter, float(pitch), segmentsNumber, angleRange,
                                         radiusInner), center, orientation), kw)


def _polygon_helix(fname, radiusOuter, pitch, segmentsNumber, angleRange, radiusInner) -> np.ndarray:
    """Local triangles (N, 3, 3) of :func:`facetPolygonHelixGenerator`: two per segment between the inner and
    outer edges, or one between the axis and the outer edge when radiusInner is 0."""
    n = _segments(fname, segmentsNumber)
    r_out = _positive(fname, "radiusOuter", radiusOuter)
    r_in = _positive(fname, "radiusInner", radiusInner, zero_ok=True)
    angles = _angles(fname, angleRange, n, helix=True)
    z = pitch * np.abs(angles - angles[0]) / (2 * math.pi)  # rising whichever way it turns
    outer = _arc(r_out, angles, z)
    tris = _strip(_HELIX_RING, _arc(r_in, angles, z), outer) if r_in > 0 else _strip(_HELIX_FAN, _axis_line(z, n),
                                                                                       outer)
    return tris.reshape(-1, 3, 3)


def facetPolygon(center, radiusOuter, orientation=None, segmentsNumber=10, angleRange=None, radiusInner=0, **kw):
    """Facets of a flat regular polygon (``radiusInner`` 0) or polygonal ring in the local xy plane.
    ``angleRange`` None is a full turn (as documented; YADE 2023.02a raises TypeError there)."""
    return _facets(_place(_polygon_helix("facetPolygon", radiusOuter, 0.0, segmentsNumber, angleRange,
                                         radiusInner), center, orientation), kw)


def facetHelix(center, radiusOuter, pitch, orientation=None, segmentsNumber=10, angleRange=None, radiusInner=0,
               **kw):
    """Facets of a helical ramp (a screw's flight) rising ``pitch`` > 0 [m] per turn along the local z."""
    _positive("facetHelix", "pitch", pitch)
    return _facets(_place(_polygon_helix("facetHelix", radiusOuter, float(pitch), segmentsNumber, angleRange,
                                         radiusInner), center, orientation), kw)


def facetSphere(center, radius, thetaResolution=8, phiResolution=8, returnElementMap=False, **kw):
    """Facets of a sphere (a UV sphere): ``phiResolution`` parallels from pole to pole (poles included),
    ``thetaResolution`` meridians. With ``returnElementMap`` also the nodes (global points) and the elements
    (triples of node indices), as YADE: ``(facets, nodes, elements)``."""
    fname = "facetSphere"
    n_theta = _segments(fname, thetaResolution)
    n_phi = _segments(fname, phiResolution)
    r = _positive(fname, "radius", radius)
    theta = 2 * math.pi * np.arange(n_theta) / n_theta
    phi = math.pi * np.arange(1, n_phi - 1) / (n_phi - 1)
    rings = np.stack([r * np.outer(np.sin(phi), np.cos(theta)), r * np.outer(np.sin(phi), np.sin(theta)),
                      r * np.repeat(np.cos(phi)[:, None], n_theta, axis=1)], axis=2).reshape(-1, 3)
    nodes = np.concatenate([[(0.0, 0.0, r)], rings, [(0.0, 0.0, -r)]]) + as_vec3(center)
    idx = 1 + np.arange(len(rings)).reshape(n_phi - 2, n_theta)   # node index of each ring point
    top, bottom = np.zeros(n_theta, int), np.full(n_theta, len(nodes) - 1)
    # each closed ring is a strip over its first n_theta points, then one closing triangle in YADE's order
    parts = [_strip(_CAP_BOTTOM, top, idx[0]), [(0, idx[0, 0], idx[0, -1])]]
    for a, b in zip(idx[:-1], idx[1:], strict=True):
        parts += [_strip(_BAND_FIRST, a, b), [(a[0], a[-1], b[-1])],
                  _strip(_BAND_SECOND, a, b), [(b[-1], b[0], a[0])]]
    parts += [_strip(_CAP_TOP, bottom, idx[-1])[::-1], [(bottom[0], idx[-1, -1], idx[-1, 0])]]
    elements = np.concatenate([np.asarray(p).reshape(-1, 3) for p in parts])
    facets = _facets(nodes[elements], kw)
    if returnElementMap:
        return facets, [tuple(float(x) for x in p) for p in nodes], [tuple(int(i) for i in e) for e in elements]
    return facets


# Corners of a box by signs (x, y, z); each face is two triangles, in YADE's face order -x, +x, -y, +y, -z, +z
# (bit k of wallMask).
_FACES = (
    (((-1, -1, -1), (-1, 1, -1), (-1, 1, 1)), ((-1, -1, -1), (-1, 1, 1), (-1, -1, 1))),
    (((1, -1, -1), (1, -1, 1), (1, 1, 1)), ((1, -1, -1), (1, 1, 1), (1, 1, -1))),
    (((-1, -1, -1), (-1, -1, 1), (1, -1, 1)), ((-1, -1, -1), (1, -1, 1), (1, -1, -1))),
    (((-1, 1, -1), (1, 1, -1), (1, 1, 1)), ((-1, 1, -1), (1, 1, 1), (-1, 1, 1))),
    (((-1, -1, -1), (1, -1, -1), (1, 1, -1)), ((-1, -1, -1), (1, 1, -1), (-1, 1, -1))),
    (((-1, -1, 1), (-1, 1, 1), (1, 1, 1)), ((-1, -1, 1), (1, 1, 1), (1, -1, 1))),
)
_SIGNS = np.array(_FACES, dtype=float)  # (6 faces, 2 triangles, 3 corners, 3 signs)


def _hexahedron(fname: str, half: np.ndarray, shear: float, wallMask, center, orientation, kw) -> list:
    """Facets of the faces selected by ``wallMask`` of the hexahedron whose corner of signs s is
    (half * s) shifted by ``shear`` [m] along x on the +z face. A face with a zero side is left out, and so is
    the + face of an axis of zero extent (it would repeat the - face), as YADE does."""
    _check(fname, 0 <= int(wallMask) <= 63, f"wallMask must be in 0..63, got {wallMask!r}")
    local = _SIGNS * half
    local[..., 0] += shear * (_SIGNS[..., 2] > 0)
    keep = [k for k in range(6) if wallMask >> k & 1 and np.all(np.delete(half, k // 2) != 0)
            and (half[k // 2] != 0 or k % 2 == 0)]
    return _facets(_place(local[keep].reshape(-1, 3, 3), center, orientation), kw)


def facetBox(center, extents, orientation=None, wallMask=63, **kw):
    """Facets of the box ``center`` +- ``extents`` (half-sizes), two per face, YADE's vertex order.

    ``wallMask`` selects the faces: bit 0 -x, 1 +x, 2 -y, 3 +y, 4 -z, 5 +z (31: open top).
    ``orientation`` rotates the box about its centre; other keywords go to ``utils.facet``.
    """
    return _hexahedron("facetBox", as_vec3(extents), 0.0, wallMask, center, orientation, kw)


def facetParallelepiped(center, extents, height, orientation=None, wallMask=63, **kw):
    """Facets of a parallelepiped (YADE's construction): its -z face is the rectangle +-extents[0] x
    +-extents[1] at z = -height, its +z face the same rectangle at z = +height, shifted along x by
    sqrt(extents[2]^2 - height^2) [m] (0 <= height <= extents[2]). ``wallMask`` as :func:`facetBox`."""
    e = as_vec3(extents)
    h = float(height)
    _check("facetParallelepiped", 0 <= h <= e[2], f"height must be in [0, extents[2]], got height={height!r} "
                                                  f"with extents[2]={e[2]!r}")
    return _hexahedron("facetParallelepiped", np.array([e[0], e[1], h]), math.sqrt(e[2] ** 2 - h ** 2), wallMask,
                       center, orientation, kw)
