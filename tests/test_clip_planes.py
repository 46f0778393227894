"""qt.Renderer() clipping planes (clipPlaneSe3, clipPlaneActive): YADE's 3D view hides a body whose centre is
behind an active plane (the side the plane's orientation turns +z away from). Reference: real YADE's snapshots
of three spheres (tests/reference/yade/clip_planes.py); granum's snapshot and the browser view's frames must
draw the same spheres."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

REF = json.loads((Path(__file__).parent / "reference" / "yade" / "clip_planes.json").read_text())
COLOURS = {"red": (1, 0, 0), "green": (0, 1, 0), "blue": (0, 0, 1)}


def _planes(case):
    from granum.mathtypes import Quaternion

    return [(pos, Quaternion(*wxyz)) for pos, wxyz in case["clipPlaneSe3"]]


@pytest.fixture
def three_spheres():
    from granum.yade import O, utils
    from granum.yade.snapshot import RENDERER, View

    O.reset()
    O.bodies.append([utils.sphere((-0.3, 0, 0), 0.5, color=COLOURS["red"]),
                     utils.sphere((0.3, 1.2, 0), 0.5, color=COLOURS["green"]),
                     utils.sphere((-2, 0, 0), 0.5, color=COLOURS["blue"])])
    v = View(lambda: O._scene)
    v.viewDir, v.upVector = (0, 0, -1), (0, 1, 0)
    v.fitAABB((-3, -1, -1), (1, 2, 1))
    saved = RENDERER.clipPlaneSe3, RENDERER.clipPlaneActive
    yield O, v, RENDERER
    RENDERER.clipPlaneSe3, RENDERER.clipPlaneActive = saved
    O.reset()


def test_defaults_are_yades():
    from granum.yade.snapshot import Renderer

    r = Renderer()
    assert [[list(map(float, p)), [q[3], q[0], q[1], q[2]]] for p, q in r.clipPlaneSe3] == \
        REF["defaults"]["clipPlaneSe3"]
    assert r.clipPlaneActive == REF["defaults"]["clipPlaneActive"]
    assert r.clip_planes().shape == (0, 2, 3)


@pytest.mark.parametrize("name", list(REF["cases"]))
def test_snapshot_draws_the_spheres_yade_draws(three_spheres, name):
    from granum.yade.snapshot import render

    O, v, r = three_spheres
    case = REF["cases"][name]
    r.clipPlaneSe3, r.clipPlaneActive = _planes(case), case["clipPlaneActive"]
    img = render(O._scene, v, r).astype(int)
    red, green, blue = img[..., 0], img[..., 1], img[..., 2]
    pixels = {"red": ((red > green + 60) & (red > blue + 60)).sum(),
              "green": ((green > red + 60) & (green > blue + 60)).sum(),
              "blue": ((blue > red + 60) & (blue > green + 60)).sum()}
    # a sphere drawn covers thousands of pixels of the 550 x 550 picture, a hidden one none
    assert {k: bool(n > 200) for k, n in pixels.items()} == case["drawn"], pixels
    assert all(n == 0 or n > 2000 for n in pixels.values()), pixels


@pytest.mark.parametrize("name", list(REF["cases"]))
def test_browser_frame_holds_the_spheres_yade_draws(three_spheres, name):
    from granum.yade.view.session import Session

    O, _, r = three_spheres
    case = REF["cases"][name]
    r.clipPlaneSe3, r.clipPlaneActive = _planes(case), case["clipPlaneActive"]
    frame = Session(O, r).frame()
    assert {k: i in frame.sphere_ids for i, k in enumerate(COLOURS)} == case["drawn"]


def test_bad_clip_planes_are_refused_by_name():
    from granum.yade.snapshot import Renderer

    r = Renderer()
    with pytest.raises(ValueError, match=r"clipPlaneSe3\[1\] must be \(position, Quaternion\)"):
        r.clipPlaneSe3 = [((0, 0, 0), (1, 0, 0, 0)), ((0, 0), "x")]
    with pytest.raises(ValueError, match="clipPlaneSe3 holds at most 3 planes"):
        r.clipPlaneSe3 = [((0, 0, 0), (1, 0, 0, 0))] * 4
    with pytest.raises(ValueError, match="clipPlaneActive holds at most 3 flags"):
        r.clipPlaneActive = [True] * 4
    assert r.clipPlaneActive == [False] * 3 and len(r.clipPlaneSe3) == 3
