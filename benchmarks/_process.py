"""Running one benchmark process and timing it, for ``benchmarks/run`` and its checks."""

from __future__ import annotations

import subprocess
import time


def timed_run(cmd: list[str], env: dict, workdir: str, timeout: float) -> tuple[str, float, str]:
    """Run ``cmd`` in ``workdir`` with the environment ``env``, its standard error joined to its output: ``(status,
    wall time of the whole process [s], output)``, the status ``"ok"``, ``"TIMEOUT"``, ``"FAIL(exec)"`` (it could not
    be started) or ``"FAIL(rc=N)"``."""
    t0 = time.perf_counter()
    try:
        p = subprocess.run(cmd, cwd=workdir, env=env, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                           stderr=subprocess.STDOUT, timeout=timeout, text=True, errors="replace")
    except subprocess.TimeoutExpired as e:
        out = e.stdout if isinstance(e.stdout, str) else (e.stdout or b"").decode("utf-8", "replace")
        return "TIMEOUT", time.perf_counter() - t0, out
    except OSError as e:
        return "FAIL(exec)", 0.0, "{}: {}".format(" ".join(cmd), e)
    return ("ok" if p.returncode == 0 else f"FAIL(rc={p.returncode})"), time.perf_counter() - t0, p.stdout
