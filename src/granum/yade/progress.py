"""The progress bar of a long ``O.run(n, True)`` in a terminal, and the line a first run's compiling prints.

The bar appears only when the run has lasted a second, when standard error is a terminal, and when the
script does not run as a batch job (whose output goes to a log file); ``GRANUM_PROGRESS=0`` turns it
off. It is redrawn at most five times a second, between compiled chunks, so it costs nothing per step.

Under the same conditions, a run in the main thread that must compile kernels missing from the disk cache (the
first run of an engine list: tens of seconds, see ARCHITECTURE.md, "Compilation") says so on one line before the
silence, and how long it took after it (:func:`compile_notice`, which :mod:`granum._compile` calls on its fast
path); a bar's rate leaves those seconds out.
"""

from __future__ import annotations

import os
import sys
import threading
import time

from granum import _compile

#: Seconds a run lasts before the bar appears, and between redraws.
SHOW_AFTER = 1.0
REDRAW_EVERY = 0.2
BAR_WIDTH = 30

#: The bar drawn last and not finished (a line without its end on the terminal), and the seconds of compiling
#: announced so far in this process (:func:`compile_notice`): a bar's rate leaves them out.
_on_screen: dict = {"bar": None, "compiling": 0.0}


def progress_wanted(stream) -> bool:
    """Whether a progress bar should be drawn on ``stream`` (asked at every ``O.run(n, True)``: the terminal first,
    the cheapest question, and the only one asked of a script's output that goes to a file or a pipe)."""
    isatty = getattr(stream, "isatty", None)
    if not (isatty and isatty()):
        return False
    from granum.yade.batch import runningInBatch

    return os.environ.get("GRANUM_PROGRESS", "") != "0" and not runningInBatch()


class Progress:
    """Progress of a run of ``total`` steps drawn on ``stream`` (standard error by default). The rate, and the time
    left, count from the first update, the end of the run's first chunk (a first run compiles its kernels before
    that chunk), and leave out the compiling announced later in the run (an engine list changed by a PyRunner):
    those seconds say nothing of the steps' speed."""

    def __init__(self, total: int, stream=None):
        self.total = max(int(total), 1)
        self.stream = stream if stream is not None else sys.stderr
        self.start = time.perf_counter()
        self.last_draw = -1.0
        self.shown = False
        self.first: tuple[int, float, float] | None = None   # (steps done, time, compiling so far) at the first update

    def update(self, done: int) -> None:
        """Steps ``done`` so far; redraws when due."""
        now = time.perf_counter()
        if self.first is None:
            self.first = (done, now, _on_screen["compiling"])
        elapsed = now - self.start
        if elapsed < SHOW_AFTER or now - self.last_draw < REDRAW_EVERY:
            return
        self.last_draw = now
        self.shown = True
        _on_screen["bar"] = self
        self.stream.write("\r" + progress_line(done, self.total, elapsed, self.rate(done, now)))
        self.stream.flush()

    def rate(self, done: int, now: float) -> float:
        """Steps a second since the first update, compiling left out (0 before it, or when none has run since)."""
        if self.first is None:
            return 0.0
        steps, start, compiling = self.first
        seconds = now - start - (_on_screen["compiling"] - compiling)
        return (done - steps) / seconds if done > steps and seconds > 0 else 0.0

    def finish(self, done: int) -> None:
        """End the bar (with the final count) if it was shown."""
        if _on_screen["bar"] is self:
            _on_screen["bar"] = None
        if self.shown:
            now = time.perf_counter()
            self.stream.write("\r" + progress_line(done, self.total, now - self.start, self.rate(done, now)) + "\n")
            self.stream.flush()


def progress_line(done: int, total: int, elapsed: float, rate: float) -> str:
    """``[#####.....]  50% 500/1000 steps, 2.0 s, 250 steps/s, 2 s left`` (``elapsed`` [s] since the run began,
    ``rate`` [steps/s]: none shown, nor the time left, when 0)."""
    frac = min(max(done / total, 0.0), 1.0)
    filled = int(round(frac * BAR_WIDTH))
    speed = f", {rate:.3g} steps/s" if rate > 0 else ""
    left = f", {(total - done) / rate:.0f} s left" if rate > 0 and done < total else ""
    return (f"[{'#' * filled}{'.' * (BAR_WIDTH - filled)}] {100 * frac:3.0f}% {done}/{total} steps, "
            f"{elapsed:.1f} s{speed}{left}  ")


def compile_notice(count: int, stream=None):
    """Called by :mod:`granum._compile` (its ``NOTICE``) before it compiles ``count`` entry points missing from the
    disk cache: writes a line on ``stream`` (standard error) when :func:`progress_wanted` and the compiling thread is
    the main one (a background run's line would land in the user's prompt), on a line of its own below a bar, and
    returns the function that ends it with the seconds taken (which a bar's rate leaves out); None (nothing
    written) otherwise. A terminal that cannot be written to any more is left alone."""
    stream = stream if stream is not None else sys.stderr
    if threading.current_thread() is not threading.main_thread() or not progress_wanted(stream):
        return None
    start = time.perf_counter()
    below = "\n" if _on_screen["bar"] is not None else ""
    parts = f"{count} part" + ("s" if count != 1 else "")
    _say(stream, f"{below}granum: compiling the kernels of this engine list ({parts}), once: later runs load them "
                 "from the cache ...")

    def done() -> None:
        seconds = time.perf_counter() - start
        _on_screen["compiling"] += seconds
        _say(stream, f" {seconds:.1f} s\n")

    return done


def _say(stream, text: str) -> None:
    try:
        stream.write(text)
        stream.flush()
    except OSError:   # the terminal has gone (a closed window): the run goes on
        pass


_compile.NOTICE = compile_notice
