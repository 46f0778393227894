"""Giving freed heap memory back to the operating system.

Building a large scene in a script makes and frees millions of small Python objects
(``utils.sphere()`` bodies, their vectors, the list handed to ``O.bodies.append``).
The C allocator keeps most of the freed memory resident for later use; at a million
spheres that is about 150 MB, which the contact pool then allocates on top of.
:func:`trim` hands it back (glibc's ``malloc_trim``; a no-op elsewhere).
"""

from __future__ import annotations

import ctypes
import ctypes.util
import functools


@functools.cache
def _malloc_trim():
    name = ctypes.util.find_library("c")
    try:
        return ctypes.CDLL(name).malloc_trim if name else None
    except (OSError, AttributeError):  # not glibc
        return None


def trim() -> None:
    """Return the C heap's free memory to the operating system (takes a few milliseconds)."""
    fn = _malloc_trim()
    if fn is not None:
        fn(0)
