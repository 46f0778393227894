"""Triangle meshes from files: STL (ASCII and binary), GTS, MEDIT ``.mesh`` (what gmsh writes), I-DEAS
universal files (``.unv``), and column text files.

Every reader returns plain arrays (coordinates in the file's units, float64) and never a half-read
mesh: a file that does not follow its format raises :class:`MeshFileError` naming the file and the
line (or, in a binary file, the triangle) where it stops making sense, and a triangle without area
(coincident or collinear vertices) or with a non-finite coordinate is refused by number.

The formats with a maintained reader are read by it: STL and MEDIT by ``meshio``, universal files
by ``pyuff`` (the optional ``mesh`` extra, ``pip install granum[mesh]``). A library's own message
seldom says where a file is wrong, so when one fails (or reads fewer triangles than the file
announces) a small scan of the file finds the first line that breaks the format, only to name it.
GTS files (the GNU Triangulated Surface library's format) have no maintained Python reader; their
grammar is four counted blocks of numbers, read here with NumPy.
"""

from __future__ import annotations

import importlib
import os
import re
import warnings

import numpy as np

__all__ = ["MeshFileError", "check_triangles", "read_gts", "read_medit", "read_stl", "read_table", "read_unv",
           "write_stl"]


class MeshFileError(ValueError):
    """A mesh or particle file that does not follow its format; the message names the file and the place."""

    def __init__(self, path, where, what):
        self.path, self.where = os.fspath(path), where
        super().__init__(f"{self.path}: {where + ': ' if where else ''}{what}")


def library(name: str, purpose: str):
    """Import the optional package ``name``, or an ImportError saying how to install it."""
    try:
        return importlib.import_module(name)
    except ImportError:
        raise ImportError(f"{purpose} needs the package {name!r}, which is not installed: "
                          f"pip install granum[mesh]") from None


def _open_check(path):
    if not os.path.isfile(path):
        raise FileNotFoundError(f"{os.fspath(path)}: no such file")


def check_triangles(tri: np.ndarray, path, label=lambda i: f"triangle {i + 1}") -> None:
    """Refuse a triangle with a non-finite coordinate or without area.

    ``tri`` (F, 3, 3) [m]: the vertices of each triangle. A triangle is degenerate when twice its area,
    |(b - a) x (c - a)|, is at most 1e-12 times the square of its longest edge (collinear vertices up
    to round-off, which a facet cannot be made of). ``label(i)`` names triangle i (0-based) in the
    message ("triangle 3", "face 3 (line 17)").
    """
    bad = np.flatnonzero(~np.all(np.isfinite(tri.reshape(len(tri), 9)), axis=1))
    if len(bad):
        raise MeshFileError(path, label(int(bad[0])), f"non-finite coordinate in {tri[bad[0]].tolist()}")
    a, b, c = tri[:, 0], tri[:, 1], tri[:, 2]
    area2 = np.linalg.norm(np.cross(b - a, c - a), axis=1)
    longest = np.max([np.sum((b - a) ** 2, axis=1), np.sum((c - b) ** 2, axis=1), np.sum((a - c) ** 2, axis=1)],
                     axis=0)
    bad = np.flatnonzero(area2 <= 1e-12 * longest)
    if len(bad):
        raise MeshFileError(path, label(int(bad[0])), f"degenerate triangle (no area): vertices {tri[bad[0]].tolist()}")


# ----------------------------------------------------------------------------- STL
def _stl_is_binary(path, size: int) -> bool:
    """Binary unless the file starts with ``solid`` and its first kilobyte is text (some binary files start
    with ``solid`` too: their header is free text, so a NUL or a size that fits the binary layout wins)."""
    with open(path, "rb") as f:
        head = f.read(1024)
    if not head.lstrip().lower().startswith(b"solid"):
        return True
    if b"\0" in head:
        return True
    if size >= 84:
        n = int(np.frombuffer(head[80:84], "<u4")[0]) if len(head) >= 84 else -1
        if 84 + 50 * n == size and not re.search(rb"\bfacet\b", head[84:]):
            return True
    return False


def _stl_ascii_problem(path) -> str | None:
    """The first line of an ASCII STL file that breaks the grammar (``line N: ...``), None if there is none.

    solid [name] / { facet normal x y z / outer loop / 3 x vertex x y z / endloop / endfacet } / endsolid
    """
    expect = ("facet", "outer", "vertex", "vertex", "vertex", "endloop", "endfacet")
    numbers = {"facet": 3, "vertex": 3}  # after "facet normal" and "vertex"
    k, n_facets, last = -1, 0, 0
    with open(path, errors="replace") as f:
        for lineno, line in enumerate(f, 1):
            words = line.split()
            if not words:
                continue
            last = lineno
            key = words[0].lower()
            if k == -1:
                if key != "solid":
                    return f"line {lineno}: expected 'solid', found {line.strip()[:60]!r}"
                k = 0
                continue
            if k == 0 and key == "endsolid":
                return None if n_facets else f"line {lineno}: the solid has no facet"
            if key != expect[k]:
                return f"line {lineno}: expected {expect[k]!r} (facet {n_facets + 1}), found {line.strip()[:60]!r}"
            vals = words[2:] if key in ("facet", "outer") else words[1:]
            if key == "outer" and words[1:2] != ["loop"]:
                return f"line {lineno}: expected 'outer loop', found {line.strip()[:60]!r}"
            if key in numbers:
                if len(vals) != 3:
                    return f"line {lineno}: expected 3 numbers after {key!r} (facet {n_facets + 1}), found {len(vals)}"
                for v in vals:
                    try:
                        float(v)
                    except ValueError:
                        return f"line {lineno}: {v!r} is not a number (facet {n_facets + 1})"
            k += 1
            if k == len(expect):
                k, n_facets = 0, n_facets + 1
    return f"line {last}: the file ends inside facet {n_facets + 1}" if k > 0 else \
        f"line {last}: the file ends before 'endsolid' (truncated?)"


def read_stl(path) -> np.ndarray:
    """Triangles (F, 3, 3) [file units] of an STL file, ASCII or binary, in file order, rounded to float32 as
    YADE reads them.

    Binary files must be 84 + 50 F bytes long for the F triangles their header announces; a shorter one
    is truncated and names the first incomplete triangle.
    """
    path = os.fspath(path)
    _open_check(path)
    size = os.path.getsize(path)
    if _stl_is_binary(path, size):
        if size < 84:
            raise MeshFileError(path, "", f"binary STL shorter than its 84-byte header ({size} bytes)")
        with open(path, "rb") as f:
            f.seek(80)
            n = int(np.frombuffer(f.read(4), "<u4")[0])
        if 84 + 50 * n != size:
            full = (size - 84) // 50
            raise MeshFileError(path, f"triangle {full + 1}" if full < n else "",
                                f"binary STL announces {n} triangles ({84 + 50 * n} bytes) but has {size} bytes"
                                + (" (truncated)" if size < 84 + 50 * n else ""))
        if n == 0:
            raise MeshFileError(path, "", "the binary STL has no triangle")
    meshio = library("meshio", "reading STL files")
    problem = None
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            mesh = meshio.stl.read(path)  # not meshio.read, which calls sys.exit on a bad file
        tri = np.concatenate([mesh.points[c.data] for c in mesh.cells if c.type == "triangle"]).astype(np.float64) \
            if mesh.cells else np.empty((0, 3, 3))
    except Exception as e:  # the library's message rarely names the place; find it
        problem, cause = (_stl_ascii_problem(path) or f"not a valid STL file ({e})"), e
    else:
        if not _stl_is_binary(path, size):
            # a file cut after a whole facet reads without error: the keyword counts tell
            with open(path, "rb") as f:
                text = f.read().lower()
            if text.count(b"endfacet") != len(tri) or b"endsolid" not in text:
                problem, cause = _stl_ascii_problem(path) or "the facets do not match 'endfacet' lines", None
    if problem is not None:
        where, _, what = problem.partition(": ") if problem.startswith("line ") else ("", "", problem)
        raise MeshFileError(path, where, what) from cause
    check_triangles(tri, path)
    # STL coordinates are single precision: binary files store float32, and YADE 2023.02a's ymport.stl reads
    # ASCII ones as float too (vertex -0.15 comes out as -0.15000000596046448, measured); granum's facets are
    # then YADE's to the bit
    return tri.astype(np.float32).astype(np.float64)


def write_stl(path, triangles, binary: bool = False, name: str = "granum") -> None:
    """Write triangles (F, 3, 3) as an STL file (ASCII, or binary with float32 coordinates)."""
    meshio = library("meshio", "writing STL files")
    tri = np.asarray(triangles, dtype=np.float64).reshape(-1, 3, 3)
    points = tri.reshape(-1, 3)
    cells = np.arange(len(points)).reshape(-1, 3)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        meshio.write_points_cells(os.fspath(path), points, [("triangle", cells)], file_format="stl",
                                  binary=binary)


# ----------------------------------------------------------------------------- GTS
def _number_lines(path):
    """(line number, words) of the lines that are not blank or comments ('#'), in file order."""
    with open(path, errors="replace") as f:
        for lineno, line in enumerate(f, 1):
            words = line.split("#", 1)[0].split()
            if words:
                yield lineno, words


def _block(path, lines, count, width, what, kind):
    """``count`` rows of the first ``width`` numbers of the next lines, as ``kind``; the line numbers."""
    rows, nums = [], []
    for i in range(count):
        try:
            lineno, words = next(lines)
        except StopIteration:
            raise MeshFileError(path, "", f"the file ends after {i} of its {count} {what}s (truncated?)") from None
        if len(words) < width:
            raise MeshFileError(path, f"line {lineno}", f"{what} {i + 1}: expected {width} numbers, found "
                                                         f"{' '.join(words)!r}")
        try:
            rows.append([kind(w) for w in words[:width]])
        except ValueError:
            raise MeshFileError(path, f"line {lineno}", f"{what} {i + 1}: {' '.join(words[:width])!r} is not "
                                                         f"{'numbers' if kind is float else 'integers'}") from None
        nums.append(lineno)
    return np.array(rows, dtype=np.float64 if kind is float else np.int64).reshape(count, width), np.array(nums)


def read_gts(path):
    """A GTS surface file: ``(vertices (V, 3) float64, edges (E, 2) vertex indices, faces (F, 3) edge indices)``,
    0-based, in file order.

    Format: a first line ``V E F`` (class names may follow), then V lines ``x y z``, E lines ``v1 v2`` and F
    lines ``e1 e2 e3`` of 1-based indices; '#' starts a comment. The three edges of a face must form a
    triangle (each shares one vertex with the next).
    """
    path = os.fspath(path)
    _open_check(path)
    lines = _number_lines(path)
    try:
        lineno, head = next(lines)
    except StopIteration:
        raise MeshFileError(path, "", "empty GTS file") from None
    try:
        nv, ne, nf = (int(w) for w in head[:3])
        if min(nv, ne, nf) < 0 or len(head) < 3:
            raise ValueError
    except ValueError:
        raise MeshFileError(path, f"line {lineno}", f"expected the counts 'vertices edges faces', found "
                                                     f"{' '.join(head)!r}") from None
    xyz, _ = _block(path, lines, nv, 3, "vertex", float)
    edges, eline = _block(path, lines, ne, 2, "edge", int)
    faces, fline = _block(path, lines, nf, 3, "face", int)
    bad = np.flatnonzero(np.any((edges < 1) | (edges > nv), axis=1))
    if len(bad):
        raise MeshFileError(path, f"line {eline[bad[0]]}", f"edge {bad[0] + 1} names vertex "
                                                            f"{edges[bad[0]].tolist()} outside 1..{nv}")
    bad = np.flatnonzero(np.any((faces < 1) | (faces > ne), axis=1))
    if len(bad):
        raise MeshFileError(path, f"line {fline[bad[0]]}", f"face {bad[0] + 1} names edge "
                                                            f"{faces[bad[0]].tolist()} outside 1..{ne}")
    edges, faces = edges - 1, faces - 1
    bad = np.flatnonzero(edges[:, 0] == edges[:, 1])
    if len(bad):
        raise MeshFileError(path, f"line {eline[bad[0]]}", f"edge {bad[0] + 1} joins vertex {edges[bad[0], 0] + 1} "
                                                            f"to itself")
    tri = face_vertices(edges, faces)
    bad = np.flatnonzero(tri[:, 0] < 0)
    if len(bad):
        raise MeshFileError(path, f"line {fline[bad[0]]}", f"the edges {(faces[bad[0]] + 1).tolist()} of face "
                                                            f"{bad[0] + 1} do not form a triangle")
    check_triangles(xyz[tri], path, lambda i: f"line {fline[i]}: face {i + 1}")
    return xyz, edges, faces


def face_vertices(edges: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Vertex indices (F, 3) of faces given by edges: the vertex of e1 not on e2, the one e1 and e2 share,
    the vertex of e2 not on e1 (GTS's order); a row of -1 where the three edges do not form a triangle."""
    e1, e2, e3 = edges[faces[:, 0]], edges[faces[:, 1]], edges[faces[:, 2]]
    out = np.full((len(faces), 3), -1, np.int64)
    for i in (0, 1):
        for j in (0, 1):
            shared = e1[:, i] == e2[:, j]
            a, b, c = e1[:, 1 - i], e1[:, i], e2[:, 1 - j]
            # e3 must join the two free ends, and the triangle must have three distinct vertices
            ok = shared & (a != c) & (((e3[:, 0] == a) & (e3[:, 1] == c)) | ((e3[:, 0] == c) & (e3[:, 1] == a)))
            out[ok] = np.stack([a, b, c], axis=1)[ok]
    return out


# ----------------------------------------------------------------------------- MEDIT (.mesh)
def _medit_problem(path) -> str | None:
    """The first line of a MEDIT file whose Vertices or Triangles block is short or not numeric."""
    width = {"vertices": 4, "triangles": 4}
    lines = _number_lines(path)
    for lineno, words in lines:
        key = words[0].lower()
        if key == "end":
            return None
        if key not in width:
            continue
        count_words = words[1:]
        if not count_words:
            try:
                lineno, count_words = next(lines)
            except StopIteration:
                return f"line {lineno}: the file ends before the number of {key}"
        try:
            count = int(count_words[0])
        except ValueError:
            return f"line {lineno}: expected the number of {key}, found {' '.join(count_words)!r}"
        for i in range(count):
            try:
                lineno, words = next(lines)
            except StopIteration:
                return f"line {lineno}: the file ends after {i} of its {count} {key} (truncated?)"
            try:
                vals = [float(w) for w in words]
            except ValueError:
                return f"line {lineno}: {key[:-1]} {i + 1}: {' '.join(words)!r} is not numbers"
            if len(vals) != width[key]:
                return f"line {lineno}: {key[:-1]} {i + 1}: expected {width[key]} numbers, found {len(vals)}"
    return None


def read_medit(path):
    """The vertices (V, 3) and triangles (F, 3) (0-based vertex indices) of a MEDIT ``.mesh`` file, the
    format gmsh writes; triangles come in file order, and other element kinds are ignored."""
    path = os.fspath(path)
    _open_check(path)
    meshio = library("meshio", "reading gmsh .mesh files")
    problem = _medit_problem(path)
    if problem is None:
        try:
            mesh = meshio.medit.read(path)  # not meshio.read, which calls sys.exit on a bad file
        except Exception as e:
            raise MeshFileError(path, "", f"not a valid MEDIT .mesh file ({e})") from e
    else:
        where, _, what = problem.partition(": ")
        raise MeshFileError(path, where, what)
    pts = np.asarray(mesh.points, dtype=np.float64)
    tris = [np.asarray(c.data, np.int64) for c in mesh.cells if c.type == "triangle"]
    tri = np.concatenate(tris) if tris else np.empty((0, 3), np.int64)
    if tri.size and (tri.min() < 0 or tri.max() >= len(pts)):
        k = int(np.flatnonzero(np.any((tri < 0) | (tri >= len(pts)), axis=1))[0])
        raise MeshFileError(path, f"triangle {k + 1}", f"names vertex {(tri[k] + 1).tolist()} outside 1..{len(pts)}")
    check_triangles(pts[tri], path)
    return pts, tri


# ----------------------------------------------------------------------------- UNV
#: I-DEAS element descriptors of 3-node triangles (thin shell, plane stress/strain, membrane...)
UNV_TRIANGLES = (41, 51, 61, 74, 81, 91)


def _parses(words, kind, count) -> bool:
    """Whether ``words`` are ``count`` values of type ``kind``."""
    try:
        return len(words) == count and all(kind(w) is not None for w in words)
    except ValueError:
        return False


def _unv_problem(path) -> str | None:
    """The first line of a universal file that breaks its layout: a dataset (between two ``-1`` lines) left open,
    a node record that is not 4 integers then 3 numbers, an element dataset line that is not integers."""
    begun, kind, rows = None, None, 0
    with open(path, errors="replace") as f:
        for lineno, line in enumerate(f, 1):
            words = line.split()
            if words == ["-1"]:
                begun, kind, rows = (lineno, None, 0) if begun is None else (None, None, 0)
                continue
            if begun is None or not words:
                continue
            if kind is None:
                kind = words[0]
                continue
            rows += 1
            if kind == "2411":  # node records: label, 3 system numbers / x y z (Fortran D exponents allowed)
                ok = _parses(words, int, 4) if rows % 2 == 1 else _parses([w.replace("D", "E") for w in words],
                                                                          float, 3)
            else:
                ok = kind != "2412" or _parses(words, int, len(words))
            if not ok:
                return f"line {lineno}: {line.strip()[:60]!r} does not fit dataset {kind} (begun at line {begun})"
    return None if begun is None else f"line {begun}: dataset {kind} is not closed by a '-1' line (truncated?)"


def read_unv(path):
    """Nodes (V, 3) and triangles (F, 3) (0-based rows of the node array) of an I-DEAS universal file:
    datasets 2411 (nodes) and 2412 (elements), of which the 3-node triangles are kept, in file order."""
    path = os.fspath(path)
    _open_check(path)
    pyuff = library("pyuff", "reading .unv files")
    problem = _unv_problem(path)
    if problem is not None:
        where, _, what = problem.partition(": ")
        raise MeshFileError(path, where, what)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            sets = pyuff.UFF(path).read_sets()
    except Exception as e:
        raise MeshFileError(path, "", f"not a valid universal file ({type(e).__name__}: {e})") from e
    sets = sets if isinstance(sets, list) else [sets]
    nodes = [s for s in sets if s.get("type") == 2411]
    elems = [s for s in sets if s.get("type") == 2412]
    if not nodes or not elems:
        raise MeshFileError(path, "", "a universal mesh needs a node dataset (2411) and an element dataset (2412)")
    num = np.concatenate([np.asarray(s["node_nums"], np.int64) for s in nodes])
    xyz = np.concatenate([np.stack([s["x"], s["y"], s["z"]], axis=1) for s in nodes]).astype(np.float64)
    rows = {int(n): i for i, n in enumerate(num)}
    tri, labels = [], []
    for s in elems:
        t = s.get("triangle")
        if not t:
            continue
        for k, (kind, nn) in enumerate(zip(t["fe_descriptor"], t["nodes_nums"], strict=True)):
            if kind in UNV_TRIANGLES:
                missing = [n for n in nn if int(n) not in rows]
                if missing:
                    raise MeshFileError(path, f"element {t['element_nums'][k]}", f"names node {missing[0]}, which "
                                                                                f"the node dataset does not have")
                tri.append([rows[int(n)] for n in nn])
                labels.append(t["element_nums"][k])
    tri = np.array(tri, dtype=np.int64).reshape(-1, 3)
    check_triangles(xyz[tri], path, lambda i: f"element {labels[i]}")
    return xyz, tri


# ----------------------------------------------------------------------------- text columns
def read_table(path, min_columns: int) -> np.ndarray:
    """The numbers of a text file (N, C) [file units], '#' lines skipped; every line must have the same
    number C >= ``min_columns`` of numbers (the error names the first line that does not)."""
    path = os.fspath(path)
    _open_check(path)
    rows, width = [], None
    for lineno, words in _number_lines(path):
        try:
            vals = [float(w) for w in words]
        except ValueError:
            raise MeshFileError(path, f"line {lineno}", f"{' '.join(words)[:80]!r} is not a row of numbers") from None
        if width is None:
            width = len(vals)
            if width < min_columns:
                raise MeshFileError(path, f"line {lineno}", f"expected at least {min_columns} columns, found {width}")
        elif len(vals) != width:
            raise MeshFileError(path, f"line {lineno}", f"expected {width} numbers like the first row, found "
                                                         f"{len(vals)}")
        rows.append(vals)
    a = np.array(rows, dtype=np.float64).reshape(len(rows), width or min_columns)
    if not np.all(np.isfinite(a)):
        i = int(np.flatnonzero(~np.all(np.isfinite(a), axis=1))[0])
        raise MeshFileError(path, f"row {i + 1}", f"non-finite value in {a[i].tolist()}")
    return a
