"""A monotonic clock readable from compiled code (for ``O.timingEnabled``).

The compiled code calls the platform's C function by name, so it can be cached on disk:
``clock_gettime`` with the monotonic clock's id as Python's :mod:`time` gives it on POSIX systems
(Linux, macOS and the BSDs number that clock differently), ``QueryPerformanceCounter`` on Windows.
"""

from __future__ import annotations

import sys
import time

from llvmlite import ir
from numba import types
from numba.core import cgutils
from numba.extending import intrinsic

_WINDOWS = sys.platform == "win32"


def _performance_frequency() -> int:
    """Ticks per second of Windows' performance counter (fixed at boot); 0 elsewhere."""
    if not _WINDOWS:
        return 0
    import ctypes

    freq = ctypes.c_int64()
    ctypes.windll.kernel32.QueryPerformanceFrequency(ctypes.byref(freq))
    return freq.value


#: the monotonic clock's id for ``clock_gettime`` on this POSIX system (unused on Windows)
_CLOCK_MONOTONIC = getattr(time, "CLOCK_MONOTONIC", 1)
#: ticks per second of Windows' performance counter (unused elsewhere)
_TICKS_PER_SECOND = _performance_frequency()


def _posix_ns(builder):
    """``clock_gettime(CLOCK_MONOTONIC)`` in ns; ``struct timespec`` is two 64-bit words on LP64 systems."""
    i32, i64 = ir.IntType(32), ir.IntType(64)
    timespec = ir.LiteralStructType([i64, i64])
    fn = cgutils.get_or_insert_function(builder.module, ir.FunctionType(i32, [i32, timespec.as_pointer()]),
                                        "clock_gettime")
    ts = cgutils.alloca_once(builder, timespec)
    builder.call(fn, [ir.Constant(i32, _CLOCK_MONOTONIC), ts])
    sec = builder.load(cgutils.gep_inbounds(builder, ts, 0, 0))
    nsec = builder.load(cgutils.gep_inbounds(builder, ts, 0, 1))
    return builder.add(builder.mul(sec, ir.Constant(i64, 1_000_000_000)), nsec)


def _windows_ns(builder):
    """``QueryPerformanceCounter`` ticks in ns: whole seconds and the remainder scaled apart (no overflow)."""
    i32, i64 = ir.IntType(32), ir.IntType(64)
    fn = cgutils.get_or_insert_function(builder.module, ir.FunctionType(i32, [i64.as_pointer()]),
                                        "QueryPerformanceCounter")
    count = cgutils.alloca_once(builder, i64)
    builder.call(fn, [count])
    ticks = builder.load(count)
    freq = ir.Constant(i64, _TICKS_PER_SECOND)
    billion = ir.Constant(i64, 1_000_000_000)
    whole = builder.mul(builder.sdiv(ticks, freq), billion)
    return builder.add(whole, builder.sdiv(builder.mul(builder.srem(ticks, freq), billion), freq))


@intrinsic
def monotonic_ns(typingctx):
    """Nanoseconds of the platform's monotonic clock, as an int64 (differences only are meaningful)."""

    def codegen(context, builder, sig, args):
        return _windows_ns(builder) if _WINDOWS else _posix_ns(builder)

    return types.int64(), codegen
