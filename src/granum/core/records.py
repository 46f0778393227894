"""Records of arrays passed to compiled kernels by reference.

Kernels receive the scene's arrays bundled in one *record*, a Numba structure
reference: it travels as a single pointer, so passing it through many small
compiled functions costs nothing, and compiled code may replace one of its arrays
(the interaction storage grows inside the step loop). Python keeps the arrays in an
ordinary named tuple and converts with :meth:`RecordSpec.to_record` /
:meth:`RecordSpec.from_record`; both conversions are compiled and cached on disk.
"""

from __future__ import annotations

from collections import namedtuple

import numpy as np
from numba import types
from numba.experimental import structref
from numba.np import numpy_support

from granum._jit import call
from granum.kernels.codegen import load_module


@structref.register
class RecordType(types.StructRef):
    """Numba type of a record: a structure of named arrays."""

    def preprocess_fields(self, fields):
        return tuple((name, types.unliteral(t)) for name, t in fields)


class Record(structref.StructRefProxy):
    """Python handle of a record (only passed between Python and kernels)."""


structref.define_boxing(RecordType, Record)


class RecordSpec:
    """Field names and array types of one kind of record.

    Args:
        name: name of the record kind (also of the Python named tuple).
        fields: ``(field name, dtype, ndim)`` for every array.
    """

    def __init__(self, name: str, fields: list[tuple[str, str, int]]):
        self.names = [f[0] for f in fields]
        self.tuple = namedtuple(name, self.names)
        self.numba_type = RecordType([(n, types.Array(numpy_support.from_dtype(np.dtype(d)), nd, "C"))
                                      for n, d, nd in fields])
        args = ", ".join(self.names)
        src = [
            f'"""Generated record conversions for {name}; do not edit."""',
            "from numba.experimental import structref",
            "from granum._jit import jit",
            "from granum.core.records import SPECS",
            f"TYPE = SPECS[{name!r}].numba_type",
            "",
            "",
            "@jit",
            f"def to_record({args}):",
            "    r = structref.new(TYPE)",
        ]
        src += [f"    r.{n} = {n}" for n in self.names]
        src += ["    return r", "", "", "@jit", "def from_record(r):",
                "    return (" + ", ".join(f"r.{n}" for n in self.names) + ",)"]
        SPECS[name] = self
        self._module = load_module(f"record_{name}", "\n".join(src) + "\n")

    def to_record(self, values) -> Record:
        """A record holding the arrays of the named tuple ``values``."""
        return call(self._module.to_record, *values)

    def from_record(self, record: Record):
        """The arrays of ``record`` as a named tuple."""
        return self.tuple(*call(self._module.from_record, record))


SPECS: dict[str, RecordSpec] = {}
