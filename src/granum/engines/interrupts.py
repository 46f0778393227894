"""Ctrl-C during a run lands at a step boundary, with every array consistent.

Python raises ``KeyboardInterrupt`` at the next bytecode after the signal, which may be between a compiled
chunk's return and the moment the runner takes the contact arrays back (the counters would then outrun
the arrays: a later run crashes, a save is rejected on load). While a run goes on in the main thread,
:func:`deferred` replaces the SIGINT handler by one that only records the signal; the run raises
``KeyboardInterrupt`` itself at the next step boundary (:func:`raise_pending`). Inside the Python code of
engines (a PyRunner's command, :func:`user_code`) a second Ctrl-C interrupts at once, so that a command
that never returns can still be stopped (its step is then left half done). Outside a run,
:func:`shielded` defers Ctrl-C over one exchange of arrays with compiled code. Threads other than the
main one never receive SIGINT, so the functions do nothing there.
"""

from __future__ import annotations

# CPython's module under ``signal``: the same calls without the conversions to and from enums (3.3 -> 0.3 us a call;
# a run in the main thread, each O.step(), installs a handler and restores the one before)
import _signal as _signals
import signal
import threading


class _Guard:
    """The SIGINT handler of a run: records the first Ctrl-C; a second one inside user code raises."""

    def __init__(self):
        self.pending = False
        self.in_user_code = False

    def __call__(self, signum, frame):
        if self.pending and self.in_user_code:
            raise KeyboardInterrupt
        self.pending = True


_active: _Guard | None = None


def _installable() -> bool:
    return threading.current_thread() is threading.main_thread() and _active is None


class _Handler:
    """Install ``guard`` as the SIGINT handler for the ``with`` block; the handler before comes back after it.

    The context managers of this module are classes, not generators: ``contextlib``'s generator protocol cost
    about a microsecond per block, and each ``O.step()`` enters two of them."""

    __slots__ = ("guard", "previous")

    def __init__(self, guard: _Guard):
        self.guard = guard

    def __enter__(self) -> _Guard:
        global _active
        self.previous = _signals.getsignal(signal.SIGINT)
        _signals.signal(signal.SIGINT, self.guard)
        _active = self.guard
        return self.guard

    def __exit__(self, *exc) -> bool:
        global _active
        _active = None
        # a handler installed from C reads as None and cannot be put back from Python: Python's default then
        previous = self.previous
        _signals.signal(signal.SIGINT, previous if previous is not None else signal.default_int_handler)
        return False


class _Nothing:
    """A ``with`` block that changes nothing (where no handler can be installed)."""

    __slots__ = ()

    def __enter__(self) -> None:
        return None

    def __exit__(self, *exc) -> bool:
        return False


_NOTHING = _Nothing()


def deferred():
    """Defer Ctrl-C for a run in the main thread (see the module docstring); elsewhere, nothing."""
    return _Handler(_Guard()) if _installable() else _NOTHING


def raise_pending() -> None:
    """At a step boundary: raise the KeyboardInterrupt that Ctrl-C asked for during the run, if any."""
    if _active is not None and _active.pending:
        _active.pending = False
        raise KeyboardInterrupt


class _UserCode:
    """The Python code of an engine inside a deferred run: a second Ctrl-C interrupts it at once."""

    __slots__ = ("guard",)

    def __init__(self, guard: _Guard):
        self.guard = guard

    def __enter__(self) -> None:
        self.guard.in_user_code = True

    def __exit__(self, *exc) -> bool:
        self.guard.in_user_code = False
        return False


def user_code():
    """The Python code of an engine: during a deferred run a second Ctrl-C interrupts it at once."""
    guard = _active
    return _NOTHING if guard is None else _UserCode(guard)


class _Shield(_Handler):
    """:func:`shielded`'s block: Ctrl-C deferred, and raised once the block has ended (unless it raised)."""

    __slots__ = ()

    def __exit__(self, kind, value, traceback) -> bool:
        super().__exit__(kind, value, traceback)
        if kind is None and self.guard.pending:
            raise KeyboardInterrupt
        return False


def shielded():
    """Defer Ctrl-C over one exchange of arrays with compiled code outside a run; raise it afterwards."""
    return _Shield(_Guard()) if _installable() else _NOTHING
