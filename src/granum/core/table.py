"""Growable structure-of-arrays tables.

Every piece of per-entity state in granum (bodies, the per-kind shape tables, ...)
lives in a :class:`Table`: a set of named NumPy columns that share one row count.
Columns are allocated with spare capacity and grown geometrically, so appending
rows is amortised O(1) and the kernels always see plain contiguous arrays. Spare rows
are zero pages the operating system has not handed out yet (``np.zeros``): a new row
gets its defaults when it is appended, so capacity costs no resident memory.

A *lazy* column (rarely used state such as permanent forces or clump-member offsets)
is not allocated until Python code first reads it as an attribute of the table;
until then :meth:`Table.stored` gives kernels an array of 0 rows, which they read as
"the default for every row".

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
        lazy: allocated on first use (see the module docstring).
    """

    name: str
    tail: tuple = ()
    dtype: str = "f8"
    default: object = 0
    doc: str = ""
    lazy: bool = False


class Table:
    """A set of NumPy columns sharing one row count, with geometric growth.

    ``generation`` counts the column arrays set on the table (growth, a lazy column's first use, a column
    replaced): a record of the arrays built when it had the same value still holds them
    (:meth:`granum.core.scene.Scene.arrays`)."""

    def __init__(self, columns: tuple[Column, ...], capacity: int = 8):
        self.generation = 0
        #: called (without arguments) whenever a column array is set, before it is: its owner's record of the old
        #: arrays must go (:meth:`granum.core.scene.Scene.forget_record`); None: nothing to call
        self.on_replace = None
        self._columns = {c.name: c for c in columns}
        self.count = 0
        self._capacity = 0
        for c in columns:
            if not c.lazy:
                setattr(self, c.name, np.zeros((0,) + c.tail, dtype=c.dtype))
        self._grow(max(capacity, 1))

    def __setattr__(self, name: str, value) -> None:
        if name in self.__dict__.get("_columns", ()):
            object.__setattr__(self, "generation", self.generation + 1)
            if self.on_replace is not None:
                self.on_replace()
        object.__setattr__(self, name, value)

    def __getattr__(self, name: str):
        # reached only for attributes not set yet: a lazy column's first use allocates it
        c = self.__dict__.get("_columns", {}).get(name)
        if c is None or not c.lazy:
            raise AttributeError(f"{type(self).__name__} has no column {name!r}")
        a = np.zeros((self._capacity,) + c.tail, dtype=c.dtype)
        a[: self.count] = c.default
        setattr(self, name, a)
        return a

    @property
    def columns(self) -> tuple[Column, ...]:
        return tuple(self._columns.values())

    def allocated(self, name: str) -> bool:
        """Whether column ``name`` holds an array of the table's capacity (lazy ones: once used)."""
        return name in self.__dict__

    def allocate(self, *names: str) -> None:
        """Allocate the lazy columns ``names`` now (their rows hold the defaults)."""
        for name in names:
            getattr(self, name)

    def stored(self, name: str) -> np.ndarray:
        """Column ``name`` as stored, without allocating it: a lazy column not used yet has 0 rows."""
        a = self.__dict__.get(name)
        if a is None:
            c = self._columns[name]
            a = np.zeros((0,) + c.tail, dtype=c.dtype)
        return a

    def _allocated_columns(self):
        return [c for c in self._columns.values() if c.name in self.__dict__]

    def _grow(self, capacity: int) -> None:
        for c in self._allocated_columns():
            old = getattr(self, c.name)
            new = np.zeros((capacity,) + c.tail, dtype=c.dtype)
            new[: self.count] = old[: self.count]
            setattr(self, c.name, new)
        self._capacity = capacity

    def _add_rows(self, k: int) -> int:
        """Add ``k`` rows, their values left as they are; return the index of the first."""
        first = self.count
        if first + k > self._capacity:
            # at least doubled, to a power of two: rows appended in one go (a list of bodies) leave room too
            self._grow(max(2 * self._capacity, 1 << (first + k - 1).bit_length()))
        self.count += k
        return first

    def append_rows(self, k: int = 1) -> int:
        """Add ``k`` rows holding the column defaults; return the index of the first."""
        first = self._add_rows(k)
        for c in self._allocated_columns():
            getattr(self, c.name)[first:first + k] = c.default
        return first

    def append_copy(self, src: Table, src_rows, k: int = 1) -> int:
        """Add ``k`` rows holding ``src[src_rows]`` (a row index when ``k`` is 1, else an index array or slice of
        ``k`` rows), as :meth:`append_rows` and :meth:`copy_rows` would, without writing the defaults first;
        return the index of the first."""
        first = self._add_rows(k)
        self.copy_rows(src, src_rows, first if k == 1 and not isinstance(src_rows, slice | np.ndarray)
                       else slice(first, first + k))
        return first

    def copy_rows(self, src: Table, src_rows, dst_rows) -> None:
        """Copy every column of ``src[src_rows]`` into rows ``dst_rows`` of this table: a row index each, or
        index arrays of one length (n,) int (one NumPy copy a column for all the rows). A lazy column this table
        has not allocated stays so while the rows copied hold its default (the source's may be allocated for other
        rows: detached bodies share one table, and one aspherical body among them must not give every later scene
        its angular momenta)."""
        mine, theirs = self.__dict__, src.__dict__   # the allocated columns (:meth:`allocated`), looked up once
        for c in self._columns.values():
            a = theirs.get(c.name)
            if a is not None:
                values = a[src_rows]
                if c.lazy and c.name not in mine and bool(np.all(values == np.asarray(c.default, dtype=c.dtype))):
                    continue
                getattr(self, c.name)[dst_rows] = values
            elif c.name in mine:
                mine[c.name][dst_rows] = c.default

    def reset_rows(self, rows) -> None:
        """Put the column defaults back into rows ``rows`` (a row index or an index array (n,) int), for reusing
        them."""
        for c in self._allocated_columns():
            getattr(self, c.name)[rows] = c.default

    def view(self, name: str) -> np.ndarray:
        """The live rows ``[0, count)`` of column ``name``."""
        return getattr(self, name)[: self.count]

    def clear(self) -> None:
        """Remove all rows (capacity is kept)."""
        self.count = 0

    def nbytes(self) -> int:
        return sum(getattr(self, c.name).nbytes for c in self._allocated_columns())
