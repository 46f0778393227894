"""The loops that replace NumPy conveniences inside kernels (granum.kernels.sorting, granum.kernels.copy) give
NumPy's results, on random data with ties and on the edge cases."""

from __future__ import annotations

import numpy as np
import pytest

from granum.kernels.copy import copy_items, copy_row, copy_rows, copy_to_row
from granum.kernels.sorting import argsort_keys, lower_bound, median


@pytest.mark.parametrize("n", [1, 2, 3, 4, 5, 10, 11, 100, 1001])
def test_median_equals_numpys(n):
    rng = np.random.default_rng(n)
    for values in (rng.random(n), rng.integers(0, 4, n).astype(float), np.full(n, 2.5), -rng.random(n) * 1e9):
        before = values.copy()
        assert median(values) == np.median(values)
        assert (values == before).all(), "median must not reorder its argument"


@pytest.mark.parametrize("top", [1, 3, 2**11, 2**20, 2**60])
def test_argsort_keys_is_numpys_stable_sort(top):
    rng = np.random.default_rng(top % 1000)
    for n in (0, 1, 2, 7, 1000, 5000):
        keys = rng.integers(0, top, n)
        assert (argsort_keys(keys) == np.argsort(keys, kind="stable")).all()


def test_lower_bound_is_searchsorted():
    rng = np.random.default_rng(7)
    a = np.sort(rng.integers(0, 50, 200))
    for x in range(-2, 53):
        assert lower_bound(a, x) == np.searchsorted(a, x, side="left")
    assert lower_bound(a[:0], 3) == 0


def test_copies_equal_slice_assignment():
    rng = np.random.default_rng(3)
    src2 = rng.random((6, 3))
    dst2 = np.zeros((8, 5))
    copy_rows(dst2, src2, 4)   # narrower source: its columns only
    expected = np.zeros((8, 5))
    expected[:4, :3] = src2[:4]
    assert (dst2 == expected).all()
    src1 = rng.integers(0, 9, 10)
    dst1 = np.full(12, -1)
    copy_items(dst1, src1, 7)
    assert (dst1[:7] == src1[:7]).all() and (dst1[7:] == -1).all()
    copy_to_row(dst2, 6, np.arange(5.0))
    assert (dst2[6] == np.arange(5.0)).all()
    copy_row(dst2, 7, 0)
    assert (dst2[7] == dst2[0]).all()
