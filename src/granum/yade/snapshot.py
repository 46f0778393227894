"""Pictures of the scene without a screen: the 3D view, its renderer options and ``SnapshotEngine``.

YADE draws its 3D view with OpenGL in a Qt window; ``qt.SnapshotEngine`` saves that window to
image files. granum has no window, so :class:`View` keeps the camera of such a view and
:func:`render` draws the scene with the software rasteriser of :mod:`granum.io.raster`:

* spheres as shaded balls in their ``color``, the other shapes as flat-shaded polygons, those their
  declaration gives (``ShapeType.faces`` in :mod:`granum.core.shapes`: facets as triangles, boxes as
  their six faces; walls are not drawn); bodies with ``wire`` (facets by default, as in YADE) as outlines;
* with ``Renderer().intrPhys``, contacts as cylinders between the body centres, their width and
  colour (blue to red) scaled by the normal force (force chains); ``intrWire`` draws thin lines;
* the periodic cell's edges in ``Renderer().cellColor``; the iteration and time in a corner
  (``View.timeDisp`` letters ``i``, ``v``, ``r`` as in YADE);
* in a periodic scene, bodies inside the cell (as YADE draws them; positions stay unwrapped in
  the scene and in output files), contacts from body 1 to the periodic image of body 2.

The default camera is YADE's: looking down the z axis (``viewDir = (0, 0, -1)``, ``upVector =
(0, 1, 0)``), perspective with a 45 degree field of view, framing the bounding box of the body
positions (or the periodic cell) when the view is opened. Pictures are 550 x 550 pixels
(``View.screenSize``) and written atomically.
"""

from __future__ import annotations

import time

import numpy as np

from granum.core.attrs import Attr, Attributed, to_bool, to_float, to_int, to_str
from granum.core.contacts import F_FN
from granum.core.shapes import ShapeKind, shape_type
from granum.engines.base import PeriodicEngine
from granum.io.atomic import atomic_path
from granum.io.raster import Canvas
from granum.mathtypes import Quaternion, Vector2i, Vector3
from granum.yade import fields

_FOV = np.pi / 4  # vertical field of view of a perspective view (QGLViewer's default)
# PIL format name and file extension of the formats SnapshotEngine.format accepts.
_FORMATS = {"PNG": ("PNG", "png"), "JPEG": ("JPEG", "jpeg"), "JPG": ("JPEG", "jpg"), "BMP": ("BMP", "bmp"),
            "PPM": ("PPM", "ppm")}
_START = time.time()


def _vec3(owner, value):
    return Vector3(*(float(x) for x in value))


#: clipping planes of the 3D view (YADE's ``OpenGLRenderer::numClipPlanes``)
NUM_CLIP_PLANES = 3


def _clip_se3(owner, value) -> list:
    """``clipPlaneSe3``: up to 3 (position [m], orientation) pairs, as YADE's list of ``Se3r``."""
    planes = list(value)
    if len(planes) > NUM_CLIP_PLANES:
        raise ValueError(f"Renderer.clipPlaneSe3 holds at most {NUM_CLIP_PLANES} planes, got {len(planes)}")
    out = []
    for k, plane in enumerate(planes):
        try:
            pos, ori = plane
            out.append((_vec3(owner, pos), ori if isinstance(ori, Quaternion) else Quaternion(*ori)))
        except (TypeError, ValueError) as e:
            raise ValueError(f"Renderer.clipPlaneSe3[{k}] must be (position, Quaternion), got {plane!r}") from e
    return out


def _clip_active(owner, value) -> list:
    flags = [bool(x) for x in value]
    if len(flags) > NUM_CLIP_PLANES:
        raise ValueError(f"Renderer.clipPlaneActive holds at most {NUM_CLIP_PLANES} flags, got {len(flags)}")
    return flags


class Renderer(Attributed):
    """Display options of the 3D view (YADE's ``OpenGLRenderer``, reached by ``qt.Renderer()``).

    Honoured by :func:`render`: ``shape`` (False hides the bodies), ``wire`` (all bodies as
    outlines), ``bgColor``, ``mask`` (draw bodies with ``groupMask & mask != 0``), ``intrPhys``,
    ``intrWire``, ``cellColor``, ``clipPlaneSe3`` with ``clipPlaneActive`` (as in YADE, a body is drawn
    whole or not at all: hidden when its centre is behind an active plane). The other attributes are
    accepted for compatibility.
    """

    def clip_planes(self) -> np.ndarray:
        """The active clipping planes as a (P, 2, 3) array of (point [m], unit normal): the normal is the
        plane's orientation applied to +z, and the side it points to is drawn. A plane without a flag (the
        lists may be shorter than 3, as YADE fills them) is off."""
        planes = [(np.asarray(pos, float), np.asarray(ori * Vector3(0, 0, 1), float))
                  for (pos, ori), on in zip(self.clipPlaneSe3, self.clipPlaneActive, strict=False) if on]
        return np.asarray(planes, float).reshape(-1, 2, 3)

    _attrs = {
        "dispScale": Attr(Vector3(1, 1, 1), "Displacement scaling (accepted, not used)", _vec3),
        "rotScale": Attr(1.0, "Rotation scaling (accepted, not used)", to_float("rotScale")),
        "lightPos": Attr(Vector3(75, 130, 0), "Position of the main light (browser view only)", _vec3),
        "light2Pos": Attr(Vector3(-130, 75, 30), "Position of the second light (browser view only)", _vec3),
        "lightColor": Attr(Vector3(0.6, 0.6, 0.6), "Colour of the main light (browser view only)", _vec3),
        "light2Color": Attr(Vector3(0.5, 0.5, 0.1), "Colour of the second light (browser view only)", _vec3),
        "cellColor": Attr(Vector3(1, 1, 0), "Colour of the periodic cell's edges", _vec3),
        "bgColor": Attr(Vector3(0.2, 0.2, 0.2), "Background colour (RGB in [0, 1])", _vec3),
        "blinkHighlight": Attr("NORMAL", "Highlight mode (accepted, not used)"),
        "wire": Attr(False, "Draw all bodies as outlines", to_bool),
        "light1": Attr(True, "Main light on (browser view only)", to_bool),
        "light2": Attr(True, "Second light on (browser view only)", to_bool),
        "dof": Attr(False, "Show blocked DOFs (accepted, not used)", to_bool),
        "id": Attr(False, "Show body ids (accepted, not used)", to_bool),
        "bound": Attr(False, "Show bounding boxes (accepted, not used)", to_bool),
        "shape": Attr(True, "Draw the bodies' shapes", to_bool),
        "intrWire": Attr(False, "Draw contacts as thin lines", to_bool),
        "intrGeom": Attr(False, "Draw contact geometry (accepted, not used)", to_bool),
        "intrPhys": Attr(False, "Draw contacts as cylinders scaled by the normal force", to_bool),
        "ghosts": Attr(True, "Draw periodic ghosts (accepted, not used)", to_bool),
        "mask": Attr(-1, "Draw only bodies with groupMask & mask != 0", to_int("mask")),
        "selId": Attr(-1, "Selected body (accepted, not used)", to_int("selId")),
        "clipPlaneSe3": Attr([(Vector3(0, 0, 0), Quaternion())] * NUM_CLIP_PLANES,
                             "Clipping planes: (a point [m], an orientation turning +z into the plane's normal); "
                             "bodies whose centre lies behind an active plane are not drawn", _clip_se3),
        "clipPlaneActive": Attr([False] * NUM_CLIP_PLANES, "Which clipping planes are on", _clip_active),
        "extraDrawers": Attr([], "Extra drawers (accepted, not used)"),
        "intrAllWire": Attr(False, "Draw potential interactions too (accepted, not used)", to_bool),
    }


#: The renderer shared by all views (YADE has one per scene; ``qt.Renderer()`` returns it).
RENDERER = Renderer()


class View:
    """Camera of a 3D view (YADE's ``GLViewer``), used for snapshots.

    ``eyePosition``, ``viewDir``, ``upVector``, ``lookAt``, ``ortho``, ``sceneRadius`` and
    ``screenSize`` can be read and set as in YADE; :meth:`center`, :meth:`fitAABB`,
    :meth:`fitSphere` and :meth:`showEntireScene` frame the scene; :meth:`saveSnapshot` writes
    a picture.
    """

    def __init__(self, scene_getter):
        self._scene_getter = scene_getter
        self.viewDir = Vector3(0, 0, -1)
        self.upVector = Vector3(0, 1, 0)
        self.ortho = False
        self.screenSize = Vector2i(550, 550)
        self.grid = (False, False, False)
        self.axes = False
        self.fps = False
        self.scale = True
        self.timeDisp = "rvi"
        self.selection = -1
        self._center = np.zeros(3)
        self.sceneRadius = 1.0
        self.eyePosition = Vector3(0, 0, 1.0 / np.sin(_FOV / 2))
        self._fitted = False
        if len(self._bodies_bbox()[0]):
            self.center(median=False)

    # ---- camera --------------------------------------------------------------------------
    @property
    def lookAt(self):
        """A point on the line of sight (the eye position plus the viewing direction)."""
        return Vector3(*(np.asarray(self.eyePosition) + np.asarray(self.viewDir)))

    @lookAt.setter
    def lookAt(self, point) -> None:
        d = np.asarray(point, float) - np.asarray(self.eyePosition, float)
        if np.linalg.norm(d) > 0:
            self.viewDir = Vector3(*(d / np.linalg.norm(d)))

    def _bodies_bbox(self):
        scene = self._scene_getter()
        if scene.periodic:
            corners = np.array([[i, j, k] for i in (0, 1) for j in (0, 1) for k in (0, 1)], float)
            return corners @ np.asarray(scene.cell_hsize, float).T, True
        b = scene.bodies
        n = scene.body_count
        keep = b.alive[:n] & (b.shape_kind[:n] != int(ShapeKind.CLUMP))
        return b.pos[:n][keep], False

    def fitSphere(self, center, radius) -> None:
        """Move the eye along the viewing direction so that the sphere (centre, radius [m]) fills the view."""
        radius = float(radius) if radius > 0 else 1.0
        self._center = np.asarray(center, float)
        self.sceneRadius = radius
        d = np.asarray(self.viewDir, float)
        dist = radius / np.sin(_FOV / 2) if not self.ortho else 2.0 * radius
        self.eyePosition = Vector3(*(self._center - d / np.linalg.norm(d) * dist))
        self._fitted = True

    def fitAABB(self, mn, mx) -> None:
        """Frame the axis-aligned box ``mn``..``mx`` [m]."""
        mn, mx = np.asarray(mn, float), np.asarray(mx, float)
        self.fitSphere((mn + mx) / 2, np.linalg.norm(mx - mn) / 2)

    def showEntireScene(self) -> None:
        """Frame the current scene centre and radius."""
        self.fitSphere(self._center, self.sceneRadius)

    def center(self, median=True, suggestedRadius=-1.0) -> None:
        """Frame the scene: all body positions (``median=False``), or the median position and the
        distance within which 75 % of the bodies lie (``median=True``, robust to stray bodies)."""
        pts, periodic = self._bodies_bbox()
        if len(pts) == 0:
            self.fitSphere(np.zeros(3), 1.0)
            return
        if median and not periodic and len(pts) > 4:
            c = np.median(pts, axis=0)
            radius = 1.5 * float(np.quantile(np.max(np.abs(pts - c), axis=1), 0.75))
        else:
            lo, hi = pts.min(axis=0), pts.max(axis=0)
            c = (lo + hi) / 2
            radius = 1.5 * float(np.max(hi - lo) / 2)  # YADE's margin around the box of positions
        self.fitSphere(c, suggestedRadius if suggestedRadius > 0 else (radius if radius > 0 else 1.0))

    def _basis(self):
        d = np.asarray(self.viewDir, float)
        d = d / np.linalg.norm(d)
        u = np.asarray(self.upVector, float)
        u = u - d * (u @ d)
        if np.linalg.norm(u) < 1e-12:  # up parallel to the view: pick any perpendicular
            u = np.cross(d, [1.0, 0, 0] if abs(d[0]) < 0.9 else [0, 1.0, 0])
        u = u / np.linalg.norm(u)
        return np.cross(d, u), u, d

    def project(self, points: np.ndarray):
        """Image coordinates, depth and pixel scale of (M, 3) points.

        Returns ``(xy (M, 2) [px], depth (M,) [m], scale (M,) [px/m])``; the scale converts a
        length at that point into pixels (it is constant for an orthographic view).
        """
        if not self._fitted:
            self.center(median=False)
        w, h = (int(x) for x in self.screenSize)
        right, up, d = self._basis()
        rel = np.asarray(points, float).reshape(-1, 3) - np.asarray(self.eyePosition, float)
        x, y, z = rel @ right, rel @ up, rel @ d
        if self.ortho:
            scale = np.full(len(z), (h / 2) / self.sceneRadius)
        else:
            f = (h / 2) / np.tan(_FOV / 2)
            with np.errstate(divide="ignore", invalid="ignore"):
                scale = np.where(z > 0, f / z, 0.0)
        return np.stack([w / 2 + x * scale, h / 2 - y * scale], axis=1), z, scale

    def near(self) -> float:
        """Smallest depth drawn [m]: nothing behind or at the eye is projected."""
        return 1e-3 * self.sceneRadius if not self.ortho else -np.inf

    def saveSnapshot(self, filename, format="PNG") -> None:
        """Render the scene and write it to ``filename`` (format PNG, JPEG, BMP or PPM)."""
        from granum.yade.omega import O

        save_picture(filename, render(O._scene, self, RENDERER), format, overlay_text(O._scene, self))

    def close(self) -> None:
        """Close the view (it no longer appears in ``qt.views()``)."""
        from granum.yade import qt

        if self in qt._views:
            qt._views.remove(self)

    def saveState(self, *args, **kw) -> None:
        """Accepted (YADE saves the camera in a slot)."""

    def loadState(self, *args, **kw) -> None:
        """Accepted (YADE restores the camera from a slot)."""


# ---- drawing ------------------------------------------------------------------------------------
def _force_colors(x: np.ndarray) -> np.ndarray:
    """Blue (0) -> cyan -> green -> yellow -> red (1), like YADE's scalar colour scale."""
    x = np.clip(x, 0.0, 1.0)[:, None]
    return np.clip(np.concatenate([4 * x - 2, 2 - np.abs(4 * x - 2), 2 - 4 * x], axis=1), 0.0, 1.0)


def _draw_wire_edges(canvas, view, ends: np.ndarray, color: np.ndarray) -> None:
    """Hairlines between (K, 2, 3) world points, skipping those with an end behind the eye."""
    if len(ends) == 0:
        return
    xy, z, _ = view.project(ends.reshape(-1, 3))
    xy, z = xy.reshape(-1, 2, 2), z.reshape(-1, 2)
    ok = np.all(z > view.near(), axis=1)
    canvas.segments(xy[ok, 0], xy[ok, 1], z[ok, 0], z[ok, 1], np.full(ok.sum(), 0.6), color[ok])


def _draw_spheres(canvas, scene, view, ids: np.ndarray, wire: bool) -> None:
    b = scene.bodies
    radius = fields.sphere_radii(scene, ids)
    xy, z, scale = view.project(b.pos[ids] + fields.wrap_shift(scene, ids))
    ok = z - radius > view.near()
    solid = ok & ~(b.wire[ids] | wire)
    rpx = np.maximum(radius * scale, 0.6)  # spheres smaller than a pixel still show as one pixel
    canvas.spheres(xy[solid, 0], xy[solid, 1], rpx[solid], z[solid], radius[solid], b.color[ids][solid])
    ring = np.nonzero(ok & (b.wire[ids] | wire))[0]
    if ring.size:  # outline: a 24-sided polygon around the silhouette, at the centre's depth
        ang = np.linspace(0, 2 * np.pi, 25)
        r = (radius * scale)[ring][:, None]
        px = xy[ring, 0][:, None] + r * np.cos(ang)
        py = xy[ring, 1][:, None] + r * np.sin(ang)
        p = np.stack([px, py], axis=2)
        zz = np.repeat(z[ring], 24)
        canvas.segments(p[:, :-1].reshape(-1, 2), p[:, 1:].reshape(-1, 2), zz, zz, np.full(zz.size, 0.6),
                        np.repeat(b.color[ids][ring], 24, axis=0))


def _draw_polygons(canvas, view, tris: np.ndarray, color: np.ndarray) -> None:
    """Flat triangles given as (F, 3, 3) world vertices."""
    if len(tris) == 0:
        return
    xy, z, _ = view.project(tris.reshape(-1, 3))
    xy, z = xy.reshape(-1, 3, 2), z.reshape(-1, 3)
    ok = np.all(z > view.near(), axis=1)
    right, up, d = view._basis()
    n = np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0])
    n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300)
    ncam = np.stack([n @ right, n @ up, -(n @ d)], axis=1)
    canvas.triangles(xy[ok], z[ok], color[ok], ncam[ok])


def _draw_faces(canvas, scene, view, kind, ids, wire_all: bool) -> None:
    """The bodies ``ids`` of shape kind ``kind`` by their polygons (:func:`granum.yade.fields.body_faces`): filled
    (each polygon as a fan of triangles), or their edges for bodies drawn as wire."""
    b = scene.bodies
    faces = fields.body_faces(scene, kind, ids) + fields.wrap_shift(scene, ids)[:, None, None, :]  # (M, F, V, 3)
    nf, nv = faces.shape[1:3]
    wire = b.wire[ids] | wire_all
    filled = faces[~wire]
    tris = np.concatenate([filled[:, :, [0, k, k + 1]] for k in range(1, nv - 1)], axis=1).reshape(-1, 3, 3)
    _draw_polygons(canvas, view, tris, np.repeat(b.color[ids][~wire], nf * (nv - 2), axis=0))
    outline = faces[wire]
    edges = np.stack([outline, np.roll(outline, -1, axis=2)], axis=3).reshape(-1, 2, 3)
    _draw_wire_edges(canvas, view, edges, np.repeat(b.color[ids][wire], nf * nv, axis=0))


def _draw_contacts(canvas, scene, view, renderer) -> None:
    rows = fields.live_contact_rows(scene)
    if rows.size == 0:
        return
    id1, id2 = fields.contact_ids(scene, rows)
    shift = fields.wrap_shift(scene, id1)  # body 1 drawn inside the periodic cell, body 2 next to it
    p1 = scene.bodies.pos[id1] + shift
    p2 = scene.bodies.pos[id2] + fields.contact_shift(scene, rows) + shift
    fn = np.linalg.norm(scene.contacts.con_f[rows, F_FN:F_FN + 3], axis=1)
    fmax = fn.max() if fn.size and fn.max() > 0 else 1.0
    rel = fn / fmax
    xy, z, scale = view.project(np.concatenate([p1, p2]))
    k = len(rows)
    ok = (z[:k] > view.near()) & (z[k:] > view.near())
    if renderer.intrPhys:
        spheres = fields.ids_of_kind(scene, ShapeKind.SPHERE)
        rmax = 0.5 * float(np.median(fields.sphere_radii(scene, spheres))) if spheres.size else \
            0.02 * view.sceneRadius
        width = rmax * rel * 0.5 * (scale[:k] + scale[k:])
        ok &= rel > 0
    else:
        width = np.full(k, 0.6)
    canvas.segments(xy[:k][ok], xy[k:][ok], z[:k][ok], z[k:][ok], width[ok], _force_colors(rel[ok]))


def render(scene, view: View, renderer: Renderer = RENDERER) -> np.ndarray:
    """Draw the scene as the view sees it; return an (height, width, 3) uint8 RGB picture."""
    w, h = (int(x) for x in view.screenSize)
    canvas = Canvas(w, h, tuple(renderer.bgColor))
    b = scene.bodies
    if renderer.shape:
        mask = renderer.mask

        planes = renderer.clip_planes()

        def of_kind(kind):
            ids = fields.ids_of_kind(scene, kind)
            ids = ids if mask == -1 else ids[(b.mask[ids] & mask) != 0]
            return ids[~fields.clipped(b.pos[ids] + fields.wrap_shift(scene, ids), planes)]

        _draw_spheres(canvas, scene, view, of_kind(ShapeKind.SPHERE), renderer.wire)
        for kind in scene.shapes:
            if shape_type(kind).faces is not None:
                _draw_faces(canvas, scene, view, kind, of_kind(kind), renderer.wire)
    if renderer.intrPhys or renderer.intrWire:
        _draw_contacts(canvas, scene, view, renderer)
    if scene.periodic:
        a, bb, c = np.asarray(scene.cell_hsize, float).T
        corners = np.array([i * a + j * bb + k * c for i in (0, 1) for j in (0, 1) for k in (0, 1)])
        pairs = [(p, q) for p in range(8) for q in range(p + 1, 8) if bin(p ^ q).count("1") == 1]
        edges = np.array([[corners[p], corners[q]] for p, q in pairs])
        _draw_wire_edges(canvas, view, edges, np.tile(np.asarray(renderer.cellColor, float), (12, 1)))
    return canvas.image()


def overlay_text(scene, view: View) -> list[str]:
    """Lines written in the picture's corner, chosen by the letters of ``view.timeDisp``."""
    lines = []
    if "i" in view.timeDisp:
        lines.append(f"#{scene.iter}")
    if "v" in view.timeDisp:
        lines.append(f"t = {scene.time:.6g} s")
    if "r" in view.timeDisp:
        lines.append("clock " + time.strftime("%H:%M:%S", time.gmtime(time.time() - _START)))
    return lines


def save_picture(path, image: np.ndarray, format: str = "PNG", text: list[str] | None = None) -> None:
    """Write an (h, w, 3) uint8 picture to ``path`` atomically, with ``text`` lines in the lower left corner."""
    from PIL import Image, ImageDraw, ImageFont

    pil_format = _FORMATS[format.upper()][0]
    img = Image.fromarray(np.ascontiguousarray(image), "RGB")
    if text:
        draw = ImageDraw.Draw(img)
        try:
            font = ImageFont.load_default(size=13)
        except TypeError:  # Pillow < 10.1 has only its small bitmap font
            font = ImageFont.load_default()
        y = img.height - 8 - 16 * len(text)
        for k, line in enumerate(text):
            draw.text((10, y + 16 * k), line, fill=(0, 190, 190) if k else (230, 230, 230), font=font)
    with atomic_path(path) as tmp:
        img.save(tmp, format=pil_format)


def _format(owner, value) -> str:
    if not isinstance(value, str) or value.upper() not in _FORMATS:
        raise ValueError(f"SnapshotEngine.format must be one of {', '.join(sorted(_FORMATS))}, got {value!r}")
    return value


class SnapshotEngine(PeriodicEngine):
    """Save pictures of the 3D view periodically (YADE ``qt.SnapshotEngine``).

    Files are ``fileBase`` + ``counter`` padded to 5 digits + ``.`` + lowercased ``format``
    (``snap-00004.png``); every file written is appended to ``snapshots``. The camera is the
    first view opened with ``qt.View()``; without one, a default view framing the scene at the
    first snapshot is used.
    """

    _attrs = {
        "fileBase": Attr("", "Base name of the pictures", to_str("fileBase")),
        "format": Attr("PNG", "Picture format: PNG, JPEG, BMP or PPM", _format),
        "counter": Attr(0, "Number appended to fileBase for the next picture", to_int("counter")),
        "snapshots": Attr([], "Files written so far", lambda o, v: [str(x) for x in v]),
        "ignoreErrors": Attr(True, "Accepted for compatibility (no timeouts without a screen)", to_bool),
        "msecSleep": Attr(0, "Accepted for compatibility [ms]", to_int("msecSleep")),
        "deadTimeout": Attr(3.0, "Accepted for compatibility [s]", to_float("deadTimeout")),
        "plot": Attr("", "Accepted for compatibility (plot.imgData is not implemented)", to_str("plot")),
    }

    def __init__(self, **kw):
        super().__init__(**kw)
        self._view: View | None = None

    def run_python(self, omega) -> None:
        from granum.yade import qt

        if qt._views:
            view = qt._views[0]
        else:
            if self._view is None:
                self._view = View(lambda: omega._scene)
            view = self._view
        _, ext = _FORMATS[self.format.upper()]
        path = f"{self.fileBase}{self.counter:05d}.{ext}"
        save_picture(path, render(omega._scene, view, RENDERER), self.format, overlay_text(omega._scene, view))
        self.snapshots.append(path)
        self.counter += 1
