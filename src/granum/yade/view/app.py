"""The page: a trame application (vtk.js in the browser) with the 3D view, the controller, the inspector
and the live plots.

The browser draws everything with vtk.js (WebGL), from arrays the server publishes in trame's shared
state (``{"bvals": base64, "dtype": ...}`` typed arrays, which vtk.js reads without parsing numbers):

* spheres as impostors: one screen-facing triangle per sphere, ray-cast per pixel onto the sphere of
  the centre and radius given (vtk.js's sphere mapper, enabled by ``client/granum-view.js``), coloured by its
  RGB: three vertices per sphere, so software WebGL (no GPU) keeps 100,000 spheres moving; there the
  page leaves out the spheres hidden behind others before each frame (same picture);
* facets, boxes and walls as one triangle mesh coloured per triangle; the periodic cell, bounds and
  contact force chains as one set of coloured lines.

The server runs in a thread of its own with its own event loop (aiohttp via trame's wslink). Every
HTTP and websocket request must carry the access token: the URL printed holds ``?token=...``, the
first request with it sets a cookie, and any request without the token or the cookie gets 403.
The controller's buttons run ``O``'s methods on a worker thread, never on the event loop.
"""

from __future__ import annotations

import asyncio
import base64
import hmac
import io
import threading
import time
from pathlib import Path

import numpy as np

from granum.yade.view import frames
from granum.yade.view.session import Session

_COOKIE = "granum_view_token"
#: the surfaces' ambient reflection: OpenGL's default ambient light (0.2), in which YADE's lights shine
AMBIENT = "{ambient: 0.2}"
#: granum's Vue plugin (client/granum-view.js), served beside trame-vtk's components (only that folder)
CLIENT_MODULE = {"serve": {"__granum_view": str(Path(__file__).parent / "client")},
                 "scripts": ["__granum_view/granum-view.js"], "vue_use": ["granum_view"]}


def typed_array(a: np.ndarray) -> dict | list:
    """A NumPy array as the typed-array record vtk.js components read (base64 of the raw bytes)."""
    a = np.ascontiguousarray(a)
    if a.size == 0:   # vtk.js decodes no empty base64 string; an empty list is an empty array to it
        return []
    return {"bvals": base64.b64encode(memoryview(a).cast("B")).decode("ascii"), "dtype": str(a.dtype),
            "shape": list(a.shape)}


def _cells(count: int, per: int) -> np.ndarray:
    """vtk.js cell array of ``count`` cells of ``per`` consecutive points: [per, i, i+1, ..., per, ...]."""
    idx = np.arange(count * per, dtype=np.uint32).reshape(count, per)
    return np.concatenate([np.full((count, 1), per, np.uint32), idx], axis=1).ravel()


def frame_state(frame: frames.Frame, previous: frames.Frame | None = None) -> dict:
    """The shared-state entries of one frame (what the page's vtk.js components are bound to); arrays equal
    to those of the ``previous`` frame published are left out (radii and colours seldom change)."""
    def same(name):
        return previous is not None and np.array_equal(getattr(frame, name), getattr(previous, name))

    out = {
        "sph_points": typed_array(frame.sphere_pos.ravel()),
        "tri_points": typed_array(frame.tri_points.ravel()),
        "line_points": typed_array(frame.line_points.ravel()),
        "n_spheres": int(len(frame.sphere_ids)),
        "iter": frame.iter,
        "sim_time": f"{frame.time:.6g}",
        "bar_lo": f"{frame.value_range[0]:.4g}",
        "bar_hi": f"{frame.value_range[1]:.4g}",
    }
    if previous is None or frame.lights != previous.lights:
        out["lights"] = [{"position": p, "focalPoint": f, "color": c} for p, f, c in frame.lights]
    if not same("sphere_radius"):
        out["sph_radius"] = typed_array(frame.sphere_radius)
    if not same("sphere_rgb"):
        out["sph_rgb"] = typed_array(frame.sphere_rgb.ravel())
    if not same("tri_rgb"):
        out["tri_polys"] = typed_array(_cells(len(frame.tri_points), 3))
        out["tri_rgb"] = typed_array(frame.tri_rgb.ravel())
    if not same("line_rgb"):
        out["line_cells"] = typed_array(_cells(len(frame.line_points), 2))
        out["line_rgb"] = typed_array(frame.line_rgb.ravel())
    return out


def click_ray(position: dict, camera: dict, size) -> tuple[np.ndarray, np.ndarray]:
    """The ray (origin, direction) through the pixel ``position`` ({x, y} from the lower left corner) of a
    view of ``size`` (width, height) [px] seen by the vtk.js ``camera`` (position, focalPoint, viewUp,
    viewAngle [deg] vertical, parallelProjection, parallelScale)."""
    eye = np.asarray(camera["position"], float)
    forward = np.asarray(camera["focalPoint"], float) - eye
    forward /= np.linalg.norm(forward)
    up = np.asarray(camera["viewUp"], float)
    up = up - forward * (up @ forward)
    up /= np.linalg.norm(up)
    right = np.cross(forward, up)
    w, h = float(size[0]), float(size[1])
    u = (2.0 * position["x"] / w - 1.0) * w / h   # horizontal offset, in units of half the view's height
    v = 2.0 * position["y"] / h - 1.0
    if camera.get("parallelProjection"):
        s = float(camera["parallelScale"])
        return eye + s * (u * right + v * up), forward
    t = np.tan(np.radians(float(camera["viewAngle"])) / 2)
    return eye, forward + t * (u * right + v * up)


def token_middleware(token: str):
    """aiohttp middleware refusing (403) every request without ``token`` in its query or cookie."""
    from aiohttp import web

    @web.middleware
    async def check(request, handler):
        given = request.query.get("token", "")
        if given and hmac.compare_digest(given, token):
            response = await handler(request)
            response.set_cookie(_COOKIE, token, httponly=True, samesite="Strict")
            return response
        cookie = request.cookies.get(_COOKIE, "")
        if cookie and hmac.compare_digest(cookie, token):
            return await handler(request)
        return web.Response(status=403, text="granum view: this URL needs the access token printed at start\n")

    return check


def plugin_element(tag: str, **props):
    """An element of granum's Vue plugin (``granum-view.js``) with its properties ``props`` (a tuple value
    binds a state expression, as in trame's widgets):

    * ``granum-sphere-impostors`` (``scale_array``), inside a ``VtkGeometryRepresentation``: its points are
      drawn as spheres (vtk.js's sphere mapper, one ray-cast triangle per sphere) of radius the point data
      array named ``scale_array``;
    * ``granum-lights`` (``lights``), inside a ``VtkView``: the scene lights (``frame_state``'s ``lights``)
      replacing vtk.js's headlight.

    When WebGL is drawn by the CPU (no GPU), the plugin also makes the page's WebGL contexts without
    multisampling, a large share of a frame's time there, and draws only the spheres that can be seen
    (occlusion culling in the page: the same picture, a fraction of the fragments to shade)."""
    from trame_client.widgets.core import AbstractElement

    class PluginElement(AbstractElement):
        def __init__(self):
            super().__init__(tag, **props)
            self.server.enable_module(CLIENT_MODULE)
            self.props += list(props)

    return PluginElement()


def build_server(session: Session, token: str):
    """The trame server with the page's layout and callbacks, bound to ``session``."""
    from trame.app import get_server
    from trame.ui.html import DivLayout
    from trame.widgets import html
    from trame.widgets import vtk as vtkw

    server = get_server(f"granum-view-{id(session)}", client_type="vue3")
    state, ctrl = server.state, server.controller
    # trame reads its options from sys.argv, which belongs to the user's script: give it none
    parse = server.cli.parse_known_args
    server.cli.parse_known_args = lambda args=None, namespace=None: parse([], namespace)

    state.update(frame_state(session.frame()))
    state.update(session.panel_state())
    state.update({"field": session.field, "fields": list(frames.FIELDS), "bar_stops": frames.colormap_stops(),
                  "run_n": 100, "dt_text": "", "plot_png": "", "plot_rows": 0,
                  "message": ""})

    @ctrl.add("on_server_bind")
    def bind(wslink_server):
        wslink_server.app.middlewares.append(token_middleware(token))

    @ctrl.add("on_server_ready")
    def ready(**_):
        session.loop = asyncio.get_running_loop()
        session.loop.create_task(_pump(session, server))

    def command(name, *args):
        session.command(name, *args)

    ctrl.play = lambda: command("play")
    ctrl.pause = lambda: command("pause")
    ctrl.step = lambda: command("step")
    ctrl.run_n = lambda n: command("run", n)
    ctrl.set_dt = lambda text: command("dt", text)
    ctrl.set_dyn_dt = lambda on: command("dynDt", on)
    ctrl.reload = lambda: command("reload")

    def edit_body(key, name, text):
        command("edit_body", key, name, text)

    def edit_engine(k, name, text):
        command("edit_engine", k, name, text)

    ctrl.reset_camera = lambda: view.reset_camera()
    ctrl.yade_camera = lambda: view.set_camera(session.camera())
    ctrl.on_client_connected.add(lambda **_: session.loop.call_later(0.5, ctrl.yade_camera))

    def on_press(position, camera, size):
        """A press of the left button on the view: the inspector shows the body under it."""
        state.update(session.pick(*click_ray(position, camera, size)))

    @state.change("field")
    def field_changed(field, **_):
        session.set_field(field)

    style = ("position:absolute;top:0;right:0;width:330px;bottom:0;overflow:auto;background:#222;color:#eee;"
             "font:13px sans-serif;padding:8px;box-sizing:border-box")
    with DivLayout(server, template_name="main"):
        with html.Div(style="position:absolute;left:0;top:0;bottom:0;right:330px"):
            # a press sends the pixel, the camera and the view's size: the server casts the ray (click_ray)
            press = ("[$event.position, trame.refs.view.getCamera(), "
                     "$event.pokedRenderer.getRenderWindow().getViews()[0].getSize()]")
            with vtkw.VtkView(ref="view", background=("bg", [0.2, 0.2, 0.2]), style="width:100%;height:100%",
                              interactor_events=("events", ["LeftButtonPress"]),
                              LeftButtonPress=(on_press, press)) as view:
                plugin_element("granum-lights", lights=("lights",))
                # spheres: impostors (granum-view.js), sized by the radius array, coloured by the RGB array;
                # AMBIENT: the sides away from the lights keep some colour (OpenGL's default ambient light)
                with vtkw.VtkGeometryRepresentation(mapper=("{colorMode: 2}",), property=(AMBIENT,)):
                    plugin_element("granum-sphere-impostors", scale_array="radius")
                    with vtkw.VtkPolyData("spheres", points=("sph_points",)):
                        with vtkw.VtkPointData():
                            vtkw.VtkDataArray(registration="setScalars", name="rgb", type="Uint8Array",
                                              number_of_components=("3",), values=("sph_rgb",))
                            vtkw.VtkDataArray(registration="addArray", name="radius", values=("sph_radius",))
                with vtkw.VtkGeometryRepresentation(mapper=("{colorMode: 2}",), property=(AMBIENT,)):
                    with vtkw.VtkPolyData("triangles", points=("tri_points",), polys=("tri_polys",)):
                        with vtkw.VtkCellData():
                            vtkw.VtkDataArray(registration="setScalars", name="rgb", type="Uint8Array",
                                              number_of_components=("3",), values=("tri_rgb",))
                # lines (wire facets, cell, bounds, force chains): their own colour, unlit
                with vtkw.VtkGeometryRepresentation(mapper=("{colorMode: 2}",),
                                                    property=("{lineWidth: 2, lighting: false}",)):
                    with vtkw.VtkPolyData("lines", points=("line_points",), lines=("line_cells",)):
                        with vtkw.VtkCellData():
                            vtkw.VtkDataArray(registration="setScalars", name="rgb", type="Uint8Array",
                                              number_of_components=("3",), values=("line_rgb",))
        with html.Div(style=style):
            html.Div("#{{ iter }}  t = {{ sim_time }} s  ({{ n_spheres }} spheres)", id="clock")
            with html.Div(style="margin:6px 0"):
                html.Button("Play", id="play", click=ctrl.play)
                html.Button("Pause", id="pause", click=ctrl.pause)
                html.Button("Step", id="step", click=ctrl.step)
                html.Input(type="number", v_model_number=("run_n",), style="width:70px", id="run_n")
                html.Button("Run N", id="run", click=(ctrl.run_n, "[run_n]"))
            with html.Div():
                html.Span("O.dt = {{ dt }} s ")
                html.Input(v_model=("dt_text",), style="width:90px", id="dt_text", placeholder="new dt")
                html.Button("Set", id="set_dt", click=(ctrl.set_dt, "[dt_text]"))
                html.Input(type="checkbox", id="dyn_dt", checked=("dyn_dt",), disabled=("!dyn_dt_available",),
                           change=(ctrl.set_dyn_dt, "[$event.target.checked]"))
                html.Span("O.dynDt ")
                html.Button("Reload", id="reload", click=ctrl.reload)
            html.Div("{{ running ? 'running' : 'paused' }}  {{ speed }}  {{ message }}", id="status")
            with html.Div(style="margin:6px 0"):
                html.Span("Colour by ")
                with html.Select(v_model=("field",), id="field"):
                    html.Option("{{ f }}", v_for="f in fields", value=("f",))
                html.Button("Fit", id="fit", click=ctrl.reset_camera)
                html.Button("YADE camera", id="yade_camera", click=ctrl.yade_camera)
            html.Div(v_show="field != 'color'", id="colorbar",
                     style=("'height:12px;background:linear-gradient(to right,' + bar_stops.join(',') + ')'",))
            html.Div("{{ bar_lo }} .. {{ bar_hi }}", v_show="field != 'color'", id="bar_range")
            html.H4("Inspector", style="margin:8px 0 2px")
            html.Div("{{ picked || 'click a body' }}", id="picked")
            # each row: the attribute's repr, typed back and assigned by its setter on Enter (inspector.py)
            with html.Details(v_for="s in inspected", key="s.key", open=("s.key == 'state'",)):
                html.Summary("{{ s.title }}", style="margin-top:4px;color:#9cf")
                _rows(server, "s.rows", "'body-' + s.key.replace(/ /g, '-') + '-' + r.name", edit_body,
                      "s.key, r.name")
            html.H4("Engines", style="margin:8px 0 2px")
            with html.Div(id="engines"):
                with html.Details(v_for="(e, k) in engines", key="k"):
                    html.Summary("{{ e.name }}")
                    _rows(server, "e.rows", "'engine-' + k + '-' + r.name", edit_engine, "k, r.name")
            html.H4("Plots ({{ plot_rows }} points)", id="plot_title", v_show="plot_png", style="margin:8px 0 2px")
            html.Img(src=("plot_png",), v_show="plot_png", id="plot", style="width:100%")
    session.view_widget = view
    return server


def _rows(server, rows: str, element_id: str, on_edit, args: str) -> None:
    """A table of attribute rows (``{name, value, editable}``, the JS expression ``rows``): an input for an
    editable value, text otherwise. The input shows the value as its placeholder and starts empty, so the
    values refreshed while the user types never overwrite the text; Enter (or leaving the field) calls
    ``on_edit(*args, text)`` (``args``: JS expressions of ``r``) and empties the field again. Each input's
    id is the JS expression ``element_id``."""
    from trame.widgets import html

    send = f"trigger('{server.trigger_name(on_edit)}', [{args}, $event.target.value]); $event.target.value = ''"
    with html.Table(style="font-size:11px;border-spacing:0;width:100%;table-layout:fixed"):
        with html.Tr(v_for=f"r in {rows}", key="r.name"):
            html.Td("{{ r.name }}", style="width:90px;padding-right:4px;overflow:hidden;text-overflow:ellipsis")
            with html.Td():
                html.Input(v_if="r.editable", placeholder=("r.value",), id=(element_id,), title=("r.value",),
                           change=f"if ($event.target.value) {{ {send} }}",
                           style="width:100%;box-sizing:border-box;font-size:11px")
                html.Div("{{ r.value }}", v_else=True, title=("r.value",),
                         style="color:#aaa;overflow:hidden;text-overflow:ellipsis;white-space:nowrap")


async def _pump(session: Session, server) -> None:
    """Publish new frames, the controller's state and the live plots, every ``session.interval`` seconds."""
    state = server.state
    while not session.closing:
        await asyncio.sleep(session.interval)
        t0 = time.perf_counter()
        try:
            update = session.poll()
        except Exception as e:  # noqa: BLE001 - shown in the page; the view goes on
            update = {"message": f"view: {type(e).__name__}: {e}"}
        if update:
            with state:   # sends the changes to the page
                state.update(update)
        if "sph_points" in update:   # a frame was published
            session.spent(time.perf_counter() - t0, publish=True)


def serve(session: Session, host: str, token: str) -> int:
    """Start the server in a daemon thread; return the port once it listens."""
    server = build_server(session, token)
    started = threading.Event()

    @server.controller.add("on_server_ready")
    def _ready(**_):
        started.set()

    def run():
        asyncio.set_event_loop(asyncio.new_event_loop())
        server.start(port=0, host=host, thread=True, open_browser=False, show_connection_info=False,
                     timeout=0, disable_logging=True)

    threading.Thread(target=run, name="granum-view", daemon=True).start()
    if not started.wait(60):
        raise RuntimeError("granum view: the web server did not start within 60 s")
    session.server = server
    return server.port


def png_of_figures(figs) -> str:
    """A data: URL of the first matplotlib figure as PNG (the page's live plot)."""
    buf = io.BytesIO()
    figs[0].savefig(buf, format="png", dpi=70)
    return "data:image/png;base64," + base64.b64encode(buf.getvalue()).decode("ascii")
