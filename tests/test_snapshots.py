"""Off-screen pictures (qt.View, qt.Renderer, qt.SnapshotEngine) and makeVideo.

Pictures are read back with Pillow and checked pixel by pixel at the places where the camera
projects the bodies; videos are probed with the ffmpeg of imageio-ffmpeg.
"""

from __future__ import annotations

import os

import numpy as np
import pytest
from PIL import Image

from granum.io.raster import Canvas


@pytest.fixture
def qt(yade):
    """``yade.qt`` with no open view and the renderer's default options (also afterwards)."""
    from granum.yade import qt, snapshot

    defaults = snapshot.Renderer().dict()
    snapshot.RENDERER.updateAttrs(defaults)  # other tests may have changed the shared renderer
    qt.close()
    yield qt
    qt.close()
    snapshot.RENDERER.updateAttrs(defaults)


def pixel(path, xy) -> np.ndarray:
    img = np.asarray(Image.open(path).convert("RGB"))
    return img[int(xy[1]), int(xy[0])].astype(int)


def around(path, xy) -> np.ndarray:
    """(9, 3) pixels of the 3 x 3 block around ``xy`` (thin lines may miss the pixel of the exact point)."""
    img = np.asarray(Image.open(path).convert("RGB")).astype(int)
    x, y = int(xy[0]), int(xy[1])
    return img[y - 1:y + 2, x - 1:x + 2].reshape(-1, 3)


def at(view, point) -> tuple[float, float]:
    """Image coordinates of a world point."""
    xy, _, _ = view.project(np.asarray([point], float))
    return float(xy[0, 0]), float(xy[0, 1])


BACKGROUND = (51, 51, 51)  # YADE's default bgColor (0.2, 0.2, 0.2)


def two_spheres(y):
    y.O.bodies.append([y.sphere((0, 0, 0), 0.5, color=(1, 0, 0)), y.sphere((2, 0, 0), 0.3, color=(0, 0, 1))])


def test_snapshot_engine_names_files_as_yade(yade, qt, tmp_path):
    two_spheres(yade)
    qt.View()
    base = str(tmp_path / "snap-")
    yade.O.engines = [yade.ForceResetter(), yade.NewtonIntegrator(),
                      qt.SnapshotEngine(fileBase=base, iterPeriod=2, label="snapshot")]
    yade.O.dt = 1e-4
    yade.O.run(7, True)
    eng = yade.O.engines[-1]
    # as YADE: the first call only sets the reference step, then steps 2, 4, 6; 5-digit counter
    assert eng.snapshots == [f"{base}{k:05d}.png" for k in range(3)]
    assert eng.counter == 3
    for f in eng.snapshots:
        with open(f, "rb") as fh:
            assert fh.read(8) == b"\x89PNG\r\n\x1a\n"
        assert Image.open(f).size == (550, 550)
    assert sorted(os.listdir(tmp_path)) == [f"snap-{k:05d}.png" for k in range(3)]  # no temporary files left


def test_picture_shows_bodies_in_their_colours(yade, qt, tmp_path):
    two_spheres(yade)
    yade.O.bodies.append(yade.facet([(-1, 1, 0), (3, 1, 0), (1, 3, 0)], wire=False, color=(0, 1, 0)))
    yade.O.bodies.append(yade.facet([(-1, -1, 0), (3, -1, 0), (1, -3, 0)], color=(1, 1, 0)))  # wire by default
    v = qt.View()
    path = str(tmp_path / "a.png")
    v.saveSnapshot(path)
    red, blue = pixel(path, at(v, (0, 0, 0))), pixel(path, at(v, (2, 0, 0)))
    assert red[0] > 150 and red[1] < 60 and red[2] < 60
    assert blue[2] > 150 and blue[0] < 60 and blue[1] < 60
    green = pixel(path, at(v, (1, 5 / 3, 0)))  # centroid of the solid facet
    assert green[1] > 120 and green[0] < 60 and green[2] < 60
    assert tuple(pixel(path, at(v, (1, -5 / 3, 0)))) == BACKGROUND  # wire facet: hollow...
    edge = around(path, at(v, (1, -1, 0)))  # ...with yellow edges
    assert np.any((edge[:, 0] > 120) & (edge[:, 1] > 120) & (edge[:, 2] < 60))
    assert tuple(pixel(path, (540, 10))) == BACKGROUND
    # shading: the lit side of a sphere is brighter than the opposite side
    left_top = pixel(path, at(v, (-0.3, 0.3, 0.3)))
    right_bottom = pixel(path, at(v, (0.3, -0.3, 0.3)))
    assert left_top[0] > right_bottom[0]


def test_nearer_body_hides_farther_one(yade, qt, tmp_path):
    # the default camera looks down the z axis: the sphere with the larger z is in front
    yade.O.bodies.append([yade.sphere((0, 0, 1), 0.5, color=(0, 1, 0)), yade.sphere((0, 0, 0), 1.0, color=(1, 0, 0))])
    v = qt.View()
    path = str(tmp_path / "z.png")
    v.saveSnapshot(path)
    front = pixel(path, at(v, (0, 0, 1.5)))
    assert front[1] > 150 and front[0] < 60
    rim = pixel(path, at(v, (-0.97, 0, 0)))  # lit side, just outside the small sphere's silhouette
    assert rim[0] > 100 and rim[1] < 60


def test_renderer_options_are_honoured(yade, qt, tmp_path):
    two_spheres(yade)
    v = qt.View()
    r = qt.Renderer()
    assert r is qt.Renderer()  # one renderer, as in YADE
    r.shape = False
    r.bgColor = (1, 1, 1)
    path = str(tmp_path / "r.png")
    v.saveSnapshot(path)
    assert tuple(pixel(path, at(v, (0, 0, 0)))) == (255, 255, 255)
    r.shape, r.wire = True, True
    v.saveSnapshot(path)
    assert tuple(pixel(path, at(v, (0, 0, 0)))) == (255, 255, 255)  # wire: the inside is empty
    outline = around(path, at(v, (0, -0.5, 0)))
    assert np.any((outline[:, 0] > 150) & (outline[:, 1] < 100))  # the red outline
    with pytest.raises(AttributeError, match="did you mean 'shape'"):
        r.shap = False


def test_force_chains_with_intrPhys(yade, qt, tmp_path):
    yade.O.bodies.append([yade.sphere((0, 0, 0), 0.5), yade.sphere((0.95, 0, 0), 0.5)])
    yade.O.engines = [yade.ForceResetter(), yade.InsertionSortCollider([yade.Bo1_Sphere_Aabb()]),
                      yade.InteractionLoop([yade.Ig2_Sphere_Sphere_ScGeom()], [yade.Ip2_FrictMat_FrictMat_FrictPhys()],
                                           [yade.Law2_ScGeom_FrictPhys_CundallStrack()]),
                      yade.NewtonIntegrator()]
    yade.O.dt = 1e-5
    yade.O.run(1, True)
    assert yade.O.interactions.countReal() == 1
    v = qt.View()
    r = qt.Renderer()
    r.shape, r.intrPhys = False, True
    path = str(tmp_path / "f.png")
    v.saveSnapshot(path)
    mid = pixel(path, at(v, (0.475, 0, 0)))
    assert mid[0] > 150 and mid[2] < 60  # the largest force is drawn red
    assert tuple(pixel(path, at(v, (0.475, 0.4, 0)))) == BACKGROUND


def test_periodic_bodies_are_drawn_inside_the_cell(yade, qt, tmp_path):
    O = yade.O
    O.periodic = True
    O.cell.hSize = yade.Matrix3(2, 0, 0, 0, 2, 0, 0, 0, 2)
    O.bodies.append(yade.sphere((2.5, 1, 1), 0.3, color=(1, 0, 0)))  # its image in the cell is at x = 0.5
    v = qt.View()
    np.testing.assert_allclose(at(v, (1, 1, 1)), (275, 275))  # a periodic view frames the cell
    path = str(tmp_path / "p.png")
    v.saveSnapshot(path)
    assert pixel(path, at(v, (0.5, 1, 1.3)))[0] > 150
    assert tuple(pixel(path, at(v, (1.5, 1, 1.3)))) == BACKGROUND
    edge = around(path, at(v, (0, 1, 2)))  # the cell's edges, in YADE's yellow
    assert np.any((edge[:, 0] > 150) & (edge[:, 1] > 150) & (edge[:, 2] < 60))


def test_view_camera(yade, qt, tmp_path):
    yade.O.bodies.append([yade.sphere((0, 0, 0), 0.1), yade.sphere((2, 1, 0.5), 0.1)])
    v = qt.View()
    assert qt.views() == [v]
    # YADE's default view: looking down z, y up, centred on the box of the body positions with a
    # radius of 1.5 times its largest half size, at the distance that fits a 45 degree field of view
    assert tuple(v.viewDir) == (0, 0, -1) and tuple(v.upVector) == (0, 1, 0)
    assert v.sceneRadius == pytest.approx(1.5)
    np.testing.assert_allclose(v.eyePosition, (1, 0.5, 0.25 + 1.5 / np.sin(np.pi / 8)))
    np.testing.assert_allclose(v.lookAt, np.asarray(v.eyePosition) + np.asarray(v.viewDir))
    np.testing.assert_allclose(at(v, (1, 0.5, 0.25)), (275, 275))  # the centre is in the middle
    assert at(v, (2, 1, 0.25))[0] > 275 and at(v, (2, 1, 0.25))[1] < 275  # x to the right, y up
    v.viewDir = (1, 0, 0)
    v.upVector = (0, 0, 1)
    v.fitAABB((-1, -1, -1), (1, 1, 1))
    np.testing.assert_allclose(v.eyePosition, (-np.sqrt(3) / np.sin(np.pi / 8), 0, 0))
    v.ortho = True
    v.screenSize = (200, 100)
    v.saveSnapshot(str(tmp_path / "o.jpeg"), format="JPEG")
    assert Image.open(tmp_path / "o.jpeg").size == (200, 100)
    v.close()
    assert qt.views() == []
    qt.Controller().anything.goes()  # windows are inert without a screen


def test_snapshot_formats(yade, qt, tmp_path):
    two_spheres(yade)
    eng = qt.SnapshotEngine(fileBase=str(tmp_path / "s"), format="JPEG", iterPeriod=1)
    eng.run_python(yade.O)
    assert eng.snapshots == [str(tmp_path / "s00000.jpeg")]
    assert Image.open(eng.snapshots[0]).format == "JPEG"
    with pytest.raises(ValueError, match="format must be one of"):
        qt.SnapshotEngine(format="TIFF")


def test_canvas_triangle_coverage_and_depth():
    c = Canvas(100, 80, background=(0, 0, 0))
    # a right triangle covering half of a 60 x 40 box, and a nearer one over part of it
    c.triangles(np.array([[[10, 10], [70, 10], [10, 50]]], float), np.array([[2.0, 2.0, 2.0]]),
                np.array([[1.0, 0, 0]]), np.array([[0, 0, 1.0]]))
    img = c.image()
    red = np.count_nonzero(img[..., 0] > 0)
    assert abs(red - 60 * 40 / 2) < 60 + 40  # area, up to the pixels along the hypotenuse
    c.triangles(np.array([[[0, 0], [100, 0], [0, 80]]], float), np.array([[3.0, 3.0, 3.0]]),
                np.array([[0, 1.0, 0]]), np.array([[0, 0, 1.0]]))
    img = c.image()
    assert img[20, 20, 0] > 0 and img[20, 20, 1] == 0  # the farther triangle stays behind
    assert img[5, 5, 1] > 0


# ---- makeVideo -------------------------------------------------------------------------------------
@pytest.fixture
def frames(tmp_path):
    paths = []
    for k in range(5):
        p = tmp_path / f"f-{k:05d}.png"
        Image.new("RGB", (64, 48), (50 * k, 0, 255 - 50 * k)).save(p)
        paths.append(str(p))
    return paths


def test_make_video(frames, tmp_path):
    ffmpeg = pytest.importorskip("imageio_ffmpeg", reason="makeVideo encodes with imageio-ffmpeg's ffmpeg")
    from granum.yade.video import makeVideo

    out = str(tmp_path / "v.mpeg")
    assert makeVideo(frames, out, fps=10) == out
    nframes, secs = ffmpeg.count_frames_and_secs(out)
    assert nframes == 5 and secs == pytest.approx(0.5)
    with open(out, "rb") as f:
        head = f.read(12)
    assert head[:4] == b"RIFF" and head[8:] == b"AVI "  # an AVI with MPEG-4 inside, as YADE's mencoder
    # an existing video is kept as v.mpeg~0; bps is the deprecated name of kbps
    with pytest.warns(DeprecationWarning, match="kbps"):
        makeVideo(str(tmp_path / "f-*.png"), out, fps=5, bps=2000)
    assert os.path.exists(out + "~0")
    assert ffmpeg.count_frames_and_secs(out) == (5, pytest.approx(1.0))
    mp4 = str(tmp_path / "v.mp4")
    makeVideo(str(tmp_path / "f-%05d.png"), mp4, fps=24)
    assert ffmpeg.count_frames_and_secs(mp4)[0] == 5
    with open(mp4, "rb") as f:
        assert f.read(12)[4:8] == b"ftyp"
    with pytest.raises(ValueError, match="no picture files"):
        makeVideo(str(tmp_path / "nothing-*.png"), out)


def test_frame_specifications(frames, tmp_path):
    from granum.yade.video import frame_files

    assert frame_files(frames[::-1]) == frames[::-1]  # a list keeps its order
    assert frame_files(str(tmp_path / "f-*.png")) == frames
    assert frame_files(str(tmp_path / "f-%05d.png")) == frames
    assert frame_files(str(tmp_path / "g-%05d.png")) == []


def test_tutorial_05_runs_headless_and_leaves_vtk_pictures_and_a_video(tmp_path):
    """The documentation's 05-3d-postprocessing.py, unmodified, run for its 20,000 steps as the GUI's
    Start button would: VTK series for ParaView, snapshots showing the force chains, the video."""
    import pathlib
    import shutil
    import subprocess
    import sys

    import imageio_ffmpeg
    import vtk

    tutorial = pathlib.Path(__file__).resolve().parents[1] / "examples" / "tutorial" / "05-3d-postprocessing.py"
    shutil.copy(tutorial, tmp_path)
    (tmp_path / "start.py").write_text("exec(open('05-3d-postprocessing.py').read())\nO.run(20001, True)\n")
    r = subprocess.run([sys.executable, "-m", "granum", "start.py"], cwd=tmp_path, capture_output=True, text=True,
                       timeout=900)
    assert r.returncode == 0, r.stderr
    spheres = sorted(tmp_path.glob("3d-vtk-spheres.*.vtu"), key=lambda p: int(p.name.split(".")[1]))
    assert [int(p.name.split(".")[1]) for p in spheres] == list(range(0, 20001, 1000))
    counts = []
    for p in (spheres[0], spheres[-1]):
        reader = vtk.vtkXMLUnstructuredGridReader()
        reader.SetFileName(str(p))
        reader.Update()
        grid = reader.GetOutput()
        radii = grid.GetPointData().GetArray("radii")
        assert radii is not None and 0.04 <= radii.GetRange()[0] <= radii.GetRange()[1] <= 0.16  # rMean .1 +-60%
        counts.append(grid.GetNumberOfPoints())
    assert counts[0] == counts[1] > 50
    assert (tmp_path / "3d-vtk-spheres.pvd").read_text().count("<DataSet") == 21
    pictures = sorted(tmp_path.glob("3d-*.png"))
    assert len(pictures) == 100  # iterPeriod=200 up to the 20,000th step, then the video is made
    img = np.asarray(Image.open(pictures[-1]).convert("RGB")).astype(int)
    drawn = np.any(np.abs(img - BACKGROUND) > 30, axis=2)
    assert drawn.mean() > 0.01, "the snapshot shows nothing but background"
    assert len({tuple(c) for c in img[drawn][::7]}) > 20, "force chains are drawn in colours of their force"
    nframes, _ = imageio_ffmpeg.count_frames_and_secs(str(tmp_path / "3d.mpeg"))
    assert nframes == 100
