"""Mesh import (``yade.ymport``), gts surfaces and the surface predicates of ``yade.pack``.

Checked against: brute-force ray counting (point in surface), files written and read back (STL), real
YADE 2023.02a's results (tests/reference/yade/ymport.py), and bad files, which must raise naming the file
and the place and leave the scene as it was.
"""

from __future__ import annotations

import math
import os

import numpy as np
import pytest
from conftest import REFERENCE, reference

from granum.io import meshfiles
from granum.io.meshfiles import MeshFileError
from granum.mathtypes import Quaternion, Vector3
from granum.yade import _surface, gts, pack, ymport

EX = "/usr/share/doc/yade/examples"
DATA = REFERENCE / "ymport_data"
needs_examples = pytest.mark.skipif(not os.path.isdir(EX), reason="YADE's examples are not installed")


# ----------------------------------------------------------------------------- point in surface
def torus(R=1.0, r=0.4, n=24, m=12):
    """A closed, non-convex torus about z: triangles (2 n m, 3, 3)."""
    u = np.arange(n) * 2 * np.pi / n
    v = np.arange(m) * 2 * np.pi / m
    U, V = np.meshgrid(u, v, indexing="ij")
    xyz = np.stack([(R + r * np.cos(V)) * np.cos(U), (R + r * np.cos(V)) * np.sin(U), r * np.sin(V)], -1)
    i, j = np.meshgrid(np.arange(n), np.arange(m), indexing="ij")
    a, b, c, d = (i, j), ((i + 1) % n, j), ((i + 1) % n, (j + 1) % m), (i, (j + 1) % m)
    tri = [np.stack([xyz[a], xyz[b], xyz[c]], -2), np.stack([xyz[a], xyz[c], xyz[d]], -2)]
    return np.concatenate([t.reshape(-1, 3, 3) for t in tri])


def octahedron_sphere(level=3):
    """A closed convex polyhedron: an octahedron subdivided ``level`` times, projected on the unit sphere."""
    tri = np.array([[[1, 0, 0], [0, 1, 0], [0, 0, 1]]], float)
    tri = np.concatenate([tri * [sx, sy, sz] for sx in (1, -1) for sy in (1, -1) for sz in (1, -1)])
    for _ in range(level):
        a, b, c = tri[:, 0], tri[:, 1], tri[:, 2]
        ab, bc, ca = (a + b) / 2, (b + c) / 2, (c + a) / 2
        tri = np.concatenate([np.stack(t, 1) for t in ((a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca))])
    return tri / np.linalg.norm(tri, axis=2, keepdims=True)


def ray_parity(tri, pts, direction):
    """Brute force: crossings of the ray from each point along ``direction`` with every triangle
    (Moller-Trumbore), odd = inside."""
    a, e1, e2 = tri[:, 0], tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]
    out = np.empty(len(pts), bool)
    for k, p in enumerate(pts):
        h = np.cross(direction, e2)
        det = np.einsum("ij,ij->i", e1, h)
        s = p - a
        u = np.einsum("ij,ij->i", s, h) / det
        q = np.cross(s, e1)
        v = q @ direction / det
        t = np.einsum("ij,ij->i", e2, q) / det
        out[k] = np.count_nonzero((u >= 0) & (v >= 0) & (u + v <= 1) & (t > 0)) % 2 == 1
    return out


@pytest.mark.parametrize("shape", ["sphere", "torus"])
def test_point_in_surface_equals_brute_force_ray_counting(shape):
    tri = octahedron_sphere() if shape == "sphere" else torus()
    rng = np.random.default_rng(7)
    lo, hi = tri.reshape(-1, 3).min(0) - 0.1, tri.reshape(-1, 3).max(0) + 0.1
    pts = lo + rng.random((3000, 3)) * (hi - lo)
    # plus points straight above or below vertices and edge midpoints: the vertical ray meets a vertex or an
    # edge exactly, which is where a naive parity count goes wrong
    verts = np.unique(tri.reshape(-1, 3), axis=0)
    mids = (tri[:, 0] + tri[:, 1]) / 2
    for base in (verts, mids):
        extra = base[rng.integers(0, len(base), 400)].copy()
        extra[:, 2] = lo[2] + rng.random(400) * (hi[2] - lo[2])
        pts = np.concatenate([pts, extra])
    grid = _surface.SurfaceGrid(tri)
    expected = ray_parity(tri, pts, np.array([0.3141, 0.2718, 0.9127]))
    got = grid.inside(pts)
    assert 0.1 < expected.mean() < 0.9
    assert np.array_equal(got, expected), np.flatnonzero(got != expected)[:10]


def test_inside_is_the_torus_formula():
    """Away from the faces, the polyhedral torus and the exact one agree (distance > the chord error)."""
    tri = torus(n=64, m=32)
    rng = np.random.default_rng(3)
    pts = rng.uniform([-1.5, -1.5, -0.5], [1.5, 1.5, 0.5], (20000, 3))
    dist = np.hypot(np.hypot(pts[:, 0], pts[:, 1]) - 1.0, pts[:, 2]) - 0.4
    clear = np.abs(dist) > 0.01  # the facets lie within 1.4 r (1 - cos(pi/32)) < 0.003 of the true torus
    got = _surface.SurfaceGrid(tri).inside(pts)
    assert np.array_equal(got[clear], dist[clear] < 0)


def test_gts_predicate_equals_yade_on_the_horse():
    ref = reference("ymport")
    path = f"{EX}/gts-horse/horse.coarse.gts"
    if not os.path.exists(path):
        pytest.skip("YADE's examples are not installed")
    s = gts.read(open(path))
    h = ref["horse"]
    assert (s.is_closed(), s.Nvertices, s.Nedges, s.Nfaces) == (h["closed"], h["Nvertices"], h["Nedges"],
                                                                  h["Nfaces"])
    assert s.volume() == pytest.approx(h["volume"], rel=1e-12)
    assert s.area() == pytest.approx(h["area"], rel=1e-12)
    pred = pack.inGtsSurface(s)
    mn, mx = (np.asarray(v) for v in pred.aabb())
    np.testing.assert_allclose([mn, mx], ref["horse_aabb"], rtol=1e-15)
    r = np.arange(-1, 18), np.arange(-1, 24), np.arange(-1, 20)
    i, j, k = np.meshgrid(*r, indexing="ij")
    pts = np.stack([mn[0] + (mx[0] - mn[0]) * (i + .37) / 17, mn[1] + (mx[1] - mn[1]) * (j + .29) / 23,
                    mn[2] + (mx[2] - mn[2]) * (k + .41) / 19], -1).reshape(-1, 3)
    for key, pad in (("horse_inside", 0.0), ("horse_inside_pad", 0.004)):
        got = "".join("01"[int(x)] for x in pred._inside(pts, pad))
        assert got == ref[key] and "1" in got
    assert len(pack.regularHexaCenters(pred, (mx[0] - mn[0]) / 40, (mx[0] - mn[0]) / 160)) == ref["horse_regularHexa"]
    s2 = gts.Surface().copy(s)
    s2.translate(0.04, 0, 0)
    u = s.union(s2)
    assert u.is_closed()
    assert u.volume() == pytest.approx(ref["horse_union"]["volume"], rel=1e-5)  # manifold3d works in float32
    assert len(pack.gtsSurface2Facets(s)) == h["facets"]


def test_open_surface_is_refused_by_the_predicate():
    ref = reference("ymport")["open_surface_pred"]
    swept = pack.sweptPolylines2gtsSurface([[Vector3(0, 0, 0), Vector3(1, 0, 0)], [Vector3(0, 1, 0), Vector3(1, 1, 0)]])
    with pytest.raises(ValueError, match="not closed") as e:
        pack.inGtsSurface(swept)
    assert ref["exception"] == "ValueError" and str(e.value).startswith(ref["message"])
    assert "of its 5 edges, 4 belong to one face only" in str(e.value)
    with pytest.raises(RuntimeError, match="not closed"):
        swept.volume()


def test_surface_objects_and_transformations():
    ref = reference("ymport")
    c = gts.cube()
    assert dict(volume=c.volume(), area=c.area(), Nvertices=c.Nvertices, Nfaces=c.Nfaces) == ref["cube"]
    c.scale(2, 3, 4)
    c.rotate(0, 0, 1, 0.5)
    c.translate(1, 2, 3)
    assert c.volume() == pytest.approx(ref["cube_transformed"]["volume"], rel=1e-14)
    got = sorted(tuple(round(x, 12) for x in v.coords()) for v in c.vertices())
    np.testing.assert_allclose(got, ref["cube_transformed"]["vertices"], atol=1e-12)
    # hand-made faces: edges must connect, orientation follows e1 then e2
    a, b, d = gts.Vertex(0, 0, 0), gts.Vertex(1, 0, 0), gts.Vertex(0, 1, 0)
    f = gts.Face(gts.Edge(a, b), gts.Edge(b, d), gts.Edge(d, a))
    assert f.vertices() == (a, b, d) and f.normal() == (0.0, 0.0, 1.0) and f.area() == 0.5
    with pytest.raises(RuntimeError, match="must connect"):
        gts.Face(gts.Edge(a, b), gts.Edge(a, d), gts.Edge(a, b))
    s = gts.Surface()
    s.add(f)
    assert not s.is_closed() and s.Nfaces == 1 and s.Nvertices == 3
    b.set(2, 0, 0)  # moving a vertex moves the surface
    assert s.area() == 1.0


def test_tessellate_is_a_geodesation_step():
    """YADE 2023.02a: gts.cube() tessellated has 48 faces, 26 vertices, 72 edges, volume 4.828427124746188 and
    area 19.07068619302529 (the new vertices lie on the unit sphere); a cube inscribed in the unit sphere tends to
    the sphere."""
    c = gts.cube()
    c.tessellate()
    assert (c.Nfaces, c.Nvertices, c.Nedges) == (48, 26, 72) and c.is_closed()
    assert c.volume() == pytest.approx(4.828427124746188, rel=1e-14)
    assert c.area() == pytest.approx(19.07068619302529, rel=1e-14)
    s = gts.cube()
    s.scale(*[1 / np.sqrt(3)] * 3)
    for _ in range(4):
        s.tessellate()
    assert s.Nfaces == 12 * 4 ** 4 and s.volume() == pytest.approx(4 / 3 * np.pi, rel=1e-2)


def test_gts_file_written_and_read_back(tmp_path):
    c = gts.cube()
    c.translate(0.5, 0, 0)
    with open(tmp_path / "c.gts", "w") as f:
        c.write(f)
    back = gts.read(open(tmp_path / "c.gts"))
    assert back.is_closed() and back.volume() == 8.0 and back.Nedges == 18
    np.testing.assert_array_equal(back.triangles(), c.triangles())


def test_surface_builders_equal_yade():
    ref = reference("ymport")
    thetas = np.arange(0, np.pi / 2, np.pi / 24)
    poly = ((1e-2, 5e-2), (5e-2, 2e-2), (7e-2, -2e-2), (1e-2, -5e-2), (1e-2, 5e-2))
    pts = pack.revolutionSurfaceMeridians([[(p[0], p[1] + 1e-2 * th) for p in poly] for th in thetas], thetas,
                                          origin=Vector3(0, -.05, .1), orientation=Quaternion((1, 1, 0), np.pi / 4))
    np.testing.assert_allclose([[list(p) for p in m] for m in pts[:3]], ref["meridians"], rtol=1e-14, atol=1e-17)
    surf = pack.sweptPolylines2gtsSurface(pts, capStart=True, capEnd=True, threshold=1e-4)
    rv = ref["revolution"]
    assert (surf.is_closed(), surf.Nvertices, surf.Nfaces) == (rv["closed"], rv["Nvertices"], rv["Nfaces"])
    assert surf.volume() == pytest.approx(rv["volume"], rel=1e-12)
    sw = pack.sweptPolylines2gtsSurface([[Vector3(0, 0, 0), Vector3(1, 0, 0), Vector3(1, 1, 0)],
                                         [Vector3(0, 0, 1), Vector3(1, 0, 1), Vector3(1, 1, 1)]])
    assert dict(Nvertices=sw.Nvertices, Nfaces=sw.Nfaces, area=sw.area(), closed=sw.is_closed()) == ref["swept"]


def test_copy_adds_faces_as_gts_does():
    """rotating-cylinder.py: ``cyl.copy(sq)`` adds the square's faces to the cylinder (GTS's surface copy)."""
    r = reference("ymport")["rotating_cylinder"]
    th = np.linspace(0, 2 * np.pi, 24, endpoint=True)
    base = [Vector3(math.cos(t), math.sin(t), -1) for t in th]
    cyl = pack.sweptPolylines2gtsSurface([base, [p + Vector3(0, 0, 2) for p in base]])
    vv = [gts.Vertex(1, 1, 0), gts.Vertex(-1, 1, 0), gts.Vertex(-1, -1, 0), gts.Vertex(1, -1, 0)]
    ee = [gts.Edge(vv[0], vv[1]), gts.Edge(vv[1], vv[2]), gts.Edge(vv[2], vv[3]), gts.Edge(vv[3], vv[0]),
          gts.Edge(vv[0], vv[2])]
    sq = gts.Surface()
    sq.add(gts.Face(ee[0], ee[1], ee[4]))
    sq.add(gts.Face(ee[2], ee[3], ee[4]))
    sq.translate(0, 0, -1)
    cyl.copy(sq)
    cyl.scale(.2, .2, .5)
    cyl.rotate(1, 0, 0, -np.pi / 4)
    fs = pack.gtsSurface2Facets(cyl)
    assert (cyl.Nfaces, cyl.Nvertices, len(fs)) == (r["Nfaces"], r["Nvertices"], r["facets"])
    assert cyl.area() == pytest.approx(r["area"], rel=1e-13)
    total = np.sum([list(b.state.pos + v) for b in fs for v in b.shape.vertices], axis=0)
    np.testing.assert_allclose(total, r["vertex_sum"], atol=1e-13)
    assert vv[0].coords() == (1.0, 1.0, -1.0)  # the copy is deep: sq's own vertices did not move


def test_single_polyline_caps():
    """clump-viscoelastic.py makes a plane as the caps of one polyline: YADE gives two faces, whatever the caps."""
    pts = [[Vector3(-.5, 0, 0), Vector3(.5, 0, 0), Vector3(.5, 0, -.5), Vector3(-.5, 0, -.5)]]
    for caps in ((True, True), (True, False), (False, True)):
        s = pack.sweptPolylines2gtsSurface(pts, capStart=caps[0], capEnd=caps[1])
        assert (s.Nfaces, s.Nvertices, s.area()) == (2, 4, 0.5)
    assert pack.sweptPolylines2gtsSurface(pts).Nfaces == 0
    p = [tuple(x) for x in pts[0]]
    # YADE's faces (vertex order as its facets give them): start cap (p1, p0, p2), (p2, p0, p3); end cap
    # (p0, p1, p2), (p0, p2, p3)
    for caps, faces in (((True, False), [(p[1], p[0], p[2]), (p[2], p[0], p[3])]),
                        ((False, True), [(p[0], p[1], p[2]), (p[0], p[2], p[3])])):
        tri = pack.sweptPolylines2gtsSurface(pts, capStart=caps[0], capEnd=caps[1]).triangles()
        assert [tuple(map(tuple, t)) for t in tri] == faces


def test_convex_polyhedron_equals_yade():
    ref = reference("ymport")["convex"]
    planes = [((0, 0, 0), (2, 0, 0)), ((1, 0, 0), (-1, 0, 0)), ((0, 0, 0), (0, 1, 0)), ((0, 1, 0), (0, -1, 0)),
              ((0, 0, 0), (0, 0, 1)), ((0, 0, 1), (0, 0, -1)), ((0, 0, 1.5), (-1, -1, -1))]
    p = pack.inConvexPolyhedron(planes)
    np.testing.assert_allclose([list(v) for v in p.aabb()], ref["aabb"], atol=1e-15)
    assert [[list(pt), pad, p(pt, pad)] for pt, pad in ref_probes(ref)] == ref["probes"]
    with pytest.raises(ValueError, match="finite volume"):
        pack.inConvexPolyhedron([((0, 0, 0), (1, 0, 0)), ((0, 0, 0), (0, 1, 0)), ((0, 0, 0), (0, 0, 1)),
                                 ((1, 1, 1), (-1, -1, 0))])


def ref_probes(ref):
    return [(tuple(pt), pad) for pt, pad, _ in ref["probes"]]


# ----------------------------------------------------------------------------- import
def global_vertices(bodies):
    return [[list(b.state.pos + v) for v in b.shape.vertices] for b in bodies]


def test_stl_equals_yade(yade):
    ref = reference("ymport")
    t = ymport.stl(str(DATA / "tet.stl"), shift=Vector3(1, 2, 3), scale=2, color=(1, 0, 0), wire=False, fixed=False)
    np.testing.assert_allclose(global_vertices(t), ref["stl_tet"]["vertices"], rtol=1e-15)
    np.testing.assert_allclose([list(b.state.pos) for b in t], ref["stl_tet"]["pos"], rtol=1e-15)
    assert [b.shape.wire for b in t] == ref["stl_tet"]["wire"] and [b.dynamic for b in t] == ref["stl_tet"]["dynamic"]
    assert [list(b.shape.color) for b in t] == ref["stl_tet"]["color"]
    t = ymport.stl(str(DATA / "tet.stl"))
    d = ref["stl_tet_default"]
    assert ([b.shape.wire for b in t], [b.dynamic for b in t], [b.state.blockedDOFs for b in t]) == \
        (d["wire"], d["dynamic"], d["blocked"])


@needs_examples
def test_example_meshes_equal_yade(yade):
    ref = reference("ymport")
    yade.O.materials.append(yade.FrictMat(young=1e6, label="m0"))
    t = ymport.stl(f"{EX}/baraban/baraban.stl", material="m0")
    r = ref["stl_baraban"]
    assert len(t) == r["n"] and t[0].material.label == r["material"]
    np.testing.assert_allclose(global_vertices(t[:3] + t[-1:]), r["first"] + r["last"], rtol=1e-15, atol=1e-15)
    t = ymport.gmsh(f"{EX}/hourglass/hourglass.mesh", shift=Vector3(0, 0, 1), scale=2,
                    orientation=Quaternion((1, 0, 0), 0.5))
    r = ref["gmsh_hourglass"]
    assert len(t) == r["n"]
    np.testing.assert_allclose(global_vertices(t[:3] + t[-1:]), r["first"] + r["last"], rtol=1e-14, atol=1e-17)
    t = ymport.unv(f"{EX}/test/unv-read/shell.unv", shift=(100, 200, 300), scale=1000)
    r = ref["unv_shell"]
    assert len(t) == r["n"]
    np.testing.assert_allclose(global_vertices(t[:3] + t[-1:]), r["first"] + r["last"], rtol=1e-14, atol=1e-11)
    f, nodes, elements = ymport.unv(f"{EX}/test/unv-read/shell.unv", returnConnectivityTable=True)
    r = ref["unv_table"]
    assert (nodes[:5], len(nodes)) == ([tuple(p) for p in r["nodes"]], r["n_nodes"])
    assert (elements[:5], len(elements)) == ([tuple(e) for e in r["elements"]], r["n_elements"])


def test_text_formats_equal_yade(yade):
    ref = reference("ymport")
    yade.O.materials.append(yade.FrictMat(young=1e6, label="m0"))
    yade.O.materials.append(yade.FrictMat(young=2e6, label="m1"))

    def spheres(bs):
        return [[list(b.state.pos), b.shape.radius, b.material.label] for b in bs]

    assert spheres(ymport.text(str(DATA / "sph.txt"), shift=Vector3(1, 0, 0), scale=2)) == ref["text"]
    assert spheres(ymport.textExt(str(DATA / "sphm.txt"), format="x_y_z_r_matId")) == ref["textExt_matId"]
    with pytest.raises(RuntimeError, match="bogus") as e:
        ymport.textExt(str(DATA / "sph.txt"), format="bogus")
    bogus = ref["textExt_bogus"]
    assert bogus["exception"] == "RuntimeError" and str(e.value).startswith(bogus["message"])
    np.testing.assert_allclose(global_vertices(ymport.textFacets(str(DATA / "facets.txt"), shift=Vector3(0, 0, 1))),
                               ref["textFacets"], atol=1e-15)
    got = ymport.textFacets(str(DATA / "facetsm.txt"), format="x1_y1_z1_x2_y2_z2_x3_y3_z3_matId")
    assert [b.material.label for b in got] == ref["textFacets_matId"]
    r = ref["textClumps"]
    ret = ymport.textClumps(str(DATA / "clumps.txt"), shift=Vector3(0, 0, 1), scale=2,
                            orientation=Quaternion((0, 0, 1), 0.5))
    assert [[c, list(m)] for c, m in ret] == r["ret"]
    b = yade.O.bodies
    np.testing.assert_allclose([list(x.state.pos) for x in b], r["pos"], rtol=1e-14, atol=1e-15)
    assert [x.isClump for x in b] == r["isClump"]


def test_export_text_read_back(yade, tmp_path):
    """Spheres saved by export.textExt come back from ymport.textExt: centres, radii, materials, attributes."""
    from granum.yade import export

    m0 = yade.O.materials.append(yade.FrictMat(label="m0"))
    yade.O.materials.append(yade.FrictMat(label="m1"))
    yade.O.bodies.append([yade.sphere((0.1 * i, 0.2, 1.0 / 3), 0.05 + 0.01 * i, material=m0 + i % 2) for i in range(5)])
    for b in yade.O.bodies:
        b.state.vel = (b.id, 2.0, 0.5)
    export.textExt(str(tmp_path / "m.txt"), format="x_y_z_r_matId")
    export.textExt(str(tmp_path / "a.txt"), format="x_y_z_r_attrs", attrs=["b.state.vel"])
    got = ymport.textExt(str(tmp_path / "m.txt"), format="x_y_z_r_matId")
    assert [(tuple(b.state.pos), b.shape.radius, b.material.label) for b in got] == \
        [(tuple(b.state.pos), b.shape.radius, b.material.label) for b in yade.O.bodies]
    attrs = []
    got = ymport.textExt(str(tmp_path / "a.txt"), format="x_y_z_r_attrs", attrs=attrs)
    assert len(got) == 5 and attrs == [[float(i), 2.0, 0.5] for i in range(5)]


def test_ymport_gts_reads_a_small_file(yade, tmp_path):
    (tmp_path / "t.gts").write_text("# a tetrahedron\n4 6 4 GtsSurface GtsFace GtsEdge GtsVertex\n"
                                    "0 0 0\n1 0 0\n0 1 0\n0 0 1\n1 2\n2 3\n3 1\n1 4\n2 4\n3 4\n"
                                    "1 5 4\n2 6 5\n3 4 6\n3 2 1\n")
    fs = ymport.gts(str(tmp_path / "t.gts"), shift=Vector3(1, 0, 0), scale=2, wire=False)
    assert len(fs) == 4 and not fs[0].shape.wire
    # face 1: edges (1 2), (2 4), (1 4) -> vertices 1, 2, 4 (e1's free end, the shared one, e2's free end)
    assert global_vertices(fs[:1]) == [[[1.0, 0.0, 0.0], [3.0, 0.0, 0.0], [1.0, 0.0, 2.0]]]
    s = gts.read(open(tmp_path / "t.gts"))
    assert s.is_closed() and abs(s.volume()) == pytest.approx(1 / 6)


def test_stl_written_and_read_back(yade, tmp_path):
    tri = torus(n=8, m=6) * [1.0, 2.0, 0.5] + [0.1, 0.2, 0.3]
    for binary in (False, True):
        path = tmp_path / f"t{int(binary)}.stl"
        meshfiles.write_stl(path, tri, binary=binary)
        got = np.array(global_vertices(ymport.stl(str(path))))
        # binary STL stores float32, and ASCII vertices are read as float32 as YADE reads them
        np.testing.assert_allclose(got, tri.astype(np.float32), rtol=1e-15, atol=1e-15)


# ----------------------------------------------------------------------------- bad input
STL = (DATA / "tet.stl").read_text()
GTS = "4 6 4\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n1 2\n2 3\n3 1\n1 4\n2 4\n3 4\n1 5 4\n2 6 5\n3 4 6\n3 2 1\n"
UNV = ("    -1\n  2411\n"
       + "".join(f"{i:10d}         0         0        11\n   {x:.16E}   {y:.16E}   0.0000000000000000E+00\n"
                 for i, x, y in ((1, 0.0, 0.0), (2, 1.0, 0.0), (3, 0.0, 1.0)))
       + "    -1\n    -1\n  2412\n         1        41         2         1         7         3\n"
       + "         1         2         3\n    -1\n")
MESH = ("MeshVersionFormatted 2\nDimension\n3\nVertices\n3\n0 0 0 1\n1 0 0 1\n0 1 0 1\nTriangles\n1\n1 2 3 1\nEnd\n")


def _binary_stl(tmp_path):
    meshfiles.write_stl(tmp_path / "b.stl", meshfiles.read_stl(DATA / "tet.stl"), binary=True)
    return (tmp_path / "b.stl").read_bytes()


BAD = {
    "stl_number": ("x.stl", lambda tp: STL.replace("vertex 0 1 0", "vertex 0 abc 0", 1), ymport.stl,
                   r"x\.stl: line 5: 'abc' is not a number"),
    "stl_truncated": ("x.stl", lambda tp: STL[: len(STL) // 2], ymport.stl, r"x\.stl: line 1[0-9]: "),
    "stl_cut_after_a_facet": ("x.stl", lambda tp: STL[: STL.index("endfacet") + 9], ymport.stl,
                              r"x\.stl: line 8: the file ends before 'endsolid'"),
    "stl_missing_vertex": ("x.stl", lambda tp: STL.replace("  vertex 0 0 1\n", "", 1), ymport.stl,
                           r"x\.stl: line \d+: expected 'vertex'"),
    "stl_degenerate": ("x.stl", lambda tp: STL.replace("vertex 0 0 1", "vertex 2 0 0", 1), ymport.stl,
                       r"x\.stl: triangle 2: degenerate"),
    "stl_binary_truncated": ("x.stl", lambda tp: _binary_stl(tp)[:-20], ymport.stl,
                             r"x\.stl: triangle 4: binary STL announces 4 triangles"),
    "gts_truncated": ("x.gts", lambda tp: GTS[:-12], ymport.gts, r"x\.gts: the file ends after 2 of its 4 faces"),
    "gts_bad_edge": ("x.gts", lambda tp: GTS.replace("3 2 1\n", "3 2 9\n"), ymport.gts,
                     r"x\.gts: line 15: face 4 names edge \[3, 2, 9\] outside 1\.\.6"),
    "gts_not_triangle": ("x.gts", lambda tp: GTS.replace("3 2 1\n", "3 2 5\n"), ymport.gts,
                         r"x\.gts: line 15: the edges \[3, 2, 5\] of face 4 do not form a triangle"),
    "gts_number": ("x.gts", lambda tp: GTS.replace("0 0 1\n", "0 0 z\n"), ymport.gts,
                   r"x\.gts: line 5: vertex 4: '0 0 z' is not numbers"),
    "gts_degenerate": ("x.gts", lambda tp: GTS.replace("0 0 1\n", "0.5 0.5 0\n"), ymport.gts,
                       r"x\.gts: line 13: face 2: degenerate"),
    "mesh_truncated": ("x.mesh", lambda tp: MESH[:-12], ymport.gmsh, r"x\.mesh: line 10: the file ends after 0 of "
                                                                     r"its 1 triangles"),
    "mesh_number": ("x.mesh", lambda tp: MESH.replace("1 0 0 1", "1 O 0 1"), ymport.gmsh,
                    r"x\.mesh: line 7: vertice 2: '1 O 0 1' is not numbers"),
    "mesh_degenerate": ("x.mesh", lambda tp: MESH.replace("0 1 0 1", "2 0 0 1"), ymport.gmsh,
                        r"x\.mesh: triangle 1: degenerate"),
    "unv_truncated": ("x.unv", lambda tp: UNV[:-11], ymport.unv, r"x\.unv: line 10: dataset 2412 is not closed"),
    "unv_number": ("x.unv", lambda tp: UNV.replace("1.0000000000000000E+00", "1.O", 1), ymport.unv,
                   r"x\.unv: line 6: .* does not fit dataset 2411"),
    "unv_degenerate": ("x.unv", lambda tp: UNV.replace("0.0000000000000000E+00   1.0000000000000000E+00",
                                                       "2.0000000000000000E+00   0.0000000000000000E+00"),
                       ymport.unv, r"x\.unv: element 1: degenerate"),
    "text_row": ("x.txt", lambda tp: "0 0 0 1\n0 0 0.5\n", ymport.text,
                 r"x\.txt: line 2: expected 4 numbers like the first row, found 3"),
    "facets_degenerate": ("x.txt", lambda tp: "0 0 0 1 0 0 2 0 0\n", ymport.textFacets, r"x\.txt: row 1: degenerate"),
    "clumps_columns": ("x.txt", lambda tp: "0 0 0 1\n", ymport.textClumps,
                       r"x\.txt: line 1: expected at least 5 columns, found 4"),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_bad_file_names_the_file_and_place_and_adds_nothing(yade, tmp_path, case):
    name, content, fn, message = BAD[case]
    data = content(tmp_path)
    path = tmp_path / name
    (path.write_bytes if isinstance(data, bytes) else path.write_text)(data)
    yade.O.bodies.append(yade.sphere((0, 0, 0), 1))
    with pytest.raises(MeshFileError, match=message):
        fn(str(path))
    assert len(yade.O.bodies) == 1


def test_small_unv_file(yade, tmp_path):
    (tmp_path / "t.unv").write_text(UNV)
    f, nodes, elements = ymport.unv(str(tmp_path / "t.unv"), shift=(0, 0, 1), returnConnectivityTable=True)
    assert global_vertices(f) == [[[0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [0.0, 1.0, 1.0]]]
    assert (nodes, elements) == ([(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0)], [(0, 1, 2)])


def test_missing_file_and_bad_arguments(yade, tmp_path):
    with pytest.raises(FileNotFoundError, match="nope.stl"):
        ymport.stl(str(tmp_path / "nope.stl"))
    with pytest.raises(NotImplementedError, match="noBound"):
        ymport.stl(str(DATA / "tet.stl"), noBound=True)
    with pytest.raises(TypeError, match="gts.Surface"):
        pack.inGtsSurface([1, 2, 3])
    with pytest.raises(RuntimeError, match="unknown format 'xyz'"):
        ymport.textFacets(str(DATA / "facets.txt"), format="xyz")


def test_a_missing_optional_package_says_how_to_install_it(yade, monkeypatch):
    import sys

    monkeypatch.setitem(sys.modules, "meshio", None)  # "import meshio" now raises ImportError
    with pytest.raises(ImportError, match=r"reading STL files needs the package 'meshio'.*pip install granum\[mesh\]"):
        ymport.stl(str(DATA / "tet.stl"))
    monkeypatch.setitem(sys.modules, "manifold3d", None)
    with pytest.raises(ImportError, match=r"boolean operations on gts surfaces needs the package 'manifold3d'"):
        gts.cube().union(gts.cube())


def test_predicate_padding_is_yades_six_point_test():
    """On a cube the padded test is exact; on a tetrahedron it tests the axes only (YADE's, measured)."""
    p = pack.inGtsSurface(gts.cube())
    assert p((0.5, 0.5, 0.5), 0.49) and not p((0.5, 0.5, 0.5), 0.51)
    assert p((1, 0, 0), 0) and not p((-1, 0, 0), 0)  # YADE: on x = 1 inside, on x = -1 outside
    s = gts.Surface()
    s._set_arrays(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1.]]), np.array([[0, 2, 1], [0, 1, 3],
                                                                                       [0, 3, 2], [1, 2, 3]]))
    t = pack.inGtsSurface(s)
    assert t((0.3, 0.3, 0.3), 0.09) and not t((0.3, 0.3, 0.3), 0.11)  # the slanted face is 0.058 away
    assert pack.inGtsSurface(s, noPad=True)((0.3, 0.3, 0.3), 0.5)
    assert math.isclose(s.volume(), 1 / 6)
