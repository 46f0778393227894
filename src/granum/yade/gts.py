"""``gts``: triangulated surfaces, the part of PyGTS (the GNU Triangulated Surface library's Python
binding) that YADE scripts use. A script run by ``granum`` finds it as ``import gts``.

Objects: :class:`Vertex` (a point), :class:`Edge` (two vertices), :class:`Face` (three edges that
form a triangle), :class:`Surface` (a set of faces). Faces and edges refer to their vertex objects,
so moving a vertex moves every face made of it, as in PyGTS. Topology (closed, manifold) is judged
from vertex pairs: two Edge objects between the same vertices are one edge.

A surface's geometry for bulk work is a pair of arrays, :meth:`Surface.arrays` -> vertices (V, 3)
and triangles (F, 3), rebuilt only after a change. Boolean operations (``union``, ``intersection``,
``difference``) are done by the ``manifold3d`` library (exact and robust on closed, manifold
surfaces; ``pip install granum[mesh]``).

The order of a face's vertices: the vertex of e1 that is not on e2, the vertex e1 and e2 share, the
vertex of e2 not on e1 (GTS's order for faces read from a file).
"""

from __future__ import annotations

import math
import os

import numpy as np

from granum.io import meshfiles

__all__ = ["Edge", "Face", "Surface", "Vertex", "cube", "read"]

#: Bumped by every change of a vertex position: surfaces rebuild their arrays when it moved on.
_moves = [0]


class Vertex:
    """A point ``(x, y, z)`` [m]."""

    __slots__ = ("_x", "_y", "_z")

    def __init__(self, x=0.0, y=0.0, z=0.0):
        self._x, self._y, self._z = float(x), float(y), float(z)

    x = property(lambda self: self._x)
    y = property(lambda self: self._y)
    z = property(lambda self: self._z)

    def coords(self):
        """``(x, y, z)``."""
        return (self._x, self._y, self._z)

    def set(self, x=0.0, y=0.0, z=0.0):
        """Move the vertex to ``(x, y, z)``."""
        self._x, self._y, self._z = float(x), float(y), float(z)
        _moves[0] += 1

    def translate(self, dx=0.0, dy=0.0, dz=0.0):
        self.set(self._x + dx, self._y + dy, self._z + dz)

    def __repr__(self):
        return f"Vertex({self._x!r}, {self._y!r}, {self._z!r})"


class Edge:
    """The segment between two distinct vertices ``v1`` and ``v2``."""

    __slots__ = ("v1", "v2")

    def __init__(self, v1, v2):
        if not (isinstance(v1, Vertex) and isinstance(v2, Vertex)):
            raise TypeError("Edge(v1, v2) needs two gts.Vertex objects")
        if v1 is v2:
            raise ValueError("Edge: the two vertices are the same")
        self.v1, self.v2 = v1, v2

    def __repr__(self):
        return f"Edge({self.v1!r}, {self.v2!r})"


class Face:
    """A triangle of three edges ``e1``, ``e2``, ``e3``, each sharing one vertex with the next."""

    __slots__ = ("e1", "e2", "e3", "_v")

    def __init__(self, e1, e2, e3):
        for e in (e1, e2, e3):
            if not isinstance(e, Edge):
                raise TypeError("Face(e1, e2, e3) needs three gts.Edge objects")
        self.e1, self.e2, self.e3 = e1, e2, e3
        self._v = self._order()

    def _order(self):
        for a, b in ((self.e1.v1, self.e1.v2), (self.e1.v2, self.e1.v1)):
            for c, d in ((self.e2.v1, self.e2.v2), (self.e2.v2, self.e2.v1)):
                if b is c and d is not a and {id(self.e3.v1), id(self.e3.v2)} == {id(a), id(d)}:
                    return (a, b, d)
        raise RuntimeError("Edges in face must connect")

    def vertices(self):
        """The three vertices (see the module's note on their order)."""
        return self._v

    def revert(self):
        """Reverse the orientation (swaps e1 and e2)."""
        self.e1, self.e2 = self.e2, self.e1
        self._v = self._order()

    def _xyz(self):
        return np.array([v.coords() for v in self._v])

    def normal(self):
        """``(v2 - v1) x (v3 - v1)``: the normal, twice the area long (PyGTS's)."""
        a, b, c = self._xyz()
        return tuple(float(x) for x in np.cross(b - a, c - a))

    def area(self):
        return 0.5 * float(np.linalg.norm(self.normal()))

    def is_compatible(self, s):
        """Whether the face's orientation agrees with the faces of surface ``s`` it shares an edge with
        (each shared edge run in opposite directions)."""
        mine = {(id(a), id(b)) for a, b in _directed(self._v)}
        return not any((id(a), id(b)) in mine for f in s._faces for a, b in _directed(f._v))

    def __repr__(self):
        return f"Face({', '.join(map(repr, self._v))})"


def _directed(v):
    return ((v[0], v[1]), (v[1], v[2]), (v[2], v[0]))


class Surface:
    """A set of faces (insertion order kept; adding a face twice keeps one)."""

    def __init__(self):
        self._faces: dict[int, Face] = {}
        self._version = 0
        self._cache = None

    # -- construction
    def add(self, item):
        """Add a Face, or all faces of another Surface."""
        faces = item._faces.values() if isinstance(item, Surface) else [item]
        for f in list(faces):
            if not isinstance(f, Face):
                raise TypeError(f"Surface.add needs a gts.Face or a gts.Surface, not {type(f).__name__}")
            self._faces.setdefault(id(f), f)
        self._version += 1
        return self

    def remove(self, face):
        self._faces.pop(id(face), None)
        self._version += 1

    def copy(self, s):
        """Add copies of the faces of ``s`` (new vertices, edges and faces) to this surface, as GTS's
        ``gts_surface_copy`` does (a deep copy when this surface is empty); returns it."""
        xyz, tri = s.arrays()
        self._set_arrays(xyz, tri, keep=True)
        return self

    def _set_arrays(self, xyz, tri, keep=False):
        """Faces made of new vertices ``xyz`` (V, 3) and triangles ``tri`` (F, 3): they replace the surface's
        faces, or with ``keep`` are added to them."""
        verts = [Vertex(*p) for p in xyz]
        edges = {}

        def edge(i, j):
            key = (min(i, j), max(i, j))
            if key not in edges:
                edges[key] = Edge(verts[i], verts[j])
            return edges[key]

        if not keep:
            self._faces = {}
        for a, b, c in tri:
            f = Face(edge(a, b), edge(b, c), edge(c, a))
            self._faces[id(f)] = f
        self._version += 1

    # -- arrays
    def arrays(self):
        """``(vertices (V, 3) float64 [m], triangles (F, 3) int64)``: the surface as arrays (granum extension).
        Fresh copies, rebuilt after any change."""
        key = (self._version, _moves[0])
        if self._cache is None or self._cache[0] != key:
            index, xyz, tri = {}, [], []
            for f in self._faces.values():
                row = []
                for v in f._v:
                    k = index.get(id(v))
                    if k is None:
                        k = index[id(v)] = len(xyz)
                        xyz.append(v.coords())
                    row.append(k)
                tri.append(row)
            self._cache = (key, np.array(xyz, dtype=np.float64).reshape(-1, 3),
                           np.array(tri, dtype=np.int64).reshape(-1, 3),
                           [v for f in self._faces.values() for v in f._v])
        return self._cache[1].copy(), self._cache[2].copy()

    def triangles(self):
        """The faces' vertices as an array (F, 3, 3) [m] (granum extension)."""
        xyz, tri = self.arrays()
        return xyz[tri]

    def _edge_use(self):
        """Number of faces on each undirected edge, keyed by the vertex-index pair."""
        _, tri = self.arrays()
        e = np.sort(np.concatenate([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [2, 0]]]), axis=1)
        return np.unique(e, axis=0, return_counts=True)

    # -- queries
    def faces(self):
        return tuple(self._faces.values())

    def vertices(self):
        """The distinct vertices, in order of first use by the faces."""
        self.arrays()
        seen, out = set(), []
        for v in self._cache[3]:
            if id(v) not in seen:
                seen.add(id(v))
                out.append(v)
        return tuple(out)

    def edges(self):
        out = {}
        for f in self._faces.values():
            for e in (f.e1, f.e2, f.e3):
                out.setdefault(frozenset((id(e.v1), id(e.v2))), e)
        return tuple(out.values())

    @property
    def Nvertices(self):
        return len(self.arrays()[0])

    @property
    def Nfaces(self):
        return len(self._faces)

    @property
    def Nedges(self):
        return len(self._edge_use()[0]) if self._faces else 0

    def is_manifold(self):
        """Every edge is shared by at most two faces."""
        return bool(np.all(self._edge_use()[1] <= 2)) if self._faces else True

    def is_closed(self):
        """Every edge is shared by exactly two faces (a watertight surface); False for an empty one."""
        return bool(self._faces) and bool(np.all(self._edge_use()[1] == 2))

    def area(self):
        """Sum of the faces' areas [m^2]."""
        t = self.triangles()
        return 0.5 * float(np.linalg.norm(np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]), axis=1).sum())

    def volume(self):
        """Enclosed volume [m^3], positive when the faces' normals point out; RuntimeError for an open surface."""
        if not self.is_closed():
            raise RuntimeError("Surface is not closed")
        t = self.triangles()
        return float(np.einsum("ij,ij->i", t[:, 0], np.cross(t[:, 1], t[:, 2])).sum() / 6.0)

    def center_of_area(self):
        t = self.triangles()
        w = np.linalg.norm(np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]), axis=1)
        return tuple(float(x) for x in (w[:, None] * t.mean(axis=1)).sum(axis=0) / w.sum())

    def center_of_mass(self):
        if not self.is_closed():
            raise RuntimeError("Surface is not closed")
        t = self.triangles()
        v = np.einsum("ij,ij->i", t[:, 0], np.cross(t[:, 1], t[:, 2]))
        return tuple(float(x) for x in (v[:, None] * t.sum(axis=1) / 4.0).sum(axis=0) / v.sum())

    def boundingBox(self):
        """``((xmin, ymin, zmin), (xmax, ymax, zmax))`` of the vertices (granum extension)."""
        xyz, _ = self.arrays()
        return tuple(map(float, xyz.min(axis=0))), tuple(map(float, xyz.max(axis=0)))

    # -- transformations (in place, on the vertex objects)
    def _transform(self, fn):
        """Move every vertex: ``fn`` maps the coordinates (V, 3) to new ones."""
        verts = self.vertices()
        new = fn(np.array([v.coords() for v in verts], dtype=np.float64).reshape(-1, 3)).tolist()
        for v, (x, y, z) in zip(verts, new, strict=True):
            v._x, v._y, v._z = x, y, z
        _moves[0] += 1

    def translate(self, dx=0.0, dy=0.0, dz=0.0):
        """Move by ``(dx, dy, dz)``."""
        d = np.array([dx, dy, dz], dtype=np.float64)
        self._transform(lambda p: p + d)

    def scale(self, dx=1.0, dy=1.0, dz=1.0):
        """Multiply the coordinates by ``(dx, dy, dz)`` (about the origin; PyGTS's defaults scale x only)."""
        d = np.array([dx, dy, dz], dtype=np.float64)
        self._transform(lambda p: p * d)

    def rotate(self, dx=0.0, dy=0.0, dz=0.0, a=0.0):
        """Rotate by angle ``a`` [rad] about the axis ``(dx, dy, dz)`` through the origin (right-hand rule)."""
        axis = np.array([dx, dy, dz], dtype=np.float64)
        n = float(np.linalg.norm(axis))
        if n == 0.0:
            raise ValueError("Surface.rotate: the axis (dx, dy, dz) is zero")
        k = axis / n
        K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
        R = np.eye(3) + math.sin(a) * K + (1 - math.cos(a)) * K @ K  # Rodrigues' formula
        self._transform(lambda p: p @ R.T)

    def cleanup(self, threshold=0.0):
        """Merge vertices closer than ``threshold`` [m], then drop faces left without three distinct vertices
        and repeated faces."""
        xyz, tri = self.arrays()
        if threshold > 0 and len(xyz):
            tri = merge_close_vertices(xyz, float(threshold))[tri]
        keep = (tri[:, 0] != tri[:, 1]) & (tri[:, 1] != tri[:, 2]) & (tri[:, 2] != tri[:, 0])
        tri = tri[keep]
        _, first = np.unique(np.sort(tri, axis=1), axis=0, return_index=True)
        tri = tri[np.sort(first)]
        used, tri = np.unique(tri, return_inverse=True)
        self._set_arrays(xyz[used], tri.reshape(-1, 3))

    def tessellate(self):
        """Split every face into 4 at new vertices on its edges (a shared edge gets one): GTS's mid-arc points,
        the edge's midpoint pushed out to the unit sphere, ``(a + b) / |a + b|``, which makes a geodesation step
        of a polyhedron inscribed in the unit sphere."""
        xyz, tri = self.arrays()
        edges = np.sort(np.concatenate([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [2, 0]]]), axis=1)
        uniq, inverse = np.unique(edges, axis=0, return_inverse=True)
        mid = len(xyz) + inverse.reshape(3, -1).T  # (F, 3): the midpoints of edges ab, bc, ca
        a, b, c = tri.T
        ab, bc, ca = mid.T
        new = np.stack([np.stack(t, 1) for t in ((a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca))], 1)
        arc = xyz[uniq[:, 0]] + xyz[uniq[:, 1]]
        arc /= np.linalg.norm(arc, axis=1, keepdims=True)
        self._set_arrays(np.concatenate([xyz, arc]), new.reshape(-1, 3))

    # -- boolean operations
    def _manifold(self):
        m3d = meshfiles.library("manifold3d", "boolean operations on gts surfaces")
        xyz, tri = self.arrays()
        if not self.is_closed():
            raise RuntimeError("boolean operations need closed surfaces; this one is open")
        return m3d, m3d.Manifold(m3d.Mesh(vert_properties=xyz.astype(np.float32), tri_verts=tri.astype(np.uint32)))

    def _boolean(self, other, op):
        m3d, a = self._manifold()
        _, b = other._manifold()
        out = getattr(a, op)(b).to_mesh()
        s = Surface()
        s._set_arrays(np.asarray(out.vert_properties, dtype=np.float64)[:, :3], np.asarray(out.tri_verts, np.int64))
        return s

    def union(self, s2):
        """The surface of the union of the two enclosed volumes (a new Surface)."""
        return self._boolean(s2, "__add__")

    def intersection(self, s2):
        return self._boolean(s2, "__xor__")

    def difference(self, s2):
        return self._boolean(s2, "__sub__")

    # -- files
    def write(self, f):
        """Write the surface in GTS format to the open text file ``f``."""
        xyz, tri = self.arrays()
        e = np.sort(np.concatenate([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [2, 0]]]), axis=1)
        edges, inverse = np.unique(e, axis=0, return_inverse=True)
        faces = inverse.reshape(3, -1).T
        f.write(f"{len(xyz)} {len(edges)} {len(faces)} GtsSurface GtsFace GtsEdge GtsVertex\n")
        f.writelines(f"{x!r} {y!r} {z!r}\n" for x, y, z in xyz.tolist())
        f.writelines(f"{a + 1} {b + 1}\n" for a, b in edges.tolist())
        f.writelines(f"{a + 1} {b + 1} {c + 1}\n" for a, b, c in faces.tolist())

    def __repr__(self):
        return f"<gts.Surface: {self.Nfaces} faces>"


def merge_close_vertices(xyz: np.ndarray, threshold: float) -> np.ndarray:
    """For each vertex (V, 3) the index of its representative after merging vertices closer than
    ``threshold`` (transitively: chains merge), the lowest index of each group."""
    rep = np.arange(len(xyz))

    def root(i):
        while rep[i] != i:
            rep[i] = rep[rep[i]]
            i = rep[i]
        return i

    order = np.argsort(xyz[:, 0], kind="stable")
    xs = xyz[order, 0]
    for k, i in enumerate(order):
        stop = np.searchsorted(xs, xs[k] + threshold, side="right")
        for j in order[k + 1:stop]:
            if np.sum((xyz[i] - xyz[j]) ** 2) < threshold * threshold:
                a, b = root(i), root(j)
                rep[max(a, b)] = min(a, b)
    return np.array([root(i) for i in range(len(xyz))])


def read(f):
    """The Surface in a GTS file: an open file (as PyGTS takes) or a path."""
    path = getattr(f, "name", f)
    if not isinstance(path, str | os.PathLike):
        raise TypeError("gts.read needs an open file or a path")
    xyz, edges, faces = meshfiles.read_gts(path)
    s = Surface()
    s._set_arrays(xyz, meshfiles.face_vertices(edges, faces))
    return s


def cube():
    """The cube [-1, 1]^3 as 12 outward-oriented faces (PyGTS's ``gts.cube``)."""
    xyz = np.array([[x, y, z] for x in (-1.0, 1.0) for y in (-1.0, 1.0) for z in (-1.0, 1.0)])
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    tri = [t for a, b, c, d in quads for t in ((a, b, c), (a, c, d))]
    s = Surface()
    s._set_arrays(xyz, np.array(tri))
    return s
