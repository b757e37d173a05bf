"""Template of the element loop of the laws' kernels, in chunks that run on threads.

The elements are cut into chunks of ``CHUNK`` consecutive elements, whatever the number of
threads.  Two consecutive elements of a cable share a node (their force and tangent
entries add into the same places); elements two apart, and elements of different cables,
share none.  So the loop runs every chunk but its first element (on numba's threads in
``force_tangent_parallel``, one after the other in ``force_tangent``: the chunks write to
different places), then the first elements of the chunks, one after the other.  Each chunk
sums its energies apart, the first elements theirs, and these sums are added in order at
the end.  Every sum is therefore taken in the same order on one thread or many: the
results are bit-identical whatever the thread count (``tests/test_mission.py``).

As ``kernels.cable`` and ``kernels.assumed_strain``, this module is a template:
``laws.codegen`` copies its functions into the module of each law, next to the template's
``span`` (the loop over a range of elements) and the law's point functions, and compiles
them there.  ``kernel`` and ``kernel_parallel`` are the law's hooks of the
evaluation contract (``contract.Term.kernels``); ``Cable.bind`` takes the second when the
system runs on more than one thread (``linalg.thread_count``).  ``span`` receives its
bounds as ``int64`` only (``np.int64`` of the constants): numba compiles a function once per
literal value of a constant argument, and each law's loop compiled twice cost the test
suite about 190 s of CPU.
"""

import numpy as np
from numba import prange

#: Elements per chunk (fixed: the order of every sum does not depend on the threads).
CHUNK = 64


def chunk(c, state, elements, law, out, coef, acc):
    """The elements of chunk ``c`` but its first (for ``c > 0``), their energies into
    ``acc[c]``."""
    first = c * CHUNK + (1 if c > 0 else 0)
    last = min(elements[4].shape[0], (c + 1) * CHUNK)
    span(first, last, np.int64(1), state, elements, law, out, coef, acc[c])  # noqa: F821


def close(state, elements, law, out, coef, acc):
    """The first elements of the chunks after the first (their energies into the last row
    of ``acc``), then the rows of ``acc`` added to ``energy`` and ``power`` in order.  One
    chunk has no such elements: ``span`` is not called (its scratch arrays, some twenty,
    cost the E-sail rig 0.35 us per evaluation)."""
    if elements[4].shape[0] > CHUNK:
        span(np.int64(CHUNK), elements[4].shape[0], np.int64(CHUNK), state,  # noqa: F821
             elements, law, out, coef, acc[-1])
    energy, power = out[4], out[5]
    for c in range(acc.shape[0]):
        energy[0] += acc[c, 0]
        energy[1] += acc[c, 1]
        power[0] += acc[c, 2]
        power[1] += acc[c, 3]


def force_tangent(state, elements, law, out, coef):
    """Add the forces of all elements to ``f`` and their tangents into ``data``, one chunk
    after the other (``kernels.cable.span`` for the arguments)."""
    acc = np.zeros(((elements[4].shape[0] + CHUNK - 1) // CHUNK + 1, 4))
    for c in range(acc.shape[0] - 1):
        chunk(c, state, elements, law, out, coef, acc)
    close(state, elements, law, out, coef, acc)


def force_tangent_parallel(state, elements, law, out, coef):
    """``force_tangent`` with the chunks on numba's threads: the same sums in the same
    order."""
    acc = np.zeros(((elements[4].shape[0] + CHUNK - 1) // CHUNK + 1, 4))
    for c in prange(acc.shape[0] - 1):
        chunk(c, state, elements, law, out, coef, acc)
    close(state, elements, law, out, coef, acc)


def arguments(pack, index, ev):
    """The arguments of ``force_tangent`` for the packed evaluation ``ev``: ``pack =
    (edofs, Sx, Sxx, w, h, ..., prm, damped)`` (the template's tables, ``elements`` of
    ``kernels.cable.span`` or ``kernels.assumed_strain.span``, then the law's values), the
    tangent entries at ``index``, int (ne, 3 nf, 3 nf)."""
    q, v, s, f, f_ext, fd, data, energy, power = ev
    prm, damped = pack[-2], pack[-1]
    scatter = index if data.size else index[:0]
    return ((q, v), pack[:-2], (prm, damped and s[3] != 0.0),
            (f, fd, data, scatter, energy, power), (s[1], s[2]))


def kernel(pack, index, ev):
    """The law's compiled hook of the evaluation contract (``contract.Term.kernels``):
    ``force_tangent`` on the packed evaluation ``ev`` (``arguments``)."""
    state, elements, law, out, coef = arguments(pack, index, ev)
    force_tangent(state, elements, law, out, coef)


def kernel_parallel(pack, index, ev):
    """``kernel`` on numba's threads (``force_tangent_parallel``)."""
    state, elements, law, out, coef = arguments(pack, index, ev)
    force_tangent_parallel(state, elements, law, out, coef)
