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

**Records that only Python makes.** The scene's and the contacts' records are made by Python
(:meth:`RecordSpec.to_record`) and held by it while any compiled code runs with them, so
compiled code need not count references to them at all: their type (:class:`UncountedRecordType`)
carries the same pointer without telling Numba that it is counted. Numba otherwise counts a
record in and out of every function that takes it -- two atomic operations per function and
record: 22 increments and as many decrements a step in a two-body scene, where the records and
the work area's pieces (:mod:`granum.kernels.scratch`) together took three quarters of the step
on a 2-core Xeon (``benchmarks/README.md``). No compiled code but ``to_record`` makes one
(``compiled_constructor`` refuses); a record compiled code returns to Python gets a reference of
its own when boxed, so returning one it was given is safe too (``to_record`` gives back the one
its new record started with).

Named tuples of arrays are no alternative: Numba passes them by value (every array
of the scene at every call) and loses writes made through their fields directly in a
``prange`` loop body (numba#7135).
"""

from __future__ import annotations

from collections import namedtuple

import numpy as np
from numba import types
from numba.core import cgutils
from numba.core.pythonapi import NativeValue
from numba.core.typing.templates import AttributeTemplate
from numba.experimental import structref
from numba.extending import box, infer_getattr, intrinsic, lower_getattr_generic, models, register_model, unbox
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


class UncountedRecordType(RecordType):
    """Numba type of a record that Python makes and holds while compiled code uses it (see the module docstring):
    the same structure reference as :class:`RecordType`, whose references compiled code does not count."""


@register_model(UncountedRecordType)
class _UncountedRecordModel(models.StructModel):
    """The structure reference's one member, the memory-info pointer, as a plain pointer: Numba's reference
    counting finds nothing to count in it."""

    def __init__(self, dmm, fe_type):
        super().__init__(dmm, fe_type, [("meminfo", types.voidptr)])


_MEMINFO = types.MemInfoPointer(types.voidptr)


def _meminfo_of(context, builder, typ, value):
    """The memory-info pointer of ``value``, a record of Numba type ``typ`` (the structure reference's one member;
    read through ``cgutils``' structure proxy, as Numba's extension examples do, not through the private helpers
    of ``numba.experimental.structref``)."""
    return cgutils.create_struct_proxy(typ)(context, builder, value=value).meminfo


@box(UncountedRecordType)
def _box_uncounted(typ, val, c):
    """The Python handle of a record compiled code returns, holding a reference of its own (counted here: the
    handle takes over the reference it is given, and compiled code owns none); ``to_record``, whose new record
    starts with one, gives that one back."""
    meminfo = _meminfo_of(c.context, c.builder, typ, val)
    c.context.nrt.incref(c.builder, _MEMINFO, meminfo)
    boxed_meminfo = c.box(_MEMINFO, meminfo)
    ctor = c.pyapi.unserialize(c.pyapi.serialize_object(Record._numba_box_))
    ty = c.pyapi.unserialize(c.pyapi.serialize_object(typ))
    res = c.pyapi.call_function_objargs(ctor, [ty, boxed_meminfo])
    for obj in (ctor, ty, boxed_meminfo):
        c.pyapi.decref(obj)
    return res


@unbox(UncountedRecordType)
def _unbox_uncounted(typ, obj, c):
    """The record of a Python handle, borrowed: the reference that unboxing the memory-info takes is given back at
    once (the caller holds the handle during the call)."""
    meminfo_obj = c.pyapi.object_getattr_string(obj, "_meminfo")
    meminfo = c.unbox(_MEMINFO, meminfo_obj).value
    c.context.nrt.decref(c.builder, _MEMINFO, meminfo)
    c.pyapi.decref(meminfo_obj)
    record = cgutils.create_struct_proxy(typ)(c.context, c.builder)
    record.meminfo = meminfo
    return NativeValue(record._getvalue())


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
        meminfo = _meminfo_of(context, builder, sig.args[0], args[0])
        return builder.bitcast(context.nrt.meminfo_data(builder, meminfo), cgutils.voidptr_t)

    return RawRecordType(record)(record), codegen


class RecordSpec:
    """Field names and array types of one kind of record.

    Args:
        name: name of the record kind (also of the Python named tuple).
        fields: ``(field name, dtype, ndim)`` for every array.
        transient: fields that hold no state (work areas whose contents a step does not read from the step
            before): checkpoints leave them out, and a record loaded from one gets them as a new record has
            them. The named tuple's class lists them in ``_transient``.
        counted: False for a record that only Python makes (:meth:`to_record`) and holds while compiled code
            uses it: its type is an :class:`UncountedRecordType`.
    """

    def __init__(self, name: str, fields: list[tuple[str, str, int]], transient: tuple[str, ...] = (),
                 counted: bool = True):
        self.names = [f[0] for f in fields]
        self.tuple = namedtuple(name, self.names)
        self.tuple._transient = frozenset(transient)
        self.counted = counted
        record_type = RecordType if counted else UncountedRecordType
        self.numba_type = record_type([(n, types.Array(numpy_support.from_dtype(np.dtype(d)), nd, "C"))
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

    def compiled_constructor(self):
        """The constructor for compiled code: ``make(*arrays)``, a record of the arrays given in field order."""
        if not self.counted:
            raise TypeError(f"{self.tuple.__name__} records are made by Python only (uncounted in compiled code)")
        return self._module.to_record

    def to_record(self, values) -> Record:
        """A record holding the arrays of the named tuple ``values``."""
        record = call(self._module.to_record, *values)
        if not self.counted:
            record._meminfo.release()   # the reference the new record started with (see _box_uncounted)
        return record

    def from_record(self, record: Record):
        """The arrays of ``record`` as a named tuple."""
        return self.tuple(*call(self._module.from_record, record))


SPECS: dict[str, RecordSpec] = {}
