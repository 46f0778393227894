"""Box shape: an oriented cuboid given by its half-sizes; bound and box-sphere geometry.

References:
    YADE documentation, sections 2.2.3.1 (``utils.box``) and 4.1.5.1.
"""

from __future__ import annotations

import math

from granum._jit import jit
from granum.core.shapes import ShapeKind
from granum.physics import registry
from granum.physics.registry import Functor, Param
from granum.physics.scgeom import scgeom_write
from granum.physics.vec import add, load3, load4, norm, quat_rotate, quat_rotate_inv, scale, sub


@jit
def bound_box(i, S, prm, out):
    """Aabb of box ``i``: centre +- sum over local axes of |R e_k| * extent_k."""
    row = S.shape_row[i]
    q = load4(S.ori, i)
    half = (0.0, 0.0, 0.0)
    for k in range(3):
        axis = (1.0 if k == 0 else 0.0, 1.0 if k == 1 else 0.0, 1.0 if k == 2 else 0.0)
        g = scale(quat_rotate(q, axis), S.box_extents[row, k])
        half = (half[0] + abs(g[0]), half[1] + abs(g[1]), half[2] + abs(g[2]))
    for k in range(3):
        out[k] = S.pos[i, k] - half[k]
        out[3 + k] = S.pos[i, k] + half[k]


@jit
def geom_box_sphere(c, id1, id2, shift, S, C, prm):
    """Box-sphere ScGeom (body 1 is the box, body 2 the sphere).

    In the box frame the point P of the box closest to the sphere centre x is x
    clamped to the extents; n = (x - P)/|x - P| and delta = r - |x - P|. When the
    centre is inside the box the normal is that of the nearest face and
    delta = r + (distance to that face). C = x - (r - delta/2) n; reference radii
    are r for both bodies. Detection (``c`` < 0) returns the separation -delta [m].
    """
    row = S.shape_row[id1]
    q = load4(S.ori, id1)
    e = (S.box_extents[row, 0], S.box_extents[row, 1], S.box_extents[row, 2])
    r = S.sphere_radius[S.shape_row[id2]]
    x = add(load3(S.pos, id2), shift)
    xl = quat_rotate_inv(q, sub(x, load3(S.pos, id1)))
    inside = abs(xl[0]) <= e[0] and abs(xl[1]) <= e[1] and abs(xl[2]) <= e[2]
    if inside:
        k = 0
        depth = e[0] - abs(xl[0])
        for j in range(1, 3):
            dj = e[j] - abs(xl[j])
            if dj < depth:
                k, depth = j, dj
        s = 1.0 if xl[k] >= 0.0 else -1.0
        nl = (s if k == 0 else 0.0, s if k == 1 else 0.0, s if k == 2 else 0.0)
        pen = r + depth
    else:
        pl = (min(max(xl[0], -e[0]), e[0]), min(max(xl[1], -e[1]), e[1]), min(max(xl[2], -e[2]), e[2]))
        d = sub(xl, pl)
        dist = norm(d)
        if c < 0:
            return dist - r
        nl = scale(d, 1.0 / dist)
        pen = r - dist
    if c < 0:
        return -pen
    n = quat_rotate(q, nl)
    scgeom_write(c, C, n, pen, sub(x, scale(n, r - 0.5 * pen)), r, r, False)
    return 0.0


@jit
def reach_box(row, S):
    """Reach of box ``row``: half its diagonal, |extents| [m]."""
    e = S.box_extents[row]
    return math.sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2])


registry.register_reach(ShapeKind.BOX, f"{__name__}:reach_box")
registry.register_functor(Functor(
    "Bo1_Box_Aabb", "bound", (ShapeKind.BOX,), None, f"{__name__}:bound_box", (),
    "Axis-aligned bound of an oriented box."))
registry.register_functor(Functor(
    "Ig2_Box_Sphere_ScGeom", "geom", (ShapeKind.BOX, ShapeKind.SPHERE), "ScGeom",
    f"{__name__}:geom_box_sphere",
    (Param("interactionDetectionFactor", 1.0, "Make the contact real closer than this factor (accepted)",
           supported=False),),
    geom_box_sphere.py_func.__doc__))
