"""A compiled value behind an address: how the one compiled Newton iteration reaches the
terms of any system.

The Newton step (``kernels.step``) is compiled once per machine; what differs from system
to system, its terms' kernels and their packed data, is reached through two compiled
functions of one signature (``solvers.compiled``: ``evaluate(blob, ev)`` and
``constrain(blob, cev)``, numba first-class functions) and one integer, ``blob``: the
address of a buffer holding the system's tuple of packs (``hold``), which those functions
read back with its type (``held``).  The step never sees the packs' types, so it is not
compiled again for each system; the two functions are, and they are small.  The two
functions reach the step as their machine addresses (``address``) and become callable
there (``function``): numba's own conversion of a compiled function into a first-class one
calls back into Python at every call of the step (tens of microseconds).

``hold`` keeps a reference to every array of the value (numba's reference counts), so the
buffer stays valid whatever Python does with its own references; ``release`` gives them
back.  Interpreted (``numba.config.DISABLE_JIT``, ``GeneralizedAlpha(compiled=False)``),
the same three calls keep the value in a dictionary under the address.
"""

from numba import types
from numba.core import cgutils
from numba.core.registry import cpu_target
from numba.experimental.function_type import _get_jit_address, _get_wrapper_address
from numba.extending import intrinsic, overload

#: The values held by address when the functions run interpreted.
_HELD = {}


def size_of(kind):
    """Bytes of a value of the numba type ``kind`` in compiled code (its buffer's size)."""
    context = cpu_target.target_context
    return context.get_abi_sizeof(context.get_value_type(kind))


def hold(address, value):
    """Store ``value`` at ``address`` (a buffer of ``size_of`` its type), keeping its
    arrays alive until ``release``."""
    _HELD[address] = value


def held(address, kind):
    """The value of type ``kind`` that ``hold`` stored at ``address``."""
    return _HELD[address]


def release(address, kind):
    """Give back what ``hold`` kept of the value of type ``kind`` at ``address``."""
    _HELD.pop(address, None)


def address(function, signature):
    """The addresses ``(jit, c)`` of the compiled ``function`` of ``signature`` (numba's
    calling convention and its C wrapper), for ``function`` in compiled code; ``function``
    itself if it is Python (interpreted)."""
    if getattr(function, "overloads", None) is None:
        return function
    return _get_jit_address(function, signature), _get_wrapper_address(function, signature)


def function(reference, kind):
    """The function of ``reference`` (``address``), of the numba ``FunctionType``
    ``kind``."""
    return reference


def _pointer(builder, context, address, kind):
    return builder.inttoptr(address, context.get_value_type(kind).as_pointer())


@intrinsic
def _store(typingctx, address, value):
    def codegen(context, builder, signature, args):
        context.nrt.incref(builder, value, args[1])
        builder.store(args[1], _pointer(builder, context, args[0], value))
    return types.void(types.int64, value), codegen


def _loader(keep):
    """An intrinsic loading the value of a type given as a ``TypeRef`` from an address: a
    new reference (``keep``: the buffer keeps its own) or the buffer's (given back)."""
    @intrinsic
    def load(typingctx, address, kind):
        value = kind.instance_type

        def codegen(context, builder, signature, args):
            loaded = builder.load(_pointer(builder, context, args[0], value))
            if keep:
                context.nrt.incref(builder, value, loaded)
            return loaded
        return value(types.int64, kind), codegen
    return load


_load, _take = _loader(True), _loader(False)


@overload(hold, jit_options={"cache": True})
def _hold(address, value):
    return lambda address, value: _store(address, value)


@overload(held, inline="always", jit_options={"cache": True})
def _held(address, kind):
    return lambda address, kind: _load(address, kind)


@overload(release, jit_options={"cache": True})
def _release(address, kind):
    def impl(address, kind):
        _take(address, kind)  # the caller drops the reference: the hold's
    return impl


@intrinsic
def _function(typingctx, reference, kind):
    value = kind.instance_type

    def codegen(context, builder, signature, args):
        jit, c = cgutils.unpack_tuple(builder, args[0])
        made = cgutils.create_struct_proxy(value)(context, builder)
        pointer = context.get_value_type(types.voidptr)
        made.jit_addr = builder.inttoptr(jit, pointer)
        made.c_addr = builder.inttoptr(c, pointer)
        made.py_addr = cgutils.get_null_value(pointer)
        return made._getvalue()
    return value(reference, kind), codegen


@overload(function, inline="always", jit_options={"cache": True})
def _function_of(reference, kind):
    return lambda reference, kind: _function(reference, kind)
