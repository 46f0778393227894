"""YADE's ``yade.export``: the scene to text and legacy VTK files.

* :func:`text`, :func:`textExt` -- sphere centres and radii as text (``#format x_y_z_r`` and
  tab-separated rows), the format YADE's ``ymport.text`` reads.
* :class:`VTKExporter` -- spheres, facets, interactions, contact points and the periodic cell as
  legacy ASCII ``.vtk`` files named ``<baseName>-<part>-<8-digit number>.vtk``, with extra data
  given as Python expressions evaluated per body (``b``) or interaction (``i``), as in YADE.

Positions, radii and vertices are read from the storage arrays; only the user's expressions are
evaluated on per-body views. For periodic output during a run, :class:`granum.yade.vtk.VTKRecorder`
writes binary VTK XML files and is much cheaper. All files are written atomically.
"""

from __future__ import annotations

import os
import warnings

import numpy as np

from granum.core.contacts import F_POINT
from granum.core.shapes import ShapeKind
from granum.io import vtklegacy
from granum.io.atomic import write_text
from granum.io.vtklegacy import num
from granum.yade import fields


def _omega():
    from granum.yade.omega import O

    return O


def _scene():
    return _omega()._scene


def _sphere_ids(mask: int) -> np.ndarray:
    scene = _scene()
    ids = fields.ids_of_kind(scene, ShapeKind.SPHERE)
    if mask != -1:
        ids = ids[(scene.bodies.mask[ids] & int(mask)) != 0]
    return ids


def textExt(filename, format="x_y_z_r", comment="", mask=-1, attrs=()):
    """Save spheres as text: ``#format <format>``, optional ``# comment`` lines, then one tab-separated row each.

    :param format: ``'x_y_z_r'`` (centre and radius [m]), ``'x_y_z_r_matId'`` (and the material's id in
        ``O.materials``, -1 if not shared) or ``'x_y_z_r_attrs'`` (and the values of the expressions in
        ``attrs``, evaluated with the sphere as ``b``; vectors and matrices give 3 and 9 columns).
    :param comment: text written after ``# `` below the format line.
    :param mask: keep only spheres with ``groupMask & mask != 0`` (-1: all).
    :return: number of spheres written.
    """
    if format not in ("x_y_z_r", "x_y_z_r_matId", "x_y_z_r_attrs"):
        raise RuntimeError("Please, specify a correct format output!")
    scene = _scene()
    ids = _sphere_ids(mask)
    table = np.column_stack([scene.bodies.pos[ids], fields.sphere_radii(scene, ids)])
    rows = [[num(x) for x in r] for r in table]
    if format == "x_y_z_r_matId":
        for row, m in zip(rows, fields.material_ids(scene)[ids], strict=True):
            row.append(str(int(m)))
    elif format == "x_y_z_r_attrs":
        O = _omega()
        ns = O.namespace()
        for row, i in zip(rows, ids, strict=True):
            body = O.bodies[int(i)]
            for expr in attrs:
                row += [num(x) for x in np.asarray(eval(expr, ns, {"b": body}), dtype=float).ravel()]
    lines = [f"#format {format}"]
    if format == "x_y_z_r_attrs":
        comment = "x y z r " + comment  # the column headers of the first four columns, as YADE
    if comment:
        lines.append(f"# {comment}")
    lines += ["\t".join(r) for r in rows]
    write_text(filename, "\n".join(lines) + "\n")
    return len(ids)


def textClumps(filename, format="x_y_z_r_clumpId", comment="", mask=-1):  # noqa: A002 (YADE's argument name)
    """Save the spherical clump members as ``x y z r clumpId`` rows (granum.yade.clump_text); return
    ``(number of clumps, number of spheres)``."""
    from granum.yade.clump_text import write

    return write(filename, format, comment, mask)


def text(filename, mask=-1):
    """Save sphere centres and radii as ``x y z r`` rows (``#format x_y_z_r`` header); return their number."""
    return textExt(filename, "x_y_z_r", mask=mask)


class VTKExporter:
    """Export spheres, facets, interactions... to legacy VTK files (YADE ``export.VTKExporter``).

    ``VTKExporter('out/run')`` writes ``out/run-spheres-00000000.vtk``, ``out/run-facets-00000000.vtk``,
    ``out/run-intrs-...``, ``out/run-cps-...`` and ``out/run-periCell-...``. Each part has its own
    counter, starting at ``startSnap`` and increased by every export of that part; ``numLabel``
    sets the number of one file without changing the counter's progression (as in YADE).

    ``what`` maps an array name to a Python expression evaluated for each exported body (``b``) or
    interaction (``i``) in the script's namespace; its first value decides whether the array is a
    scalar, a vector (3 values) or a tensor (3x3). Expressions giving another type are skipped
    with a warning.
    """

    def __init__(self, baseName, startSnap=0):
        self.baseName = os.fspath(baseName)
        self.startSnap = int(startSnap)
        self.snapCount: dict[str, int] = {}

    # ---- helpers --------------------------------------------------------------------------
    def _file(self, part: str, numLabel) -> str:
        count = self.snapCount.get(part, self.startSnap)
        self.snapCount[part] = count + 1
        label = count if numLabel is None else int(numLabel)
        return f"{self.baseName}-{part}-{label:08d}.vtk"

    @staticmethod
    def _array(key: str, expr: str, values: list):
        """Values of one exported expression as an array, or None (with a warning) if not exportable."""
        arr = np.asarray(values, dtype=float) if values else np.zeros(0)
        if arr.ndim == 1 or arr.shape[1:] in ((3,), (3, 3)):
            return arr
        warnings.warn(f"VTKExporter: {key}={expr!r} gives values of shape {arr.shape[1:]}; only numbers, "
                      "Vector3 and Matrix3 can be exported, skipped", stacklevel=4)
        return None

    def _evaluate(self, what: dict, objects: list, name: str) -> dict:
        """Evaluate each expression of ``what`` on every object (bound to ``name``) -> name: array."""
        ns = _omega().namespace()
        out = {}
        for key, expr in (what or {}).items():
            arr = self._array(key, expr, [eval(expr, ns, {name: obj}) for obj in objects])
            if arr is not None:
                out[key] = arr
        return out

    @staticmethod
    def _ids(ids, kind: ShapeKind) -> np.ndarray:
        scene = _scene()
        if isinstance(ids, str):
            if ids != "all":
                raise ValueError(f"VTKExporter: ids must be 'all' or a list of body ids, got {ids!r}")
            return fields.ids_of_kind(scene, kind)
        ids = np.asarray(list(ids), dtype=np.int64).reshape(-1)
        n = scene.body_count
        bad = ids[(ids < 0) | (ids >= n)]
        if bad.size:
            raise IndexError(f"VTKExporter: body id {int(bad[0])} out of range (there are {n} bodies)")
        keep = scene.bodies.alive[ids] & (scene.bodies.shape_kind[ids] == int(kind))
        return ids[keep]  # bodies of another shape are skipped, as in YADE

    # ---- parts ----------------------------------------------------------------------------
    def exportSpheres(self, ids="all", what={}, comment="comment", numLabel=None, useRef=False):  # noqa: B006
        """Export spheres: centres (``refPos`` with ``useRef``) as points, ``radius`` and ``what`` as point data."""
        scene = _scene()
        ids = self._ids(ids, ShapeKind.SPHERE)
        pos = (scene.bodies.ref_pos if useRef else scene.bodies.pos)[ids]
        data = {"radius": fields.sphere_radii(scene, ids)}
        O = _omega()
        data.update(self._evaluate(what, [O.bodies[int(i)] for i in ids], "b"))
        vtklegacy.write_polydata(self._file("spheres", numLabel), pos, point_data=data, comment=comment)

    def exportFacets(self, ids="all", what={}, comment="comment", numLabel=None):  # noqa: B006
        """Export facets as triangles (three points each); ``what`` gives cell data."""
        scene = _scene()
        ids = self._ids(ids, ShapeKind.FACET)
        verts = fields.facet_vertices(scene, ids)
        O = _omega()
        data = self._evaluate(what, [O.bodies[int(i)] for i in ids], "b")
        vtklegacy.write_polydata(self._file("facets", numLabel), verts.reshape(-1, 3),
                                 polygons=np.arange(3 * len(ids)).reshape(-1, 3), cell_data=data, comment=comment)

    def _interactions(self, ids) -> list:
        O = _omega()
        if isinstance(ids, str):
            if ids != "all":
                raise ValueError(f"VTKExporter: ids must be 'all' or a list of (id1, id2), got {ids!r}")
            return list(O.interactions)
        out = []
        for a, b in ids:
            i = O.interactions[int(a), int(b)]
            if i.isReal:
                out.append(i)
        return out

    def exportInteractions(self, ids="all", what={}, verticesWhat={}, comment="comment",  # noqa: B006
                           numLabel=None, useRef=False):
        """Export real interactions as lines between the two body centres (two points per line).

        ``what`` (with ``i``) gives cell data; ``verticesWhat`` gives point data evaluated with the
        body of each end as ``b`` (and both bodies as ``b1``, ``b2``).
        """
        scene = _scene()
        intrs = self._interactions(ids)
        pairs = np.array([(i.id1, i.id2) for i in intrs], dtype=np.int64).reshape(-1, 2)
        pos = scene.bodies.ref_pos if useRef else scene.bodies.pos
        points = pos[pairs.ravel()]
        cell = self._evaluate(what, intrs, "i")
        point = {}
        if verticesWhat:
            O = _omega()
            ns = O.namespace()
            ends = [(O.bodies[int(a)], O.bodies[int(b)]) for a, b in pairs]
            for key, expr in verticesWhat.items():
                values = [eval(expr, ns, {"b": b, "b1": b1, "b2": b2}) for b1, b2 in ends for b in (b1, b2)]
                arr = self._array(key, expr, values)
                if arr is not None:
                    point[key] = arr
        vtklegacy.write_polydata(self._file("intrs", numLabel), points, lines=np.arange(len(points)).reshape(-1, 2),
                                 point_data=point, cell_data=cell, comment=comment)

    def exportContactPoints(self, ids="all", what={}, useRef={}, comment="comment", numLabel=None):  # noqa: B006
        """Export the contact points of real interactions as points; ``what`` (with ``i``) gives point data."""
        from granum.yade.interactions import find_contact

        scene = _scene()
        intrs = self._interactions(ids)
        rows = [find_contact(scene, i.id1, i.id2) for i in intrs]
        points = scene.contacts.con_f[np.asarray(rows, dtype=np.int64), F_POINT:F_POINT + 3].reshape(-1, 3)
        data = self._evaluate(what, intrs, "i")
        vtklegacy.write_polydata(self._file("cps", numLabel), points, point_data=data, comment=comment)

    def exportPeriodicCell(self, comment="comment", numLabel=None):
        """Export the periodic cell as one hexahedron (nothing happens in an aperiodic scene)."""
        scene = _scene()
        if not scene.periodic:
            warnings.warn("VTKExporter.exportPeriodicCell: the scene is not periodic, nothing exported",
                          stacklevel=2)
            return
        a, b, c = np.asarray(scene.cell_hsize, float).T
        corners = np.array([c, b + c, a + b + c, a + c, 0 * a, b, a + b, a])
        vtklegacy.write_unstructured_grid(self._file("periCell", numLabel), corners, [range(8)], [12],
                                          comment=comment)

    def exportPolyhedra(self, *args, **kw):
        raise NotImplementedError("VTKExporter.exportPolyhedra: granum has no polyhedra")

    def exportPotentialBlocks(self, *args, **kw):
        raise NotImplementedError("VTKExporter.exportPotentialBlocks: granum has no potential blocks")

    def exportFacetsAsMesh(self, *args, **kw):
        raise NotImplementedError("VTKExporter.exportFacetsAsMesh is not implemented in granum; "
                                  "use exportFacets")
