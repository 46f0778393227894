"""Start-up times (``benchmarks/run --startup``): a first run from an empty cache, and a cached start.

* **First run**: ``granum -jN examples/bouncing_sphere.py`` with ``GRANUM_CACHE_DIR`` a new, empty folder, so
  that every kernel its scene needs is compiled (on two processes, see ARCHITECTURE.md, "Compilation"), and the
  example's 2e6 steps run. The wall time of the whole process counts.
* **Cached start and one step**: ``bouncing_sphere.py`` with ``BENCH_STEPS=1 BENCH_WARMUP=0`` (two spheres, one
  step), the whole process's wall time, with granum's cache warm: one untimed run first compiles its code if
  needed and lets Python keep the bytecode of granum's modules (``PYTHONDONTWRITEBYTECODE`` unset for that run:
  an installed package has its bytecode compiled at install). YADE runs the same script, taking turns with
  granum.

The fastest run of each counts (``--repeat``; the first run at most twice, about 20 s each). Targets: the
speed issue's, a first run within 8 s, a cached start and one step within 1 s.
"""

from __future__ import annotations

import os
import tempfile

from _process import timed_run

HERE = os.path.dirname(os.path.abspath(__file__))
EXAMPLE = os.path.join(os.path.dirname(HERE), "examples", "bouncing_sphere.py")
FIRST_RUN_TARGET = 8.0   # seconds
CACHED_START_TARGET = 1.0   # seconds


def _wall(cmd: list[str], env: dict, workdir: str, timeout: float) -> tuple[float | None, str]:
    """Run ``cmd``; its wall time [s] (None when it failed) and its output's tail."""
    status, wall, out = timed_run(cmd, env, workdir, timeout)
    return (wall if status == "ok" else None), f"{status}: {out[-4000:]}"


def startup_check(args, granum, yade, workdir, failures, log) -> None:
    """Measure and print the first run and the cached start (module docstring)."""
    threads = args.threads
    base = dict(os.environ, MPLBACKEND="Agg")
    runs = args.repeat if args.repeat is not None else (1 if args.quick else 3)

    first = []
    for _ in range(min(2, runs)):
        env = dict(base, GRANUM_CACHE_DIR=tempfile.mkdtemp(prefix="granum-empty-cache-", dir=workdir))
        log(f"[startup] granum -j{threads} examples/bouncing_sphere.py, empty cache")
        wall, out = _wall(granum + [f"-j{threads}", EXAMPLE], env, workdir, args.timeout)
        if wall is None:
            failures.append(("granum", "startup first run", "FAIL", out))
            break
        first.append(wall)

    script = os.path.join(HERE, "bouncing_sphere.py")
    base.update(BENCH_STEPS="1", BENCH_WARMUP="0")
    warm_env = {k: v for k, v in base.items() if k != "PYTHONDONTWRITEBYTECODE"}
    log("[startup] granum bouncing_sphere.py, one step, untimed (fills the cache)")
    wall, out = _wall(granum + [f"-j{threads}", script], warm_env, workdir, args.timeout)
    if wall is None:
        failures.append(("granum", "startup cached", "FAIL", out))
        return
    programs = [("granum", granum + [f"-j{threads}", script])]
    if yade:
        programs.append(("YADE", yade + ["-n", "-x", f"-j{threads}", script]))
    cached = {name: [] for name, _ in programs}
    for _ in range(runs):
        for name, cmd in programs:
            log(f"[startup] {name} bouncing_sphere.py, one step")
            wall, out = _wall(cmd, base, workdir, args.timeout)
            if wall is None:
                failures.append((name, "startup cached", "FAIL", out))
                return
            cached[name].append(wall)

    print(f"start-up, -j{threads} (wall time of the whole process, fastest of the runs):")
    if first:
        verdict = "PASS" if min(first) <= FIRST_RUN_TARGET else "FAIL"
        print(f"  first run of examples/bouncing_sphere.py, empty cache: {min(first):.2f} s "
              f"(runs: {', '.join(f'{w:.2f}' for w in first)}; target <= {FIRST_RUN_TARGET:g} s: {verdict})")
    g = min(cached["granum"])
    verdict = "PASS" if g <= CACHED_START_TARGET else "FAIL"
    print(f"  cached start and one step (bouncing_sphere.py, BENCH_STEPS=1): granum {g:.2f} s "
          f"(runs: {', '.join(f'{w:.2f}' for w in cached['granum'])}; target <= {CACHED_START_TARGET:g} s: {verdict})")
    if "YADE" in cached:
        y = min(cached["YADE"])
        print(f"  the same under YADE: {y:.2f} s (runs: {', '.join(f'{w:.2f}' for w in cached['YADE'])}); "
              f"granum/YADE {y / g:.2f}x")
