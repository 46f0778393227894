"""YADE's ``yade.timing``: per-engine time statistics (``O.timingEnabled``)."""

from __future__ import annotations


def reset() -> None:
    """Zero the engines' execTime and execCount."""
    from granum.yade.omega import O

    for e in O.engines:
        e.execTime = 0
        e.execCount = 0


def stats() -> None:
    """Print the time spent in each engine."""
    from granum.yade.omega import O

    total = sum(e.execTime for e in O.engines) or 1
    print(f"{'Name':<40}{'Count':>12}{'Time':>16}{'Rel. time':>12}")
    for e in O.engines:
        name = e.label or type(e).__name__
        print(f"{name:<40}{e.execCount:>12}{e.execTime / 1000:>14.0f}us{100 * e.execTime / total:>11.2f}%")
