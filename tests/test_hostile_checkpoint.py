"""O.load of crafted checkpoints: decompression bombs, values the setters refuse, out-of-range codes and
counters. Each is refused with a CheckpointError naming the file and what is wrong; the scene is kept."""

from __future__ import annotations

import bz2
import gzip
import io
import os
import subprocess
import sys
import zipfile

import numpy as np
import pytest
from conftest import frict_engines

from granum.core.arrays import S_DT, SI_HOOK
from granum.core.contacts import C_CONTACTS, C_REPLACED, I_LAW, NCTR
from granum.io.checkpoint import CheckpointError
from granum.io.checkpoint_formats import container_read, container_write, header_make, json_canonical

BOMB_BYTES = 2 << 30  # what a bomb would inflate to [bytes]


def _two_spheres_in_contact(yade) -> None:
    O = yade.O
    O.bodies.append([yade.sphere((0, 0, 0), 0.1), yade.sphere((0.19, 0, 0), 0.1)])
    O.engines = frict_engines(yade) + [yade.PyRunner(command="pass", iterPeriod=10, label="ticker")]
    O.dt = 1e-5
    O.run(3, True)
    assert len(O.interactions) == 1


@pytest.fixture
def saved(yade, tmp_path):
    """A valid checkpoint of a two-sphere scene; the scene stays loaded."""
    _two_spheres_in_contact(yade)
    path = tmp_path / "good.yade"
    yade.O.save(str(path))
    return path


def _crafted(saved, tmp_path, edit, name="crafted.yade"):
    """A copy of ``saved`` with ``edit(meta, arrays)`` applied and checksums made to match again."""
    with open(saved, "rb") as f:
        meta, arrays = container_read(f, str(saved))
    arrays = {k: a.copy() for k, a in arrays.items()}
    edit(meta, arrays)
    path = tmp_path / name
    with open(path, "wb") as f:
        container_write(f, "yade", None, meta, arrays)
    return path


def _refused(yade, path, *words) -> None:
    """Loading ``path`` raises a CheckpointError naming it and ``words``; the current scene is kept."""
    before = (yade.O.iter, [tuple(b.state.pos) for b in yade.O.bodies], len(yade.O.interactions))
    with pytest.raises(CheckpointError, match=str(path)) as err:
        yade.O.load(str(path))
    for w in words:
        assert w in str(err.value), f"{w!r} not in {err.value}"
    assert before == (yade.O.iter, [tuple(b.state.pos) for b in yade.O.bodies], len(yade.O.interactions))
    yade.O.run(2, True)  # still runnable


def _set(key, index, value):
    return lambda meta, arrays: arrays[key].__setitem__(index, value)


# ---- values the setters refuse ----------------------------------------------------------------
@pytest.mark.parametrize(("edit", "words"), [
    (_set("scene/shapes/SPHERE/radius", 0, 0.0), ("O.bodies[0].shape.radius", "positive and finite")),
    (_set("scene/shapes/SPHERE/radius", 1, np.nan), ("O.bodies[1].shape.radius", "positive and finite")),
    (_set("scene/scal", S_DT, -1e-5), ("O.dt", "not negative")),
    (_set("scene/scal", S_DT, np.inf), ("O.dt", "finite time step")),
    (_set("scene/cell_hsize", (0, 0), -1.0), ("O.cell.hSize", "positive volume")),
    (_set("scene/bodies/pos", (1, 2), np.nan), ("O.bodies[1].state.pos", "must be finite")),
    (_set("scene/bodies/vel", (0, 0), np.inf), ("O.bodies[0].state.vel", "must be finite")),
    (_set("scene/bodies/mass", 0, -2.0), ("O.bodies[0].state.mass", "non-negative")),
    (_set("scene/bodies/ori", 0, 0.0), ("O.bodies[0].state.ori", "non-zero quaternion")),
], ids=["zero radius", "NaN radius", "negative dt", "infinite dt", "negative cell volume", "NaN position",
        "infinite velocity", "negative mass", "zero quaternion"])
def test_values_the_setters_refuse_are_refused_on_load(yade, saved, tmp_path, edit, words):
    _refused(yade, _crafted(saved, tmp_path, edit), "invalid checkpoint", *words)


def test_a_dead_body_row_may_hold_anything(yade, saved, tmp_path):
    """Only bodies in use are checked: an erased body's stale row (here NaN) does not block loading."""
    yade.O.bodies.erase(1)
    yade.O.save(str(saved))
    path = _crafted(saved, tmp_path, _set("scene/bodies/pos", (1, 0), np.nan))
    yade.O.load(str(path))
    assert len(yade.O.bodies) == 2 and yade.O.bodies[1] is None


def test_setters_and_loader_share_one_rule(yade):
    """The setter refuses what the loader refuses, with the same words (granum.core.validate)."""
    s = yade.sphere((0, 0, 0), 0.1)
    with pytest.raises(ValueError, match="radius must be positive and finite"):
        s.shape.radius = 0.0
    with pytest.raises(ValueError, match="O.dt must be a finite time step in seconds, not negative"):
        yade.O.dt = -1.0
    with pytest.raises(ValueError, match="Cell.hSize must be finite with a positive volume"):
        yade.O.cell.hSize = ((-1, 0, 0), (0, 1, 0), (0, 0, 1))


def test_an_out_of_range_functor_code_is_refused_before_any_kernel_is_built(yade, saved, tmp_path):
    """A contact's law code beyond the registry is refused while loading; the scene and its kernels are kept."""
    path = _crafted(saved, tmp_path, _set("scene/contacts/con_i", (0, I_LAW), 999))
    _refused(yade, path, "law functor code out of range")


@pytest.mark.parametrize(("edit", "words"), [
    (_set("scene/contacts/ctr", C_CONTACTS, 10 ** 6), ("interaction counters exceed their arrays",)),
    (_set("scene/iscal", SI_HOOK, 10 ** 6), ("engine hook index out of range",)),
    (lambda meta, arrays: meta["scene"]["bodies"]["table"].__setitem__("count", 10 ** 6), ("rows in a capacity",)),
    # the per-body index is built in place when read stale (b.intrs() right after the load)
    (lambda meta, arrays: arrays.__setitem__("scene/contacts/csr_con", arrays["scene/contacts/csr_con"][:1]),
     ("per-body contact index shorter than the contacts",)),
], ids=["contact counter", "engine hook", "body count", "per-body index"])
def test_counters_beyond_their_arrays_are_refused(yade, saved, tmp_path, edit, words):
    _refused(yade, _crafted(saved, tmp_path, edit), *words)


def test_a_material_with_a_refused_parameter_is_refused(yade, saved, tmp_path):
    """Materials are rebuilt through their constructors, so their setters' checks apply."""
    def edit(meta, arrays):
        material = next(o for o in meta["objects"] if o["class"] == "FrictMat")
        material["attrs"]["density"] = -1.0
    _refused(yade, _crafted(saved, tmp_path, edit), "cannot rebuild FrictMat", "FrictMat.density must be")


# ---- decompression bombs ------------------------------------------------------------------------
def _inner_bomb(saved) -> bytes:
    """A ``.yade`` zip whose first member is the real manifest, followed by 64 MiB of zeros."""
    return saved.read_bytes()[:4096] + bytes(64 << 20)


def _outer_bomb(saved, compression: str) -> bytes:
    """``compression`` (gzip or bz2) streams inflating to :data:`BOMB_BYTES`, starting as a real checkpoint."""
    compress = gzip.compress if compression == "gz" else bz2.compress
    return compress(_inner_bomb(saved)) + compress(bytes(64 << 20)) * (BOMB_BYTES // (64 << 20) - 1)


@pytest.mark.parametrize("compression", ["gz", "bz2"])
def test_a_compressed_bomb_is_refused_while_inflating(yade, saved, tmp_path, compression):
    """2 GiB of zeros behind a real manifest, in a file of a few kB: refused after what the manifest allows."""
    path = tmp_path / f"bomb.yade.{compression}"
    path.write_bytes(_outer_bomb(saved, compression))
    assert path.stat().st_size < BOMB_BYTES // 500  # gzip: 1:1000, bzip2: 1:10^6
    _refused(yade, path, "inflates to more than", "decompression bomb")


def test_a_compressed_bomb_without_a_manifest_is_refused_at_the_allowance(yade, tmp_path):
    """Zeros only (no zip inside): the fixed allowance / ratio stops it."""
    path = tmp_path / "zeros.xml.bz2"
    path.write_bytes(bz2.compress(bytes(64 << 20)) * 32)
    _refused(yade, path, "inflates to more than")


def test_a_compressed_bomb_stays_within_100_MB_of_memory(saved, tmp_path):
    """Measured in a fresh process with tracemalloc: the peak of memory allocated while refusing the bomb."""
    path = tmp_path / "bomb.yade.bz2"
    path.write_bytes(_outer_bomb(saved, "bz2"))
    script = ("import tracemalloc, granum.yade as y\n"
              "from granum.io.checkpoint import CheckpointError\n"
              "tracemalloc.start()\n"
              f"try:\n    y.O.load({str(path)!r})\n"
              "except CheckpointError:\n    print('refused', tracemalloc.get_traced_memory()[1])\n")
    out = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=600, check=True)
    word, peak = out.stdout.split()
    assert word == "refused" and int(peak) < 100 << 20, out.stdout


def test_a_compressed_zip_member_is_refused(yade, saved, tmp_path):
    """A deflated member (256 MiB of zeros in 0.25 MB) is refused by its compression method, before inflating."""
    with zipfile.ZipFile(saved) as z:
        members = {n: z.read(n) for n in z.namelist()}
    victim = "arrays/scene/bodies/pos.npy"
    path = tmp_path / "member-bomb.yade"
    with zipfile.ZipFile(path, "w") as z:
        for n, data in members.items():
            if n != victim:
                z.writestr(n, data)
        info = zipfile.ZipInfo(victim)
        info.compress_type = zipfile.ZIP_DEFLATED
        with z.open(info, "w", force_zip64=True) as m:  # streamed: the bomb is never in memory here
            for _ in range(256):
                m.write(bytes(1 << 20))
    _refused(yade, path, victim, "is compressed")


def test_a_member_larger_than_the_manifest_says_is_refused(yade, saved, tmp_path):
    """A stored member holding more than its array's shape x item size (+ header) is refused by its size."""
    with zipfile.ZipFile(saved) as z:
        members = {n: z.read(n) for n in z.namelist()}
    victim = "arrays/scene/bodies/pos.npy"
    members[victim] += bytes(1 << 20)
    path = tmp_path / "padded.yade"
    with zipfile.ZipFile(path, "w") as z:
        for n, data in members.items():
            z.writestr(n, data)
    _refused(yade, path, victim, "the manifest allows at most")


def test_an_npy_header_claiming_a_huge_shape_is_refused_before_allocation(yade, saved, tmp_path):
    """The .npy header is checked against the manifest before any array is made from it."""
    with zipfile.ZipFile(saved) as z:
        members = {n: z.read(n) for n in z.namelist()}
    victim = "arrays/scene/bodies/mass.npy"
    header = io.BytesIO()
    np.lib.format.write_array_header_1_0(header, {"descr": "<f8", "fortran_order": False, "shape": (10 ** 11,)})
    members[victim] = header.getvalue()
    path = tmp_path / "huge-npy.yade"
    with zipfile.ZipFile(path, "w") as z:
        for n, data in members.items():
            z.writestr(n, data)
    _refused(yade, path, "'scene/bodies/mass'", "the manifest says")


def test_a_manifest_declaring_huge_arrays_cannot_inflate_a_compressed_file(yade, saved, tmp_path):
    """A crafted manifest may declare any shape (its digest recomputed); the ratio cap still stops inflation."""
    meta, arrays = container_read(open(saved, "rb"), str(saved))
    header = header_make(meta, arrays)
    header["arrays"]["scene/bodies/mass"]["shape"] = [1 << 28]
    body = io.BytesIO()
    with zipfile.ZipFile(body, "w") as z:
        z.writestr("granum.json", json_canonical(header))
    path = tmp_path / "declared.yade.gz"
    path.write_bytes(gzip.compress(body.getvalue()[:-22]) + gzip.compress(bytes(64 << 20)) * 32)
    _refused(yade, path, "inflates to more than")


# ---- documented behaviour ------------------------------------------------------------------------
def test_a_loaded_pyrunner_runs_its_command_as_documented(yade, tmp_path):
    """A checkpoint's PyRunner is code run at O.run (as in YADE); O.load's docstring says to trust the file."""
    marker = tmp_path / "ran.txt"
    yade.O.bodies.append(yade.sphere((0, 0, 0), 0.1))
    yade.O.engines = [yade.PyRunner(command=f"open(r'{marker}', 'w').write('yes')", iterPeriod=1)]
    yade.O.dt = 1e-5
    path = tmp_path / "runner.yade"
    yade.O.save(str(path))
    yade.O.reset()
    yade.O.load(str(path))
    assert not marker.exists(), "loading runs no code"
    yade.O.run(3, True)
    assert marker.read_text() == "yes"
    assert "trust" in yade.O.load.__doc__


def test_an_existing_file_is_intact_after_a_refused_load(yade, saved, tmp_path):
    """Refusing a hostile file changes no file: the good checkpoint still loads."""
    good = saved.read_bytes()
    bad = _crafted(saved, tmp_path, _set("scene/scal", S_DT, -1.0))
    _refused(yade, bad)
    assert saved.read_bytes() == good
    yade.O.load(str(saved))
    assert yade.O.iter == 3 and os.path.exists(bad)


def _counters(count: int):
    """An edit giving the contacts' counters ``count`` entries (the first ones kept, any new ones zero)."""
    def edit(meta, arrays):
        ctr = arrays["scene/contacts/ctr"]
        arrays["scene/contacts/ctr"] = np.concatenate([ctr, np.zeros(max(0, count - len(ctr)), ctr.dtype)])[:count]
    return edit


def test_more_counters_than_this_granum_has_are_refused(yade, saved, tmp_path):
    """Compiled code reads every counter without bounds checks: a file with more of them is not this granum's."""
    _refused(yade, _crafted(saved, tmp_path, _counters(NCTR + 1)), "contacts.ctr holds", f"this granum has {NCTR}")


def test_a_checkpoint_with_fewer_counters_loads_with_the_missing_ones_zero(yade, saved, tmp_path):
    """Earlier versions kept fewer counters (9 until C_REPLACED): such a checkpoint loads with the others zero, its
    contact kept, and runs on as the saved scene does."""
    O = yade.O
    O.load(str(_crafted(saved, tmp_path, _counters(C_REPLACED))))
    assert len(O._scene.contacts.ctr) == NCTR and O._scene.contacts.ctr[C_REPLACED] == 0
    assert O.interactions.countReal() == 1
    O.run(20, True)
    older = O.bodies.arrays("pos", "vel")
    O.load(str(saved))
    O.run(20, True)
    now = O.bodies.arrays("pos", "vel")
    assert all(np.array_equal(older[k], now[k]) for k in ("pos", "vel"))
