"""O.save / O.load: exact resumption, every format, atomic writes and clear errors for bad files."""

from __future__ import annotations

import bz2
import os
import pathlib
import subprocess
import sys
import zipfile

import numpy as np
import pytest
from conftest import REFERENCE, frict_engines

from granum.io.checkpoint import CheckpointError

FORMATS = ["scene.yade", "scene.xml", "scene.h5", "scene.yade.gz", "scene.xml.bz2", "scene.h5.gz", "scene.bz2"]


def _state(yade) -> dict[str, np.ndarray]:
    """Everything that evolves: kinematics of every body, cell, clock, energies and contact forces."""
    O = yade.O
    b = O._scene.bodies
    n = b.count
    out = {k: getattr(b, k)[:n].copy() for k in ("pos", "vel", "ori", "ang_vel", "ang_mom", "force", "torque")}
    out["clock"] = np.array([O.iter, O.time, O.dt])
    out["cell"] = np.asarray(O.cell.hSize).copy()
    out["energy"] = np.array(sorted(O.energy.items()), dtype=object)
    contacts = sorted((i.id1, i.id2, *i.phys.normalForce, *i.phys.shearForce) for i in O.interactions)
    out["contacts"] = np.array(contacts)
    return out


def _assert_same(a: dict, b: dict) -> None:
    assert a.keys() == b.keys()
    for k in a:
        assert a[k].shape == b[k].shape, k
        assert (a[k] == b[k]).all(), f"{k} differs after save/load"


def _frictional_box_with_clumps(yade) -> None:
    """Spheres and two clumps settling in a facet box: frictional contacts sliding with shear history."""
    O = yade.O
    O.bodies.append(yade.geom.facetBox((0.5, 0.5, 0.5), (0.5, 0.5, 0.5), wallMask=31))
    sp = yade.pack.SpherePack()
    sp.makeCloud((0, 0, 0), (1, 1, 0.6), rMean=0.06, rRelFuzz=0.3, seed=3)
    sp.toSimulation()
    O.bodies.appendClumped([yade.sphere((0.3, 0.3, 0.85), 0.06), yade.sphere((0.38, 0.3, 0.85), 0.05)])
    O.bodies.appendClumped([yade.sphere((0.7, 0.6, 0.8), 0.05), yade.sphere((0.7, 0.68, 0.8), 0.05),
                            yade.sphere((0.7, 0.64, 0.88), 0.04)])
    O.engines = frict_engines(yade, gravity=(0, 0, -9.81), damping=0.2) + [
        yade.PyRunner(command="pass", iterPeriod=50, label="ticker")]
    O.dt = 0.5 * yade.PWaveTimeStep()
    O.trackEnergy = True


def _periodic_compression(yade) -> None:
    """A periodic cloud under PeriTriaxController: the cell deforms, contacts cross the boundary."""
    sp = yade.pack.SpherePack()
    sp.makeCloud((0, 0, 0), (1, 1, 1), rMean=0.08, rRelFuzz=0.3, periodic=True, seed=2)
    sp.toSimulation()
    yade.O.engines = frict_engines(yade, damping=0.4)[:3] + [
        yade.PeriTriaxController(goal=(-1e5, -1e5, -1e5), stressMask=7, dynCell=True, maxStrainRate=(1, 1, 1),
                                 maxUnbalanced=0.05, relStressTol=1e-2, label="triax"),
        yade.NewtonIntegrator(damping=0.4)]
    yade.O.dt = 0.5 * yade.PWaveTimeStep()


SCENES = {"frictional box with clumps": (_frictional_box_with_clumps, 1500),
          "periodic compression": (_periodic_compression, 3000)}


@pytest.mark.fallback
@pytest.mark.parametrize("scene", SCENES)
@pytest.mark.parametrize("fmt", ["scene.yade", "scene.xml.bz2", "scene.h5"])
def test_load_and_continue_equals_the_uninterrupted_run_bitwise(yade, tmp_path, scene, fmt):
    """Save mid-run, run on; load, run on the same steps: every body, contact, cell and energy is identical."""
    build, steps = SCENES[scene]
    build(yade)
    yade.O.run(steps, True)
    sliding = [i for i in yade.O.interactions if np.linalg.norm(np.asarray(i.phys.shearForce)) > 0]
    assert len(sliding) > 10, "the scene must carry shear history"
    path = tmp_path / fmt
    yade.O.save(str(path))
    yade.O.run(steps, True)
    uninterrupted = _state(yade)
    yade.O.reset()
    yade.O.load(str(path))
    assert yade.O.iter == steps
    yade.O.run(steps, True)
    _assert_same(uninterrupted, _state(yade))
    # labels, PyRunner schedules and controller state came back as the engines of the loaded scene
    labelled = yade.O.engines[-1] if scene == "frictional box with clumps" else yade.O.engines[3]
    assert labelled.label in ("ticker", "triax")


def test_every_extension_round_trips_and_is_detected_from_content(yade, tmp_path):
    """All formats hold the same scene; a checkpoint renamed to another extension still loads."""
    _frictional_box_with_clumps(yade)
    yade.O.run(300, True)
    yade.O.tags["note"] = "<&> ünïcode \x01"
    reference = _state(yade)
    for name in FORMATS:
        yade.O.save(str(tmp_path / name))
    for name in FORMATS:
        renamed = tmp_path / ("copy-of-" + name.replace(".", "_"))
        renamed.write_bytes((tmp_path / name).read_bytes())
        for p in (tmp_path / name, renamed):
            yade.O.reset()
            yade.O.load(str(p))
            _assert_same(reference, _state(yade))
            assert yade.O.tags["note"] == "<&> ünïcode \x01"
    assert zipfile.is_zipfile(tmp_path / "scene.yade")
    assert bz2.decompress((tmp_path / "scene.xml.bz2").read_bytes()).startswith(b"<?xml")


def test_checkpoint_resumes_in_a_new_process(yade, tmp_path):
    """A checkpoint written here resumes under the granum launcher with the same trajectory."""
    _frictional_box_with_clumps(yade)
    yade.O.run(500, True)
    yade.O.save(str(tmp_path / "s.yade.gz"))
    yade.O.run(200, True)
    expected = np.array([b.state.pos for b in yade.O.bodies])
    script = tmp_path / "resume.py"
    script.write_text("import numpy\nO.load('s.yade.gz')\nO.run(200, True)\n"
                      "numpy.save('pos.npy', numpy.array([b.state.pos for b in O.bodies]))\n")
    subprocess.run([sys.executable, "-m", "granum", str(script)], cwd=tmp_path, check=True, timeout=600)
    assert (np.load(tmp_path / "pos.npy") == expected).all()


_PILE = """
O.reset()
O.bodies.append([sphere((0, 0, 0), 0.01, fixed=True)] + [sphere((1e-4 * k, 0, 0.0199 * k), 0.01) for k in range(1, 4)])
O.engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb()]),
             InteractionLoop([Ig2_Sphere_Sphere_ScGeom()], [Ip2_FrictMat_FrictMat_FrictPhys()],
                             [Law2_ScGeom_FrictPhys_CundallStrack()]),
             NewtonIntegrator(gravity=(0, 0, -9.81), damping=0.2)]
O.dt = 0.5 * PWaveTimeStep()
O.run(300, True)
"""


def test_a_law_registered_but_unused_when_saving_does_not_stop_a_resume(tmp_path):
    """A script that defined its own law (with contact history columns of its own: examples/user_law.py) saves a
    scene whose contacts do not use it; a new process without that law resumes it with the same trajectory.
    Only the history columns and functors the saved contacts use must mean the same in both."""
    example = pathlib.Path(__file__).resolve().parents[1] / "examples" / "user_law.py"
    (tmp_path / "save.py").write_text(
        f"import numpy\nexec(compile(open({str(example)!r}).read(), 'user_law.py', 'exec'))\n" + _PILE
        + "O.save('s.yade')\nO.run(200, True)\n"
        "numpy.save('expected.npy', numpy.array([b.state.pos for b in O.bodies]))\n")
    (tmp_path / "resume.py").write_text(
        "import numpy\nO.load('s.yade')\nO.run(200, True)\n"
        "numpy.save('pos.npy', numpy.array([b.state.pos for b in O.bodies]))\n")
    for script in ("save.py", "resume.py"):
        subprocess.run([sys.executable, "-m", "granum", script], cwd=tmp_path, check=True, timeout=600,
                       capture_output=True)
    assert (np.load(tmp_path / "pos.npy") == np.load(tmp_path / "expected.npy")).all()


def test_history_columns_the_saved_pool_holds_must_mean_the_same():
    """A group of history columns within the saved pool's width that is missing here, or placed elsewhere, is
    refused naming it; one beyond the width is not looked at."""
    from granum.io.checkpoint import _history_check, layout

    now = layout()["contact_history"]
    width = max(first + count for first, count in now.values())
    _history_check({**now, "users_law": [width, 4]}, width, "f")           # beyond the pool: not used
    with pytest.raises(CheckpointError, match="other contact history \\(users_law"):
        _history_check({**now, "users_law": [width - 1, 4]}, width, "f")
    name, (first, count) = next(iter(now.items()))
    with pytest.raises(CheckpointError, match=f"other contact history \\({name}"):
        _history_check({**now, name: [first + 1, count]}, width, "f")


def _damage(path: pathlib.Path, how: str) -> None:
    data = path.read_bytes()
    if how == "truncated":
        data = data[: len(data) // 2]
    elif how == "cut at the end":
        data = data[:-7]
    else:
        k = len(data) * 3 // 5
        if path.suffix == ".h5":  # HDF5 files have free space: hit the data of the largest array
            import h5py

            with h5py.File(path, "r") as h:
                sets = []
                h.visititems(lambda _, d: sets.append(d) if isinstance(d, h5py.Dataset) else None)
                big = max(sets, key=lambda d: d.nbytes)
                k = big.id.get_offset() + big.nbytes // 2
        data = data[:k] + bytes([data[k] ^ 0x10]) + data[k + 1:]
    path.write_bytes(data)


@pytest.mark.parametrize("name", ["scene.yade", "scene.xml", "scene.h5", "scene.yade.gz", "scene.xml.bz2"])
@pytest.mark.parametrize("how", ["truncated", "cut at the end", "one byte flipped"])
def test_damaged_checkpoints_raise_a_clear_error_and_keep_the_scene(yade, tmp_path, name, how):
    """Truncated or corrupted files are refused with CheckpointError; the current scene is untouched."""
    _frictional_box_with_clumps(yade)
    yade.O.run(100, True)
    path = tmp_path / name
    yade.O.save(str(path))
    _damage(path, how)
    before = _state(yade)
    with pytest.raises(CheckpointError, match=str(path)):
        yade.O.load(str(path))
    _assert_same(before, _state(yade))
    yade.O.run(10, True)  # still runnable


def test_foreign_files_are_named_for_what_they_are(yade, tmp_path):
    """Real YADE checkpoints, other zips, XML, HDF5 and text files get errors that say what they are."""
    import h5py

    yade_dir = REFERENCE / "checkpoint"
    cases = {yade_dir / "yade_scene.yade": "YADE checkpoint", yade_dir / "yade_scene.xml": "YADE checkpoint"}
    other_zip = tmp_path / "other.yade"
    with zipfile.ZipFile(other_zip, "w") as z:
        z.writestr("x.txt", "hello")
    other_xml = tmp_path / "other.xml"
    other_xml.write_text("<root><a/></root>")
    other_h5 = tmp_path / "other.h5"
    with h5py.File(other_h5, "w") as h:
        h["x"] = np.arange(3)
    text = tmp_path / "notes.yade"
    text.write_text("just some notes\n")
    empty = tmp_path / "empty.yade"
    empty.write_bytes(b"")
    cases.update({other_zip: "zip archive but not a granum checkpoint", other_xml: "XML document but not",
                  other_h5: "HDF5 file but not", text: "not a granum checkpoint", empty: "empty file"})
    for path, message in cases.items():
        with pytest.raises(CheckpointError, match=message):
            yade.O.load(str(path))
    with pytest.raises(FileNotFoundError, match="does not exist"):
        yade.O.load(str(tmp_path / "missing.yade"))


def test_a_failed_save_leaves_the_previous_checkpoint_intact(yade, tmp_path):
    """A scene holding code cannot be saved: the error names it and the old file stays loadable."""
    _frictional_box_with_clumps(yade)
    yade.O.run(100, True)
    path = tmp_path / "scene.yade"
    yade.O.save(str(path))
    good = path.read_bytes()

    class MyEngine(yade.PyRunner):  # a class defined by a script: a checkpoint stores no code
        pass

    yade.O.engines = yade.O.engines + [MyEngine(command="pass", iterPeriod=1)]
    with pytest.raises(CheckpointError, match="MyEngine"):
        yade.O.save(str(path))
    assert path.read_bytes() == good
    assert sorted(os.listdir(tmp_path)) == ["scene.yade"], "no temporary file is left behind"
    yade.O.load(str(path))
    assert yade.O.iter == 100


def test_checkpoints_never_unpickle(yade, tmp_path):
    """An .npy member holding pickled objects is refused before anything is unpickled."""
    _frictional_box_with_clumps(yade)
    path = tmp_path / "scene.yade"
    yade.O.save(str(path))
    with zipfile.ZipFile(path) as z:
        members = {n: z.read(n) for n in z.namelist()}
    victim = next(n for n in members if n.endswith(".npy"))
    buf = pathlib.Path(tmp_path / "obj.npy")
    np.save(buf, np.array([{"evil": 1}], dtype=object), allow_pickle=True)
    members[victim] = buf.read_bytes()
    with zipfile.ZipFile(path, "w") as z:
        for n, data in members.items():
            z.writestr(n, data)
    with pytest.raises(CheckpointError):
        yade.O.load(str(path))


def test_the_stages_work_area_is_not_saved(yade, tmp_path):
    """The contact record's ``scratch`` holds a step's temporaries, no state: checkpoints leave it out, and a
    loaded scene starts with an empty one (the resumed run's bits are checked above)."""
    _frictional_box_with_clumps(yade)
    yade.O.run(20, True)
    assert yade.O._scene.contacts.scratch.size > 0
    yade.O.save(str(tmp_path / "scene.yade"))
    names = zipfile.ZipFile(tmp_path / "scene.yade").namelist()
    assert any("con_f" in n for n in names)
    assert not any("scratch" in n for n in names)
    yade.O.reset()
    yade.O.load(str(tmp_path / "scene.yade"))
    assert yade.O._scene.contacts.scratch.size == 0
