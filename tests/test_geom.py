"""yade.geom's facet generators: YADE 2023.02a's facets in YADE's order (tests/reference/yade/geom.json), the
analytic surfaces they lie on, and refused arguments."""

import json
import math
from pathlib import Path

import numpy as np
import pytest

import granum.yade as yade
from granum.yade import geom

REF = json.loads((Path(__file__).parent / "reference" / "yade" / "geom.json").read_text())


def vertices(facets):
    """Global vertices of each facet, (N, 3, 3)."""
    return np.array([[np.asarray((f.state.pos + f.state.ori * v)._a) for v in f.shape.vertices] for f in facets])


def normals(tris):
    n = np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0])
    return n / np.linalg.norm(n, axis=1)[:, None]


def call(case):
    name, args, kw = REF[case]["call"]
    kw = dict(kw)
    if "orientation" in kw:
        kw["orientation"] = yade.Quaternion(*kw["orientation"])
    return getattr(geom, name)(*args, **kw)


CASES = [c for c, v in REF.items() if "facets" in v["result"]]
ERRORS = [c for c, v in REF.items() if v["result"].get("exception") == "RuntimeError"]


@pytest.mark.parametrize("case", CASES)
def test_facets_match_yade(case):
    """Same facets, same order, same vertex order (hence normals) as YADE."""
    out = call(case)
    ref = REF[case]["result"]
    if "nodes" in ref:
        out, nodes, elements = out
        np.testing.assert_allclose(nodes, ref["nodes"], atol=1e-12)
        assert [list(e) for e in elements] == ref["elements"]
    np.testing.assert_allclose(vertices(out), ref["facets"], atol=1e-12)
    if "attrs" in ref:
        assert [[list(f.shape.color), f.shape.wire, f.mask, f.dynamic] for f in out] == ref["attrs"]


@pytest.mark.parametrize("case", ERRORS)
def test_refused_like_yade(case):
    """What YADE refuses is refused, with a message naming the argument and its value."""
    name, args, kw = REF[case]["call"]
    with pytest.raises(RuntimeError) as err:
        call(case)
    assert isinstance(err.value, ValueError)
    bad = {**dict(zip(["center", "a", "b", "c", "d"], args, strict=False)), **kw}
    assert any(repr(v) in str(err.value) for k, v in bad.items() if k != "center"), str(err.value)


def test_polygon_default_range_is_a_full_turn():
    """YADE 2023.02a raises TypeError for facetPolygon without angleRange; its documentation says a full turn."""
    assert "exception" in REF["polygon_default_range"]["result"]
    tris = vertices(geom.facetPolygon((0, 0, 0), 2, segmentsNumber=4))
    assert len(tris) == 4
    np.testing.assert_allclose(vertices(geom.facetPolygon((0, 0, 0), 2, segmentsNumber=4, angleRange=(0, 2 * math.pi))),
                               tris)


def test_cylinder_on_its_surface():
    """A tilted, shifted cylinder: side vertices at the radius, caps at +-h/2, normals radial or axial,
    4 facets per segment."""
    c, r, h, n = np.array([1.0, -2.0, 0.5]), 0.7, 1.3, 24
    q = yade.Quaternion((1, 2, 3), 0.4)
    rot = np.asarray(q.toRotationMatrix()._a)
    tris = vertices(geom.facetCylinder(c, r, h, orientation=q, segmentsNumber=n))
    assert tris.shape == (4 * n, 3, 3)
    local = (tris - c) @ rot  # back to the cylinder's frame
    side, caps = local.reshape(n, 4, 3, 3)[:, 2:], local.reshape(n, 4, 3, 3)[:, :2]
    np.testing.assert_allclose(np.hypot(side[..., 0], side[..., 1]), r, rtol=1e-12)
    np.testing.assert_allclose(np.abs(side[..., 2]), h / 2, rtol=1e-12)
    np.testing.assert_allclose(caps[:, 0, :, 2], h / 2, rtol=1e-12)
    np.testing.assert_allclose(caps[:, 1, :, 2], -h / 2, rtol=1e-12)
    ns = normals(side.reshape(-1, 3, 3))
    np.testing.assert_allclose(ns[:, 2], 0, atol=1e-12)  # each vertex is half a segment from the normal's angle
    radial = side.reshape(-1, 3, 3) * [1, 1, 0] / r
    np.testing.assert_allclose(np.abs(np.einsum("ik,ijk->ij", ns, radial)), math.cos(math.pi / n), rtol=1e-12)
    np.testing.assert_allclose(np.abs(normals(caps.reshape(-1, 3, 3))[:, 2]), 1, rtol=1e-12)
    # the side's area tends to the lateral area 2 pi r h (a polygon of n sides: n * 2 r sin(pi/n) * h)
    area = 0.5 * np.linalg.norm(np.cross(side[..., 1, :] - side[..., 0, :], side[..., 2, :] - side[..., 0, :]),
                                axis=-1).sum()
    assert area == pytest.approx(n * 2 * r * math.sin(math.pi / n) * h, rel=1e-12)


def test_cone_helix_sphere_on_their_surfaces():
    """Cone vertices at radius linear in height; helix vertices at z = pitch * angle / 2 pi; sphere vertices
    at the radius with outward-or-inward normals consistent per band."""
    tris = vertices(geom.facetCone((0, 0, 0), 2.0, 1.0, 1.0, segmentsNumber=12, wallMask=4))
    rho = np.hypot(tris[..., 0], tris[..., 1])
    np.testing.assert_allclose(rho, 1.5 + tris[..., 2], rtol=1e-12)
    pitch, r_out, r_in = 0.3, 1.0, 0.25
    tris = vertices(geom.facetHelix((0, 0, 0), r_out, pitch, segmentsNumber=16, radiusInner=r_in,
                                    angleRange=(0, 4 * math.pi)))
    assert len(tris) == 32
    ang = np.unwrap(np.arctan2(tris[:, :, 1], tris[:, :, 0]).ravel(order="F")).reshape(3, -1).T
    rho = np.hypot(tris[..., 0], tris[..., 1])
    assert np.all(np.isclose(rho, r_out) | np.isclose(rho, r_in))
    phase = np.mod(tris[..., 2] * 2 * math.pi / pitch - ang + math.pi, 2 * math.pi) - math.pi
    np.testing.assert_allclose(phase, 0, atol=1e-9)
    c = np.array([1.0, 2.0, 3.0])
    facets, nodes, elements = geom.facetSphere(c, 2.0, thetaResolution=10, phiResolution=7, returnElementMap=True)
    tris = vertices(facets)
    assert len(tris) == 2 * 10 + 2 * 10 * (7 - 3) and len(nodes) == 2 + 10 * 5
    np.testing.assert_allclose(np.linalg.norm(tris - c, axis=2), 2.0, rtol=1e-12)
    np.testing.assert_allclose(tris, np.array(nodes)[np.array(elements)], rtol=0, atol=1e-14)


def test_parallelepiped_and_bunker():
    """A parallelepiped's +z face is its -z face shifted by sqrt(e2^2 - h^2) along x and up by 2h; a bunker's
    parts stack from its centre: pipe (radius dOutput/2), cone, cylinder (radius dBunker/2)."""
    e, h = np.array([1.0, 2.0, 3.0]), 1.5
    tris = vertices(geom.facetParallelepiped((0, 0, 0), e, h, wallMask=16 | 32))
    bottom, top = tris[:2].reshape(-1, 3), tris[2:].reshape(-1, 3)
    np.testing.assert_allclose(np.sort(top[:, 0]) - np.sort(bottom[:, 0]), math.sqrt(e[2] ** 2 - h ** 2), rtol=1e-12)
    np.testing.assert_allclose(top[:, 2] - bottom[:, 2], 2 * h)
    tris = vertices(geom.facetBunker((0, 0, 0), 2.0, 1.0, 3.0, 1.0, hPipe=0.5, segmentsNumber=8))
    z, rho = tris[..., 2], np.hypot(tris[..., 0], tris[..., 1])
    assert z.min() == 0 and z.max() == pytest.approx(4.5)
    np.testing.assert_allclose(rho[z < 0.5 - 1e-12], 0.5)
    np.testing.assert_allclose(rho[z > 1.5 + 1e-12], 1.0)
    assert not ((z > 0.5 + 1e-12) & (z < 1.5 - 1e-12)).any()  # the cone's vertices are on its rims only
    np.testing.assert_allclose(rho[np.isclose(z, 1.5)], 1.0)


def test_keywords_reach_utils_facet():
    f = geom.facetCylinder((0, 0, 0), 1, 1, segmentsNumber=3, wallMask=4, mask=6, wire=False, color=(0, 1, 0))
    assert {(b.mask, b.shape.wire, tuple(b.shape.color)) for b in f} == {(6, False, (0.0, 1.0, 0.0))}
    with pytest.raises(TypeError):
        geom.facetSphere((0, 0, 0), 1, unknownKeyword=1)


@pytest.mark.parametrize("call", [
    lambda: geom.facetCylinder((0, 0, 0), float("nan"), 1),
    lambda: geom.facetCylinder((0, 0, 0), 1, 1, segmentsNumber=4.5),
    lambda: geom.facetSphere((0, 0, 0), 1, thetaResolution=-3),
    lambda: geom.facetBunker((0, 0, 0), 2, 1, 3, 1, segmentsNumber=0),
    lambda: geom.facetPolygon((0, 0, 0), 1, radiusInner=-0.5),
    lambda: geom.facetBox((0, 0, 0), (1, 1, 1), wallMask=64),
])
def test_bad_values_refused(call):
    with pytest.raises(ValueError):
        call()
