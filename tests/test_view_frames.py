"""The browser view's data and rules, without a browser: frames, picking, refusals, no port in scripts."""

from __future__ import annotations

import sys

import numpy as np
import pytest

from granum.yade import O, qt, utils, view
from granum.yade.snapshot import RENDERER
from granum.yade.view import frames
from granum.yade.view.session import Session


@pytest.fixture
def scene():
    O.reset()
    O.bodies.append([utils.sphere((0, 0, 0), 0.5), utils.sphere((0, 0, 3), 1.0),
                     utils.facet([(0, 0, -2), (1, 0, -2), (0, 1, -2)]), utils.wall(-5, axis=2),
                     utils.box((4, 0, 0), (0.5, 0.5, 0.5))])
    O.bodies[0].state.vel = (3, 4, 0)
    yield O
    O.reset()


def test_frame_holds_every_shape(scene):
    f = frames.take_frame(O._scene)
    assert list(f.sphere_ids) == [0, 1]
    np.testing.assert_allclose(f.sphere_radius, [0.5, 1.0])
    # the facet is drawn as wire (YADE's default for facets): 3 edges; the box's 6 faces as 12 triangles,
    # the wall as 2 triangles
    assert len(f.line_points) == 3
    assert len(f.tri_points) == 12 + 2
    assert f.field == "color" and f.value_range == (0.0, 0.0)


def test_frame_coloured_by_speed(scene):
    f = frames.take_frame(O._scene, field="velocity")
    assert f.value_range == (0.0, 5.0)
    np.testing.assert_array_equal(f.sphere_rgb[0], frames.colormap_rgb(np.array([5.0]), 0, 5)[0])
    with pytest.raises(ValueError, match="stress"):
        frames.take_frame(O._scene, field="stress")


def test_periodic_cell_and_bounds_are_lines(scene):
    O.periodic = True
    O.cell.setBox(10, 10, 10)
    f = frames.take_frame(O._scene, frames.Options(bound=False))
    assert len(f.line_points) == 3 + 12
    ends = f.line_points[-12:].reshape(-1, 3)
    assert ends.min() == 0 and ends.max() == 10


def test_pick_is_the_first_sphere_hit(scene):
    f = frames.take_frame(O._scene)
    assert frames.pick(f, (0, 0, 10), (0, 0, -1)) == 1          # the upper sphere hides the lower
    assert frames.pick(f, (0, 0, -10), (0, 0, 1)) == 0
    assert frames.pick(f, (0.9, 0, 10), (0, 0, -1)) == 1        # inside radius 1 only
    assert frames.pick(f, (0, 0.45, -10), (0, 0, 1)) == 0
    assert frames.pick(f, (2, 2, 10), (0, 0, -1)) == -1
    assert frames.pick(f, (0, 0, 10), (0, 0, 1)) == -1          # behind the eye


def test_renderer_options_not_drawn_are_refused_by_name(scene):
    s = Session(O, RENDERER)
    RENDERER.intrGeom = True
    try:
        with pytest.raises(NotImplementedError, match="intrGeom"):
            s.options()
    finally:
        RENDERER.intrGeom = False
    assert s.options().shape is True


def test_a_script_opens_no_port(scene, capsys, monkeypatch):
    monkeypatch.setattr(view, "_hinted", False)
    view.forbid()
    v = qt.View()
    assert view.current() is None
    assert "--view" in capsys.readouterr().err
    v.close()


def test_without_trame_the_view_says_how_to_install(scene, monkeypatch):
    monkeypatch.setitem(sys.modules, "trame", None)
    view.allow()
    try:
        with pytest.raises(ImportError, match=r"granum\[view\]"):
            qt.View()
    finally:
        view.forbid()
        qt.close()


def test_granum_script_run_opens_no_port(tmp_path):
    """`granum script.py` (no --view) whose script calls qt.View(): no server, a line saying how to see it."""
    import os
    import subprocess
    from pathlib import Path

    script = tmp_path / "viewing.py"
    script.write_text("from yade import qt\nfrom granum.yade import view\nqt.View()\nqt.Controller()\n"
                      "print('SERVED', view.current() is not None)\n")
    src = str(Path(__file__).resolve().parents[1] / "src")
    env = {**os.environ, "PYTHONPATH": src + os.pathsep + os.environ.get("PYTHONPATH", "")}
    out = subprocess.run([sys.executable, "-m", "granum", str(script)], capture_output=True, text=True, env=env,
                         timeout=120, cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    assert "SERVED False" in out.stdout
    assert "granum --view" in out.stderr and "http://" not in out.stderr


def test_periodic_ghosts(scene):
    """A sphere crossing a face of the cell is drawn again one cell vector away; one inside is not."""
    O.reset()
    O.periodic = True
    O.cell.setBox(10, 10, 10)
    O.bodies.append([utils.sphere((0.5, 5, 5), 1.0), utils.sphere((5, 5, 5), 1.0), utils.sphere((12, 9.5, 5), 1.0)])
    f = frames.take_frame(O._scene)
    assert sorted(f.sphere_ids.tolist()) == [0, 0, 1, 2, 2]
    np.testing.assert_allclose(f.sphere_pos[f.sphere_ids == 0], [[0.5, 5, 5], [10.5, 5, 5]])
    np.testing.assert_allclose(f.sphere_pos[f.sphere_ids == 2], [[2, 9.5, 5], [2, -0.5, 5]])
    assert len(frames.take_frame(O._scene, frames.Options(ghosts=False)).sphere_ids) == 3


def test_engine_list_gives_each_engine_attributes(scene):
    from granum.yade import NewtonIntegrator

    O.engines = [NewtonIntegrator(damping=0.3, label="newton")]
    s = Session(O, RENDERER)
    (e,) = s.panel_state()["engines"]
    assert e["name"] == "NewtonIntegrator (newton)"
    rows = {r["name"]: r for r in e["rows"]}
    assert rows["damping"] == {"name": "damping", "value": "0.3", "editable": True}
    assert rows["gravity"]["value"] == "Vector3(0,0,0)"


def _served_by_granum_view(tmp_path, *options):
    """Start ``granum --view [options] script.py`` (an empty scene) and return (process, URL printed)."""
    import os
    import subprocess
    import time
    from pathlib import Path

    script = tmp_path / "empty.py"
    script.write_text("print('LOADED')\n")
    src = str(Path(__file__).resolve().parents[1] / "src")
    env = {**os.environ, "PYTHONPATH": src + os.pathsep + os.environ.get("PYTHONPATH", ""), "DISPLAY": ""}
    proc = subprocess.Popen([sys.executable, "-m", "granum", "--view", *options, str(script)], cwd=tmp_path, env=env,
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    end = time.monotonic() + 120
    for line in proc.stderr:
        if line.startswith("granum view: http"):
            return proc, line.split()[-1]
        if time.monotonic() > end:
            break
    proc.kill()
    raise AssertionError(f"granum --view printed no URL (exit status {proc.wait()})")


@pytest.mark.parametrize("option, listening, not_listening", [
    ((), "127.0.0.1", "127.0.0.2"),                                # loopback only by default
    (("--view-host", "127.0.0.2"), "127.0.0.2", "127.0.0.1"),      # another interface when asked
])
def test_view_listens_only_on_the_host_asked_for(tmp_path, option, listening, not_listening):
    import signal
    import urllib.error
    import urllib.request

    proc, url = _served_by_granum_view(tmp_path, *option)
    try:
        assert url.startswith(f"http://{listening}:")
        port = url.split(":")[2].split("/")[0]
        assert urllib.request.urlopen(url, timeout=10).status == 200
        with pytest.raises(urllib.error.HTTPError) as refused:      # the token is needed on every interface
            urllib.request.urlopen(f"http://{listening}:{port}/", timeout=10)
        assert refused.value.code == 403
        with pytest.raises(urllib.error.URLError) as closed:         # nothing listens on the other address
            urllib.request.urlopen(url.replace(listening, not_listening), timeout=10)
        assert isinstance(closed.value.reason, ConnectionRefusedError)
    finally:
        proc.send_signal(signal.SIGINT)   # Ctrl-C ends `granum --view`
        assert proc.wait(30) == 0


def test_lights_shine_at_the_scene_from_yades_positions(scene):
    """qt.Renderer()'s two lights (on by default) shine from lightPos/light2Pos at the centre of what is
    drawn, in their colours; a light switched off is left out."""
    s = Session(O, RENDERER)
    f = frames.take_frame(O._scene, s.options())
    lo = np.min([f.sphere_pos.min(axis=0), f.tri_points.reshape(-1, 3).min(axis=0),
                 f.line_points.reshape(-1, 3).min(axis=0)], axis=0)
    hi = np.max([f.sphere_pos.max(axis=0), f.tri_points.reshape(-1, 3).max(axis=0),
                 f.line_points.reshape(-1, 3).max(axis=0)], axis=0)
    (p1, c1, rgb1), (p2, c2, rgb2) = f.lights
    assert p1 == (75, 130, 0) and rgb1 == pytest.approx((0.6, 0.6, 0.6))
    assert p2 == (-130, 75, 30) and rgb2 == pytest.approx((0.5, 0.5, 0.1))
    np.testing.assert_allclose(c1, (lo + hi) / 2, rtol=1e-6)
    assert c1 == c2
    RENDERER.light1 = False
    RENDERER.light2Color = (1, 0, 0)
    try:
        ((p, _, rgb),) = frames.take_frame(O._scene, s.options()).lights
        assert p == (-130, 75, 30) and rgb == (1, 0, 0)
    finally:
        RENDERER.light1 = True
        RENDERER.light2Color = (0.5, 0.5, 0.1)
