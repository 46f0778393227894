"""Growable structure-of-arrays tables.

Every piece of per-entity state in granum (bodies, the per-kind shape tables, ...)
lives in a :class:`Table`: a set of named NumPy columns that share one row count.
Columns are allocated with spare capacity and grown geometrically, so appending
rows is amortised O(1) and the kernels always see plain contiguous arrays.

A column array is replaced when the table grows; code that keeps a column across
an append must fetch it again (views in :mod:`granum.yade` always read the column
through the table for that reason).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Column:
    """Declaration of one table column.

    Attributes:
        name: attribute name of the column on the table.
        tail: shape of one row, e.g. ``(3,)`` for a vector, ``()`` for a scalar.
        dtype: NumPy dtype.
        default: value of a new row (broadcast to ``tail``).
        doc: meaning, units and shape of the column.
    """

    name: str
    tail: tuple = ()
    dtype: str = "f8"
    default: object = 0
    doc: str = ""


class Table:
    """A set of NumPy columns sharing one row count, with geometric growth."""

    def __init__(self, columns: tuple[Column, ...], capacity: int = 8):
        self._columns = {c.name: c for c in columns}
        self.count = 0
        self._capacity = 0
        for c in columns:
            setattr(self, c.name, np.empty((0,) + c.tail, dtype=c.dtype))
        self._grow(max(capacity, 1))

    @property
    def columns(self) -> tuple[Column, ...]:
        return tuple(self._columns.values())

    def _grow(self, capacity: int) -> None:
        for c in self._columns.values():
            old = getattr(self, c.name)
            new = np.empty((capacity,) + c.tail, dtype=c.dtype)
            new[: self.count] = old[: self.count]
            new[self.count:] = c.default
            setattr(self, c.name, new)
        self._capacity = capacity

    def append_rows(self, k: int = 1) -> int:
        """Add ``k`` rows holding the column defaults; return the index of the first."""
        first = self.count
        if first + k > self._capacity:
            self._grow(max(2 * self._capacity, first + k))
        self.count += k
        return first

    def copy_row(self, src: Table, src_row: int, dst_row: int) -> None:
        """Copy every column of ``src[src_row]`` into row ``dst_row`` of this table."""
        for name in self._columns:
            getattr(self, name)[dst_row] = getattr(src, name)[src_row]

    def reset_row(self, row: int) -> None:
        """Put the column defaults back into row ``row`` (for reusing it)."""
        for c in self._columns.values():
            getattr(self, c.name)[row] = c.default

    def view(self, name: str) -> np.ndarray:
        """The live rows ``[0, count)`` of column ``name``."""
        return getattr(self, name)[: self.count]

    def clear(self) -> None:
        """Remove all rows (capacity is kept)."""
        for c in self._columns.values():
            getattr(self, c.name)[:] = c.default
        self.count = 0

    def nbytes(self) -> int:
        return sum(getattr(self, c.name).nbytes for c in self._columns.values())
