"""Legacy ASCII VTK files (``.vtk``, "VTK DataFile Version 3.0"), as YADE's ``export.VTKExporter`` writes.

A file holds one ``POLYDATA`` data set (points, optional polygons or lines, and point/cell
attributes) or one small ``UNSTRUCTURED_GRID`` (the periodic cell). Each attribute is
``SCALARS`` ((n,) values), ``VECTORS`` ((n, 3)) or ``TENSORS`` ((n, 3, 3)), chosen from the shape
of its array. Numbers are written as the shortest text that reads back exactly. The file is written atomically.
"""

from __future__ import annotations

import numpy as np

from granum.io.atomic import write_text


def num(x) -> str:
    """Shortest text that reads back as the same float; integral values without '.0' (``2``, ``0.3``)."""
    text = repr(float(x))
    return text[:-2] if text.endswith(".0") else text


def _fmt(values) -> str:
    return " ".join(num(x) for x in values)


def _attributes(name: str, values) -> list[str]:
    """Lines of one attribute; its kind comes from the shape of ``values``."""
    name = "_".join(str(name).split()) or "unnamed"  # names are single tokens in this format
    arr = np.asarray(values, dtype=float)
    if arr.ndim == 1:
        return [f"SCALARS {name} double 1", "LOOKUP_TABLE default", *(num(x) for x in arr), ""]
    if arr.ndim == 2 and arr.shape[1] == 3:
        return [f"VECTORS {name} double", *(_fmt(v) for v in arr), ""]
    if arr.ndim == 3 and arr.shape[1:] == (3, 3):
        out = [f"TENSORS {name} double"]
        for m in arr:
            out += [_fmt(row) for row in m] + [""]
        return out + [""]
    raise ValueError(f"VTK attribute {name!r}: values must be scalars, 3-vectors or 3x3 tensors, "
                     f"got shape {arr.shape[1:]}")


def _header(comment: str, dataset: str, points: np.ndarray) -> list[str]:
    return ["# vtk DataFile Version 3.0.", " ".join(str(comment).splitlines()) or " ", "ASCII", "",
            f"DATASET {dataset}", f"POINTS {len(points)} double", *(_fmt(p) for p in points), ""]


def write_polydata(path, points, *, polygons=None, lines=None, point_data: dict | None = None,
                   cell_data: dict | None = None, comment: str = "comment") -> None:
    """Write a legacy ASCII ``POLYDATA`` file.

    :param points: (N, 3) coordinates [m].
    :param polygons: list of point-index sequences (e.g. (F, 3) triangles), or None.
    :param lines: (K, 2) point indices of line ends, or None.
    :param point_data: name -> (N,), (N, 3) or (N, 3, 3) values; ``cell_data`` likewise per cell.
    :param comment: the file's one-line title (newlines are replaced by spaces).
    """
    points = np.asarray(points, float).reshape(-1, 3)
    out = _header(comment, "POLYDATA", points)
    ncell = 0
    for keyword, cells in (("POLYGONS", polygons), ("LINES", lines)):
        if cells is None:
            continue
        cells = [list(map(int, c)) for c in cells]
        size = sum(len(c) + 1 for c in cells)
        out += [f"{keyword} {len(cells)} {size}", *(" ".join(map(str, [len(c), *c])) for c in cells), ""]
        ncell += len(cells)
    for section, data, n in (("POINT_DATA", point_data, len(points)), ("CELL_DATA", cell_data, ncell)):
        if not data:
            continue
        out.append(f"{section} {n}")
        for name, values in data.items():
            if len(values) != n:
                raise ValueError(f"VTK {section} {name!r} has {len(values)} values, expected {n}")
            out += _attributes(name, values)
    write_text(path, "\n".join(out) + "\n")


def write_unstructured_grid(path, points, cells, cell_types, comment: str = "comment") -> None:
    """Write a legacy ASCII ``UNSTRUCTURED_GRID`` file without attributes.

    :param points: (N, 3) coordinates [m].
    :param cells: list of point-index sequences, one per cell.
    :param cell_types: VTK cell type code of each cell (12: hexahedron).
    """
    points = np.asarray(points, float).reshape(-1, 3)
    cells = [list(map(int, c)) for c in cells]
    out = _header(comment, "UNSTRUCTURED_GRID", points)
    out += [f"CELLS {len(cells)} {sum(len(c) + 1 for c in cells)}",
            *(" ".join(map(str, [len(c), *c])) for c in cells), "",
            f"CELL_TYPES {len(cells)}", *(str(int(t)) for t in cell_types)]
    write_text(path, "\n".join(out) + "\n")
