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
"""

from __future__ import annotations

import ctypes
import ctypes.util
import functools

#: blocks of this size and more get pages of their own, returned to the system when freed [bytes]
MMAP_THRESHOLD = 4 << 20
_M_MMAP_THRESHOLD = -3  # glibc's mallopt parameter


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
    """Fix the allocator's mmap threshold (once per process; see the module docstring)."""
    fn = _libc_function("mallopt")
    if fn is not None:
        fn(_M_MMAP_THRESHOLD, MMAP_THRESHOLD)
