"""Broad phase (InsertionSortCollider) against brute-force searches written here.

The collider may use any algorithm; what it must produce is fixed: the bound of a
body is the axis-aligned box of its shape enlarged by the Verlet distance, and the
potential pairs are exactly the pairs of live bodies whose bounds overlap (touching
counts) and whose masks share a bit. While bodies move, no geometric contact may be
missed even though the collider does not run every step.
"""

from __future__ import annotations

import numpy as np
import pytest
from conftest import frict_engines

from granum.core.contacts import C_COLLIDER_RUNS

BOUND_FUNCTORS = ("Bo1_Sphere_Aabb", "Bo1_Facet_Aabb", "Bo1_Wall_Aabb", "Bo1_Box_Aabb")


# ---- independent reference computations --------------------------------------------------

def rotation_matrix(q) -> np.ndarray:
    """Rotation matrix of a quaternion given as YADE orders it: (x, y, z, w)."""
    x, y, z, w = np.asarray(q, float) / np.linalg.norm(np.asarray(q, float))
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ])


def verlet_distance(yade, verlet_dist: float) -> float:
    """The enlargement: verletDist itself, or |verletDist| times the smallest sphere radius."""
    if verlet_dist >= 0:
        return verlet_dist
    radii = [b.shape.radius for b in yade.O.bodies if isinstance(b.shape, yade.Sphere)]
    return -verlet_dist * min(radii)


def facet_vertices(b) -> np.ndarray:
    """Global vertices (3, 3) of a facet body."""
    local = np.array([np.asarray(v, float) for v in b.shape.vertices])
    return np.asarray(b.state.pos, float) + local @ rotation_matrix(b.state.ori).T


def expected_bounds(yade, v: float):
    """Brute-force bounds (lo, hi), masks and liveness of all body ids."""
    O = yade.O
    n = len(O.bodies)
    lo = np.full((n, 3), np.inf)
    hi = np.full((n, 3), -np.inf)
    mask = np.zeros(n, np.int64)
    alive = np.zeros(n, bool)
    for i in range(n):
        b = O.bodies[i]
        if b is None:
            continue
        alive[i] = True
        mask[i] = b.mask
        c = np.asarray(b.state.pos, float)
        s = b.shape
        if isinstance(s, yade.Sphere):
            lo[i], hi[i] = c - s.radius - v, c + s.radius + v
        elif isinstance(s, yade.Facet):
            x = facet_vertices(b)
            lo[i], hi[i] = x.min(axis=0) - v, x.max(axis=0) + v
        elif isinstance(s, yade.Wall):
            lo[i], hi[i] = -np.inf, np.inf
            lo[i, s.axis], hi[i, s.axis] = c[s.axis] - v, c[s.axis] + v
        elif isinstance(s, yade.Box):
            half = np.abs(rotation_matrix(b.state.ori)) @ np.asarray(s.extents, float)
            lo[i], hi[i] = c - half - v, c + half + v
        else:  # pragma: no cover - the tests build no other shape
            raise AssertionError(f"unexpected shape {s!r}")
    return lo, hi, mask, alive


def brute_pairs(lo, hi, mask, alive) -> set:
    """All (i, j), i < j, of live bodies with overlapping bounds on all axes and a common mask bit."""
    ids = np.nonzero(alive)[0]
    out = set()
    for s in range(0, ids.size, 256):
        a = ids[s:s + 256]
        ok = np.all((lo[a, None, :] <= hi[None, ids, :]) & (lo[None, ids, :] <= hi[a, None, :]), axis=2)
        ok &= (mask[a, None] & mask[None, ids]) != 0
        ok &= ids[None, :] > a[:, None]
        p, q = np.nonzero(ok)
        out.update(zip(a[p].tolist(), ids[q].tolist(), strict=True))
    return out


def collider_pairs(O) -> list:
    """The pairs listed by O.interactions.all(onlyReal=False), as (min id, max id), in list order."""
    return [(min(i.id1, i.id2), max(i.id1, i.id2)) for i in O.interactions.all(onlyReal=False)]


def point_triangle_distance(p: np.ndarray, tri: np.ndarray) -> np.ndarray:
    """Distance of points ``p`` (N, 3) to the triangle ``tri`` (3, 3) (projection or edges)."""
    a, b, c = tri
    n = np.cross(b - a, c - a)
    n /= np.linalg.norm(n)
    d_plane = (p - a) @ n
    proj = p - d_plane[:, None] * n
    inside = np.ones(len(p), bool)  # projection inside: same side of the three edges
    for u, w in ((a, b), (b, c), (c, a)):
        inside &= np.cross(w - u, proj - u) @ n >= 0
    best = np.where(inside, np.abs(d_plane), np.inf)
    for u, w in ((a, b), (b, c), (c, a)):
        e = w - u
        t = np.clip((p - u) @ e / (e @ e), 0.0, 1.0)
        best = np.minimum(best, np.linalg.norm(p - (u + t[:, None] * e), axis=1))
    return best


# ---- scenes ------------------------------------------------------------------------------

def static_engines(yade, verlet_dist):
    """Collider only: nothing moves, so the bounds and pairs can be recomputed exactly."""
    kw = {} if verlet_dist is None else {"verletDist": verlet_dist}
    return [yade.ForceResetter(), yade.InsertionSortCollider([getattr(yade, f)() for f in BOUND_FUNCTORS], **kw)]


def unit(rng) -> np.ndarray:
    v = rng.normal(size=3)
    return v / np.linalg.norm(v)


def add_spheres(yade, centers, radii, masks=None):
    masks = np.ones(len(radii), int) if masks is None else masks
    return yade.O.bodies.append([yade.sphere(tuple(c), float(r), mask=int(m))
                                 for c, r, m in zip(centers, radii, masks, strict=True)])


def build_dense(yade, seed, n=2000):
    """Random cloud (radius ratio up to 4, mixed masks) in a facet box, with random facets,
    walls through the cloud and rotated boxes; masks exclude some pairs."""
    rng = np.random.default_rng(seed)
    r0 = 0.01
    side = 0.7 * (n / 2000) ** (1 / 3)
    radii = r0 * (1 + 3 * rng.random(n))
    centers = rng.random((n, 3)) * side
    add_spheres(yade, centers, radii, rng.choice([1, 2, 3, 4, 5], size=n))
    O = yade.O
    O.bodies.append(yade.geom.facetBox((side / 2,) * 3, (side / 2,) * 3))
    for k in range(8):  # small facets (binned with the spheres) and large ones
        size = (0.02 if k % 2 else 0.6) * side
        p = rng.random(3) * side
        O.bodies.append(yade.facet([tuple(p + size * unit(rng)) for _ in range(3)], mask=4 if k == 3 else 1))
    O.bodies.append([yade.wall(side / 3, 0), yade.wall(0.6 * side, 1, mask=2),
                     yade.wall((0, 0, 0.25 * side), 2, mask=6)])
    O.bodies.append(yade.box((side / 2,) * 3, (0.1, 0.2, 0.04),
                             orientation=yade.Quaternion(tuple(unit(rng)), 0.7), mask=6))
    O.bodies.append(yade.box(tuple(rng.random(3) * side), (0.01, 0.02, 0.015),
                             orientation=yade.Quaternion(tuple(unit(rng)), 2.1)))


def build_sparse(yade, seed):
    """300 spheres of radius 0.01 spread over a 1e4 box (most cells empty), some in close pairs,
    some touching a wall, a facet or a rotated box."""
    rng = np.random.default_rng(seed)
    L, r = 1e4, 0.01
    centers = list(rng.random((150, 3)) * L)
    for _ in range(50):  # close pairs: bounds overlapping or not
        c = rng.random(3) * L
        centers += [c, c + rng.uniform(0.005, 0.06) * unit(rng)]
    for _ in range(25):  # near the wall x = L/2
        c = rng.random(3) * L
        c[0] = L / 2 + rng.uniform(-0.03, 0.03)
        centers.append(c)
    facet_p = np.array([0.3, 0.6, 0.2]) * L
    box_c = np.array([0.7, 0.2, 0.8]) * L
    for _ in range(12):
        centers.append(facet_p + rng.uniform(-0.05, 0.05, 3))
        centers.append(box_c + rng.uniform(-0.08, 0.08, 3))
    centers = np.array(centers)
    add_spheres(yade, centers, np.full(len(centers), r), rng.choice([1, 1, 1, 2], size=len(centers)))
    O = yade.O
    O.bodies.append(yade.facet([tuple(facet_p + 0.04 * unit(rng)) for _ in range(3)]))
    O.bodies.append(yade.wall(L / 2, 0, mask=3))
    O.bodies.append(yade.box(tuple(box_c), (0.03, 0.05, 0.02), orientation=yade.Quaternion(tuple(unit(rng)), 1.0)))
    O.bodies.append(yade.geom.facetBox((L / 2,) * 3, (L / 2,) * 3))


def build_lattice(yade, seed, n=8):
    """Spheres of radius 0.5 on an integer lattice: all 26 neighbours' bounds touch exactly."""
    g = np.arange(n, dtype=float)
    centers = np.stack(np.meshgrid(g, g, g, indexing="ij"), axis=-1).reshape(-1, 3)
    add_spheres(yade, centers, np.full(len(centers), 0.5))


def build_outliers(yade, seed):
    """A small cloud and a few spheres that escaped very far (the grid spans 1e7 m)."""
    rng = np.random.default_rng(seed)
    n = 300
    add_spheres(yade, rng.random((n, 3)) * 0.5, 0.01 * (1 + 3 * rng.random(n)))
    add_spheres(yade, [(1e7, 1e7, 1e7), (-1e7, -1e7, -1e7), (1e7, -1e7, 1e7 + 0.01)], [0.02, 0.02, 0.02])
    yade.O.bodies.append(yade.wall(0.25, 2))


def build_escaped(yade, seed):
    """A cluster of overlapping spheres and one that escaped 2**21 diameters away on each axis
    (a grid of sphere-sized cells would have 2**63 of them; a sweep and prune does not care)."""
    rng = np.random.default_rng(seed)
    cluster = np.vstack([np.zeros(3), rng.integers(0, 12, (20, 3)) * 0.25])  # exact bounds
    add_spheres(yade, cluster, np.full(21, 0.5))
    add_spheres(yade, [(2 ** 21 - 1,) * 3], [0.5])


def build_mesh_first(yade, seed):
    """A drum of facets appended before the spheres (the facets have the lower ids), spheres inside and across
    its wall, facets wholly outside the spheres' grid (their cells are clamped) and one facet spanning a
    hundred times the drum (too many cells: tested against all bodies)."""
    rng = np.random.default_rng(seed)
    O = yade.O
    O.bodies.append(yade.geom.facetCylinder((0, 0, 0), 0.2, 0.3, segmentsNumber=24, wallMask=7))
    O.bodies.append([yade.facet([tuple(np.array(c) + 0.15 * unit(rng)) for _ in range(3)])
                     for c in ((0.6, 0, 0), (0, -0.5, 0.4))])
    O.bodies.append(yade.facet([(-20, -20, 0.01), (20, -20, 0.02), (0, 20, -0.01)]))
    n = 1500
    rho = 0.21 * np.sqrt(rng.random(n))
    phi = 2 * np.pi * rng.random(n)
    centers = np.stack([rho * np.cos(phi), rho * np.sin(phi), rng.uniform(-0.16, 0.16, n)], axis=1)
    add_spheres(yade, centers, 0.008 * (1 + rng.random(n)))


BUILDERS = {"dense": build_dense, "mesh_first": build_mesh_first, "sparse": build_sparse,
            "lattice": build_lattice, "outliers": build_outliers,
            "escaped": build_escaped,
            "parallel": lambda y, s: build_dense(y, s, n=4500)}  # over granum's PARALLEL_THRESHOLD (4096)


def run_static(yade, scene, seed, verlet_dist):
    BUILDERS[scene](yade, seed)
    yade.O.engines = static_engines(yade, verlet_dist)
    yade.O.step()
    return verlet_distance(yade, -0.5 if verlet_dist is None else verlet_dist)


STATIC_CASES = [
    ("dense", 1, None), ("dense", 2, 0.0), ("dense", 3, 0.004), ("dense", 4, -0.3),
    ("sparse", 5, None), ("sparse", 6, 0.02), ("sparse", 7, 0.0),
    ("lattice", 0, 0.0), ("lattice", 0, None),
    ("outliers", 8, None), ("escaped", 10, 0.0),
    ("parallel", 9, None), ("mesh_first", 11, None), ("mesh_first", 12, 0.0),
]


# ---- 1. pairs == brute force ---------------------------------------------------------------

@pytest.mark.parametrize(("scene", "seed", "verlet_dist"), STATIC_CASES)
def test_pairs_are_exactly_the_brute_force_overlaps(yade, scene, seed, verlet_dist):
    """The potential pairs are exactly the mask-compatible bound overlaps found by an O(N^2) search."""
    v = run_static(yade, scene, seed, verlet_dist)
    expected = brute_pairs(*expected_bounds(yade, v))
    listed = collider_pairs(yade.O)
    found = set(listed)
    assert len(expected) > 0
    missing = sorted(expected - found)
    extra = sorted(found - expected)
    assert not missing, f"{len(missing)} pairs missed, e.g. {missing[:5]}"
    assert not extra, f"{len(extra)} pairs without overlapping bounds or masks, e.g. {extra[:5]}"
    assert listed == sorted(found), "pairs must be listed by (id1, id2), without duplicates"
    assert yade.O.interactions.countReal() == 0
    assert len(yade.O.interactions) == len(expected)


def test_lattice_has_the_26_touching_neighbours(yade):
    """Touching bounds count: a cubic lattice of touching spheres (verletDist=0) pairs all 26 neighbours."""
    n = 8
    run_static(yade, "lattice", 0, 0.0)
    pairs = set(collider_pairs(yade.O))
    assert len(pairs) == 3 * (n - 1) * n * n + 6 * (n - 1) ** 2 * n + 4 * (n - 1) ** 3
    centre = (3 * n + 3) * n + 3  # sphere (3, 3, 3)
    assert sum(centre in p for p in pairs) == 26


def test_masks_exclude_pairs(yade):
    """Bodies whose masks share no bit are never paired, even with overlapping bounds."""
    O = yade.O
    O.bodies.append([yade.sphere((0, 0, 0), 1, mask=1), yade.sphere((1, 0, 0), 1, mask=2),
                     yade.sphere((0, 1, 0), 1, mask=3), yade.sphere((1, 1, 0), 1, mask=4),
                     yade.wall(0.5, 0, mask=4), yade.box((0.5, 0.5, 0), (0.2, 0.2, 0.2), mask=8)])
    O.engines = static_engines(yade, 0.1)
    O.step()
    assert collider_pairs(O) == [(0, 2), (1, 2), (3, 4)]


def test_avoid_self_interaction_mask_excludes_pairs_of_equal_masks(yade):
    """avoidSelfInteractionMask: equal masks sharing a bit with it do not pair (as real YADE 2023.02a)."""
    O = yade.O
    O.bodies.append([yade.sphere((0, 0, 0), 1), yade.sphere((2.5, 0, 0), 1), yade.sphere((0, 2.5, 0), 1, mask=3),
                     yade.sphere((2.5, 2.5, 0), 1, mask=3), yade.sphere((5, 0, 0), 1, mask=2)])
    O.engines = [yade.ForceResetter(),
                 yade.InsertionSortCollider([yade.Bo1_Sphere_Aabb()], verletDist=1.0, avoidSelfInteractionMask=2)]
    O.step()
    # real YADE lists (0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (3, 4): not (2, 3) (same mask 3, 3 & 2 != 0)
    assert collider_pairs(O) == [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (3, 4)]


# ---- 2. bounds == brute force --------------------------------------------------------------

@pytest.mark.parametrize(("scene", "seed", "verlet_dist"),
                         [c for c in STATIC_CASES if c[0] in ("dense", "sparse")])
def test_bounds_are_the_shape_aabbs_enlarged_by_the_verlet_distance(yade, scene, seed, verlet_dist):
    """body.bound.min/max equal the brute-force Aabb of the shape enlarged by the Verlet distance."""
    v = run_static(yade, scene, seed, verlet_dist)
    lo, hi, _, _ = expected_bounds(yade, v)
    got_lo = np.array([np.asarray(b.bound.min, float) for b in yade.O.bodies])
    got_hi = np.array([np.asarray(b.bound.max, float) for b in yade.O.bodies])
    scale = 1e-13 * max(1.0, np.abs(lo[np.isfinite(lo)]).max())
    np.testing.assert_array_equal(np.isinf(got_lo), np.isinf(lo))
    np.testing.assert_array_equal(np.isinf(got_hi), np.isinf(hi))
    np.testing.assert_allclose(got_lo, lo, rtol=0, atol=scale)
    np.testing.assert_allclose(got_hi, hi, rtol=0, atol=scale)


def test_negative_verlet_distance_follows_the_smallest_sphere(yade):
    """verletDist < 0 is relative to the smallest sphere radius, also after a smaller sphere is added."""
    O = yade.O
    O.bodies.append([yade.sphere((0, 0, 0), 0.2), yade.sphere((1, 0, 0), 0.1)])
    O.engines = static_engines(yade, -0.5)
    O.step()
    assert np.asarray(O.bodies[0].bound.min) == pytest.approx([-0.25] * 3, abs=1e-15)
    O.bodies.append(yade.sphere((3, 0, 0), 0.02))
    O.step()
    assert np.asarray(O.bodies[0].bound.max) == pytest.approx([0.21] * 3, abs=1e-15)
    assert np.asarray(O.bodies[2].bound.min) == pytest.approx([2.97, -0.03, -0.03], abs=1e-15)


# ---- 3. no contact missed while bodies move ------------------------------------------------

def falling_cloud(yade, seed, num=700):
    """Tutorial-02-like: a random loose cloud in a closed facet box, under gravity, with random velocities."""
    O = yade.O
    facets = O.bodies.append(yade.geom.facetBox((0.5, 0.5, 0.5), (0.5, 0.5, 0.5)))
    sp = yade.pack.SpherePack()
    sp.makeCloud((0, 0, 0), (1, 1, 1), rMean=0.03, rRelFuzz=0.5, num=num, seed=seed)
    spheres = sp.toSimulation()
    rng = np.random.default_rng(seed)
    for i in spheres:
        O.bodies[i].state.vel = tuple(rng.normal(scale=1.5, size=3))
    O.engines = frict_engines(yade, gravity=(0, 0, -9.81), damping=0.4)
    O.dt = 0.5 * yade.PWaveTimeStep()
    return facets, spheres


class ContactChecker:
    """Checks, for the positions a step starts from, that the geometric contacts are exactly real."""

    def __init__(self, yade, facets):
        self.O = yade.O
        self.yade = yade
        self.facets = {f: facet_vertices(yade.O.bodies[f]) for f in facets}
        self.checked = 0
        self.touching = set()  # ids of the spheres seen in contact

    def spheres(self):
        O = self.O
        ids = [b.id for b in O.bodies if isinstance(b.shape, self.yade.Sphere)]
        pos = np.array([np.asarray(O.bodies[i].state.pos, float) for i in ids])
        rad = np.array([O.bodies[i].shape.radius for i in ids])
        return np.array(ids), pos, rad

    def step(self):
        ids, pos, rad = self.spheres()  # the positions the collider and InteractionLoop see
        self.O.step()
        O = self.O
        d = np.linalg.norm(pos[:, None, :] - pos[None, :, :], axis=2)
        touch = np.triu(d < rad[:, None] + rad[None, :], 1)
        for a, b in zip(*np.nonzero(touch), strict=True):
            assert O.interactions.has(int(ids[a]), int(ids[b]), onlyReal=True), \
                f"iter {O.iter}: spheres {ids[a]} and {ids[b]} overlap but do not interact"
        self.checked += int(touch.sum())
        self.touching.update(ids[np.nonzero(touch.any(axis=0) | touch.any(axis=1))[0]].tolist())
        dist_facet = {f: point_triangle_distance(pos, tri) for f, tri in self.facets.items()}
        for f, dist in dist_facet.items():
            for a in np.nonzero(dist < rad)[0]:
                assert O.interactions.has(f, int(ids[a]), onlyReal=True), \
                    f"iter {O.iter}: sphere {ids[a]} touches facet {f} but does not interact"
                self.checked += 1
        row = {int(i): k for k, i in enumerate(ids)}
        for intr in O.interactions:
            i1, i2 = intr.id1, intr.id2
            if i1 in row and i2 in row:
                a, b = row[i1], row[i2]
                assert d[a, b] <= rad[a] + rad[b] + 1e-12, f"iter {O.iter}: ({i1}, {i2}) real but apart"
            elif i1 in dist_facet and i2 in row:
                assert dist_facet[i1][row[i2]] <= rad[row[i2]] + 1e-12, f"iter {O.iter}: ({i1}, {i2}) apart"


def test_no_contact_is_missed_while_bodies_move(yade):
    """Falling cloud: every step, geometric contacts == real ones, though the collider seldom runs."""
    facets, spheres = falling_cloud(yade, seed=11)
    O = yade.O
    check = ContactChecker(yade, facets)
    steps = 300
    for _ in range(steps):
        check.step()
    runs = int(O._scene.contacts.ctr[C_COLLIDER_RUNS])
    assert check.checked > 1000, "the test must see many contacts"
    assert 3 <= runs <= steps // 10, f"the collider ran {runs} times in {steps} steps"


def test_no_contact_is_missed_when_all_but_one_move_together(yade):
    """A lattice of separate spheres drifting as one, one of them sliding sideways into its neighbour: the
    detection's common bound of all motions is small, and the contact still appears in the first step
    the two overlap."""
    O = yade.O
    r, n = 0.01, 5
    s = 2.5 * r
    spheres = O.bodies.append([yade.sphere((i * s, j * s, k * s), r) for k in range(n) for j in range(n)
                               for i in range(n)])
    for i in spheres:
        O.bodies[i].state.vel = (0.5, 0.0, -0.2)
    mover = spheres[62]  # the centre sphere, towards its neighbour along -y and (less) along +x
    O.bodies[mover].state.vel = (0.7, -1.0, -0.2)
    O.engines = frict_engines(yade)
    O.dt = 0.2 * yade.PWaveTimeStep()
    check = ContactChecker(yade, [])
    while check.checked < 20 and O.iter < 2000:
        check.step()
    assert check.checked >= 20 and check.touching == {mover, mover - n}


def test_no_contact_is_missed_by_a_turning_facet(yade):
    """A long facet turning about its centre sweeps its tip through a sphere at rest: only its rotation
    moves anything, and every step the interaction is real exactly when the sphere touches the turned
    facet."""
    O = yade.O
    r = 0.02
    facet = O.bodies.append(yade.facet([(0, -0.1, 0), (0, 0.1, 0), (0.5, 0, 0)]))  # centre near x = 0.09
    ball = O.bodies.append(yade.sphere((0.45, 0, 0.1), r))
    b = O.bodies[facet]
    b.state.blockedDOFs = "xyzXYZ"
    b.state.angVel = (0, -2.0, 0)  # the tip at x = 0.5 rises towards the ball
    O.engines = frict_engines(yade)
    O.dt = 1e-4
    touched = []
    for _ in range(1500):
        dist = point_triangle_distance(np.asarray(O.bodies[ball].state.pos, float)[None, :],
                                       facet_vertices(O.bodies[facet]))[0]
        O.step()
        real = O.interactions.has(facet, ball, onlyReal=True)
        assert real == (dist < r), f"iter {O.iter}: distance {dist}, interaction real: {real}"
        touched.append(real)
    assert any(touched) and not touched[0]


def test_no_contact_is_missed_in_a_turning_box(yade):
    """The falling cloud in its facet box turning about the box's centre, over several collider runs: after
    the first run the budgets of sphere-facet pairs hold the rotation allowance that the last interval saw
    (the sphere pairs' bound leaves the facets' rotation out), and still every step the geometric contacts
    are exactly the real ones."""
    from granum.core.arrays import S_TURN_ALLOWANCE

    facets, _ = falling_cloud(yade, seed=5, num=300)
    O = yade.O
    turn = yade.RotationEngine(ids=facets, rotationAxis=(1, 1, 0), angularVelocity=3.0, rotateAroundZero=True,
                               zeroPoint=(0.5, 0.5, 0.5))
    O.engines = O.engines[:3] + [turn] + O.engines[3:]  # O.engines is a copy, as in YADE: insert into it does nothing
    check = ContactChecker(yade, facets)
    allowances = set()
    for _ in range(300):
        check.facets = {f: facet_vertices(O.bodies[f]) for f in facets}
        check.step()
        allowances.add(float(O._scene.scal[S_TURN_ALLOWANCE]))
    runs = int(O._scene.contacts.ctr[C_COLLIDER_RUNS])
    assert check.checked > 1000 and runs >= 3
    assert len(allowances) >= 3 and min(allowances) == 0.0  # a new allowance per run, none before the first


def test_no_contact_is_missed_by_a_sphere_swinging_back(yade):
    """A sphere swings to and fro above another that creeps towards its path, with a Verlet distance so
    large that the collider never runs again: a pair's budget is measured from where it was last
    evaluated, so the sphere coming back over its partner, after an evaluation far from it, is seen in
    the first step the two overlap."""
    O = yade.O
    r, amplitude = 0.01, 0.05
    below, swinging = O.bodies.append([yade.sphere((0, 0, 0), r, fixed=True), yade.sphere((0, 3 * r, 0), r,
                                                                                          fixed=True)])
    O.bodies[below].state.vel = (0, 0.1, 0)  # 1.5 r towards the swinging sphere's path in 1500 steps
    O.engines = frict_engines(yade)
    O.engines[1].verletDist = 3 * amplitude
    swing = yade.HarmonicMotionEngine(ids=[swinging], A=(amplitude, 0, 0), f=(20, 0, 0))
    O.engines = O.engines[:2] + [swing] + O.engines[2:]
    O.dt = 1e-4
    check = ContactChecker(yade, [])
    while O.iter < 1500:
        check.step()
    assert int(O._scene.contacts.ctr[C_COLLIDER_RUNS]) == 1
    # overlap is possible in the last 500 steps only, for up to 40 steps per pass of the swinging sphere (6 m/s
    # across a chord of at most 2.6 r), twice: about 50 checked contacts
    assert check.checked >= 20 and check.touching == {below, swinging}


# ---- 4. erasing and appending bodies during a run ------------------------------------------

def test_erased_body_loses_its_interactions_and_is_never_paired_again(yade):
    """Erasing a body ends its real interactions at once; later collider runs never pair it."""
    facets, spheres = falling_cloud(yade, seed=12, num=400)
    O = yade.O
    O.run(60, True)
    k = max(spheres, key=lambda i: len(O.bodies[i].intrs()))
    partners = {i.id1 + i.id2 - k for i in O.bodies[k].intrs()}
    assert partners
    n_real = O.interactions.countReal()
    runs = int(O._scene.contacts.ctr[C_COLLIDER_RUNS])
    assert O.bodies.erase(k)
    assert O.bodies[k] is None
    assert O.interactions.countReal() == n_real - len(partners)
    assert O.interactions.withBody(k) == []
    assert not any(O.interactions.has(k, j, onlyReal=True) for j in partners)
    for _ in range(150):
        O.step()
        assert all(k not in (i.id1, i.id2) for i in O.interactions.all(onlyReal=False))
    assert O._scene.contacts.ctr[C_COLLIDER_RUNS] > runs + 1, "the collider must have run again"
    # the pairs are still exactly the overlaps of the live bodies' bounds (from the last collider run)
    n = len(O.bodies)
    lo, hi = np.full((n, 3), np.inf), np.full((n, 3), -np.inf)
    mask, alive = np.zeros(n, np.int64), np.zeros(n, bool)
    for b in O.bodies:
        lo[b.id], hi[b.id] = np.asarray(b.bound.min), np.asarray(b.bound.max)
        mask[b.id], alive[b.id] = b.mask, True
    assert not alive[k]
    assert set(collider_pairs(O)) == brute_pairs(lo, hi, mask, alive)


def test_erasing_a_body_removes_its_potential_interactions_at_once(yade):
    """After O.bodies.erase(k) no interaction, potential or real, involves k (as in real YADE)."""
    O = yade.O
    O.bodies.append([yade.sphere((0, 0, 0), 1), yade.sphere((2.5, 0, 0), 1), yade.sphere((0, 2.5, 0), 1)])
    O.engines = static_engines(yade, 1.0)
    O.step()
    assert collider_pairs(O) == [(0, 1), (0, 2), (1, 2)]
    O.bodies.erase(1)
    # real YADE 2023.02a: O.interactions.all(False) gives (0, 2) only, has(0, 1) is False
    assert collider_pairs(O) == [(0, 2)]
    assert not O.interactions.has(0, 1)
    assert O.interactions.withBodyAll(1) == []


def test_bodies_appended_between_runs_interact(yade):
    """Bodies appended between O.run(n, True) calls are paired at the next step and make contacts."""
    facets, spheres = falling_cloud(yade, seed=13, num=400)
    O = yade.O
    rng = np.random.default_rng(13)
    O.run(50, True)
    # a sphere overlapping an existing one, and one pressed onto the bottom face
    s = O.bodies[spheres[17]]
    r_new = 0.02
    direction = unit(rng)
    a = O.bodies.append(yade.sphere(tuple(np.asarray(s.state.pos) + direction * (s.shape.radius + r_new - 0.003)),
                                    r_new))
    b = O.bodies.append(yade.sphere((0.123, 0.456, 0.5 * r_new), r_new))
    O.run(1, True)
    assert O.interactions.has(a, s.id, onlyReal=True)
    bottom = [f for f in facets if point_triangle_distance(np.array([[0.123, 0.456, 0.0]]),
                                                           facet_vertices(O.bodies[f]))[0] < 1e-12]
    assert any(O.interactions.has(f, b, onlyReal=True) for f in bottom)
    # a batch appended next to existing spheres, thrown at them, checked every step like the cloud
    ids0, pos, rad = ContactChecker(yade, facets).spheres()
    new, vel = [], []
    while len(new) < 40:
        k, r, n = rng.integers(len(ids0)), rng.uniform(0.015, 0.03), unit(rng)
        c = pos[k] + n * (rad[k] + r + rng.uniform(0.0005, 0.003))
        if np.all(np.abs(c - 0.5) < 0.5 - r) and np.all(np.linalg.norm(pos - c, axis=1) > rad + r):
            pos, rad = np.vstack([pos, c]), np.append(rad, r)
            new.append(yade.sphere(tuple(c), r))
            vel.append(tuple(-1.5 * n))
    ids = O.bodies.append(new)
    for i, v in zip(ids, vel, strict=True):
        O.bodies[i].state.vel = v
    check = ContactChecker(yade, facets)
    for _ in range(80):
        check.step()
    assert len(check.touching & set(ids)) >= 20, "the new spheres must have collided"


def test_pair_budgets_are_rounded_down_to_float32():
    """A stored budget (float32) never exceeds the separation it was computed from, and loses
    at most three float32 steps (granum.kernels.motion.budget_f32); the float32 values themselves stay."""
    from granum.kernels.motion import budget_f32

    rng = np.random.default_rng(7)
    xs = np.concatenate([rng.uniform(0, 1e-2, 500), rng.uniform(-1e-3, 1e-3, 100), 10.0 ** rng.uniform(-30, 3, 400),
                         [0.0, 0.1, 1 / 3, np.inf, -np.inf, 1e-44, -1e-44, 5e-46, -5e-46, 1e-40, -1e-40, 1e39, -1e39],
                         rng.uniform(-1, 1, 100).astype(np.float32).astype(float)])   # float32 values
    for x in xs:
        g = np.float32(budget_f32(float(x)))
        assert float(g) <= x
        if np.isfinite(x) and abs(x) <= np.finfo(np.float32).max:
            assert x - float(g) <= 3 * float(np.spacing(np.float32(abs(x)))) * 1.0001
            if float(np.float32(x)) == x:
                assert float(g) == x
