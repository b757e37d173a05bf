"""A compiled value behind an address, and compiled functions called through theirs: how
the one compiled Newton iteration reaches the terms of any system, and how a system's
terms reach their kernels.

The Newton step (``kernels.step``) is compiled once per machine; what differs from system
to system, its terms' kernels and their packed data, is reached through two compiled
functions of one signature (``solvers.compiled``: ``evaluate(blob, ev)`` and
``constrain(blob, cev)``, numba first-class functions) and one integer, ``blob``: the
address of a buffer holding the system's tuple of packs (``hold``), which those functions
read back with its type (``held``).  The step never sees the packs' types, so it is not
compiled again for each system; the two functions are, and they are small: they call the
kernels through the kernels' addresses too, held with the packs, so that numba does not
link the kernels' code into them (LLVM would optimise it again in every system's module).
A compiled function reaches its caller as its machine address (``address``: numba's
calling convention, that of a direct call) and becomes callable there (``function``):
numba's own conversion of a compiled function into a first-class one calls back into
Python at every call of the step (tens of microseconds).

``hold`` keeps a reference to every array of the value (numba's reference counts), so the
buffer stays valid whatever Python does with its own references; ``release`` gives them
back.  From Python, ``keep`` and ``drop`` do the same leaf by leaf (an array or a scalar
at its offset in the buffer), each leaf by a function compiled once per leaf type: no
function is compiled for the type of each system's tuple (numba's unboxing of a tuple of
arrays is about half a second of compilation per type).  Interpreted
(``numba.config.DISABLE_JIT``, ``GeneralizedAlpha(compiled=False)``), the calls keep the
value in a dictionary under the address too, and ``function`` gives back the compiled
function of an address (the kernels stay compiled) or the Python function of the number
``address`` gave in its place.
"""

import functools

from llvmlite import ir
from numba import njit, types
from numba.core import cgutils
from numba.core.registry import cpu_target
from numba.experimental.function_type import _get_jit_address
from numba.extending import lower_builtin, type_callable

#: The values held by address when the functions run interpreted.
_HELD = {}

#: The compiled functions of the addresses ``address`` gave, for ``function`` interpreted
#: (it also keeps them, and so their machine code, alive).
_ADDRESSED = {}


def _per_type(make):
    """``make(kind)`` made once per numba type ``kind``, looked up by its identity (the
    type is kept, so its identity stays its own; numba interns its types, and an equal
    type of another identity is looked up by its hash): a numba type's hash walks the
    whole type, 5-10 us for the E-sail rig's held arguments at every look-up in a
    ``functools.cache``."""
    made = functools.cache(make)
    by_id = {}

    @functools.wraps(make)
    def once(kind):
        found = by_id.get(id(kind))
        if found is None:
            found = by_id[id(kind)] = (kind, made(kind))
        return found[1]
    return once


@_per_type
def size_of(kind):
    """Bytes of a value of the numba type ``kind`` in compiled code (its buffer's size;
    once per type: LLVM's layout of the E-sail rig's held arguments took 0.1 ms, twice at
    every run's start)."""
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


@_per_type
def _leaves(kind):
    """``(offset, type)`` of the leaves of a value of the numba type ``kind`` (its members
    that are not tuples, depth first) in its buffer, as LLVM lays out numba's value."""
    if not isinstance(kind, types.BaseTuple):
        return ((0, kind),)
    context = cpu_target.target_context
    layout, data = context.get_value_type(kind), context.target_data
    found = []
    for k, member in enumerate(kind):
        at = (k * layout.element.get_abi_size(data) if isinstance(layout, ir.ArrayType)
              else layout.get_element_offset(data, k))
        found += [(at + offset, leaf) for offset, leaf in _leaves(member)]
    return tuple(found)


@_per_type
def _counted(kind):
    """The leaves of ``_leaves(kind)`` that hold references (the arrays)."""
    models = cpu_target.target_context.data_model_manager
    return tuple((at, leaf) for at, leaf in _leaves(kind) if models[leaf].contains_nrt_meminfo())


@_per_type
def _tuples(kind):
    """Which members of the numba tuple type ``kind`` are tuples."""
    return tuple(isinstance(member, types.BaseTuple) for member in kind)


def _values(kind, value):
    """The leaves of ``value``, of the numba type ``kind``, in the order of ``_leaves``."""
    if not isinstance(kind, types.BaseTuple):
        return [value]
    leaves = []
    for member, tuple_, item in zip(kind, _tuples(kind), value):
        if tuple_:
            leaves += _values(member, item)
        else:
            leaves.append(item)
    return leaves


@njit(cache=True)
def _put(address, leaf):
    hold(address, leaf)


@njit(cache=True)
def _take(address, kind):
    release(address, kind)


def keep(address, value, kind):
    """From Python: ``hold`` ``value`` of the numba type ``kind`` at ``address`` (a buffer
    of ``size_of(kind)``), leaf by leaf; ``drop`` gives it back."""
    for (offset, _), leaf in zip(_leaves(kind), _values(kind, value)):
        _put(address + offset, leaf)
    hold(address, value)


def entry(function, signature):
    """The machine code of the numba dispatcher ``function`` for the argument types
    ``signature`` (compiled for them, or read from the cache, first), behind the unboxing
    of its arguments alone: a dispatcher types every argument at every call."""
    function.compile(signature)
    return function.overloads[signature].entry_point


@_per_type
def _taker(leaf):
    """``_take``'s ``entry`` for a leaf of the numba type ``leaf``: the dispatcher would
    type its second argument, a numba type, at every call (a ``TypeRef`` made and hashed:
    5 us a leaf, 0.6 ms at every start of a run of the E-sail rig)."""
    return entry(_take, (types.int64, types.TypeRef(leaf)))


def drop(address, kind):
    """From Python: ``release`` the value of the numba type ``kind`` that ``keep`` held at
    ``address``, leaf by leaf (those with references: the arrays)."""
    for offset, leaf in _counted(kind):
        _taker(leaf)(address + offset, leaf)
    release(address, kind)


def address(function, signature):
    """The address of the compiled ``function`` of ``signature`` (numba's calling
    convention; compiled for it first, or read from the cache), for ``function`` in
    compiled code; a number standing for it if it is Python (interpreted: ``function``
    gives it back)."""
    if getattr(function, "overloads", None) is None:
        _ADDRESSED[id(function)] = function
        return id(function)
    return _jit_address(function, signature)


@functools.cache
def _jit_address(function, signature):
    """``address`` of a compiled ``function``, once per function and signature (its
    machine code stays where it is while the process lives: ``_ADDRESSED`` keeps it)."""
    jit = _get_jit_address(function, signature)
    _ADDRESSED[jit] = function
    return jit


def function(reference, kind):
    """The function of ``reference`` (``address``), of the numba ``FunctionType``
    ``kind``."""
    return _ADDRESSED.get(reference, reference)


def _pointer(builder, context, address, kind):
    return builder.inttoptr(address, context.get_value_type(kind).as_pointer())


# In compiled code the four calls are typed and lowered in place (numba's low-level
# extension API): an ``overload`` would be a function compiled for every type it meets, a
# second or more of compilation for every system's terms.

def _typer(result):
    """A typer of a call ``(address, value or kind)`` whose result type is ``result(second
    argument's type)``, for an integer address."""
    def typing(context):
        def typer(address, second):
            if isinstance(address, types.Integer):
                return result(second)
        return typer
    return typing


def _instance(kind):
    return kind.instance_type if isinstance(kind, types.TypeRef) else None


type_callable(hold)(_typer(lambda value: types.none))
type_callable(held)(_typer(_instance))
type_callable(release)(_typer(lambda kind: types.none if _instance(kind) else None))
type_callable(function)(_typer(
    lambda kind: _instance(kind) if isinstance(_instance(kind), types.FunctionType) else None))


@lower_builtin(hold, types.Integer, types.Any)
def _lower_hold(context, builder, signature, args):
    value = signature.args[1]
    context.nrt.incref(builder, value, args[1])
    builder.store(args[1], _pointer(builder, context, args[0], value))
    return context.get_dummy_value()


@lower_builtin(held, types.Integer, types.TypeRef)
def _lower_held(context, builder, signature, args):
    loaded = builder.load(_pointer(builder, context, args[0], signature.return_type))
    if context.enable_nrt:  # a new reference (borrowed where compiled without counts)
        context.nrt.incref(builder, signature.return_type, loaded)
    return loaded


@lower_builtin(release, types.Integer, types.TypeRef)
def _lower_release(context, builder, signature, args):
    value = signature.args[1].instance_type
    loaded = builder.load(_pointer(builder, context, args[0], value))
    context.nrt.decref(builder, value, loaded)  # the hold's reference
    return context.get_dummy_value()


@lower_builtin(function, types.Integer, types.TypeRef)
def _lower_function(context, builder, signature, args):
    made = cgutils.create_struct_proxy(signature.return_type)(context, builder)
    pointer = context.get_value_type(types.voidptr)
    made.jit_addr = builder.inttoptr(args[0], pointer)
    made.c_addr = cgutils.get_null_value(pointer)  # called at jit_addr alone
    made.py_addr = cgutils.get_null_value(pointer)
    return made._getvalue()
