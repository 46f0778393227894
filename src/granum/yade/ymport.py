"""``yade.ymport``: particles and surfaces from files, as lists of bodies (YADE 2023.02a's functions).

Each function reads the whole file (:mod:`granum.io.meshfiles`), transforms the coordinates with
NumPy, makes every body with ``utils.facet``/``utils.sphere`` and only then returns the list, so a bad
file raises (naming the file and the line or triangle) before anything reaches the scene.
``textClumps``, which adds its clumps to ``O.bodies`` itself as in YADE, makes all spheres first.

Coordinates become ``scale * x + shift`` (``gmsh`` and ``textClumps``: ``orientation * (scale * x) +
shift``). Facet vertices keep the file's order, facets the file's order of triangles.

Deviations from YADE 2023.02a, where YADE's result is plainly a bug: YADE's ``ymport.gts`` returns
None (granum: the list of facets its documentation promises); YADE's readers of STL files return
garbage or a shorter list for a malformed or truncated file (granum raises).
"""

from __future__ import annotations

import numpy as np

from granum.io import meshfiles
from granum.mathtypes import Matrix3, Quaternion, Vector3, as_vec3

__all__ = ["gmsh", "gts", "stl", "text", "textClumps", "textExt", "textFacets", "unv"]

#: the defaults YADE gives (never modified)
_ORIGIN = Vector3(0, 0, 0)
_NO_ROTATION = Quaternion((1, 0, 0), 0)


def _place(points, shift, scale, orientation=None) -> np.ndarray:
    """``orientation * (scale * points) + shift`` for points (..., 3) [m]."""
    p = float(scale) * np.asarray(points, dtype=np.float64)
    if orientation is not None:
        p = p @ np.asarray(Matrix3(orientation if isinstance(orientation, Quaternion) else Quaternion(orientation))).T
    return p + as_vec3(shift)


def _facets(tri, kw) -> list:
    from granum.yade import utils  # lazy: the scene code imports this module

    return [utils.facet([Vector3(*map(float, v)) for v in t], **kw) for t in tri]


def _spheres(xyzr, kw) -> list:
    from granum.yade import utils

    return [utils.sphere(Vector3(*map(float, row[:3])), float(row[3]), **kw) for row in xyzr]


def stl(file, dynamic=None, fixed=True, wire=True, color=None, highlight=False, noBound=False, material=-1,
        scale=1.0, shift=_ORIGIN):
    """Facets of an STL file (ASCII or binary), one per triangle, vertices ``scale * v + shift``.

    ``dynamic``/``fixed``/``wire``/``color``/``highlight``/``noBound``/``material`` are ``utils.facet``'s
    (``color`` None: a random colour per facet)."""
    tri = _place(meshfiles.read_stl(file), shift, scale)
    return _facets(tri, dict(dynamic=dynamic, fixed=fixed, wire=wire, color=color, highlight=highlight,
                             noBound=noBound, material=material))


def gts(meshfile, shift=_ORIGIN, scale=1.0, **kw):
    """Facets of a GTS surface file (one per face, in file order); ``**kw`` goes to ``utils.facet``."""
    xyz, edges, faces = meshfiles.read_gts(meshfile)
    return _facets(_place(xyz, shift, scale)[meshfiles.face_vertices(edges, faces)], kw)


def gmsh(meshfile="file.mesh", shift=_ORIGIN, scale=1.0, orientation=_NO_ROTATION, **kw):
    """Facets of the triangles of a MEDIT ``.mesh`` file (what gmsh writes), vertices
    ``orientation * (scale * v) + shift``; ``**kw`` goes to ``utils.facet``."""
    pts, tri = meshfiles.read_medit(meshfile)
    return _facets(_place(pts, shift, scale, orientation)[tri], kw)


def unv(fileName, shift=(0, 0, 0), scale=1.0, returnConnectivityTable=False, **kw):
    """Facets of the 3-node triangles of an I-DEAS universal file; ``**kw`` goes to ``utils.facet``.

    With ``returnConnectivityTable``: ``(facets, nodes, elements)``, nodes as ``(x, y, z)`` tuples (as in the
    file, not shifted or scaled) and elements as 0-based ``(i, j, k)`` rows of ``nodes``."""
    xyz, tri = meshfiles.read_unv(fileName)
    facets = _facets(_place(xyz, shift, scale)[tri], kw)
    if returnConnectivityTable:
        return facets, [tuple(map(float, p)) for p in xyz], [tuple(map(int, t)) for t in tri]
    return facets


def textExt(fileName, format="x_y_z_r", shift=_ORIGIN, scale=1.0, attrs=None, **kw):
    """Spheres from a text file with one sphere a line (``#`` lines skipped), columns by ``format``:

    * ``'x_y_z_r'``: centre and radius;
    * ``'x_y_z_r_matId'``: and the material id (overrides ``material`` in ``**kw``);
    * ``'x_y_z_r_attrs'``: and any further columns, appended to the list ``attrs`` one list per sphere.

    Centres become ``scale * x + shift``, radii ``scale * r``; ``**kw`` goes to ``utils.sphere``."""
    formats = {"x_y_z_r": 4, "x_y_z_r_matId": 5, "x_y_z_r_attrs": 4}
    if format not in formats:
        # RuntimeError, as YADE's (and export.textExt's)
        raise RuntimeError(f"Please, specify a correct format output! ymport.textExt: unknown format {format!r} "
                           f"(one of {', '.join(formats)})")
    a = meshfiles.read_table(fileName, formats[format])
    if format != "x_y_z_r_attrs" and a.shape[1] != formats[format]:
        raise meshfiles.MeshFileError(fileName, "line 1", f"format {format!r} has {formats[format]} columns, "
                                                          f"the file {a.shape[1]}")
    xyzr = np.column_stack([_place(a[:, :3], shift, scale), float(scale) * a[:, 3]])
    if format == "x_y_z_r_matId":
        bodies = [_spheres(row[None], {**kw, "material": int(m)})[0] for row, m in zip(xyzr, a[:, 4], strict=True)]
    else:
        bodies = _spheres(xyzr, kw)
    if format == "x_y_z_r_attrs" and attrs is not None:
        attrs.extend(row[4:].tolist() for row in a)
    return bodies


def text(fileName, shift=_ORIGIN, scale=1.0, **kw):
    """Spheres from a file of ``x y z r`` lines (``textExt`` with format ``'x_y_z_r'``)."""
    return textExt(fileName, "x_y_z_r", shift, scale, **kw)


def textFacets(fileName, format="x1_y1_z1_x2_y2_z2_x3_y3_z3", shift=_ORIGIN, scale=1.0, attrs=None, **kw):
    """Facets from a text file with one facet a line (``#`` lines skipped), columns by ``format``:
    ``'x1_y1_z1_x2_y2_z2_x3_y3_z3'`` (the three vertices), ``..._matId`` (and a material id),
    ``'id_..._matId'`` (a leading body id, not used, and a material id), or ``..._attrs`` (further
    columns appended to ``attrs``). Vertices become ``scale * x + shift``; ``**kw`` goes to ``utils.facet``."""
    base = "x1_y1_z1_x2_y2_z2_x3_y3_z3"
    formats = {base: (0, 9), base + "_matId": (0, 10), "id_" + base + "_matId": (1, 11), base + "_attrs": (0, 9)}
    if format not in formats:
        raise RuntimeError(f"Please, specify a correct format output! ymport.textFacets: unknown format {format!r} "
                           f"(one of {', '.join(formats)})")
    first, width = formats[format]
    a = meshfiles.read_table(fileName, width)
    if not format.endswith("_attrs") and a.shape[1] != width:
        raise meshfiles.MeshFileError(fileName, "line 1", f"format {format!r} has {width} columns, the file "
                                                          f"{a.shape[1]}")
    tri = a[:, first:first + 9].reshape(-1, 3, 3)
    meshfiles.check_triangles(tri, fileName, lambda i: f"row {i + 1}")
    tri = _place(tri, shift, scale)
    if format.endswith("_matId"):
        bodies = [_facets(t[None], {**kw, "material": int(m)})[0] for t, m in zip(tri, a[:, width - 1], strict=True)]
    else:
        bodies = _facets(tri, kw)
    if format.endswith("_attrs") and attrs is not None:
        attrs.extend(row[9:].tolist() for row in a)
    return bodies


def textClumps(fileName, shift=_ORIGIN, discretization=0, orientation=_NO_ROTATION, scale=1.0,
               **kw):
    """Clumps of spheres from a file of ``x y z r clumpId`` lines, added to ``O.bodies``: the spheres of
    each clump id (ids in order of first appearance) are appended and clumped (``appendClumped``).
    Centres become ``orientation * (scale * x) + shift``, radii ``scale * r``; ``**kw`` goes to
    ``utils.sphere``. Returns ``[(clumpId, [member ids]), ...]``."""
    from granum.yade.omega import O

    a = meshfiles.read_table(fileName, 5)
    if a.shape[1] != 5:
        raise meshfiles.MeshFileError(fileName, "line 1", f"expected the 5 columns x y z r clumpId, found {a.shape[1]}")
    xyzr = np.column_stack([_place(a[:, :3], shift, scale, orientation), float(scale) * a[:, 3]])
    spheres = _spheres(xyzr, kw)  # all made (and checked) before the first is added
    _, first, group = np.unique(a[:, 4], return_index=True, return_inverse=True)
    return [O.bodies.appendClumped([spheres[i] for i in np.flatnonzero(group == g)], discretization)
            for g in np.argsort(first, kind="stable")]
