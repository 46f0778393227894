"""PyRunner: a periodic engine that executes a Python command in the script's namespace."""

from __future__ import annotations

import traceback

from granum.core.attrs import Attr, to_bool, to_str
from granum.engines.base import PeriodicEngine


class PyRunner(PeriodicEngine):
    """Execute ``command`` (Python source) periodically, in the namespace of the script.

    ``PyRunner(command='checkUnbalanced()', iterPeriod=100)``; the periods are those
    of :class:`~granum.engines.base.PeriodicEngine`. ``command`` may be changed while
    the simulation runs (also from within the command itself).
    """

    _attrs = {
        "command": Attr("", "Python source to execute", to_str("command")),
        "ignoreErrors": Attr(False, "Print errors raised by the command and go on", to_bool),
        "updateGlobals": Attr(True, "Accepted for compatibility", to_bool),
    }

    def __init__(self, command: str = "", **kw):
        super().__init__(command=command, **kw)

    def run_python(self, omega) -> None:
        if not self.command:
            return
        try:
            compiled = self.__dict__.get("_compiled")
            if compiled is None or compiled[0] != self.command:   # once per command: a run may call it often
                compiled = (self.command, compile(self.command, "<string>", "exec"))
                object.__setattr__(self, "_compiled", compiled)
            exec(compiled[1], omega.namespace())
        except Exception as e:
            if not self.ignoreErrors:
                raise PyRunnerError(yade_report(self.command, e)) from e
            traceback.print_exc()


class PyRunnerError(RuntimeError):
    """An exception raised by a PyRunner's command, reported as YADE reports it (a RuntimeError naming the
    command, the error and its stack trace); the original exception is its ``__cause__``."""


def yade_report(command: str, exc: BaseException) -> str:
    """YADE's message for an exception raised by ``command``: the trace starts at the command's own frame."""
    trace = traceback.format_exception(type(exc), exc, exc.__traceback__.tb_next)
    return f"PyRunner error.\n\nCOMMAND: {command!r}\n\nERROR:\n{exc}\n\nSTACK TRACE:\n" + "\n".join(trace)
