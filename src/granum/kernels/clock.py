"""A monotonic clock readable from compiled code (for ``O.timingEnabled``)."""

from __future__ import annotations

from llvmlite import ir
from numba import types
from numba.core import cgutils
from numba.extending import intrinsic

#: CLOCK_MONOTONIC of Linux's clock_gettime.
_CLOCK_MONOTONIC = 1


@intrinsic
def monotonic_ns(typingctx):
    """Nanoseconds of the monotonic clock (``clock_gettime(CLOCK_MONOTONIC)``), as an int64.

    The C function is called by name, so code using it can be cached on disk."""

    def codegen(context, builder, sig, args):
        i32, i64 = ir.IntType(32), ir.IntType(64)
        timespec = ir.LiteralStructType([i64, i64])
        fn = cgutils.get_or_insert_function(builder.module, ir.FunctionType(i32, [i32, timespec.as_pointer()]),
                                            "clock_gettime")
        ts = cgutils.alloca_once(builder, timespec)
        builder.call(fn, [ir.Constant(i32, _CLOCK_MONOTONIC), ts])
        sec = builder.load(cgutils.gep_inbounds(builder, ts, 0, 0))
        nsec = builder.load(cgutils.gep_inbounds(builder, ts, 0, 1))
        return builder.add(builder.mul(sec, ir.Constant(i64, 1_000_000_000)), nsec)

    return types.int64(), codegen
