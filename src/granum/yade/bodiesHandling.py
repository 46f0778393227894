"""YADE's ``yade.bodiesHandling``: extents of sphere packs and facet sets, moving and copying spheres.

Bodies are given as ids or as :class:`~granum.yade.bodies.Body` objects; ``mask``
keeps those whose mask shares a bit with it (-1: all). Lengths are in metres.
"""

from __future__ import annotations

import math

import numpy as np

from granum.core.shapes import ShapeKind
from granum.mathtypes import Vector3, as_quat_wxyz, as_vec3
from granum.yade.formulas import rotate
from granum.yade.omega import O

__all__ = ["spheresPackDimensions", "facetsDimensions", "spheresModify", "sphereDuplicate"]


def _ids(bodies) -> np.ndarray:
    """Body ids of a list of ids and/or Body objects, as an int array (K,)."""
    return np.array([b if isinstance(b, int | np.integer) else b.id for b in bodies], dtype=np.int64)


def _of_kind(bodies, kind: ShapeKind, mask: int) -> np.ndarray:
    """The ids among ``bodies`` that are live bodies of shape ``kind`` whose mask passes."""
    b = O._scene.bodies
    ids = _ids(bodies)
    ids = ids[(ids >= 0) & (ids < b.count)]
    keep = b.alive[ids] & (b.shape_kind[ids] == kind)
    if mask != -1:
        keep &= (b.mask[ids] & mask) != 0
    return ids[keep]


def _extents(lo: np.ndarray, hi: np.ndarray, ids: np.ndarray) -> dict:
    """The YADE dictionary of a bounding box from per-item lower/upper corners (K, 3)."""
    mn, mx = lo.min(axis=0), hi.max(axis=0)
    return {"max": Vector3(*mx), "min": Vector3(*mn),
            "maxId": Vector3(*ids[np.argmax(hi, axis=0)].astype(float)),
            "minId": Vector3(*ids[np.argmin(lo, axis=0)].astype(float)),
            "center": Vector3(*(0.5 * (mn + mx))), "extends": Vector3(*(mx - mn))}


def _refuse_empty(bodies) -> None:
    if len(bodies) == 0:  # YADE 2023.02a raises this very warning class for an empty list
        raise RuntimeWarning("Only a list of particles with length > 1 can be analyzed")


def spheresPackDimensions(idSpheres=(), mask=-1) -> dict:
    """Bounding box of the spheres among ``idSpheres`` (other shapes are skipped), with their totals.

    Keys: ``min``, ``max`` (corners, radii included) [m], ``minId``, ``maxId`` (per axis,
    the sphere reaching the corner), ``center``, ``extends`` (sizes) [m], ``volume``
    [m^3], ``mass`` [kg], ``number``. An empty list raises RuntimeWarning, as in YADE.
    """
    _refuse_empty(idSpheres)
    ids = _of_kind(idSpheres, ShapeKind.SPHERE, mask)
    s = O._scene
    r = s.shapes[ShapeKind.SPHERE].radius[s.bodies.shape_row[ids]]
    p = s.bodies.pos[ids]
    out = _extents(p - r[:, None], p + r[:, None], ids)
    out.update(volume=float((4.0 / 3.0 * math.pi * r ** 3).sum()), mass=float(s.bodies.mass[ids].sum()),
               number=int(ids.size))
    return out


def facetsDimensions(idFacets=(), mask=-1) -> dict:
    """Bounding box of the vertices of facets ``idFacets``: keys as :func:`spheresPackDimensions`
    without volume and mass. A body that is not a facet raises TypeError."""
    _refuse_empty(idFacets)
    s = O._scene
    ids = _ids(idFacets)
    wrong = ids[s.bodies.shape_kind[ids] != ShapeKind.FACET]
    if wrong.size:
        raise TypeError(f"facetsDimensions: body {int(wrong[0])} is not a Facet")
    ids = _of_kind(ids, ShapeKind.FACET, mask)
    local = s.shapes[ShapeKind.FACET].vertices[s.bodies.shape_row[ids]]  # (K, 3 vertices, 3)
    ori = np.repeat(s.bodies.ori[ids], 3, axis=0)
    v = s.bodies.pos[ids][:, None, :] + rotate(ori, local.reshape(-1, 3)).reshape(-1, 3, 3)
    out = _extents(v.min(axis=1), v.max(axis=1), ids)
    out["number"] = int(ids.size)
    return out


def sphereDuplicate(idSphere):
    """A new, detached sphere like body ``idSphere`` (position, radius, material, colour, mask,
    mass, inertia, blocked DOFs); False if that body is not a sphere. Append it to O.bodies."""
    from granum.yade.utils import sphere

    b = O.bodies[idSphere]
    if O._scene.bodies.shape_kind[idSphere] != ShapeKind.SPHERE:
        return False
    copy = sphere(b.state.pos, b.shape.radius, color=b.shape.color, material=b.material, mask=b.mask)
    copy.state.mass = b.state.mass
    copy.state.inertia = b.state.inertia
    copy.state.blockedDOFs = b.state.blockedDOFs
    return copy


def spheresModify(idSpheres=(), mask=-1, shift=(0.0, 0.0, 0.0), scale=1.0, orientation=None,
                  copy=False):
    """Rotate by ``orientation``, scale by ``scale`` about the centre of their bounding box, then shift
    by ``shift`` [m] the spheres among ``idSpheres`` (all spheres whose mask passes if empty).

    ``orientation`` (a Quaternion; None: no rotation) turns the positions only.
    Radii scale too; masses by scale^3 and inertias by scale^5.
    With ``copy`` the bodies are left alone and modified detached copies are returned
    (to append to O.bodies); otherwise returns True.
    """
    s = O._scene
    if len(idSpheres) == 0:
        idSpheres = np.nonzero(s.bodies.alive[:s.bodies.count])[0]
    ids = _of_kind(idSpheres, ShapeKind.SPHERE, mask)
    if ids.size == 0:
        return [] if copy else True
    center = np.asarray(spheresPackDimensions(ids)["center"]._a)
    rel = s.bodies.pos[ids] - center
    if orientation is not None:
        rel = rotate(np.broadcast_to(as_quat_wxyz(orientation), (ids.size, 4)), rel)
    pos = center + scale * rel + as_vec3(shift)
    targets = [sphereDuplicate(int(i)) for i in ids] if copy else [O.bodies[int(i)] for i in ids]
    for b, p in zip(targets, pos, strict=True):
        b.state.pos = p
        b.shape.radius = b.shape.radius * scale
        b.state.mass = b.state.mass * scale ** 3
        b.state.inertia = np.asarray(b.state.inertia._a) * scale ** 5
    return targets if copy else True
