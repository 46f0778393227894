"""The browser view (granum.yade.view) driven in headless Chromium: YADE's tutorial 02 (gravity deposition)
is served, then the page is checked as a user would see it.

These tests need Debian's ``chromium`` and ``chromium-driver`` (``.ci/run`` installs them) and the ``view``
extra; they fail, never skip, when either is missing. Screenshots are kept in ``tests/artifacts/view/``
(ignored by git); the path is printed.
"""

from __future__ import annotations

import os
import re
import shutil
import sys
import time
import types
import urllib.error
import urllib.request
from pathlib import Path

import numpy as np
import pytest

TUTORIAL = Path(__file__).resolve().parents[1] / "examples" / "tutorial" / "02-gravity-deposition.py"
ARTIFACTS = Path(__file__).resolve().parent / "artifacts" / "view"


def _wait(predicate, timeout=90.0, what="condition"):
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        value = predicate()
        if value:
            return value
        time.sleep(0.2)
    raise AssertionError(f"timed out after {timeout} s waiting for {what}")


@pytest.fixture(scope="module")
def served(tmp_path_factory):
    """Tutorial 02 loaded as ``granum --view`` loads it; yields (session, O)."""
    from granum import cli
    from granum.yade import O, pack, utils, view

    saved = sys.argv[:], sys.path[:], sys.modules.get("__main__"), os.getcwd()
    os.chdir(tmp_path_factory.mktemp("view"))   # the tutorial writes its plot and data files here
    O.reset()
    view.allow()
    session = view.open_view(open_browser=False)
    # one packing and one set of colours in every run: the tutorial's makeCloud draws its seed from the system's
    # entropy and its spheres' colours from utils' generator, and the pictures compared below are of them (a
    # clip-plane comparison once fell 0.3 % under its threshold on another packing)
    entropy, pack.secrets = pack.secrets, types.SimpleNamespace(randbits=lambda k: 20261207)
    utils._rng.seed(20261207)
    try:
        cli.run_script(str(TUTORIAL), [])
    except BaseException:
        os.chdir(saved[3])
        raise
    finally:
        pack.secrets = entropy
        sys.argv[:], sys.path[:] = saved[0], saved[1]
        sys.modules["__main__"] = saved[2]
    yield session, O   # still in the temporary folder: the tests' runs write the tutorial's files there too
    O.pause()
    O.wait()
    os.chdir(saved[3])
    view.close_view()
    view.forbid()
    O.reset()
    from granum.yade import plot

    plot.reset()   # nothing left for plot's exit-time refresh to write
    plot.resetData()


@pytest.fixture(scope="module")
def browser(served):
    chromium, driver_path = shutil.which("chromium"), shutil.which("chromedriver")
    if not chromium or not driver_path:
        pytest.fail("the browser view's tests need Debian's chromium and chromium-driver "
                    "(apt-get install -y chromium chromium-driver; .ci/run installs them)")
    from selenium import webdriver

    options = webdriver.ChromeOptions()
    options.binary_location = chromium
    for arg in ("--headless=new", "--no-sandbox", "--window-size=1000,700", "--use-angle=swiftshader",
                "--enable-unsafe-swiftshader", "--force-device-scale-factor=1"):
        options.add_argument(arg)
    driver = webdriver.Chrome(options=options, service=webdriver.ChromeService(executable_path=driver_path))
    ARTIFACTS.mkdir(parents=True, exist_ok=True)
    print(f"\nview screenshots in {ARTIFACTS}")
    session, _ = served
    driver.get(session.url)
    _wait(lambda: "spheres" in _text(driver, "clock"), what="the page")
    yield driver
    driver.quit()


def _text(driver, element_id):
    from selenium.webdriver.common.by import By

    try:
        return driver.find_element(By.ID, element_id).text
    except Exception:  # noqa: BLE001 - not there yet
        return ""


def _click(driver, element_id):
    from selenium.webdriver.common.by import By

    driver.find_element(By.ID, element_id).click()


def _canvas_picture(driver, name):
    """The view's canvas as an (h, w, 3) uint8 array, cropped from a screenshot kept as an artefact."""
    from PIL import Image
    from selenium.webdriver.common.by import By

    path = ARTIFACTS / f"{name}.png"
    driver.save_screenshot(str(path))
    canvas = driver.find_element(By.TAG_NAME, "canvas")
    x, y, w, h = (int(round(v)) for v in (canvas.location["x"], canvas.location["y"], canvas.size["width"],
                                            canvas.size["height"]))
    return np.asarray(Image.open(path).convert("RGB"))[y:y + h, x:x + w]


def test_the_page_needs_the_token(served):
    session, _ = served
    base, token = session.url.split("?token=")
    assert base.startswith("http://127.0.0.1:")
    for url in (base, base + "?token=" + "x" * len(token)):
        with pytest.raises(urllib.error.HTTPError) as refused:
            urllib.request.urlopen(url, timeout=10)
        assert refused.value.code == 403
    assert urllib.request.urlopen(session.url, timeout=10).status == 200


def _page_and_snapshot(browser, session, O, name):
    """The page's canvas and granum's snapshot of the same scene, camera and picture size, both lit by one
    white light at the eye (YADE's side lights leave the far sides of spheres near the background's grey;
    for comparing shapes the light shines from the eye, a light setting the page honours). Returns the two
    (h, w) masks of the pixels covered by bodies."""
    from PIL import Image

    from granum.yade.snapshot import RENDERER, View, render

    saved = RENDERER.lightPos, RENDERER.lightColor, RENDERER.light2
    RENDERER.lightPos, RENDERER.lightColor, RENDERER.light2 = session.camera()["position"], (1, 1, 1), False
    try:
        _click(browser, "yade_camera")
        time.sleep(3)
        page = _canvas_picture(browser, name)
    finally:
        RENDERER.lightPos, RENDERER.lightColor, RENDERER.light2 = saved
    v = View(lambda: O._scene)
    v.screenSize = (page.shape[1], page.shape[0])
    soft = render(O._scene, v, RENDERER)
    Image.fromarray(soft).save(ARTIFACTS / f"{name}-snapshot.png")
    bg = np.asarray(RENDERER.bgColor) * 255

    def covered(img):
        return np.abs(img.astype(float) - bg).max(axis=2) > 25

    return covered(page), covered(soft)


def _assert_same_coverage(a, b):
    """The pixels covered in the page (``a``) and in the snapshot (``b``) agree: the renderers shade rims and
    draw lines differently (2 px wide in the page, hairlines in the snapshot), so each covered pixel is
    looked for within 3 px in the other picture."""
    def grown(mask, px=3):
        out = mask.copy()
        for dy in range(-px, px + 1):
            for dx in range(-px, px + 1):
                out |= np.roll(np.roll(mask, dy, axis=0), dx, axis=1)
        return out

    page_in_soft = (a & grown(b)).sum() / a.sum()
    soft_in_page = (b & grown(a)).sum() / b.sum()
    print(f"covered: page {a.mean():.3f}, snapshot {b.mean():.3f}; "
          f"page in snapshot {page_in_soft:.3f}, snapshot in page {soft_in_page:.3f}")
    assert page_in_soft > 0.97 and soft_in_page > 0.97


def test_spheres_drawn_as_the_snapshot_draws_them(served, browser):
    """The page's camera is the qt.View()'s: the pixels the page covers with bodies are those granum's own
    software renderer (saveSnapshot) covers, for the same camera and picture size."""
    from granum.yade import qt

    session, O = served
    _canvas_picture(browser, "tutorial02-yade-lights")
    a, b = _page_and_snapshot(browser, session, O, "tutorial02-start")
    assert not qt._views   # tutorial 02 opens no qt.View(): the page frames the scene as a new one does
    assert b.mean() > 0.2        # the cloud of tutorial 02 fills much of the view
    _assert_same_coverage(a, b)


def test_a_clip_plane_hides_the_bodies_behind_it(served, browser):
    """qt.Renderer().clipPlaneSe3/clipPlaneActive: a plane through the cloud's middle, its normal along +x
    (the view's right), hides the bodies whose centre is on its left, in the page as in the snapshot."""
    from granum.mathtypes import Quaternion
    from granum.yade.snapshot import RENDERER

    session, O = served
    mid = np.median(np.asarray([b.state.pos for b in O.bodies]), axis=0)
    whole = _page_and_snapshot(browser, session, O, "tutorial02-unclipped")[0]
    saved = RENDERER.clipPlaneSe3, RENDERER.clipPlaneActive
    RENDERER.clipPlaneSe3 = [(tuple(mid), Quaternion((0, 1, 0), np.pi / 2))] + saved[0][1:]
    RENDERER.clipPlaneActive = [True, False, False]
    try:
        a, b = _page_and_snapshot(browser, session, O, "tutorial02-clipped")
    finally:
        RENDERER.clipPlaneSe3, RENDERER.clipPlaneActive = saved
    _assert_same_coverage(a, b)
    w = a.shape[1]
    cut = int(np.nonzero(whole.any(axis=0))[0].mean())   # about the cloud's middle column
    print(f"covered left of the middle: {whole[:, :cut].sum()} px unclipped, {a[:, :cut].sum()} clipped; "
          f"right: {whole[:, cut:].sum()} and {a[:, cut:].sum()}")
    # left: only the rims of spheres centred right of the plane and the box's lines remain
    assert a[:, :cut - w // 20].sum() < 0.1 * whole[:, :cut - w // 20].sum()
    assert a[:, cut + w // 20:].sum() > 0.9 * whole[:, cut + w // 20:].sum()


def test_software_webgl_draws_without_multisampling(served, browser):
    """Chromium without a GPU draws WebGL with SwiftShader: the view's context is made without multisampling
    (a quarter of a frame's CPU time there; granum-view.js), and it is the context vtk.js draws on."""
    renderer, attributes = browser.execute_script("""
        const probe = document.createElement('canvas').getContext('webgl2');
        const info = probe.getExtension('WEBGL_debug_renderer_info');
        const gl = document.querySelector('canvas').getContext('webgl2');
        return [probe.getParameter(info.UNMASKED_RENDERER_WEBGL), gl.getContextAttributes()];""")
    assert "SwiftShader" in renderer
    assert attributes["antialias"] is False
    assert attributes["depth"] is True and attributes["alpha"] is True   # vtk.js's own attributes kept


def test_occlusion_culling_leaves_the_picture_unchanged(served, browser):
    """On software WebGL the page draws only the spheres that can be seen (granum-view.js): the hidden ones
    are left out, and the picture is the same, pixel for pixel to within one level of rounding, as with every
    sphere drawn, from the YADE camera and from a camera turned to look through the cloud's depth."""
    session, O = served
    n = len(session.frame().sphere_ids)
    _click(browser, "yade_camera")
    time.sleep(2)
    turn = """const v = trame.refs.view, cam = v.getCamera(), f = cam.focalPoint;
        const r = Math.hypot(...[0, 1, 2].map((i) => cam.position[i] - f[i]));
        v.setCamera({position: [f[0] + 0.3 * r, f[1] + 0.1 * r, f[2] - 0.95 * r]});"""
    for name, script in (("yade-camera", ""), ("turned", turn)):
        browser.execute_script(script)
        pictures, drawn = {}, {}
        for culling in (True, False):
            browser.execute_script(f"window.granum_view.setCulling({str(culling).lower()});")
            time.sleep(2)
            drawn[culling] = browser.execute_script("return window.granum_view.spheresDrawn")
            pictures[culling] = _canvas_picture(browser, f"tutorial02-culling-{name}-{'on' if culling else 'off'}")
        browser.execute_script("window.granum_view.setCulling(true);")
        difference = np.abs(pictures[True].astype(int) - pictures[False]).max(axis=2)
        print(f"{name}: {drawn[True]} of {n} spheres drawn with culling; {(difference > 0).sum()} pixels differ, "
              f"by at most {difference.max()} levels")
        assert drawn[False] is None and 0 < drawn[True] < n
        # A sphere wrongly left out shows the surface behind it: another colour and shade (keeping the nearer
        # half of the spheres culling kept: 13,488 pixels differed, by up to 246 levels). CI once saw a single
        # pixel inside a shaded sphere at blue 20 against 19, cause not found (the two pictures are drawn from
        # different vertex data: the culled subset nearest first, all spheres in id order); such rounding is
        # allowed in a few pixels only.
        assert difference.max() <= 1
        assert (difference > 0).sum() <= 5
    _click(browser, "yade_camera")


def test_play_advances_and_pause_stops(served, browser):
    session, O = served
    start = O.iter
    _click(browser, "play")
    _wait(lambda: O.iter > start + 200, what="O.iter to advance after play")
    _click(browser, "pause")
    _wait(lambda: not O.running, what="the run to stop after pause")
    stopped = O.iter
    time.sleep(1.0)
    assert O.iter == stopped
    _wait(lambda: f"#{stopped} " in _text(browser, "clock"), timeout=10, what="the page to show the iteration")
    _canvas_picture(browser, "tutorial02-paused")


def _pick_at_the_centre(browser):
    """Click the middle of the view; the inspector's body id and its state's rows once they are shown."""
    from selenium.webdriver.common.action_chains import ActionChains
    from selenium.webdriver.common.by import By

    _click(browser, "yade_camera")
    time.sleep(2)
    ActionChains(browser).move_to_element(browser.find_element(By.TAG_NAME, "canvas")).click().perform()
    text = _wait(lambda: _text(browser, "picked") if _text(browser, "picked").startswith("id ") else "",
                 timeout=20, what="the inspector")
    _wait(lambda: _value(browser, "body-state-pos"), timeout=10, what="the inspector's rows")
    return int(re.match(r"id (\d+)", text).group(1))


def _value(driver, element_id):
    """The value an inspector's input shows (its placeholder: the field itself is for typing)."""
    from selenium.webdriver.common.by import By

    try:
        return driver.find_element(By.ID, element_id).get_attribute("placeholder")
    except Exception:  # noqa: BLE001 - not there yet
        return ""


def _type_into(driver, element_id, text):
    """Type into an inspector's input and press Enter (its change event)."""
    from selenium.webdriver.common.by import By
    from selenium.webdriver.common.keys import Keys

    driver.find_element(By.ID, element_id).send_keys(text + Keys.ENTER)


def test_clicking_a_body_shows_its_id_and_position(served, browser):
    from granum.yade.view.inspector import parse_value

    session, O = served
    i = _pick_at_the_centre(browser)
    b = O.bodies[i]
    np.testing.assert_allclose(parse_value(_value(browser, "body-state-pos")), np.asarray(b.state.pos),
                               rtol=1e-12, atol=1e-12)
    # the click was at the view's centre: the body is on the camera's axis (YADE's view looks down -z)
    cam = session.camera()
    eye, focal = np.asarray(cam["position"]), np.asarray(cam["focalPoint"])
    axis = (focal - eye) / np.linalg.norm(focal - eye)
    rel = np.asarray(b.state.pos) - eye
    assert np.linalg.norm(rel - axis * (rel @ axis)) <= b.shape.radius * 1.05


def test_editing_a_bodys_velocity_in_the_inspector(served, browser):
    """A velocity typed in the inspector is the body's; a bad one shows the setter's error, as in a script."""
    from granum.mathtypes import Vector3

    session, O = served
    assert not O.running
    i = _pick_at_the_centre(browser)
    _type_into(browser, "body-state-vel", "Vector3(0.5,-0.25,2)")
    _wait(lambda: O.bodies[i].state.vel == Vector3(0.5, -0.25, 2), timeout=20, what="the velocity edited")
    _wait(lambda: _value(browser, "body-state-vel") == "Vector3(0.5,-0.25,2)", timeout=10,
          what="the inspector to show the new velocity")
    with pytest.raises(ValueError) as script:
        O.bodies[i].state.vel = (1, 2)
    _type_into(browser, "body-state-vel", "(1, 2)")
    expected = f"O.bodies[{i}].state.vel = (1, 2): {script.value}"
    _wait(lambda: expected in _text(browser, "status"), timeout=20, what="the setter's error in the page")
    assert O.bodies[i].state.vel == Vector3(0.5, -0.25, 2)
    O.bodies[i].state.vel = (0, 0, 0)


def test_editing_an_engine_attribute(served, browser):
    from selenium.webdriver.common.by import By

    session, O = served
    k = next(k for k, e in enumerate(O.engines) if type(e).__name__ == "NewtonIntegrator")
    before = O.engines[k].damping
    browser.find_elements(By.CSS_SELECTOR, "#engines summary")[k].click()
    _wait(lambda: _value(browser, f"engine-{k}-damping"), timeout=10, what="the engine's rows")
    _type_into(browser, f"engine-{k}-damping", "0.125")
    _wait(lambda: O.engines[k].damping == 0.125, timeout=20, what="the damping edited")
    _type_into(browser, f"engine-{k}-damping", "'much'")
    _wait(lambda: "NewtonIntegrator.damping must be a number" in _text(browser, "status"), timeout=20,
          what="the setter's error in the page")
    assert O.engines[k].damping == 0.125
    O.engines[k].damping = before


def test_live_plot_gains_points(served, browser):
    session, O = served

    def points():
        m = re.search(r"\((\d+) points\)", _text(browser, "plot_title"))
        return int(m.group(1)) if m else -1

    before = points()
    from selenium.webdriver.common.by import By

    field = browser.find_element(By.ID, "run_n")

    def shows_400():
        """The field holds 400, typed at least one poll ago: under load the state's round trip to the server
        could land between the clearing and the keys (CI once ran 23,401 steps, until the tutorial's
        checkUnbalanced paused it), so it is typed again until it stays."""
        if field.get_property("value") == "400":
            return True
        field.clear()
        field.send_keys("400")
        time.sleep(0.5)
        return False

    _wait(shows_400, timeout=30, what="the run field to hold 400")
    _wait(lambda: not O.running, what="an earlier run to stop")  # else O.iter moves after it is read
    start = O.iter
    _click(browser, "run")
    _wait(lambda: O.iter >= start + 400 and not O.running, what="run N to finish")
    assert O.iter == start + 400
    _wait(lambda: points() > before, timeout=20, what="the plot to gain points")
    _canvas_picture(browser, "tutorial02-plot")


def test_reload_goes_back_to_the_saved_scene(served, browser):
    """Tutorial 02 ends with O.saveTmp(): the controller's Reload brings its first step back."""
    session, O = served
    if O.iter == 0:
        O.run(10, True)
    _click(browser, "reload")
    _wait(lambda: O.iter == 0, timeout=30, what="O.reload")
    _wait(lambda: "#0 " in _text(browser, "clock"), timeout=10, what="the page to show iteration 0")


def test_colour_by_speed_shows_the_range_on_the_colour_bar(served, browser):
    from selenium.webdriver.common.by import By
    from selenium.webdriver.support.ui import Select

    session, O = served
    if O.iter == 0:
        O.run(200, True)
    speeds = [np.linalg.norm(np.asarray(b.state.vel)) for b in O.bodies]
    Select(browser.find_element(By.ID, "field")).select_by_value("velocity")

    def bar():   # the range shown, once the frame coloured by speed has arrived
        parts = _text(browser, "bar_range").split(" .. ")
        return tuple(map(float, parts)) if len(parts) == 2 and float(parts[1]) > 0 else None

    lo, hi = _wait(bar, timeout=20, what="the colour bar")
    assert lo == pytest.approx(min(speeds), rel=1e-3, abs=1e-12)
    assert hi == pytest.approx(max(speeds), rel=1e-3)
    assert browser.find_element(By.ID, "colorbar").is_displayed()
    _canvas_picture(browser, "tutorial02-speed")
    Select(browser.find_element(By.ID, "field")).select_by_value("color")
