"""What a run in a terminal says: the line of a first run's compiling, the progress bar's rate."""

from __future__ import annotations

import io
import re
import threading
from types import SimpleNamespace

import pytest

from granum import _compile
from granum.yade import progress
from granum.yade.progress import Progress, compile_notice


class _Terminal(io.StringIO):
    def isatty(self):
        return True


@pytest.fixture
def terminal_wanted(monkeypatch):
    for name in ("YADE_BATCH", "PARAM_TABLE", "GRANUM_PROGRESS"):
        monkeypatch.delenv(name, raising=False)
    monkeypatch.setitem(progress._on_screen, "bar", None)   # whatever an earlier test left drawn


def test_a_first_run_says_that_it_compiles_in_a_terminal_only(monkeypatch, terminal_wanted):
    """The line a first run writes before compiling (granum.yade.progress.compile_notice), ended by the time taken;
    nothing on a stream that is not a terminal, from a thread other than the main one (a background run), in a batch
    job, or with GRANUM_PROGRESS=0."""
    terminal = _Terminal()
    done = compile_notice(5, terminal)
    assert terminal.getvalue().startswith("granum: compiling the kernels of this engine list (5 parts)")
    assert not terminal.getvalue().endswith("\n")
    done()
    assert re.search(r" \d+\.\d s\n$", terminal.getvalue())
    assert _compile.NOTICE is compile_notice   # granum.yade installs it
    pipe = io.StringIO()
    assert compile_notice(5, pipe) is None and pipe.getvalue() == ""
    background, quiet = [], _Terminal()
    thread = threading.Thread(target=lambda: background.append(compile_notice(5, quiet)))
    thread.start()
    thread.join()
    assert background == [None] and quiet.getvalue() == ""
    monkeypatch.setenv("YADE_BATCH", "x.table:2")
    assert compile_notice(5, terminal := _Terminal()) is None and terminal.getvalue() == ""
    monkeypatch.delenv("YADE_BATCH")
    monkeypatch.setenv("GRANUM_PROGRESS", "0")
    assert compile_notice(5, terminal := _Terminal()) is None and terminal.getvalue() == ""


def test_the_bars_rate_leaves_out_the_first_chunks_compiling(monkeypatch, terminal_wanted):
    """A first run's first chunk (one step) lasts as long as its compiling: the rate and the time left count from
    the end of it, the elapsed time from the start."""
    clock = iter([0.0, 40.0, 41.0, 42.0])   # start; the first chunk ends after 40 s of compiling; two more updates
    monkeypatch.setattr(progress, "time", SimpleNamespace(perf_counter=lambda: next(clock)))
    terminal = _Terminal()
    bar = Progress(3001, terminal)
    bar.update(1)
    bar.update(1001)
    assert terminal.getvalue().endswith("1001/3001 steps, 41.0 s, 1e+03 steps/s, 2 s left  ")
    bar.finish(3001)
    assert terminal.getvalue().endswith("3001/3001 steps, 42.0 s, 1.5e+03 steps/s  \n")



def test_compiling_during_a_run_starts_a_line_below_the_bar_and_is_left_out_of_its_rate(monkeypatch, terminal_wanted):
    """An engine list changed during a run compiles anew: its line starts below the bar (which has no line end),
    and the bar's rate leaves its seconds out."""
    now = [0.0]
    monkeypatch.setattr(progress, "time", SimpleNamespace(perf_counter=lambda: now[0]))
    terminal = _Terminal()
    bar = Progress(5001, terminal)
    now[0] = 2.0
    bar.update(1)
    now[0] = 3.0
    bar.update(1001)   # 1,000 steps a second
    done = compile_notice(4, terminal)
    assert terminal.getvalue().endswith("4 s left  \ngranum: compiling the kernels of this engine list (4 parts)"
                                        ", once: later runs load them from the cache ...")
    now[0] = 23.0      # 20 s of compiling
    done()
    now[0] = 24.0
    bar.update(2001)
    assert terminal.getvalue().endswith(" 20.0 s\n\r[############..................]  40% 2001/5001 steps, 24.0 s, "
                                        "1e+03 steps/s, 3 s left  ")
    bar.finish(5001)
    terminal2 = _Terminal()
    compile_notice(1, terminal2)()   # no bar on screen after finish: no line break first
    assert terminal2.getvalue().startswith("granum: compiling the kernels of this engine list (1 part), once")
