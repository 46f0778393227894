"""Values that kernels are compiled for: the value is part of the argument's Numba type.

A :class:`Static` passed to a compiled function makes Numba compile that function for
its value, as it does for each distinct argument type, and the functions below it see
the value while they are compiled: an ``@overload`` can choose its implementation by it
(:mod:`granum.kernels.dispatch` compiles only the functors an engine lists, the
collider only the broad phase of its kind of cell). At run time the argument is an
empty pointer. Values are tuples of strings, integers and booleans, which name the
compiled variant in the disk cache.
"""

from __future__ import annotations

from numba import types
from numba.core import cgutils
from numba.extending import NativeValue, models, register_model, typeof_impl, unbox

from granum._jit import overload


class Static:
    """A compile-time value for kernels (a hashable tuple)."""

    __slots__ = ("value",)

    def __init__(self, value: tuple):
        if not isinstance(value, tuple):
            raise TypeError(f"a static value is a tuple, not {type(value).__name__}")
        hash(value)
        self.value = value

    def __repr__(self):
        return f"Static{self.value!r}"


class StaticType(types.Type):
    """Numba type of a :class:`Static`: it holds the value."""

    def __init__(self, value: tuple):
        self.value = value
        super().__init__(name=f"Static{value!r}")


def static_value(typ, kind: str):
    """The value of ``typ`` if it is a :class:`StaticType` whose value starts with ``kind``, else None."""
    if isinstance(typ, StaticType) and typ.value[:1] == (kind,):
        return typ.value
    return None


@typeof_impl.register(Static)
def _typeof_static(value, context):
    return StaticType(value.value)


register_model(StaticType)(models.OpaqueModel)


@unbox(StaticType)
def _unbox_static(typ, obj, c):
    return NativeValue(cgutils.get_null_value(c.context.get_value_type(typ)))


def static_switch(stub, kind: str, when_true, when_false) -> None:
    """Let compiled code call ``stub(flag, *args)`` with a static ``(kind, bool)`` flag: the call compiles to
    ``when_true(*args)`` or ``when_false(*args)`` by the flag's value, and the other function is not compiled.
    ``stub`` is a Python function with the call's signature that raises if Python calls it."""

    @overload(stub)
    def choose(flag, *args):
        value = static_value(flag, kind)
        if value is None:
            return None
        target = when_true if value[1] else when_false
        return lambda flag, *args: target(*args)


def static_bool(flag):
    """The boolean of a static ``(kind, bool)`` flag (compiled code only), a constant the compiler folds: a branch
    on it leaves the machine code (the functions it calls are compiled all the same; :func:`static_switch` leaves
    them out). ``flag`` stands for itself; Python never calls this."""
    raise TypeError("static_bool is called from compiled kernels only")


@overload(static_bool)
def _static_bool(flag):
    if isinstance(flag, StaticType) and len(flag.value) == 2 and isinstance(flag.value[1], bool):
        value = flag.value[1]
        return lambda flag: value
    return None
