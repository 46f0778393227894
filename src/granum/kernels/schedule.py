"""Which thread runs which block of a parallel loop: each its own range first, then the others'.

The parallel kernels over the scene loop over fixed blocks of ``BLOCK`` items (:mod:`granum._jit`). Numba's
OpenMP loops split the iterations evenly and statically, so a step lasts as long as its slowest
thread. On a shared host one core often runs slower than the other for a while (another machine's
work on it); with a static split the whole step waits for it. At 1e5 spheres, with a busy loop
sharing the second core, the contact update took 11.2 ms per step with the static split and 8.0 ms
with the blocks shared out as here (4.9 ms either way on a quiet machine); with the busy loop at
nice 5, whole steps ran at 51-59 steps/s against 43-49.

Each worker takes the blocks of its own contiguous range in order, so it streams through memory as
with a static split; a worker that has finished takes blocks from the others' ranges, one at a time,
through an atomic counter per range. Each block is run exactly once, and a block's results never
depend on the thread that runs it: kernels stay bitwise independent of the number of threads.

A kernel loops like this::

    queue = block_queue(nblocks)
    for w in prange(queue_workers(queue)):
        b = next_block(queue, w, -1)
        while b >= 0:
            work_block(b, ...)
            b = next_block(queue, w, b)

The serial variant of a kernel (:func:`granum._jit.kernel`) reads these three names as the
``serial_*`` functions below: one worker counts the blocks up, with no queue to allocate and no
atomic operation (a step of a two-body scene runs about ten such loops: with queues, the bouncing
sphere ran at 6.8-7.2e5 steps/s instead of 9.8-10.9e5).
With ``GRANUM_NOPAR=1`` the parallel variants run the queue on one thread, which takes every block in
order.
"""

from __future__ import annotations

import numpy as np
from llvmlite import ir
from numba import types
from numba.core import cgutils
from numba.extending import intrinsic

from granum._jit import SERIAL_GLOBALS, jit
from granum.core.atomic import fetch_add

#: int64 slots per worker in a queue: its range's counter and its cursor on a cache line of their own
_SLOTS = 8


@intrinsic
def thread_count(typingctx):
    """Numba's current number of threads (``numba.get_num_threads()``).

    Calls the threading layer's C function by name, as Numba registers it when it starts its threads
    (:mod:`granum._jit` does that at import): ``numba.get_num_threads`` itself holds the function's
    address, which keeps the kernels that use it out of the on-disk cache."""

    def codegen(context, builder, sig, args):
        # declared as Numba's parallel loops declare it (intp), so that both can share a module; the C
        # function returns an int, whose 32 bits are kept
        fn = cgutils.get_or_insert_function(builder.module, ir.FunctionType(cgutils.intp_t, []), "get_num_threads")
        return builder.sext(builder.trunc(builder.call(fn, []), ir.IntType(32)), ir.IntType(64))

    return types.int64(), codegen


@jit
def block_queue(nblocks):
    """Queue of blocks ``0..nblocks-1`` for one worker per thread (see :func:`queue_of`)."""
    return queue_of(nblocks, thread_count())


@jit
def queue_of(nblocks, workers):
    """Queue of blocks ``0..nblocks-1`` for ``workers`` workers (int64 array).

    Slots: ``[0]`` workers, ``[1]`` blocks; for worker ``w`` at ``_SLOTS * (w + 1)``: the next block
    of range ``w`` (``w * nblocks // workers`` up to the next range's start), then how many ranges
    worker ``w`` has exhausted."""
    queue = np.zeros(_SLOTS * (workers + 1), np.int64)
    queue[0] = workers
    queue[1] = nblocks
    for w in range(workers):
        queue[_SLOTS * (w + 1)] = w * nblocks // workers
    return queue


@jit
def queue_workers(queue):
    """Number of workers a queue was made for (the ``prange`` length)."""
    return queue[0]


@jit
def next_block(queue, w, b):
    """The next block for worker ``w``, or -1 when no block is left: its own range first, then those of
    the workers after it (``b``, the worker's previous block or -1, is not needed: the counters know)."""
    workers = queue[0]
    nblocks = queue[1]
    cursor = _SLOTS * (w + 1) + 1
    while queue[cursor] < workers:
        r = (w + queue[cursor]) % workers
        claimed = fetch_add(queue, _SLOTS * (r + 1), 1)
        if claimed < (r + 1) * nblocks // workers:
            return claimed
        queue[cursor] += 1
    return -1


@jit
def serial_block_queue(nblocks):
    """Serial stand-in for :func:`block_queue`: the number of blocks."""
    return nblocks


@jit
def serial_queue_workers(queue):
    """Serial stand-in for :func:`queue_workers`: one worker."""
    return 1


@jit
def serial_next_block(queue, w, b):
    """Serial stand-in for :func:`next_block`: the block after ``b``, or -1 after the last one."""
    return b + 1 if b + 1 < queue else -1


SERIAL_GLOBALS.update(block_queue=serial_block_queue, queue_workers=serial_queue_workers,
                      next_block=serial_next_block)
