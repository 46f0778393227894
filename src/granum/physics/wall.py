"""Wall shape: an infinite axis-aligned plane; bound and wall-sphere geometry.

References:
    YADE documentation, sections 2.2.3.1 (``utils.wall``) and 2.6.3 (oedometric test).
"""

from __future__ import annotations

import math

from granum._jit import jit
from granum.core.shapes import ShapeKind
from granum.physics import registry
from granum.physics.facet import HERTZIAN_RADIUS
from granum.physics.registry import Functor, Param
from granum.physics.scgeom import scgeom_write
from granum.physics.vec import add, load3


@jit
def bound_wall(i, S, prm, out):
    """Aabb of a wall: a single coordinate along its axis, infinite along the others."""
    a = S.wall_axis[S.shape_row[i]]
    for k in range(3):
        if k == a:
            out[k] = S.pos[i, k]
            out[3 + k] = S.pos[i, k]
        else:
            out[k] = -math.inf
            out[3 + k] = math.inf


@jit
def geom_wall_sphere(c, id1, id2, shift, S, C, prm):
    """Wall-sphere ScGeom (body 1 is the wall, body 2 the sphere).

    With the wall at coordinate w on axis a and the sphere centre x: d = x_a - w,
    the normal is +-e_a (towards the sphere, or fixed by the wall's ``sense``),
    delta = r - |d|, and C is the sphere centre projected on the plane. The reference radii are r for
    both (``hertzian``: 1e8 r for the wall, as YADE).
    A wall with ``sense`` = +1 (-1) interacts only with spheres on its positive
    (negative) side. Detection (``c`` < 0) returns the separation |d| - r [m]; a sphere
    on the side the wall ignores must first cross the plane: separation |d|.
    """
    row = S.shape_row[id1]
    a = S.wall_axis[row]
    sense = S.wall_sense[row]
    r = S.sphere_radius[S.shape_row[id2]]
    x = add(load3(S.pos, id2), shift)
    d = x[a] - S.pos[id1, a]
    if c < 0:
        return abs(d) - r if sense == 0 or sense * d >= 0.0 else abs(d)
    if sense != 0:
        side = float(sense)
    else:
        side = 1.0 if d >= 0.0 else -1.0
    n = (side if a == 0 else 0.0, side if a == 1 else 0.0, side if a == 2 else 0.0)
    pen = r - side * d
    point = (S.pos[id1, 0] if a == 0 else x[0], S.pos[id1, 1] if a == 1 else x[1], S.pos[id1, 2] if a == 2 else x[2])
    r1 = HERTZIAN_RADIUS * r if prm[HERTZIAN] != 0.0 else r
    scgeom_write(c, C, n, pen, point, r1, r, prm[NO_RATCH] != 0.0)
    return 0.0


registry.register_functor(Functor(
    "Bo1_Wall_Aabb", "bound", (ShapeKind.WALL,), None, f"{__name__}:bound_wall", (),
    "Axis-aligned bound of a wall (infinite in the plane)."))
IG2_WALL_SCGEOM = Functor(
    "Ig2_Wall_Sphere_ScGeom", "geom", (ShapeKind.WALL, ShapeKind.SPHERE), "ScGeom",
    f"{__name__}:geom_wall_sphere",
    (Param("noRatch", True, "Use reference radii as lever arms in the relative velocity [-]"),
     Param("hertzian", False, "The wall's reference radius (refR1) is 1e8 times the sphere's instead of equal to "
                              "it (closer to Hertz's theory, where it is infinite) [-]")),
    geom_wall_sphere.py_func.__doc__)
registry.register_functor(IG2_WALL_SCGEOM)
#: place of ``noRatch`` in the functor's row ``prm``
NO_RATCH = IG2_WALL_SCGEOM.slot("noRatch")
HERTZIAN = IG2_WALL_SCGEOM.slot("hertzian")
