"""Sphere shape: bound and sphere-sphere contact geometry.

References:
    YADE documentation, section 3.3.1 (sphere-sphere ScGeom), equations (3.3,1)-(3.3,6).
"""

from __future__ import annotations

from granum._jit import jit
from granum.core.shapes import ShapeKind
from granum.physics import registry
from granum.physics.registry import Functor, Param
from granum.physics.scgeom import scgeom_write
from granum.physics.vec import add, load3, norm, scale, sub


@jit
def bound_sphere(i, S, prm, out):
    """Aabb of sphere ``i``: centre +- radius (radius times ``aabbEnlargeFactor`` if > 0)."""
    r = S.sphere_radius[S.shape_row[i]]
    if prm[ENLARGE_FACTOR] > 0.0:
        r *= prm[ENLARGE_FACTOR]
    for k in range(3):
        out[k] = S.pos[i, k] - r
        out[3 + k] = S.pos[i, k] + r


@jit
def sphere_pair(id1, id2, shift, S):
    """Radii r1, r2 [m], centre x1 [m], branch vector d = x2 + shift - x1 [m] and its length [m] of spheres
    id1, id2 (body 2's periodic image shifted by ``shift``): what every sphere-sphere geometry starts from."""
    r1 = S.sphere_radius[S.shape_row[id1]]
    r2 = S.sphere_radius[S.shape_row[id2]]
    p1 = load3(S.pos, id1)
    d = sub(add(load3(S.pos, id2), shift), p1)
    return r1, r2, p1, d, norm(d)


@jit
def geom_sphere_sphere(c, id1, id2, shift, S, C, prm):
    """Sphere-sphere ScGeom.

    .. math::
        \\delta = r_1 + r_2 - |x_2 - x_1|, \\quad n = (x_2 - x_1)/|x_2 - x_1|,
        \\quad C = x_1 + (r_1 - \\delta/2)\\, n

    A potential pair becomes real when |x2 - x1| <= f (r1 + r2), f being
    ``interactionDetectionFactor`` (prm[DETECTION_FACTOR]). Detection (``c`` < 0) returns the
    separation |x2 - x1| - f (r1 + r2) [m] (see the geometry protocol in
    :mod:`granum.physics.registry`); with ``c`` >= 0 the geometry is written and 0 returned.
    """
    r1, r2, p1, d, dist = sphere_pair(id1, id2, shift, S)
    if c < 0:
        return dist - prm[DETECTION_FACTOR] * (r1 + r2)
    pen = r1 + r2 - dist
    n = scale(d, 1.0 / dist)
    scgeom_write(c, C, n, pen, add(p1, scale(n, r1 - 0.5 * pen)), r1, r2, prm[AVOID_RATCHETING] != 0.0)
    return 0.0


BO1_SPHERE = Functor(
    "Bo1_Sphere_Aabb", "bound", (ShapeKind.SPHERE,), None, f"{__name__}:bound_sphere",
    (Param("aabbEnlargeFactor", -1.0, "Scale the radius of the bound by this factor if positive [-]"),),
    "Axis-aligned bound of a sphere.")
registry.register_functor(BO1_SPHERE)
IG2_SPHERE_SCGEOM = Functor(
    "Ig2_Sphere_Sphere_ScGeom", "geom", (ShapeKind.SPHERE, ShapeKind.SPHERE), "ScGeom",
    f"{__name__}:geom_sphere_sphere",
    (Param("interactionDetectionFactor", 1.0,
           "Make the contact real when the distance is below this factor times r1 + r2 [-]"),
     Param("avoidGranularRatcheting", True,
           "Use reference radii as lever arms in the relative velocity (see ScGeom) [-]")),
    geom_sphere_sphere.py_func.__doc__)
registry.register_functor(IG2_SPHERE_SCGEOM)
#: places of the functors' parameters in their rows ``prm``
ENLARGE_FACTOR = BO1_SPHERE.slot("aabbEnlargeFactor")
DETECTION_FACTOR = IG2_SPHERE_SCGEOM.slot("interactionDetectionFactor")
AVOID_RATCHETING = IG2_SPHERE_SCGEOM.slot("avoidGranularRatcheting")
