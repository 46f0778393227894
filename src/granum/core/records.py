"""Records of arrays passed to compiled kernels by reference.

Kernels receive the scene's arrays bundled in one *record*, a Numba structure
reference: it travels as a single pointer, and compiled code may replace one of its
arrays (the interaction storage grows inside the step loop). Python keeps the arrays
in an ordinary named tuple and converts with :meth:`RecordSpec.to_record` /
:meth:`RecordSpec.from_record`; both conversions are compiled and cached on disk.

**Raw views for hot loops.** A record is reference counted, and so is every array
read from it: compiled code updates those counters -- atomic operations -- each time
a record is passed to a function or a field is read. In the per-contact loops that
made two thirds of the run time, and with two threads the counters' cache lines
bounced between the cores, so a step got slower with ``-j2`` than with ``-j1``.
Hot loops therefore work on :func:`raw` views: a plain pointer to the record's
fields, whose arrays come out *borrowed* (:func:`borrow`: no memory-info pointer), so
no reference is ever counted. A raw view is valid while its record is alive and
none of the record's arrays is replaced: stages take it from their own arguments
(kept alive by their caller) after the last replacement.

Named tuples of arrays are no alternative: Numba passes them by value (every array
of the scene at every call) and loses writes made through their fields directly in a
``prange`` loop body (numba#7135).
"""

from __future__ import annotations

from collections import namedtuple

import numpy as np
from numba import types
from numba.core import cgutils
from numba.core.typing.templates import AttributeTemplate
from numba.experimental import structref
from numba.extending import infer_getattr, intrinsic, lower_getattr_generic, models, register_model
from numba.np import numpy_support

from granum._codegen import load_module
from granum._jit import call


@structref.register
class RecordType(types.StructRef):
    """Numba type of a record: a structure of named arrays."""

    def preprocess_fields(self, fields):
        return tuple((name, types.unliteral(t)) for name, t in fields)


class Record(structref.StructRefProxy):
    """Python handle of a record (only passed between Python and kernels)."""


structref.define_boxing(RecordType, Record)


def _borrowed(context, builder, ty, value):
    """LLVM value of ``value`` (Numba type ``ty``) with the memory-info pointer of every array cleared."""
    if isinstance(ty, types.Array):
        ary = context.make_array(ty)(context, builder, value=value)
        ary.meminfo = cgutils.get_null_value(ary.meminfo.type)
        ary.parent = cgutils.get_null_value(ary.parent.type)
        return ary._getvalue()
    if isinstance(ty, types.BaseTuple):
        for k, t in enumerate(ty):
            value = builder.insert_value(value, _borrowed(context, builder, t, builder.extract_value(value, k)), k)
    return value


@intrinsic
def borrow(typingctx, a):
    """``a`` -- an array, or a tuple of arrays, scalars and tuples -- without ownership of its arrays
    (compiled code only): same data, shapes and strides, no memory-info pointers, so reference
    counting does nothing. Whoever owns the arrays must keep them alive while the result is used."""

    def codegen(context, builder, sig, args):
        return _borrowed(context, builder, sig.args[0], args[0])

    return a(a), codegen


class RawRecordType(types.Type):
    """Numba type of a raw view of a record of type ``record_type`` (see the module docstring)."""

    def __init__(self, record_type: RecordType):
        self.record_type = record_type
        super().__init__(name=f"Raw[{record_type.name}]")


register_model(RawRecordType)(models.OpaqueModel)


@infer_getattr
class _RawRecordAttributes(AttributeTemplate):
    key = RawRecordType

    def generic_resolve(self, typ, attr):
        return typ.record_type.field_dict.get(attr)


@lower_getattr_generic(RawRecordType)
def _raw_getattr(context, builder, typ, value, attr):
    payload = typ.record_type.get_data_type()
    ptr = builder.bitcast(value, context.data_model_manager[payload].get_value_type().as_pointer())
    data = cgutils.create_struct_proxy(payload)(context, builder, ref=ptr)
    field = builder.load(data._get_ptr_by_name(attr))
    # the fields do not change while a raw view is in use (its contract), so LLVM may keep them in
    # registers across the stores into the arrays instead of reloading them after each store
    field.set_metadata("invariant.load", builder.module.add_metadata([]))
    return _borrowed(context, builder, typ.record_type.field_dict[attr], field)


@intrinsic
def raw(typingctx, record):
    """Raw view of ``record`` (compiled code only): a pointer to its fields, read as borrowed arrays."""
    if not isinstance(record, RecordType):
        return None

    def codegen(context, builder, sig, args):
        ptr = structref._Utils(context, builder, sig.args[0]).get_data_pointer(args[0])
        return builder.bitcast(ptr, cgutils.voidptr_t)

    return RawRecordType(record)(record), codegen


class RecordSpec:
    """Field names and array types of one kind of record.

    Args:
        name: name of the record kind (also of the Python named tuple).
        fields: ``(field name, dtype, ndim)`` for every array, or ``(field name, dtype, ndim, layout)`` with the
            array's memory order, ``"C"`` (the default: row after row), ``"F"`` (column after column) or ``"CF"``
            (either, for one field: a record has a Numba type for each, and code compiles for the one it gets).
        transient: fields that hold no state (work areas whose contents a step does not read from the step
            before): checkpoints leave them out, and a record loaded from one gets them as a new record has
            them. The named tuple's class lists them in ``_transient``.
    """

    def __init__(self, name: str, fields: list[tuple[str, str, int]], transient: tuple[str, ...] = ()):
        self.names = [f[0] for f in fields]
        #: per field, the memory order its arrays have: "C", "F", or "CF" (either: the record has a type for each)
        self.layouts = {f[0]: f[3] if len(f) > 3 else "C" for f in fields}
        either = [n for n, lay in self.layouts.items() if lay == "CF"]
        if len(either) > 1:
            raise ValueError(f"record {name}: at most one field may be stored in either order, not {either}")
        #: the field stored in either order (None: none)
        self.either = either[0] if either else None
        self.tuple = namedtuple(name, self.names)
        self.tuple._transient = frozenset(transient)
        #: the Numba type of a record, by the memory order of the field ``either`` ("C" only when there is none)
        self.numba_types = {order: RecordType([(f[0], types.Array(numpy_support.from_dtype(np.dtype(f[1])), f[2],
                                                                  order if f[0] == self.either else
                                                                  self.layouts[f[0]])) for f in fields])
                            for order in (("C", "F") if self.either else ("C",))}
        self.numba_type = self.numba_types["C"]
        args = ", ".join(self.names)
        src = [
            f'"""Generated record conversions for {name}; do not edit."""',
            "from numba.experimental import structref",
            "from granum._jit import jit",
            "from granum.core.records import SPECS",
        ]
        for order in self.numba_types:
            src += [f"TYPE_{order} = SPECS[{name!r}].numba_types[{order!r}]", "", "", "@jit",
                    f"def to_record_{order}({args}):", f"    r = structref.new(TYPE_{order})"]
            src += [f"    r.{n} = {n}" for n in self.names]
            src += ["    return r", "", ""]
        src += ["@jit", "def from_record(r):", "    return (" + ", ".join(f"r.{n}" for n in self.names) + ",)"]
        SPECS[name] = self
        self._module = load_module(f"record_{name}", "\n".join(src) + "\n")

    def compiled_constructor(self):
        """The constructor for compiled code: ``make(*arrays)``, a record of the arrays given in field order (the
        field ``either`` in C order)."""
        return self._module.to_record_C

    def to_record(self, values) -> Record:
        """A record holding the arrays of the named tuple ``values`` (typed by the order of the field ``either``)."""
        order = "C"
        if self.either is not None:
            a = getattr(values, self.either)
            order = "F" if a.flags.f_contiguous and not a.flags.c_contiguous else "C"
        return call(getattr(self._module, f"to_record_{order}"), *values)

    def from_record(self, record: Record):
        """The arrays of ``record`` as a named tuple."""
        return self.tuple(*call(self._module.from_record, record))


SPECS: dict[str, RecordSpec] = {}
