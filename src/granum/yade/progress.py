"""The progress bar of a long ``O.run(n, True)`` in a terminal.

It appears only when the run has lasted a second, when standard error is a terminal, and when the
script does not run as a batch job (whose output goes to a log file); ``GRANUM_PROGRESS=0`` turns it
off. It is redrawn at most five times a second, between compiled chunks, so it costs nothing per step.
"""

from __future__ import annotations

import os
import sys
import time

#: Seconds a run lasts before the bar appears, and between redraws.
SHOW_AFTER = 1.0
REDRAW_EVERY = 0.2
BAR_WIDTH = 30


def progress_wanted(stream) -> bool:
    """Whether a progress bar should be drawn on ``stream`` (asked at every ``O.run(n, True)``: the terminal first,
    the cheapest question, and the only one asked of a script's output that goes to a file or a pipe)."""
    isatty = getattr(stream, "isatty", None)
    if not (isatty and isatty()):
        return False
    from granum.yade.batch import runningInBatch

    return os.environ.get("GRANUM_PROGRESS", "") != "0" and not runningInBatch()


class Progress:
    """Progress of a run of ``total`` steps drawn on ``stream`` (standard error by default)."""

    def __init__(self, total: int, stream=None):
        self.total = max(int(total), 1)
        self.stream = stream if stream is not None else sys.stderr
        self.start = time.perf_counter()
        self.last_draw = -1.0
        self.shown = False

    def update(self, done: int) -> None:
        """Steps ``done`` so far; redraws when due."""
        now = time.perf_counter()
        elapsed = now - self.start
        if elapsed < SHOW_AFTER or now - self.last_draw < REDRAW_EVERY:
            return
        self.last_draw = now
        self.shown = True
        self.stream.write("\r" + progress_line(done, self.total, elapsed))
        self.stream.flush()

    def finish(self, done: int) -> None:
        """End the bar (with the final count) if it was shown."""
        if self.shown:
            self.stream.write("\r" + progress_line(done, self.total, time.perf_counter() - self.start) + "\n")
            self.stream.flush()


def progress_line(done: int, total: int, elapsed: float) -> str:
    """``[#####.....]  50% 500/1000 steps, 2.0 s, 250 steps/s, 2 s left``."""
    frac = min(max(done / total, 0.0), 1.0)
    filled = int(round(frac * BAR_WIDTH))
    rate = done / elapsed if elapsed > 0 else 0.0
    left = f", {(total - done) / rate:.0f} s left" if rate > 0 and done < total else ""
    return (f"[{'#' * filled}{'.' * (BAR_WIDTH - filled)}] {100 * frac:3.0f}% {done}/{total} steps, "
            f"{elapsed:.1f} s, {rate:.3g} steps/s{left}  ")
