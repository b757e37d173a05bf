"""Template of the element loop of the laws' kernels, in chunks that run on threads.

The elements are cut into chunks of ``CHUNK`` consecutive elements, whatever the number of
threads.  Two consecutive elements of a cable share a node (their force and tangent
entries add into the same places); elements two apart, and elements of different cables,
share none.  So the loop runs every chunk but its first element (on numba's threads in
``kernel_parallel``, one after the other in ``kernel``: the chunks write to different
places), then the first elements of the chunks, one after the other.  Each chunk sums its
energies apart, the first elements theirs, and these sums are added in order at the end.
Every sum is therefore taken in the same order on one thread or many: the results are
bit-identical whatever the thread count (``tests/test_mission.py``).

This module is a template: ``laws.codegen.loop`` copies ``kernel`` twice into one module
for every law, as ``kernel`` and as ``kernel_parallel`` (compiled with ``parallel=True``,
where ``prange`` runs on threads), and compiles them there once per machine.  They are the
laws' hooks of the evaluation contract (``contract.Term.kernels``); ``Cable.bind`` takes
the second when the system runs on more than one thread (``linalg.thread_count``).  Each
calls the ``span`` of a law's module (the template's loop over a range of elements, with
the law's point functions) at the address its pack ends with (``laws.codegen.hook``),
compiled for the one signature ``SPAN``: compiled in each law's module around its
``span``, the loop was 30 compilations of a cold test run (22 s of CPU), LLVM optimising
the linked ``span`` again in each.  ``kernel`` is one function: its parts as
functions that numba inlines (``inline="always"``) cost a fifth more compile time, numba
typing an inlined function again at each inlining.  ``span`` receives its bounds as
``int64`` only (``np.int64`` of the constants): numba compiles a function once per literal
value of a constant argument, and each law's loop compiled twice cost the test suite about
190 s of CPU.
"""

import numpy as np
from numba import prange, types

#: Elements per chunk (fixed: the order of every sum does not depend on the threads).
CHUNK = 64

_VECTOR = types.float64[::1]

#: The signature of a template's ``span(first, last, step, state, elements, law, out,
#: coef, acc)`` as ``kernel`` calls it, the same for every law and template (the tables
#: ``(edofs, Sx, Sxx, w, h)``, the law's values and whether it damps, the packed
#: evaluation's arrays): ``kernel`` calls the law's ``span`` at the address its pack
#: ends with, compiled for it (``laws.codegen.hook``).
SPAN = types.none(
    types.int64, types.int64, types.int64, types.UniTuple(_VECTOR, 2),
    types.Tuple((types.int64[:, ::1], types.float64[:, :, ::1], types.float64[:, :, ::1],
                 types.float64[:, ::1], _VECTOR)),
    types.Tuple((_VECTOR, types.boolean)),
    types.Tuple((_VECTOR, _VECTOR, _VECTOR, types.int64[:, :, ::1], _VECTOR, _VECTOR)),
    types.UniTuple(types.float64, 2), _VECTOR)


def kernel(pack, index, ev):
    """The law's compiled hook of the evaluation contract (``contract.Term.kernels``): add
    the forces of all elements to ``f`` and their tangents into ``data`` for the packed
    evaluation ``ev``; ``pack = (edofs, Sx, Sxx, w, h, ..., prm, damped, span)`` (the
    template's tables, ``elements`` of ``kernels.cable.span`` or
    ``kernels.assumed_strain.span``, then the law's values, and the address of the law's
    ``span``, ``kernels.erased.address`` of ``SPAN``), the tangent entries at ``index``,
    int (ne, 3 nf, 3 nf).

    The chunks but their first elements, each chunk's energies into its row of ``acc``,
    then the first elements of the chunks after the first into the last row (none with
    one chunk: ``span`` is not called, its scratch arrays, some twenty, cost the E-sail rig
    0.35 us per evaluation), then the rows added in order."""
    q, v, s, f, f_ext, fd, data, energy, power = ev
    state, elements, law = (q, v), pack[:-3], (pack[-3], pack[-2] and s[3] != 0.0)
    out = (f, fd, data, index if data.size else index[:0], energy, power)
    coef = (s[1], s[2])
    span = function(pack[-1], SPAN)  # noqa: F821 (placed by laws.codegen.loop)
    ne = elements[4].shape[0]
    acc = np.zeros(((ne + CHUNK - 1) // CHUNK + 1, 4))
    for c in prange(acc.shape[0] - 1):
        span(np.int64(c * CHUNK + (1 if c > 0 else 0)), min(ne, (c + 1) * CHUNK),
             np.int64(1), state, elements, law, out, coef, acc[c])
    if ne > CHUNK:
        span(np.int64(CHUNK), ne, np.int64(CHUNK), state, elements, law, out, coef, acc[-1])
    for c in range(acc.shape[0]):
        energy[0] += acc[c, 0]
        energy[1] += acc[c, 1]
        power[0] += acc[c, 2]
        power[1] += acc[c, 3]
