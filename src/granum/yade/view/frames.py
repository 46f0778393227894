"""What the browser view draws, taken from the scene's arrays in one go (NumPy only, no web library).

A :class:`Frame` is a copy of everything the page needs for one picture: sphere centres, radii and
colours (drawn as sphere impostors), the triangles of facets, boxes and walls, and line segments
(periodic cell, bounding boxes, contacts). :func:`take_frame` builds it with whole-column operations, so a
frame of 100,000 spheres costs a few milliseconds; it is called between compiled chunks of a run (never
inside the step loop) or while the simulation is idle.

Colours: ``field`` chooses what the bodies are coloured by (:data:`FIELDS`): their ``shape.color``, or a
scalar (speed, displacement from ``refPos``, id, radius, coordination number) mapped through a
colour map between the frame's minimum and maximum, which the page shows as a colour bar.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from granum.core.contacts import F_FN
from granum.core.shapes import ShapeKind, shape_type
from granum.yade import fields

#: body fields the view colours by; "color" is each body's own ``shape.color``
FIELDS = ("color", "velocity", "displacement", "id", "radius", "coordination")
#: colour map of scalar fields (a matplotlib name; the page's colour bar shows the same stops)
COLORMAP = "viridis"


class Frame(NamedTuple):
    """One picture's worth of data (float32 for the browser; ``S`` spheres, ``T`` triangles, ``L`` lines)."""

    iter: int
    time: float
    sphere_ids: np.ndarray       # (S,) int64 body ids
    sphere_pos: np.ndarray       # (S, 3) float32 centres drawn (wrapped into a periodic cell) [m]
    sphere_radius: np.ndarray    # (S,) float32 [m]
    sphere_rgb: np.ndarray       # (S, 3) uint8 colours
    tri_points: np.ndarray       # (T, 3, 3) float32 corners [m]
    tri_rgb: np.ndarray          # (T, 3) uint8 colours
    line_points: np.ndarray      # (L, 2, 3) float32 ends [m]
    line_rgb: np.ndarray         # (L, 3) uint8 colours
    field: str                   # what colours the bodies (one of FIELDS)
    value_range: tuple[float, float]  # the scalar field's range mapped onto the colour bar (0, 0 for "color")
    lights: tuple = ()           # ((position, focal point, RGB), ...) of the lights on, shining at the centre


class Options(NamedTuple):
    """The renderer options a frame honours (``qt.Renderer()``'s attributes of the same names)."""

    shape: bool = True
    wire: bool = False
    bound: bool = False
    intrPhys: bool = False
    intrWire: bool = False
    mask: int = -1
    ghosts: bool = True
    dispScale: tuple = (1.0, 1.0, 1.0)
    cellColor: tuple = (1.0, 1.0, 0.0)
    #: the lights on, ((position [m], RGB in [0, 1]), ...): YADE's light1/lightPos/lightColor and light2/...
    lights: tuple = ()
    #: the active clipping planes, ((point [m], unit normal), ...): bodies whose drawn centre is behind one
    #: are left out (``Renderer.clip_planes``, YADE's clipPlaneSe3/clipPlaneActive)
    clip_planes: tuple = ()


def _rgb(colors: np.ndarray) -> np.ndarray:
    return np.clip(np.asarray(colors, float) * 255.0 + 0.5, 0, 255).astype(np.uint8)


def colormap_rgb(values: np.ndarray, lo: float, hi: float) -> np.ndarray:
    """(M, 3) uint8 colours of ``values`` mapped linearly from [lo, hi] onto :data:`COLORMAP`."""
    import matplotlib

    t = (np.asarray(values, float) - lo) / (hi - lo) if hi > lo else np.zeros(len(values))
    return _rgb(matplotlib.colormaps[COLORMAP](np.clip(t, 0.0, 1.0))[:, :3])


def colormap_stops(n: int = 9) -> list[str]:
    """``n`` CSS colours along :data:`COLORMAP`, low to high (the page's colour bar)."""
    return ["#{:02x}{:02x}{:02x}".format(*c) for c in colormap_rgb(np.linspace(0, 1, n), 0.0, 1.0)]


def body_values(scene, ids: np.ndarray, field: str) -> np.ndarray:
    """(M,) the scalar ``field`` of bodies ``ids`` (speed [m/s], displacement [m], id, radius [m],
    number of contacts)."""
    b = scene.bodies
    if field == "velocity":
        return np.linalg.norm(b.vel[ids], axis=1)
    if field == "displacement":
        return np.linalg.norm(b.pos[ids] - b.ref_pos[ids], axis=1)
    if field == "id":
        return ids.astype(float)
    if field == "radius":
        radius = np.zeros(len(ids))
        spheres = b.shape_kind[ids] == int(ShapeKind.SPHERE)
        radius[spheres] = fields.sphere_radii(scene, ids[spheres])
        return radius
    if field == "coordination":
        return fields.coord_numbers(scene)[ids].astype(float)
    raise ValueError(f"view: cannot colour by {field!r}; fields: {', '.join(FIELDS)}")


def _displaced(scene, ids: np.ndarray, scale: np.ndarray) -> np.ndarray:
    """(M, 3) drawn positions: the reference position plus the displacement scaled per axis by
    ``dispScale`` (YADE's renderer scales displacements this way), wrapped into a periodic cell."""
    b = scene.bodies
    pos = b.pos[ids]
    if np.any(scale != 1.0):
        pos = b.ref_pos[ids] + (pos - b.ref_pos[ids]) * scale
    return pos + fields.wrap_shift(scene, ids)


def _box_edges(lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """(M * 12, 2, 3) edges of the axis-aligned boxes lo..hi, both (M, 3)."""
    corners = np.stack([np.where(np.array([i, j, k], bool), hi, lo)
                        for i in (0, 1) for j in (0, 1) for k in (0, 1)], axis=1)   # (M, 8, 3)
    pairs = [(p, q) for p in range(8) for q in range(p + 1, 8) if bin(p ^ q).count("1") == 1]
    return np.stack([corners[:, [p for p, _ in pairs]], corners[:, [q for _, q in pairs]]], axis=2).reshape(-1, 2, 3)


def _wall_quads(scene, ids: np.ndarray, extent: tuple[np.ndarray, np.ndarray]) -> np.ndarray:
    """(M, 4, 3) squares drawing the walls ``ids`` (infinite planes) across the box ``extent`` of the other
    bodies, as YADE draws a wall as a finite grid."""
    b = scene.bodies
    axis = scene.shapes[ShapeKind.WALL].axis[b.shape_row[ids]].astype(int)
    lo, hi = extent
    quads = np.empty((len(ids), 4, 3))
    for k, (i, a) in enumerate(zip(ids, axis, strict=True)):
        u, v = [d for d in range(3) if d != a]
        for c, (su, sv) in enumerate(((0, 0), (1, 0), (1, 1), (0, 1))):
            quads[k, c, a] = b.pos[i, a]
            quads[k, c, u] = (lo[u], hi[u])[su]
            quads[k, c, v] = (lo[v], hi[v])[sv]
    return quads


def take_frame(scene, options: Options | None = None, field: str = "color") -> Frame:
    """Copy what the view draws from ``scene`` now (see the module's docstring)."""
    if field not in FIELDS:
        raise ValueError(f"view: cannot colour by {field!r}; fields: {', '.join(FIELDS)}")
    options = options or Options()
    b = scene.bodies
    n = scene.body_count
    scale = np.asarray(options.dispScale, float)
    keep = b.alive[:n].copy()
    if options.mask != -1:
        keep &= (b.mask[:n] & options.mask) != 0
    if options.clip_planes:
        live = np.nonzero(keep)[0]
        keep[live[fields.clipped(_displaced(scene, live, scale), options.clip_planes)]] = False
    drawn = np.nonzero(keep)[0]
    if field == "color":
        value_range = (0.0, 0.0)
        colors = _rgb(b.color[drawn])
    else:
        values = body_values(scene, drawn, field)
        value_range = (float(values.min()), float(values.max())) if values.size else (0.0, 0.0)
        colors = colormap_rgb(values, *value_range)
    rows = np.full(n, -1)   # a drawn body's row in `colors`
    rows[drawn] = np.arange(drawn.size)
    kind = b.shape_kind[drawn]

    spheres = drawn[kind == int(ShapeKind.SPHERE)] if options.shape else drawn[:0]
    sphere_pos = _displaced(scene, spheres, scale)
    radius = fields.sphere_radii(scene, spheres)
    if scene.periodic and options.ghosts:
        spheres, sphere_pos, radius = _with_ghosts(scene, spheres, sphere_pos, radius)
    extent = (sphere_pos.min(axis=0), sphere_pos.max(axis=0)) if spheres.size else (np.zeros(3), np.ones(3))

    tris, tri_rgb, lines, line_rgb = [], [], [], []
    for k in scene.shapes if options.shape else ():
        if k == ShapeKind.SPHERE or shape_type(k).faces is None:
            continue
        ids = drawn[kind == int(k)]
        if not ids.size:
            continue
        shift = _displaced(scene, ids, scale) - b.pos[ids]
        faces = fields.body_faces(scene, k, ids) + shift[:, None, None, :]          # (M, F, V, 3)
        nf, nv = faces.shape[1:3]
        wire = b.wire[ids] | options.wire
        fans = np.concatenate([faces[~wire][:, :, [0, j, j + 1]] for j in range(1, nv - 1)], axis=1)
        tris.append(fans.reshape(-1, 3, 3))
        tri_rgb.append(np.repeat(colors[rows[ids[~wire]]], nf * (nv - 2), axis=0))
        outline = faces[wire]
        lines.append(np.stack([outline, np.roll(outline, -1, axis=2)], axis=3).reshape(-1, 2, 3))
        line_rgb.append(np.repeat(colors[rows[ids[wire]]], nf * nv, axis=0))
    walls = drawn[kind == int(ShapeKind.WALL)] if options.shape else drawn[:0]
    if walls.size:
        quads = _wall_quads(scene, walls, extent)
        tris.append(np.concatenate([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]]))
        tri_rgb.append(np.tile(colors[rows[walls]], (2, 1)))
    if options.bound:
        live = drawn[kind != int(ShapeKind.CLUMP)]
        lines.append(_box_edges(b.bound_min[live], b.bound_max[live]))
        line_rgb.append(np.tile(np.array([[255, 255, 0]], np.uint8), (len(live) * 12, 1)))
    if options.intrPhys or options.intrWire:
        ends, rgb = contact_lines(scene)
        lines.append(ends)
        line_rgb.append(rgb)
    if scene.periodic:
        h = np.asarray(scene.cell_hsize, float)
        unit = _box_edges(np.zeros((1, 3)), np.ones((1, 3)))
        lines.append(unit @ h.T)
        line_rgb.append(np.tile(_rgb(np.asarray(options.cellColor, float)[None]), (12, 1)))

    def stack(parts, shape, dtype):
        return np.concatenate(parts).astype(dtype) if parts else np.zeros((0, *shape), dtype)

    tri_points, line_points = stack(tris, (3, 3), np.float32), stack(lines, (2, 3), np.float32)
    return Frame(
        iter=int(scene.iter), time=float(scene.time), sphere_ids=spheres,
        sphere_pos=sphere_pos.astype(np.float32),
        sphere_radius=radius.astype(np.float32),
        sphere_rgb=colors[rows[spheres]],
        tri_points=tri_points, tri_rgb=stack(tri_rgb, (3,), np.uint8),
        line_points=line_points, line_rgb=stack(line_rgb, (3,), np.uint8),
        field=field, value_range=value_range,
        lights=_aimed(options.lights, [sphere_pos, tri_points.reshape(-1, 3), line_points.reshape(-1, 3)]))


def _aimed(lights, points) -> tuple:
    """``lights`` ((position, RGB), ...) as ((position, focal point, RGB), ...), each shining from its
    position at the centre of the box around ``points`` (arrays of (M, 3)): YADE's lights are points far
    from the scene (75 to 1500 m in its examples), whose rays are nearly parallel across it."""
    points = [p for p in points if len(p)]
    centre = ((np.min([p.min(axis=0) for p in points], axis=0) + np.max([p.max(axis=0) for p in points], axis=0)) / 2
              if points else np.zeros(3))
    return tuple((tuple(map(float, pos)), tuple(map(float, centre)), tuple(map(float, rgb))) for pos, rgb in lights)


def _with_ghosts(scene, ids, pos, radius):
    """Spheres plus their periodic images across each face of the cell they cross (YADE's ghosts): a sphere
    within its radius of a face is drawn again one cell vector away. Images across edges and corners (two or
    three faces at once) are not drawn."""
    h = np.asarray(scene.cell_hsize, float)
    frac = np.linalg.solve(h, pos.T).T                        # in [0, 1) inside the cell
    normals = np.linalg.inv(h)                                 # row k: normal of the faces k, scaled by 1/height
    reach = radius[:, None] * np.linalg.norm(normals, axis=1)  # the radius in fractional units, per axis
    parts_ids, parts_pos, parts_r = [ids], [pos], [radius]
    for k in range(3):
        for crossing, sign in ((frac[:, k] < reach[:, k], 1.0), (1.0 - frac[:, k] < reach[:, k], -1.0)):
            parts_ids.append(ids[crossing])
            parts_pos.append(pos[crossing] + sign * h[:, k])
            parts_r.append(radius[crossing])
    return np.concatenate(parts_ids), np.concatenate(parts_pos), np.concatenate(parts_r)


def contact_lines(scene) -> tuple[np.ndarray, np.ndarray]:
    """(K, 2, 3) segments between the centres of bodies in contact (to body 2's periodic image) and
    their (K, 3) uint8 colours, blue (no normal force) to red (the largest), YADE's force chains."""
    rows = fields.live_contact_rows(scene)
    id1, id2 = fields.contact_ids(scene, rows)
    shift = fields.wrap_shift(scene, id1)
    p1 = scene.bodies.pos[id1] + shift
    p2 = scene.bodies.pos[id2] + fields.contact_shift(scene, rows) + shift
    fn = np.linalg.norm(scene.contacts.con_f[rows, F_FN:F_FN + 3], axis=1)
    rel = fn / fn.max() if fn.size and fn.max() > 0 else fn
    x = rel[:, None]
    rgb = np.clip(np.concatenate([4 * x - 2, 2 - np.abs(4 * x - 2), 2 - 4 * x], axis=1), 0.0, 1.0)
    return np.stack([p1, p2], axis=1), _rgb(rgb)


def pick(frame: Frame, origin, direction) -> int:
    """The id of the sphere of ``frame`` that the ray ``origin + t * direction`` (t > 0) hits first, or -1.

    A body picked in the page: the browser sends the ray through the clicked pixel; the spheres are
    intersected exactly (``|o + t d - c| = r``), the nearest hit wins.
    """
    o = np.asarray(origin, float)
    d = np.asarray(direction, float)
    d = d / np.linalg.norm(d)
    rel = frame.sphere_pos.astype(float) - o
    along = rel @ d
    miss2 = np.einsum("ij,ij->i", rel, rel) - along ** 2
    r2 = frame.sphere_radius.astype(float) ** 2
    hit = (miss2 <= r2) & (along > 0)
    if not hit.any():
        return -1
    t = along - np.sqrt(np.maximum(r2 - miss2, 0.0))
    t[~hit] = np.inf
    return int(frame.sphere_ids[int(np.argmin(t))])
