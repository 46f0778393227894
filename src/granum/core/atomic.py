"""Atomic read-modify-write of array elements from compiled code.

Integer additions commute, so counts made with :func:`fetch_add` from parallel loops are the same whatever
the order the threads run in (the block queue of :mod:`granum.kernels.schedule`, the per-body counts of
broken contacts of :mod:`granum.physics.cpm`).
"""

from __future__ import annotations

from numba import types
from numba.core import cgutils
from numba.extending import intrinsic


@intrinsic
def fetch_add(typingctx, a, i, v):
    """Atomically add ``v`` to ``a[i]`` (1-d int64 array) and return the value before.

    No bounds check and no negative indexing: ``0 <= i < len(a)`` is the caller's to keep."""
    if not (isinstance(a, types.Array) and a.ndim == 1 and a.dtype == types.int64
            and isinstance(i, types.Integer) and isinstance(v, types.Integer)):
        return None

    def codegen(context, builder, sig, args):
        aryty = sig.args[0]
        ary = context.make_array(aryty)(context, builder, args[0])
        ptr = cgutils.get_item_pointer(context, builder, aryty, ary, [args[1]])
        val = context.cast(builder, args[2], sig.args[2], types.int64)
        # only atomicity is needed: the end of the parallel loop orders the blocks' writes
        return builder.atomic_rmw("add", ptr, val, "monotonic")

    return types.int64(a, i, v), codegen
