"""Copies between arrays inside kernels, written as loops.

Assigning one array to a slice of another (``a[:n] = b[:n]``, ``a[i] = row``) makes
Numba compile a broadcast check that formats its error message with the shapes: about
two seconds of compilation per combination of array types, paid on every first run.
Kernels copy with these loops instead; the callers guarantee the shapes.
"""

from __future__ import annotations

from granum._jit import jit


@jit
def copy_items(dst, src, n):
    """``dst[:n] = src[:n]`` for 1-D arrays."""
    for i in range(n):
        dst[i] = src[i]


@jit
def copy_rows(dst, src, n):
    """``dst[:n, :m] = src[:n]`` for 2-D arrays, ``m`` the columns of ``src`` (``dst`` may be wider)."""
    for i in range(n):
        for j in range(src.shape[1]):
            dst[i, j] = src[i, j]


@jit
def copy_to_row(a, i, row):
    """``a[i, :] = row`` for a 2-D array and a 1-D array ``row``."""
    for j in range(a.shape[1]):
        a[i, j] = row[j]
