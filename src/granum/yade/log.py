"""``yade.log``: per-class filter levels of log messages, on Python's :mod:`logging`.

YADE filters the messages of each C++ class by a level from ``NOFILTER`` (0, only unconditional messages)
to ``TRACE`` (6, everything); a class without a level of its own uses ``Default``. granum keeps the same
interface over Python's loggers: the messages of class ``X`` go to the logger ``granum.X``, whose parent
``granum`` carries the ``Default`` level, and YADE's level ``L`` lets through the Python records of
severity :data:`PYTHON_THRESHOLD` ``[L]`` and above. The names a level can be set for are the classes a
script sees (engines, functors, shapes, materials...), plus ``Default``; any other name is an error, as in
YADE.
"""

from __future__ import annotations

import logging
import os
import sys

NOFILTER = 0
FATAL = 1
ERROR = 2
WARN = 3
INFO = 4
DEBUG = 5
TRACE = 6

#: the level of a class without a level of its own (YADE starts with WARN)
_INITIAL_DEFAULT = WARN
#: Python's record level for YADE's TRACE (below logging.DEBUG)
TRACE_RECORD_LEVEL = 5
#: the lowest Python record severity that YADE's filter level lets through
PYTHON_THRESHOLD = {NOFILTER: logging.CRITICAL + 10, FATAL: logging.CRITICAL, ERROR: logging.ERROR,
                    WARN: logging.WARNING, INFO: logging.INFO, DEBUG: logging.DEBUG, TRACE: TRACE_RECORD_LEVEL}
#: the Python record level of a message of each YADE level, and its label as YADE prints it
_RECORD = {NOFILTER: (logging.CRITICAL + 10, "NOFILTER"), FATAL: (logging.CRITICAL, "FATAL ERROR"),
           ERROR: (logging.ERROR, "ERROR"), WARN: (logging.WARNING, "WARNING"), INFO: (logging.INFO, "INFO"),
           DEBUG: (logging.DEBUG, "DEBUG"), TRACE: (TRACE_RECORD_LEVEL, "TRACE")}
_COLOURS = {NOFILTER: "36", FATAL: "91", ERROR: "31", WARN: "95", INFO: "96", DEBUG: "94", TRACE: "92"}

ROOT = "granum"
_STREAMS = {"cout": lambda: sys.stdout, "cerr": lambda: sys.stderr, "clog": lambda: sys.stderr}


class _YadeFormatter(logging.Formatter):
    """``<LEVEL> Class: message`` as YADE prints it, with or without terminal colours."""

    use_colours = True

    def format(self, record):
        yade_level = getattr(record, "yade_level", None)
        if yade_level is None:
            yade_level = min(PYTHON_THRESHOLD, key=lambda lv: abs(PYTHON_THRESHOLD[lv] - record.levelno))
        label = _RECORD[yade_level][1]
        where = record.name[len(ROOT) + 1:] if record.name.startswith(ROOT + ".") else record.name
        if self.use_colours:
            label = f"\033[{_COLOURS[yade_level]}m{label}\033[0m"
            where = f"\033[93m{where}\033[0m"
        return f"<{label}> {where}: {record.getMessage()}"


_formatter = _YadeFormatter()
_outputs: list[str] = []


def _root() -> logging.Logger:
    return logging.getLogger(ROOT)


def _check_level(level: int) -> int:
    if not isinstance(level, int) or isinstance(level, bool):
        raise TypeError(f"the level must be an int, not {type(level).__name__}")
    if not NOFILTER <= level <= TRACE:
        raise RuntimeError("The level must be >= NOFILTER (0) and <= TRACE (6), other values are not meaningful. "
                           "To unset level to \"Default\" level use function unsetLevel(…).")
    return level


def _yade_level(python_level: int) -> int:
    return next(lv for lv, threshold in PYTHON_THRESHOLD.items() if threshold == python_level)


def _known_names() -> list[str]:
    from granum.yade import namespace

    return sorted(name for name, value in namespace().items() if isinstance(value, type))


def _check_name(class_name: str) -> str:
    if class_name != "Default" and class_name not in _known_names():
        raise RuntimeError(f"{class_name} is not recognized: granum has no class of that name to log for.")
    return class_name


def setLevel(className: str, level: int) -> None:
    """Set the filter level (``NOFILTER`` 0 ... ``TRACE`` 6) of one class; ``Default`` sets the default.

    :raises RuntimeError: an unknown class name or a level outside 0...6 (as YADE).
    """
    _check_level(level)
    _check_name(className)
    logger = _root() if className == "Default" else logging.getLogger(f"{ROOT}.{className}")
    logger.setLevel(PYTHON_THRESHOLD[level])


def unsetLevel(className: str) -> None:
    """Let a class use the ``Default`` level again; unsetting ``Default`` lets everything through (TRACE)."""
    _check_name(className)
    if className == "Default":
        _root().setLevel(PYTHON_THRESHOLD[TRACE])
    else:
        logging.getLogger(f"{ROOT}.{className}").setLevel(logging.NOTSET)


def setDefaultLogLevel(level: int) -> None:
    """The same as ``setLevel("Default", level)``."""
    setLevel("Default", level)


def getDefaultLogLevel() -> int:
    """The ``Default`` filter level."""
    return _yade_level(_root().level)


def getMaxLevel() -> int:
    """The highest level messages can be filtered at: TRACE (YADE: the ``MAX_LOG_LEVEL`` it was compiled with)."""
    return TRACE


def _level_of(name: str) -> int:
    level = logging.getLogger(f"{ROOT}.{name}").level
    return -1 if level == logging.NOTSET else _yade_level(level)


def getAllLevels() -> dict:
    """Every class a level can be set for, with its level, -1 where it uses ``Default``; and ``Default``."""
    levels = {name: _level_of(name) for name in _known_names()}
    levels["Default"] = getDefaultLogLevel()
    return dict(sorted(levels.items()))


def getUsedLevels() -> dict:
    """The classes with a level of their own, and ``Default``."""
    return {name: level for name, level in getAllLevels().items() if level != -1}


def setUseColors(useColors: bool) -> None:
    """Turn terminal colours in log messages on or off (on by default; off suits a log file)."""
    _formatter.use_colours = bool(useColors)


def _handler_for(streamName: str) -> logging.Handler:
    if streamName in _STREAMS:
        handler = logging.StreamHandler(_STREAMS[streamName]())
    else:
        handler = logging.FileHandler(streamName)
    handler.setFormatter(_formatter)
    handler.yade_stream = streamName
    return handler


def setOutputStream(streamName: str, reset: bool) -> None:
    """Send log messages to ``cout``, ``cerr``, ``clog`` (the default, standard error) or to the file of that name.

    :param reset: remove the outputs set before; when False the new one is added to them.
    """
    root = _root()
    if reset:
        for handler in list(root.handlers):
            root.removeHandler(handler)
            handler.close()
        _outputs.clear()
    root.addHandler(_handler_for(streamName))
    _outputs.append(streamName)


def resetOutputStream() -> None:
    """Back to the default: every message on ``clog`` (standard error)."""
    setOutputStream("clog", True)


def defaultConfigFileName() -> str:
    """The configuration file read at start-up by YADE (``logging.conf`` in :data:`yade.config.confDir`)."""
    from granum.yade.config import confDir

    return os.path.join(confDir, "logging.conf")


def saveConfigFile(fname: str) -> None:
    """Write the colours, outputs and levels in use to ``fname``, in YADE's format (``Name level`` lines)."""
    lines = ["# YADE LOG config file", "# special keywords are:", '# 1. "Default" to set default filter level',
             '# 2. "colors" to indicate if colors should be used, use 0 or 1.',
             '# 3. "output" to redirect output to cout, cerr, clog stream or to a file',
             f"colors {int(_formatter.use_colours)}"]
    lines += [f"output {name}" for name in _outputs]
    lines += [f"{name} {level}" for name, level in getUsedLevels().items()]
    with open(fname, "w") as fh:
        fh.write("\n".join(lines) + "\n")


def readConfigFile(fname: str) -> None:
    """Apply a file written by :func:`saveConfigFile` (``#`` starts a comment)."""
    first_output = True
    with open(fname) as fh:
        for raw in fh:
            line = raw.split("#", 1)[0].strip()
            if not line:
                continue
            key, value = line.rsplit(None, 1)
            if key == "colors":
                setUseColors(bool(int(value)))
            elif key == "output":
                setOutputStream(value, first_output)
                first_output = False
            else:
                setLevel(key, int(value))


def _emit(level: int, message: str) -> None:
    record_level = _RECORD[level][0]
    logger = logging.getLogger(f"{ROOT}.log")
    if logger.isEnabledFor(record_level):
        logger.log(record_level, message, extra={"yade_level": level})


def testAllLevels() -> None:
    """Send one test message at each level, to see which the filters let through and where they go."""
    for level, (_, label) in sorted(_RECORD.items()):
        _emit(level, f"Test log level: LOG_{level}_{label.split()[0]}, test int: {level}")


def testOnceLevels() -> None:
    """YADE's messages printed once per run are a C++ macro; granum has none to test."""
    raise NotImplementedError("yade.log.testOnceLevels: granum has no once-only log messages")


def testTimedLevels() -> None:
    """YADE's rate-limited messages are a C++ macro; granum has none to test."""
    raise NotImplementedError("yade.log.testTimedLevels: granum has no rate-limited log messages")


_root().setLevel(PYTHON_THRESHOLD[_INITIAL_DEFAULT])
_root().propagate = False
resetOutputStream()
