"""Giving freed heap memory back to the operating system.

Building a large scene in a script makes and frees millions of small Python objects
(``utils.sphere()`` bodies, their vectors, the list handed to ``O.bodies.append``).
The C allocator keeps most of the freed memory resident for later use; at a million
spheres that is about 150 MB, which the contact pool then allocates on top of.
:func:`trim` hands it back (glibc's ``malloc_trim``; a no-op elsewhere).

The kernels also allocate temporaries of tens of MB each step at that size. glibc
serves a block above its mmap threshold with its own pages, returned when freed, but
raises the threshold to the size of every such block freed, so that from the second
step on these blocks come from the heap and stay resident. :func:`configure` fixes
the threshold at :data:`MMAP_THRESHOLD` (glibc's ``mallopt``).

Below that threshold the opposite matters: a temporary at the top of the heap is handed
back to the system as soon as it is freed (glibc trims a free top above 128 kB), and
the same block allocated again in the next step faults its pages in again. At 1e5
spheres that was about 1 ms per step of the InteractionLoop's 20 (its 3 MB of body
motions). :func:`configure` therefore lets the heap keep :data:`TRIM_THRESHOLD` of free
top before trimming: the temporaries of one step, not the garbage of a scene's
construction, which :func:`trim` still hands back.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import functools

#: blocks of this size and more get pages of their own, returned to the system when freed [bytes]
MMAP_THRESHOLD = 4 << 20
#: free memory at the top of the heap kept for the next step's temporaries [bytes]
TRIM_THRESHOLD = 16 << 20
_M_TRIM_THRESHOLD = -1  # glibc's mallopt parameters
_M_MMAP_THRESHOLD = -3


@functools.cache
def _libc_function(name: str):
    lib = ctypes.util.find_library("c")
    try:
        return getattr(ctypes.CDLL(lib), name) if lib else None
    except (OSError, AttributeError):  # not glibc
        return None


def trim() -> None:
    """Return the C heap's free memory to the operating system (takes a few milliseconds)."""
    fn = _libc_function("malloc_trim")
    if fn is not None:
        fn(0)


@functools.cache
def configure() -> None:
    """Fix the allocator's mmap and trim thresholds (once per process; see the module docstring)."""
    fn = _libc_function("mallopt")
    if fn is not None:
        fn(_M_MMAP_THRESHOLD, MMAP_THRESHOLD)
        fn(_M_TRIM_THRESHOLD, TRIM_THRESHOLD)
