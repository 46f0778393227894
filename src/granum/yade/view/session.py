"""One browser view's link to the simulation: frames, controller commands, inspector, live plots.

Frames come from the scene's arrays at two moments only: between compiled chunks of a run
(:meth:`Session.between_chunks`, registered in ``O.chunk_hooks``; it copies a frame at most every
:attr:`Session.interval` seconds and otherwise returns at once), and, while no run goes on, from the
server's own polling. The step loop itself is never entered. :attr:`Session.hook_seconds` adds up the time
the hook takes, for the overhead measure (``benchmarks/view_fps.py``).

Commands from the page (play, pause, step, run N, O.dt, edits in the inspector and the engine list) run
on one worker thread, in order, so the web server's event loop never waits for a step.
"""

from __future__ import annotations

import threading
import time
import types
from concurrent.futures import ThreadPoolExecutor

import numpy as np

from granum.yade.view import frames, inspector

#: the largest share of the run's wall time the view may take (frames and publishing them, server side)
BUDGET = 0.04
#: shortest and longest time between two frames while a run goes on [s]
MIN_INTERVAL, MAX_INTERVAL = 0.1, 5.0

#: renderer options the browser view draws; any other option set away from its default is refused by name
DRAWN = ("shape", "wire", "bound", "intrPhys", "intrWire", "mask", "ghosts", "dispScale", "cellColor", "bgColor",
         "light1", "lightPos", "lightColor", "light2", "light2Pos", "light2Color", "clipPlaneSe3", "clipPlaneActive")


class Session:
    """The state shared by the page's server thread, the run's thread and the user's thread."""

    def __init__(self, omega, renderer):
        self.omega = omega
        self.renderer = renderer
        self.field = "color"
        self.interval = MIN_INTERVAL  # time between two frames [s], widened by spent() to stay within BUDGET
        self.closing = False
        self.loop = None             # the server's event loop, once it runs
        self.server = None
        self.view_widget = None
        self.url = ""
        self.hook_seconds = 0.0      # wall time spent in between_chunks [s]
        self.publish_seconds = 0.0   # wall time the server's loop spent publishing frames [s]
        self._frame_cost = 0.0
        self._publish_cost = 0.0
        self.hook_calls = 0
        self.frames_taken = 0
        self._lock = threading.Lock()
        self._fresh: frames.Frame | None = None   # taken by the run's thread, not yet published
        self._shown: frames.Frame | None = None   # the frame the page shows (for picking)
        self._last_take = 0.0
        self._idle_key = None
        self._plots = False          # plot.plot() was called: show the figures
        self._plot_key = None
        self._plot_time = 0.0
        self._worker = ThreadPoolExecutor(1, thread_name_prefix="granum-view-command")
        self.message = ""
        self.picked_id = -1

    # ---- frames ------------------------------------------------------------------------------
    def options(self) -> frames.Options:
        """The renderer's options as the frame reads them; refuses, by name, options the view cannot draw."""
        r = self.renderer
        for name, spec in r._attrs.items():
            if name not in DRAWN and getattr(r, name) != spec.default:
                raise NotImplementedError(f"the browser view does not draw qt.Renderer().{name}; set it back to "
                                          f"{spec.default!r} (drawn: {', '.join(DRAWN)})")
        lights = ((r.light1, r.lightPos, r.lightColor), (r.light2, r.light2Pos, r.light2Color))
        return frames.Options(shape=r.shape, wire=r.wire, bound=r.bound, intrPhys=r.intrPhys, intrWire=r.intrWire,
                              mask=r.mask, ghosts=r.ghosts, dispScale=tuple(r.dispScale), cellColor=tuple(r.cellColor),
                              lights=tuple((tuple(pos), tuple(rgb)) for on, pos, rgb in lights if on),
                              clip_planes=tuple(tuple(map(tuple, plane)) for plane in r.clip_planes().tolist()))

    def frame(self) -> frames.Frame:
        """A frame of the current scene, taken now."""
        f = frames.take_frame(self.omega._scene, self.options(), self.field)
        self.frames_taken += 1
        return f

    def between_chunks(self, scene) -> None:
        """``O.chunk_hooks`` entry: copy a frame if the last one is older than :attr:`interval`."""
        t0 = time.perf_counter()
        self.hook_calls += 1
        if t0 - self._last_take >= self.interval and scene is self.omega._scene:
            try:
                f = self.frame()
            except NotImplementedError as e:
                self.message = str(e)
            else:
                with self._lock:
                    self._fresh = f
            self._last_take = t0
            self.spent(time.perf_counter() - t0, publish=False)
        self.hook_seconds += time.perf_counter() - t0

    def spent(self, seconds: float, publish: bool) -> None:
        """Account the time a frame took to take (``publish`` False) or to publish, and, while a run goes on,
        space frames so that taking and publishing them stay within :data:`BUDGET` of the wall time (up to
        frames :data:`MAX_INTERVAL` apart)."""
        if publish:
            self.publish_seconds += seconds
            self._publish_cost = seconds
        else:
            self._frame_cost = seconds
        wanted = (self._frame_cost + self._publish_cost) / BUDGET if self.omega.running else 0.0
        self.interval = min(max(MIN_INTERVAL, wanted), MAX_INTERVAL)

    def set_field(self, field: str) -> None:
        if field not in frames.FIELDS:
            raise ValueError(f"view: cannot colour by {field!r}; fields: {', '.join(frames.FIELDS)}")
        self.field = field
        self._idle_key = None

    def _next_frame(self) -> frames.Frame | None:
        """The frame to publish: the run's latest, or one taken now if the idle scene changed."""
        with self._lock:
            f, self._fresh = self._fresh, None
        if f is not None or self.omega.running:
            return f
        s = self.omega._scene
        r = self.renderer
        key = (id(s), s.iter, s.body_count, s.time, self.field,
               tuple((n, str(getattr(r, n))) for n in r._attrs))
        if key == self._idle_key:
            return None
        self._idle_key = key
        return self.frame()

    def camera(self) -> dict:
        """vtk.js camera of the first ``qt.View()`` (or a new one framing the scene): eye, look-at point, up
        vector, YADE's 45 degree vertical field of view, so the page shows what ``saveSnapshot`` draws."""
        from granum.yade import qt
        from granum.yade.snapshot import View

        v = qt._views[0] if qt._views else View(lambda: self.omega._scene)
        if not v._fitted:
            v.center(median=False)
        eye = np.asarray(v.eyePosition, float)
        d = np.asarray(v.viewDir, float) / np.linalg.norm(v.viewDir)
        dist = max(float(np.linalg.norm(eye - v._center)), 1e-9)
        return {"position": eye.tolist(), "focalPoint": (eye + d * dist).tolist(),
                "viewUp": list(map(float, v.upVector)), "viewAngle": 45.0, "parallelProjection": bool(v.ortho),
                "parallelScale": float(v.sceneRadius), "clippingRange": [v.near() if not v.ortho else 1e-6 * dist,
                                                                         dist + 4 * v.sceneRadius]}

    # ---- what the page shows -----------------------------------------------------------------
    def panel_state(self) -> dict:
        O = self.omega

        def line(e):
            label = f" ({e.label})" if getattr(e, "label", "") else ""
            return type(e).__name__ + label + (" [dead]" if getattr(e, "dead", False) else "")

        return {"running": bool(O.running), "dt": f"{O.dt:.6g}", "bg": list(map(float, self.renderer.bgColor)),
                "speed": f"{O.speed:.4g} steps/s",
                "engines": [{"name": line(e), "rows": inspector.declared_rows(e)} for e in O.engines],
                "dyn_dt": bool(O.dynDt), "dyn_dt_available": bool(O.dynDtAvailable), "message": self.message,
                **self.inspected()}

    def poll(self) -> dict:
        """What changed since the last poll, as shared-state entries (called on the server's loop)."""
        from granum.yade.view.app import frame_state

        update = self.panel_state()
        try:
            f = self._next_frame()
        except NotImplementedError as e:
            update["message"] = self.message = str(e)
            f = None
        if f is not None:
            update.update(frame_state(f, self._shown))
            self._shown = f
        update.update(self._plot_update())
        return update

    def pick(self, origin, direction) -> dict:
        """The inspector's state entries for the sphere of the frame shown that the ray clicked hits first
        (none picked if it hits nothing)."""
        f = self._shown
        self.picked_id = frames.pick(f, origin, direction) if f is not None else -1
        return self.inspected()

    def inspected(self) -> dict:
        """The inspector's state entries: ``picked`` (a line naming the picked body, "" if none) and
        ``inspected`` (its sections of editable rows, :func:`inspector.body_sections`)."""
        i = self.picked_id
        b = self.omega.bodies[i] if 0 <= i < len(self.omega.bodies) else None
        if b is None:
            self.picked_id = -1
            return {"picked": "", "inspected": []}
        head = (f"id {i}: {type(b.shape).__name__}, {type(b.mat).__name__} {b.mat.label or b.mat.id}, "
                f"mass {b.state.mass:.6g}, {len(b.intrs())} contacts")
        return {"picked": head, "inspected": inspector.body_sections(self.omega, i)}

    # ---- controller ----------------------------------------------------------------------------
    def command(self, name: str, *args) -> None:
        """Queue a controller command (play, pause, step, run N, dt, dynDt, reload, edit_body (section key,
        attribute, text), edit_engine (index in O.engines, attribute, text)) on the worker thread."""
        self._worker.submit(self._run_command, name, *args)

    def _run_command(self, name: str, *args) -> None:
        O = self.omega
        where = name
        try:
            if name == "play":
                O.run()
            elif name == "pause":
                O.pause()
                O.wait()
            elif name == "step":
                if not O.running:
                    O.step()
            elif name == "run":
                n = int(args[0])
                if n < 1:
                    raise ValueError(f"run N needs a positive number of steps, got {n}")
                O.run(n)
            elif name == "dt":
                O.dt = float(args[0])
            elif name == "dynDt":
                O.dynDt = bool(args[0])
            elif name == "reload":
                O.pause()
                O.wait()
                O.reload()
            elif name == "edit_body":
                key, attr, text = args
                where = f"{inspector.path(self.picked_id, key)}.{attr} = {text}"
                inspector.assign(inspector.resolve(O, self.picked_id, key), attr, text)
            elif name == "edit_engine":
                k, attr, text = args
                where = f"O.engines[{k}].{attr} = {text}"
                inspector.assign(O.engines[int(k)], attr, text)
            self.message = ""
        except Exception as e:  # noqa: BLE001 - shown in the page, where the user clicked
            self.message = f"{where}: {e}"
        self._idle_key = None

    # ---- live plots ----------------------------------------------------------------------------
    def show_plots(self) -> None:
        """``plot.plot()`` was called: the page shows the figures, updated while ``plot.live``."""
        self._plots = True
        self._plot_key = None

    def _plot_update(self) -> dict:
        from granum.yade import plot

        if not self._plots or not plot.plots:
            return {}
        key = (plot._nrows(), tuple(plot.data))
        now = time.monotonic()
        if key == self._plot_key or (self._plot_key is not None and
                                     (not plot.live or now - self._plot_time < plot.liveInterval)):
            return {}
        from matplotlib.figure import Figure

        from granum.yade.view.app import png_of_figures

        try:
            figs, _ = plot._make_figures(types.SimpleNamespace(figure=Figure), True)
        except ValueError:   # the run's thread was adding a row meanwhile (columns of unequal length): next poll
            return {}
        self._plot_key, self._plot_time = key, now
        return {"plot_png": png_of_figures(figs), "plot_rows": key[0]}

    def close(self) -> None:
        self.closing = True
        if self.between_chunks in self.omega.chunk_hooks:
            self.omega.chunk_hooks.remove(self.between_chunks)
        self._worker.shutdown(wait=False)
