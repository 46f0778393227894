"""Order statistics, a stable sort and a binary search for the broad phase, as plain loops.

``np.median``, ``np.argsort(kind="mergesort")`` and ``np.searchsorted`` compile NumPy's
general machinery (partitioning, a templated merge sort) into every first run, at one to
two seconds each. The broad phase needs only a median of bound sizes, a stable order of
non-negative integer cell keys and the position of a key among sorted ones, which these
few loops give.
"""

from __future__ import annotations

import numpy as np

from granum._jit import jit

#: Bits of a key sorted per pass of :func:`argsort_keys`.
_DIGIT_BITS = 11


@jit
def kth_smallest(a, k):
    """The ``k``-th smallest value (0-based) of the 1-D float array ``a``, which is reordered (quickselect)."""
    lo = 0
    hi = a.shape[0] - 1
    while lo < hi:
        pivot = a[(lo + hi) // 2]
        i = lo
        j = hi
        while i <= j:
            while a[i] < pivot:
                i += 1
            while a[j] > pivot:
                j -= 1
            if i <= j:
                a[i], a[j] = a[j], a[i]
                i += 1
                j -= 1
        if k <= j:
            hi = j
        elif k >= i:
            lo = i
        else:
            break
    return a[k]


@jit
def median(values):
    """Median of a non-empty 1-D float array without NaN, as ``np.median`` computes it (``values`` is not changed)."""
    a = values.copy()
    n = a.shape[0]
    upper = kth_smallest(a, n // 2)
    if n % 2:
        return upper
    # after the selection the lower half holds the n // 2 smallest values
    lower = a[0]
    for t in range(1, n // 2):
        lower = max(lower, a[t])
    return 0.5 * (lower + upper)


@jit(shared=True)   # the collider's and the compaction's sort: compiled once (granum._linking)
def argsort_keys(keys):
    """Indices (int64) that sort the non-negative int64 ``keys``, equal keys in index order (LSD radix sort)."""
    n = keys.shape[0]
    order = np.arange(n)
    if n < 2:
        return order
    top = 0
    for t in range(n):
        top = max(top, keys[t])
    spare = np.empty(n, np.int64)
    mask = (1 << _DIGIT_BITS) - 1
    count = np.empty(mask + 2, np.int64)
    shift = 0
    while top >> shift > 0:
        count[:] = 0
        for t in range(n):
            count[(keys[order[t]] >> shift & mask) + 1] += 1
        for d in range(mask + 1):
            count[d + 1] += count[d]
        for t in range(n):
            d = keys[order[t]] >> shift & mask
            spare[count[d]] = order[t]
            count[d] += 1
        order, spare = spare, order
        shift += _DIGIT_BITS
    return order


@jit
def lower_bound(a, x):
    """First index of the sorted 1-D array ``a`` whose value is not below ``x`` (``np.searchsorted(a, x)``)."""
    lo = 0
    hi = a.shape[0]
    while lo < hi:
        mid = (lo + hi) // 2
        if a[mid] < x:
            lo = mid + 1
        else:
            hi = mid
    return lo
