"""Atomic file writes: readers never see a half-written file.

Output files are often watched while a simulation runs (ParaView reloading a time series, a
video encoder picking up snapshots), so every writer in granum writes into a temporary file in
the destination directory and moves it over the target with :func:`os.replace`, which is atomic
on POSIX and Windows when both paths are on the same file system.
"""

from __future__ import annotations

import contextlib
import os
import tempfile


def _umask() -> int:
    # os.umask can only be read by setting it; done once, at import, before any thread writes files
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


_FILE_MODE = 0o666 & ~_umask()


@contextlib.contextmanager
def atomic_path(path: str | os.PathLike):
    """Context manager giving a temporary path next to ``path``; on success it replaces ``path``.

    The caller (or a program it runs) writes the temporary file; if the block raises, the
    temporary file is removed and ``path`` is left as it was. The file gets the permissions an
    ordinary ``open(path, 'w')`` would give (mkstemp alone would give 0600).
    """
    path = os.fspath(path)
    directory = os.path.dirname(os.path.abspath(path))
    fd, tmp = tempfile.mkstemp(dir=directory, prefix="." + os.path.basename(path) + ".", suffix=".tmp")
    os.close(fd)
    try:
        yield tmp
        os.chmod(tmp, _FILE_MODE)
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise


def write_bytes(path: str | os.PathLike, data: bytes) -> None:
    """Write ``data`` to ``path`` atomically."""
    with atomic_path(path) as tmp, open(tmp, "wb") as f:
        f.write(data)


def write_text(path: str | os.PathLike, text: str) -> None:
    """Write ``text`` (UTF-8) to ``path`` atomically."""
    write_bytes(path, text.encode("utf-8"))
