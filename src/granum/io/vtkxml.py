"""VTK XML writers: unstructured grids (``.vtu``), poly-data lines (``.vtp``) and ``.pvd`` collections.

Only the small part of the format that particle output needs is written, from NumPy arrays and
without the ``vtk`` package:

* Data arrays go to one ``<AppendedData encoding="raw">`` block after the XML header (binary,
  little-endian, ``header_type="UInt64"``): each array is an 8-byte length followed by its bytes,
  or with ``compress=True`` a zlib block header ``[1, n, n, compressed n]`` followed by the zlib
  stream (the layout of VTK's ``vtkZLibDataCompressor``). ``ascii=True`` writes the values inline
  as text instead.
* Floating arrays are written as ``Float64`` (positions included: VTK's default ``Float32``
  points would lose digits of large coordinates), integers as ``Int64``, cell types as ``UInt8``.

Every file is written atomically (see :mod:`granum.io.atomic`). The format is described in
"VTK File Formats", section "XML File Formats", of the VTK user's guide.
"""

from __future__ import annotations

import os
import sys
import zlib

import numpy as np

from granum.io.atomic import write_bytes, write_text

#: VTK cell type codes used by granum.
VTK_VERTEX = 1
VTK_LINE = 3
VTK_TRIANGLE = 5
VTK_POLYGON = 7
VTK_QUAD = 9


def _quoteattr(text: str) -> str:
    """``text`` as a quoted XML attribute value (:func:`xml.sax.saxutils.quoteattr`, imported on first use: that
    module imports urllib.request, http.client and ssl, about 10 ms of every start)."""
    from xml.sax.saxutils import quoteattr as quote

    return quote(text)


def polygon_type(nvertices: int) -> int:
    """VTK cell type of a polygon of ``nvertices`` vertices: triangle, quad, or the general polygon."""
    return {3: VTK_TRIANGLE, 4: VTK_QUAD}.get(nvertices, VTK_POLYGON)

_TYPE_NAMES = {"f": "Float64", "i": "Int64", "u": "UInt8", "b": "UInt8"}
_DTYPES = {"Float64": "<f8", "Int64": "<i8", "UInt8": "u1"}


def _as_array(values, vtk_type: str | None = None) -> tuple[np.ndarray, str]:
    """Values as a contiguous little-endian array of a VTK type; also return the type's name."""
    arr = np.asarray(values)
    if vtk_type is None:
        vtk_type = _TYPE_NAMES.get(arr.dtype.kind, "Float64")
        if vtk_type == "UInt8" and arr.dtype.kind == "u" and arr.dtype.itemsize > 1:
            vtk_type = "Int64"
    return np.ascontiguousarray(arr, dtype=_DTYPES[vtk_type]), vtk_type


class _Writer:
    """Accumulates the XML text and the appended binary blocks of one file."""

    def __init__(self, ascii: bool, compress: bool):
        self.ascii = ascii
        self.compress = compress and not ascii
        self.lines: list[str] = []
        self.blocks: list[bytes] = []
        self.offset = 0

    def _encode(self, raw: bytes) -> bytes:
        if not self.compress:
            return np.uint64(len(raw)).tobytes() + raw
        if not raw:  # zero blocks: the header is just [0, 0, 0]
            return np.zeros(3, "<u8").tobytes()
        packed = zlib.compress(raw, 6)
        return np.array([1, len(raw), len(raw), len(packed)], "<u8").tobytes() + packed

    def array(self, indent: str, name: str | None, values, vtk_type: str | None = None) -> None:
        """One ``<DataArray>``: (n,) values have one component, (n, k) values have k."""
        arr, vtk_type = _as_array(values, vtk_type)
        ncomp = 1 if arr.ndim <= 1 else int(np.prod(arr.shape[1:]))
        attrs = f'type="{vtk_type}"'
        if name is not None:
            attrs += f" Name={_quoteattr(name)}"
        attrs += f' NumberOfComponents="{ncomp}"'
        if self.ascii:
            if vtk_type == "Float64":
                text = " ".join(repr(float(x)) for x in arr.ravel())  # repr: shortest exact decimal
            else:
                text = " ".join(str(int(x)) for x in arr.ravel())
            self.lines.append(f'{indent}<DataArray {attrs} format="ascii">{text}</DataArray>')
            return
        self.lines.append(f'{indent}<DataArray {attrs} format="appended" offset="{self.offset}"/>')
        block = self._encode(arr.tobytes())
        self.blocks.append(block)
        self.offset += len(block)

    def data_section(self, tag: str, data: dict | None) -> None:
        self.lines.append(f"      <{tag}>")
        for name, values in (data or {}).items():
            self.array("        ", name, values)
        self.lines.append(f"      </{tag}>")

    def finish(self, path, kind: str) -> None:
        compressor = ' compressor="vtkZLibDataCompressor"' if self.compress else ""
        head = ['<?xml version="1.0"?>',
                f'<VTKFile type="{kind}" version="1.0" byte_order="LittleEndian" header_type="UInt64"{compressor}>',
                f"  <{kind}>", *self.lines, f"  </{kind}>"]
        if self.ascii:
            write_text(path, "\n".join(head + ["</VTKFile>", ""]))
            return
        head += ['  <AppendedData encoding="raw">', "   _"]
        tail = "\n  </AppendedData>\n</VTKFile>\n"
        write_bytes(path, "\n".join(head).encode() + b"".join(self.blocks) + tail.encode())


def _check_data(what: str, data: dict | None, n: int) -> None:
    for name, values in (data or {}).items():
        if len(values) != n:
            raise ValueError(f"{what} array {name!r} has {len(values)} rows, expected {n}")


def write_unstructured_grid(path, points, connectivity, offsets, types, point_data: dict | None = None,
                            cell_data: dict | None = None, *, ascii: bool = False, compress: bool = False) -> None:
    """Write a ``.vtu`` file.

    :param points: (N, 3) point coordinates [m].
    :param connectivity: (L,) point indices of all cells, one cell after the other.
    :param offsets: (M,) end of each cell in ``connectivity`` (VTK's convention: exclusive end).
    :param types: (M,) VTK cell type codes (``VTK_VERTEX``, ``VTK_TRIANGLE``...).
    :param point_data: name -> (N,) or (N, k) values; ``cell_data``: name -> (M,) or (M, k).
    :param ascii: write the values as text; ``compress``: zlib-compress the binary blocks.
    """
    points = np.asarray(points, float).reshape(-1, 3)
    types = np.asarray(types)
    _check_data("point", point_data, len(points))
    _check_data("cell", cell_data, len(types))
    w = _Writer(ascii, compress)
    w.lines.append(f'    <Piece NumberOfPoints="{len(points)}" NumberOfCells="{len(types)}">')
    w.data_section("PointData", point_data)
    w.data_section("CellData", cell_data)
    w.lines.append("      <Points>")
    w.array("        ", "Points", points, "Float64")
    w.lines.append("      </Points>")
    w.lines.append("      <Cells>")
    w.array("        ", "connectivity", connectivity, "Int64")
    w.array("        ", "offsets", offsets, "Int64")
    w.array("        ", "types", types, "UInt8")
    w.lines.append("      </Cells>")
    w.lines.append("    </Piece>")
    w.finish(path, "UnstructuredGrid")


def write_poly_lines(path, points, lines, point_data: dict | None = None, cell_data: dict | None = None, *,
                     ascii: bool = False, compress: bool = False) -> None:
    """Write a ``.vtp`` file whose cells are straight lines.

    :param points: (N, 3) point coordinates [m].
    :param lines: (K, 2) point indices of the two ends of each line.
    :param point_data: name -> (N,) or (N, k) values; ``cell_data``: name -> (K,) or (K, k).
    """
    points = np.asarray(points, float).reshape(-1, 3)
    lines = np.asarray(lines, np.int64).reshape(-1, 2)
    _check_data("point", point_data, len(points))
    _check_data("cell", cell_data, len(lines))
    w = _Writer(ascii, compress)
    w.lines.append(f'    <Piece NumberOfPoints="{len(points)}" NumberOfVerts="0" NumberOfLines="{len(lines)}" '
                   'NumberOfStrips="0" NumberOfPolys="0">')
    w.data_section("PointData", point_data)
    w.data_section("CellData", cell_data)
    w.lines.append("      <Points>")
    w.array("        ", "Points", points, "Float64")
    w.lines.append("      </Points>")
    w.lines.append("      <Lines>")
    w.array("        ", "connectivity", lines.ravel(), "Int64")
    w.array("        ", "offsets", 2 * np.arange(1, len(lines) + 1), "Int64")
    w.lines.append("      </Lines>")
    w.lines.append("    </Piece>")
    w.finish(path, "PolyData")


def write_pvd(path, entries) -> None:
    """Write a ParaView collection: ``entries`` is a sequence of ``(time [s], file name)``.

    File names are written relative to the directory of ``path`` (how ParaView resolves them).
    """
    base = os.path.dirname(os.path.abspath(path))
    rows = []
    for t, name in entries:
        rel = os.path.relpath(os.path.abspath(name), base)
        if sys.platform == "win32":
            rel = rel.replace("\\", "/")
        rows.append(f'    <DataSet timestep="{float(t)!r}" group="" part="0" file={_quoteattr(rel)}/>')
    write_text(path, "\n".join(['<?xml version="1.0"?>',
                                '<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">',
                                "  <Collection>", *rows, "  </Collection>", "</VTKFile>", ""]))
