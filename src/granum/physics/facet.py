"""Facet (triangle) shape: bound and facet-sphere contact geometry.

A facet is stored by its three vertices relative to the body position (YADE places
the body at the centre of the inscribed circle) in the body's local frame.

References:
    YADE documentation, sections 2.2.3.1 (``utils.facet``) and 4.1.3 (facets);
    C. Ericson, *Real-Time Collision Detection* (2005), section 5.1.5 (closest point
    on a triangle).
"""

from __future__ import annotations

import math

from granum._jit import jit
from granum.core.shapes import ShapeKind
from granum.physics import registry
from granum.physics.registry import Functor, Param
from granum.physics.scgeom import scgeom_write
from granum.physics.vec import add, dot, load3, load4, norm, quat_rotate, scale, sub

#: a flat body's reference radius in sphere radii with ``hertzian`` (YADE's: nearly infinite, finite for R*)
HERTZIAN_RADIUS = 1e8


@jit
def facet_vertex(i, k, S):
    """Global position of vertex ``k`` of facet body ``i`` [m]."""
    row = S.shape_row[i]
    v = (S.facet_vertices[row, k, 0], S.facet_vertices[row, k, 1], S.facet_vertices[row, k, 2])
    return add(load3(S.pos, i), quat_rotate(load4(S.ori, i), v))


@jit
def closest_point_triangle(p, a, b, c):
    """Point of triangle (a, b, c) closest to ``p``, by Voronoi regions of the triangle."""
    ab = sub(b, a)
    ac = sub(c, a)
    ap = sub(p, a)
    d1 = dot(ab, ap)
    d2 = dot(ac, ap)
    if d1 <= 0.0 and d2 <= 0.0:
        return a
    bp = sub(p, b)
    d3 = dot(ab, bp)
    d4 = dot(ac, bp)
    if d3 >= 0.0 and d4 <= d3:
        return b
    vc = d1 * d4 - d3 * d2
    if vc <= 0.0 and d1 >= 0.0 and d3 <= 0.0:
        return add(a, scale(ab, d1 / (d1 - d3)))
    cp = sub(p, c)
    d5 = dot(ab, cp)
    d6 = dot(ac, cp)
    if d6 >= 0.0 and d5 <= d6:
        return c
    vb = d5 * d2 - d1 * d6
    if vb <= 0.0 and d2 >= 0.0 and d6 <= 0.0:
        return add(a, scale(ac, d2 / (d2 - d6)))
    va = d3 * d6 - d5 * d4
    if va <= 0.0 and d4 - d3 >= 0.0 and d5 - d6 >= 0.0:
        return add(b, scale(sub(c, b), (d4 - d3) / ((d4 - d3) + (d5 - d6))))
    inv = 1.0 / (va + vb + vc)
    return add(a, add(scale(ab, vb * inv), scale(ac, vc * inv)))


@jit
def bound_facet(i, S, prm, out):
    """Aabb of facet ``i``: the box spanned by its three vertices."""
    for k in range(3):
        out[k] = math.inf
        out[3 + k] = -math.inf
    for v in range(3):
        x = facet_vertex(i, v, S)
        for k in range(3):
            out[k] = min(out[k], x[k])
            out[3 + k] = max(out[3 + k], x[k])


@jit
def geom_facet_sphere(c, id1, id2, shift, S, C, prm):
    """Facet-sphere ScGeom (body 1 is the facet, body 2 the sphere).

    The contact is with the point P of the triangle closest to the sphere centre x:
    on the face (n is the facet normal, turned towards the sphere), on an edge or
    on a vertex (n = (x - P)/|x - P|). delta = r - |x - P|,
    C = x - (r - delta/2) n. The reference radii are 2r (facet; ``hertzian``: 1e8 r, the flat surface of
    Hertz's theory, as YADE) and r (sphere).
    Detection (``c`` < 0) returns the separation |x - P| - r [m] (|distance to the plane| - r
    when that already exceeds r).
    """
    r = S.sphere_radius[S.shape_row[id2]]
    x = add(load3(S.pos, id2), shift)
    row = S.shape_row[id1]
    q = load4(S.ori, id1)
    nf = quat_rotate(q, (S.facet_normal[row, 0], S.facet_normal[row, 1], S.facet_normal[row, 2]))
    plane_dist = dot(sub(x, load3(S.pos, id1)), nf)
    if c < 0 and abs(plane_dist) > r:
        return abs(plane_dist) - r
    p = closest_point_triangle(x, facet_vertex(id1, 0, S), facet_vertex(id1, 1, S), facet_vertex(id1, 2, S))
    d = sub(x, p)
    dist = norm(d)
    if c < 0:
        return dist - r
    if dist > 0.0:
        n = scale(d, 1.0 / dist)
    else:
        n = nf
    pen = r - dist
    r1 = HERTZIAN_RADIUS * r if prm[HERTZIAN] != 0.0 else 2.0 * r
    scgeom_write(c, C, n, pen, sub(x, scale(n, r - 0.5 * pen)), r1, r, False)
    return 0.0


@jit
def reach_facet(row, S):
    """Reach of facet ``row``: the largest distance from the body position to a vertex [m]."""
    r = 0.0
    for k in range(3):
        r = max(r, math.sqrt(S.facet_vertices[row, k, 0] ** 2 + S.facet_vertices[row, k, 1] ** 2
                             + S.facet_vertices[row, k, 2] ** 2))
    return r


registry.register_reach(ShapeKind.FACET, f"{__name__}:reach_facet")
registry.register_functor(Functor(
    "Bo1_Facet_Aabb", "bound", (ShapeKind.FACET,), None, f"{__name__}:bound_facet", (),
    "Axis-aligned bound of a facet."))
IG2_FACET_SCGEOM = Functor(
    "Ig2_Facet_Sphere_ScGeom", "geom", (ShapeKind.FACET, ShapeKind.SPHERE), "ScGeom",
    f"{__name__}:geom_facet_sphere",
    (Param("shrinkFactor", 0.0, "Shrink the facet for the contact test (accepted)", supported=False),
     Param("hertzian", False, "The facet's reference radius (refR1) is 1e8 times the sphere's instead of twice it "
                              "(closer to Hertz's theory, where it is infinite) [-]")),
    geom_facet_sphere.py_func.__doc__)
registry.register_functor(IG2_FACET_SCGEOM)
#: place of ``hertzian`` in the functor's row ``prm``
HERTZIAN = IG2_FACET_SCGEOM.slot("hertzian")
