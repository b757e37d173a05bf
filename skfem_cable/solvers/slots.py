"""The slots of a system's compiled step: its terms' kernels and its nonlinear constraints'
in order, each with its pack and its tangent positions, and the kernels' addresses.

A system's terms module (``solvers.compiled.system_module``) calls slot ``k`` as
``kernel(packs[k], indices[k], ev)`` (``cev`` for a constraint, ``contract``), through the
kernel's machine address held with the packs (``kernels.erased.address``): numba does not
link the kernels' code into the module, so LLVM does not optimise every kernel again in
every system's module, and the module depends on the kernels' numba types alone
(``FunctionType``), not on their code.  Each kernel is compiled (or read from its own
cache) for exactly the types the module calls it with; an edited kernel is recompiled by
its own cache's stamp (``kernels.cache``), and its new address is taken at the next run.
A Python part (a term's ``add`` hook, a constraint without kernel) is a ``PYTHON`` slot,
called back by the module (``numba.objmode``).
"""

import numba
import numpy as np

from ..core.contract import NO_INDEX
from ..kernels import erased

#: The slot of a Python part in the sequences of kernels given to the terms module.
PYTHON = "python"


def term_slots(lay, key):
    """``(functions, packs, indices)`` of the slots of the terms of ``lay`` in order (a
    term's kernels, or one ``PYTHON`` slot for an ``add`` hook, its pack the ``key`` of
    the ``PythonParts``, its index ``NO_INDEX``: the compiled code does not read it, and
    a term's own index, an array of any shape, would give the step a signature, and a
    compilation, per shape), and the Python terms ``{slot: (term, index)}``."""
    slots, python = [], {}
    for term, index in lay.body_terms + lay.load_terms:
        if term.add is not None:
            python[len(slots)] = (term, index)
        index = NO_INDEX if index is None or term.add is not None else index
        kernels = ((PYTHON, np.int64(key)),) if term.add is not None else term.kernels
        slots += [(function, pack, index) for function, pack in kernels]
    return tuple(zip(*slots)) if slots else ((), (), ()), python


def constraint_slots(system, lay, key):
    """The same for the nonlinear constraints of ``lay`` (a compiled ``kernel`` or a
    ``PYTHON`` slot), and the Python constraints ``{slot: k}``."""
    slots, python = [], {}
    for k in lay.nonlinear:
        kernel = getattr(system.constraints[k], "kernel", None)
        if kernel is None:
            python[len(slots)] = k
        function, pack = (PYTHON, np.int64(key)) if kernel is None else kernel
        slots.append((function, pack, lay.cindex[k]))
    return tuple(zip(*slots)) if slots else ((), (), ()), python


def _addresses(functions, packs, indices, evaluation):
    """The numba function types and the addresses of the kernels ``functions``, each
    compiled (or read from its cache) for its slot's pack and index, of the numba types
    ``packs[k]`` and ``indices[k]``, and the evaluation tuple of type ``evaluation``;
    ``PYTHON`` and 0 for a ``PYTHON`` slot."""
    kinds, references = [], []
    for k, kernel in enumerate(functions):
        if kernel is PYTHON:
            kinds.append(PYTHON)
            references.append(0)
            continue
        args = (packs[k], indices[k], evaluation)
        kernel.compile(args)
        signature = kernel.overloads[args].signature
        kinds.append(numba.types.FunctionType(signature))
        references.append(erased.address(kernel, signature))
    return tuple(kinds), tuple(references)


def addressed(terms, constraints, types):
    """The function types and the addresses of the kernels of the slots ``terms =
    (functions, ev)`` and ``constraints`` (``(cfunctions, cev)``; ``ev``, ``cev``: the
    numba types of the evaluation tuples): ``(kinds, ckinds), (references,
    creferences)``; ``types``: the numba type of ``(packs, indices, cpacks, cindices)``.
    The terms module reads ``(packs, indices, references, cpacks, cindices,
    creferences)`` from its address."""
    (functions, ev), (cfunctions, cev) = terms, constraints
    kinds, references = _addresses(functions, types[0], types[1], ev)
    ckinds, creferences = _addresses(cfunctions, types[2], types[3], cev)
    return (kinds, ckinds), (references, creferences)
