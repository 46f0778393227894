"""YADE's ``yade.timing``: per-engine time statistics (``O.timingEnabled``).

With ``O.timingEnabled = True`` every compiled stage reads a monotonic clock around its run inside
the compiled step loop (:mod:`granum.kernels.steploop`) and Python engines are timed when they run;
the totals go to each engine's ``execTime`` [ns] and ``execCount``.
"""

from __future__ import annotations


def reset() -> None:
    """Zero the engines' execTime and execCount."""
    from granum.yade.omega import O

    for e in O.engines:
        e.execTime = 0
        e.execCount = 0


def stats() -> None:
    """Print the time spent in each engine, as YADE does (labelled engines by their label, quoted)."""
    from granum.yade.omega import O

    engines = list(O.engines)
    total = sum(e.execTime for e in engines)
    print(f"{'Name':<50}{'Count':>10}{'Time':>21}{'Rel. time':>21}")
    print("-" * 103)
    for e in engines:
        name = f'"{e.label}"' if e.label else type(e).__name__
        rel = 100.0 * e.execTime / total if total else 0.0
        print(f"{name:<50}{e.execCount:>10}{e.execTime / 1000:>19.3f}us{rel:>20.2f}%")
    print(f"{'TOTAL':<50}{'':>10}{total / 1000:>19.3f}us{100.0 if total else 0.0:>20.2f}%")
