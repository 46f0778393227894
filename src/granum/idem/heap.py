"""Indexed binary min-heap over contact indices, for the article's "smallest first" selection.

Each iteration of the compression phase picks the contact with the smallest relative normal
velocity, each iteration of the release phase the one with the largest stored energy, and
one impulse changes the keys of all contacts of the two bodies involved. A heap keeps each
selection and each key change at O(log n) instead of a scan of all contacts.

``keys`` (nc,) float64 per contact, ``heap`` (nc,) contact at each heap slot, ``where`` (nc,)
slot of each contact or -1. Ties on the key are ordered by contact index, so the selection
never depends on insertion order.
"""

from __future__ import annotations

import numpy as np

from granum._jit import jit
from granum.kernels.copy import copy_items


@jit
def before(keys, a, b):
    """Whether contact ``a`` comes before ``b``: smaller key, then smaller index."""
    return keys[a] < keys[b] or (keys[a] == keys[b] and a < b)


@jit
def sift_up(keys, heap, where, i):
    c = heap[i]
    while i > 0:
        p = (i - 1) // 2
        if before(keys, heap[p], c):
            break
        heap[i] = heap[p]
        where[heap[i]] = i
        i = p
    heap[i] = c
    where[c] = i


@jit
def sift_down(keys, heap, where, size, i):
    c = heap[i]
    while True:
        left = 2 * i + 1
        if left >= size:
            break
        child = left
        if left + 1 < size and before(keys, heap[left + 1], heap[left]):
            child = left + 1
        if before(keys, c, heap[child]):
            break
        heap[i] = heap[child]
        where[heap[i]] = i
        i = child
    heap[i] = c
    where[c] = i


@jit
def push(keys, heap, where, size, c):
    """Insert contact ``c`` (its key already in ``keys[c]``); returns the new size."""
    heap[size] = c
    where[c] = size
    sift_up(keys, heap, where, size)
    return size + 1


@jit
def update(keys, heap, where, size, c, key):
    """Set the key of contact ``c`` (which must be in the heap) and restore the heap order."""
    keys[c] = key
    i = where[c]
    sift_up(keys, heap, where, i)
    sift_down(keys, heap, where, size, where[c])


@jit
def clear(heap, where, size):
    """Empty the heap (marks its contacts absent); returns 0."""
    for i in range(size):
        where[heap[i]] = -1
    return 0


@jit
def collect(keys, heap, size, limit, out, stack):
    """Write into ``out`` the contacts whose key is <= ``limit``, in increasing index; return how many.

    Depth-first walk from the root that prunes every subtree whose root exceeds ``limit``
    (heap order), so the cost is proportional to the number collected. ``stack`` (nc,) scratch.
    """
    if size == 0 or keys[heap[0]] > limit:
        return 0
    n = 0
    top = 0
    stack[0] = 0
    top = 1
    while top > 0:
        top -= 1
        i = stack[top]
        out[n] = heap[i]
        n += 1
        for child in (2 * i + 1, 2 * i + 2):
            if child < size and keys[heap[child]] <= limit:
                stack[top] = child
                top += 1
    # sorted by index: the order fixes the summation order of the group's impulses
    if n > 32:
        copy_items(out, np.sort(out[:n]), n)
        return n
    for u in range(1, n):
        v = out[u]
        w = u - 1
        while w >= 0 and out[w] > v:
            out[w + 1] = out[w]
            w -= 1
        out[w + 1] = v
    return n
