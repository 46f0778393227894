"""``makeVideo``: a video from picture files, encoded by the ffmpeg shipped with ``imageio-ffmpeg``.

YADE's ``utils.makeVideo`` runs ``mencoder`` (two-pass MPEG-4 in an AVI file, whatever the file
name says). granum encodes with ffmpeg from the ``imageio-ffmpeg`` package from PyPI, so no system
program is needed: MPEG-4 part 2 video (``-c:v mpeg4``, any frame rate, bit rate ``kbps``), in the
container the extension names (``.mp4``, ``.mov``, ``.mkv``, ``.avi``) or, for any other name
(``.mpeg``, ``.mpg``...), in AVI as YADE does. Frames are padded to even sizes for the YUV 4:2:0
pixel format players expect.
"""

from __future__ import annotations

import glob
import os
import re
import shutil
import subprocess
import tempfile
import warnings

from granum.io.atomic import atomic_path

_MUXERS = {".mp4": "mp4", ".m4v": "mp4", ".mov": "mov", ".mkv": "matroska", ".avi": "avi"}


def _ffmpeg() -> str:
    try:
        import imageio_ffmpeg
    except ImportError:
        exe = shutil.which("ffmpeg")
        if exe:
            return exe
        raise RuntimeError("makeVideo needs ffmpeg: install the imageio-ffmpeg package "
                           "(pip install imageio-ffmpeg) or put ffmpeg on the PATH") from None
    return imageio_ffmpeg.get_ffmpeg_exe()


def frame_files(frameSpec) -> list[str]:
    """The picture files of a frame specification, in order.

    A list or tuple is taken as is; a string with ``%`` is a printf pattern (``snap-%05d.png``)
    expanded from 0 (or 1) up to the first missing number; any other string is a shell
    wildcard, expanded and sorted.
    """
    if isinstance(frameSpec, (list, tuple)):
        return [os.fspath(f) for f in frameSpec]
    spec = os.fspath(frameSpec)
    if re.search(r"%0?\d*d", spec):
        for start in (0, 1):
            files = []
            k = start
            while os.path.exists(spec % k):
                files.append(spec % k)
                k += 1
            if files:
                return files
        return []
    return sorted(glob.glob(spec))


def _free_backup_name(out: str) -> str:
    k = 0
    while os.path.exists(f"{out}~{k}"):
        k += 1
    return f"{out}~{k}"


def makeVideo(frameSpec, out, renameNotOverwrite=True, fps=24, kbps=6000, bps=None):
    """Make a video from picture files (YADE ``utils.makeVideo``).

    :param frameSpec: list of files in order, a shell wildcard (``'snap-*.png'``) or a printf
        pattern (``'snap-%05d.png'``).
    :param out: video file to write.
    :param renameNotOverwrite: move an existing ``out`` to ``out~0`` (``~1``...) instead of
        overwriting it.
    :param fps: frames per second.
    :param kbps: bit rate [kbit/s]; ``bps`` is its deprecated name (same meaning, as in YADE).
    :return: ``out``.
    """
    if bps is not None:
        warnings.warn("makeVideo: bps is deprecated, use kbps instead (the significance is the same, but the "
                      "name is more precise)", DeprecationWarning, stacklevel=2)
        kbps = bps
    out = os.fspath(out)
    files = frame_files(frameSpec)
    if not files:
        raise ValueError(f"makeVideo: no picture files match {frameSpec!r}")
    missing = [f for f in files if not os.path.isfile(f)]
    if missing:
        raise FileNotFoundError(f"makeVideo: no such picture file: {missing[0]}")
    if renameNotOverwrite and os.path.exists(out):
        backup = _free_backup_name(out)
        print(f"Renaming existing file {out} to {backup}")
        os.rename(out, backup)
    muxer = _MUXERS.get(os.path.splitext(out)[1].lower(), "avi")
    ext = os.path.splitext(files[0])[1]
    with tempfile.TemporaryDirectory(prefix="granum-video-") as tmpdir:
        # ffmpeg reads numbered frames; link (or copy) the given files in their order
        for k, f in enumerate(files):
            link = os.path.join(tmpdir, f"frame{k:06d}{ext}")
            try:
                os.symlink(os.path.abspath(f), link)
            except OSError:
                shutil.copyfile(f, link)
        with atomic_path(out) as tmp:
            cmd = [_ffmpeg(), "-y", "-loglevel", "error", "-framerate", str(fps),
                   "-i", os.path.join(tmpdir, f"frame%06d{ext}"),
                   "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2", "-c:v", "mpeg4", "-b:v", f"{int(kbps)}k",
                   "-pix_fmt", "yuv420p", "-f", muxer, tmp]
            run = subprocess.run(cmd, capture_output=True, text=True)
            if run.returncode != 0:
                raise RuntimeError(f"makeVideo: ffmpeg failed ({run.returncode}): {run.stderr.strip()}")
    print(f"makeVideo: {out} ({len(files)} frames at {fps} fps)")
    return out
