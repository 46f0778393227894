"""A step's temporaries, carved out of one work area kept from step to step.

The stages need temporaries each step: the bodies' motions since the collider ran (N, 4), per-block
counts and sums, the detection's candidate lists. Allocated each step, they were eleven allocations a
step in a Cundall-Strack scene (``NUMBA_NRT_STATS``): at two bodies, ``malloc``, ``free`` and Numba's
memory-info bookkeeping took about a fifth of the step (``perf``), and at 1e6 bodies each array of tens of
MB faulted its pages in again each step. Instead a stage asks :func:`area` for the words it needs and
takes its pieces one after the other with the ``take_*`` functions::

    w = area(C, nb * 4 + pair_blocks * 3)
    motion, at = take_f8(w, 0, nb * 4)
    motion = rows_of(motion, 4)   # (nb, 4)
    hits, at = take_i8(w, at, pair_blocks * 3)

The work area is the contact record's ``scratch`` (float64, 1-D), grown by half at least when a step
needs more, so that it is replaced O(log n) times in a run. It is not state: checkpoints leave it out
(:attr:`granum.core.records.RecordSpec.transient`), and a piece holds whatever an earlier stage left
there (a larger area starts with the words of the one it replaces: the interaction loop finds the motions
the collider's check left, :func:`granum.kernels.motion.take_motions`), so a stage zeroes what must start at
zero. The area and its pieces are *borrowed* (:func:`granum.core.records.borrow`): no reference to them is
counted, which spares a step two atomic operations per piece and per function a piece is passed to (26
increments and as many decrements a step in a two-body scene, each 7-9 ns on a 2-core Xeon). So they are
valid until the next call of :func:`area`, which may replace the array: use no piece after a later
:func:`area` call. Take the raw view of the record (:func:`granum.core.records.raw`) after :func:`area` too,
which may replace one of its arrays.
"""

from __future__ import annotations

import numpy as np
from numba import types
from numba.core import cgutils
from numba.extending import intrinsic

from granum._jit import jit
from granum.core.contacts import C_REPLACED
from granum.core.records import borrow
from granum.kernels.copy import copy_items


@jit(inline="always")  # a few instructions: no call
def area(C, words):
    """``C.scratch`` with room for at least ``words`` float64 words (replaced by a larger array holding the same words
    first if needed), borrowed: valid until the next call (see the module docstring)."""
    if C.scratch.shape[0] < words:
        grown = np.empty(max(words, C.scratch.shape[0] + C.scratch.shape[0] // 2))
        copy_items(grown, C.scratch, C.scratch.shape[0])
        C.scratch = grown
        C.ctr[C_REPLACED] += 1
    return borrow(C.scratch)


@jit(inline="always")  # a few instructions: no call
def words_i4(n):
    """Words holding ``n`` int32 values."""
    return (n + 1) // 2


@jit(inline="always")  # a few instructions: no call
def take_f8(w, at, n):
    """``n`` float64 values of the work area ``w`` from word ``at`` (1-D), and the word after them."""
    return piece(w, at, n, np.float64), at + n


@jit(inline="always")  # a few instructions: no call
def take_i8(w, at, n):
    """``n`` int64 values from word ``at`` (1-D), and the word after them."""
    return piece(w, at, n, np.int64), at + n


@jit(inline="always")  # a few instructions: no call
def take_i4(w, at, n):
    """``n`` int32 values from word ``at`` (1-D), and the word after them."""
    return piece(w, at, n, np.int32), at + words_i4(n)


@intrinsic
def piece(typingctx, w, at, n, dtype):
    """``n`` values of the NumPy scalar type ``dtype`` laid from word ``at`` of the float64 work area ``w``
    (1-D, C-contiguous, the same memory; the caller keeps them inside ``w``). Slicing and ``view`` would do
    the same, ``view`` at half a second of compilation per type."""
    if not (isinstance(w, types.Array) and w.ndim == 1 and w.layout == "C" and w.dtype == types.float64
            and isinstance(at, types.Integer) and isinstance(n, types.Integer)
            and isinstance(dtype, types.NumberClass)):
        return None
    result_type = types.Array(dtype.instance_type, 1, "C")

    def codegen(context, builder, sig, args):
        src = context.make_array(sig.args[0])(context, builder, value=args[0])
        start = context.cast(builder, args[1], sig.args[1], types.intp)
        count = context.cast(builder, args[2], sig.args[2], types.intp)
        itemsize = context.get_constant(types.intp,
                                        context.get_abi_sizeof(context.get_data_type(dtype.instance_type)))
        return _view(context, builder, sig.return_type, src, builder.gep(src.data, [start]), [count], itemsize)

    return result_type(w, at, n, dtype), codegen


@intrinsic
def rows_of(typingctx, a, cols):
    """The 1-D C-contiguous array ``a`` seen as rows of ``cols`` items (2-D, C-contiguous, ``a.size // cols``
    rows; the same memory). ``reshape`` would do the same through a C helper of Numba's, a call per piece and
    step."""
    if not (isinstance(a, types.Array) and a.ndim == 1 and a.layout == "C" and isinstance(cols, types.Integer)):
        return None

    def codegen(context, builder, sig, args):
        src = context.make_array(sig.args[0])(context, builder, value=args[0])
        ncols = context.cast(builder, args[1], sig.args[1], types.intp)
        return _view(context, builder, sig.return_type, src, src.data, [builder.sdiv(src.nitems, ncols), ncols],
                     src.itemsize)

    return a.copy(ndim=2, layout="C")(a, cols), codegen


def _view(context, builder, ty, src, data, shape, itemsize):
    """LLVM value of a C-contiguous array of Numba type ``ty`` over ``src``'s memory (the array structure
    ``src`` of an intrinsic's argument): items of ``itemsize`` bytes from the pointer ``data``, of ``shape``
    (LLVM integers). It holds a new reference to ``src``'s memory, as an intrinsic's result must."""
    out = context.make_array(ty)(context, builder)
    strides = [itemsize]
    for extent in reversed(shape[1:]):
        strides.insert(0, builder.mul(extent, strides[0]))
    nitems = shape[0]
    for extent in shape[1:]:
        nitems = builder.mul(nitems, extent)
    out.meminfo = src.meminfo
    out.parent = src.parent
    out.nitems = nitems
    out.itemsize = itemsize
    out.data = builder.bitcast(data, out.data.type)
    out.shape = cgutils.pack_array(builder, shape)
    out.strides = cgutils.pack_array(builder, strides)
    result = out._getvalue()
    context.nrt.incref(builder, ty, result)
    return result
