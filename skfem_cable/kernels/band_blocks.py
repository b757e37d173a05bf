"""The independent band blocks of a bordered matrix and their coupling to its border,
factored and solved for numba-compiled code, on numba's threads on request: the part that
the bordered band LU (``kernels.bordered``, a dense border) and the two-level Schur LU
(``kernels.schur``, a sparse border and its own bordered band LU) share, compiled once for
both (it was compiled for each: the same loops over storage of two types).

In the ordering ``perm`` the matrix is ``[[B, E], [F, D]]``: ``B`` (``nb x nb``) a band of
half-width ``band`` that falls apart into *blocks* ``B_j`` no entry couples (an E-sail's
tethers, each with its pin's multipliers), ``k`` border unknowns last.  Block ``j``
touches a few border unknowns, ``T_j`` (the hub's coordinates; its tip): it stores
``E_j = E[R_j, T_j]``, ``F_j`` and ``W_j = B_j^{-1} E_j`` on them alone, ``(|T_j|,
n_j)``, and its part ``F_j W_j`` of the Schur complement as a ``|T_j| x |T_j|`` matrix
whose entries the border's LU places in ``S`` (``s_pos``).  The block elimination of the
bordered band (Golub & Van Loan, Matrix Computations, 4th ed., 2013, sec. 4.5.4; Saad,
Iterative Methods for Sparse Linear Systems, 2nd ed., 2003, eq. (14.9)):

* ``factor``: for every block (at once on numba's threads when the storage is made with
  ``threads > 1``: ``prange``) LAPACK's banded LU of ``B_j`` (``band_sweeps.band_lu``,
  ``dgbtf2`` without its BLAS calls), copied apart
  for the solves (``band_sweeps.split``); ``X_j = B_j^{-1} P_j`` for the unit columns
  ``P_j`` of its cover rows and ``W_j = X_j E_j[R_j]``, or a band solve per column of
  ``E_j`` (``direct``; ``layout.Touch.cover``); its part ``F_j W_j`` from its coupling
  columns alone; then, in the order of the blocks (the same sum whatever the number of
  threads), ``S = D - sum_j F_j W_j``;
* a solve, around the border's: ``y = B^{-1} x_B`` and ``g = x_D - F y``
  (``substitute``), then, ``x_D' = S^{-1} g`` solved by the caller, ``x_B' = y - W x_D'``
  (``correct``).

The storage ``front = (blocks, perm, target, position, s_pos, s_data)`` (``storage``):
``blocks = (addresses, ab, ipiv, band, ints, work, starts, rows_ptr, rows, cols_ptr,
cols, X, x_ptr, touch_ptr, touch, direct, E, F, W, e_ptr, parts, p_ptr, infos, lower,
upper)`` (LAPACK addresses; the band in the ``kernels.lapack`` layout, its pivots
(1-based within each block) and half-width; int32 scratch of the border's LAPACK
calls (``band_lu`` calls none); float scratch (n);
the blocks' first band unknowns (``nblocks + 1``); the cover rows of each block
(CSR-like, band indices) and its coupling columns; the ``X_j``, flat at ``x_ptr``; the
border unknowns each block touches (CSR-like) and which of them ``W_j`` takes by a band
solve (int8); ``E_j``, ``F_j`` ``(n_j, |T_j|)`` and ``W_j`` flat at ``e_ptr``; the parts
flat at ``p_ptr``; each block's LAPACK ``info``; the
factor split for the solves, ``(nb, band)`` and ``(nb, 2 band + 1)``); the ordering;
for every CSR value of the matrix its place (int8; 0: band, 1: E, 2: F, 3: S) and flat
position there; the places of the parts' entries in ``s_data``, the border's values
``S``.  One type for both LUs: every kernel here compiles once.  ``parallel``: ``True``
if the blocks run on threads, else ``None`` (numba prunes a branch on ``None`` when it
compiles: on one thread the threaded loops, seconds to compile, are neither compiled nor
linked into the Newton step).
"""

import numpy as np
from numba import njit, prange

from .band_sweeps import band_lu, band_substitute, pair_substitute, split, split_substitute

#: The stages of a block (``_block``).  Plain ints: numba types a global int as its
#: literal value, so ``_block`` and ``_blocks`` are compiled once per stage, each with
#: the other stages' branches pruned; one int64 stage for all three compiled once, but
#: made the bordered LU of the full-size sail 1.2 to 1.3 times slower (its factor and
#: solve: a larger ``_block`` called per block, not inlined).  A needed variant.
FACTOR, SUBSTITUTE, CORRECT = 0, 1, 2

#: The decorator of this module's compiled functions: compiled code alone calls them
#: (``kernels.bordered``, ``kernels.schur``), so without numba's Python and C wrappers,
#: which box and unbox their arguments for a call from Python (the blocks' tuple of 25
#: arrays: 0.6 s of each of ``_block``'s three compilations) or serve a C pointer (a call
#: from Python would crash).
inner = njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)

#: ``inner`` with the loops of ``prange`` on numba's threads.
threaded = njit(cache=True, parallel=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)


@inner
def factor(front, data, parallel):
    """Factor the blocks of the matrix with CSR values ``data`` and sum the border's
    ``S = D - sum_j F_j W_j`` into ``s_data``; returns the (original) unknown of a zero
    pivot (the first block's, in the ordering), or -1."""
    blocks, perm, target, position, s_pos, s_data = front
    ab, starts, E, F, parts, infos = (blocks[1], blocks[6], blocks[16], blocks[17],
                                      blocks[20], blocks[22])
    _scatter(data, target, position, ab, E, F, s_data, parallel)
    _blocks(blocks, FACTOR, parallel)
    for j in range(starts.size - 1):
        if infos[j] > 0:
            return perm[starts[j] + infos[j] - 1]
    for i in range(parts.size):  # in the order of the blocks
        s_data[s_pos[i]] -= parts[i]
    return -1


@inner
def substitute(front, rhs, parallel):
    """A solve's first half: ``rhs`` in the ordering into ``work``, ``y = B^{-1} x_B``
    there, and ``g = x_D - F y``; returns ``g`` (``work``'s border part, a view)."""
    blocks, perm = front[0], front[1]
    ab, work, starts, cols_ptr, cols, touch_ptr, touch, F, e_ptr = (
        blocks[1], blocks[5], blocks[6], blocks[9], blocks[10], blocks[13], blocks[14],
        blocks[17], blocks[19])
    for i in range(perm.size):
        work[i] = rhs[perm[i]]
    _blocks(blocks, SUBSTITUTE, parallel)
    g = work[ab.shape[0]:]
    for j in range(starts.size - 1):  # in the order of the blocks
        near = touch[touch_ptr[j]:touch_ptr[j + 1]]
        t = near.size
        for i in range(cols_ptr[j], cols_ptr[j + 1]):  # F_j (n_j, t) flat
            p = cols[i]
            yp = work[p]
            fp = F[e_ptr[j] + (p - starts[j]) * t: e_ptr[j] + (p - starts[j] + 1) * t]
            for a in range(t):
                g[near[a]] -= fp[a] * yp
    return g


@inner
def correct(front, out, parallel):
    """A solve's second half, the border's ``x_D'`` in ``work``: ``x_B' = y - W x_D'``
    (none without a border), and ``work`` in the original ordering into ``out``."""
    blocks, perm = front[0], front[1]
    if perm.size > blocks[1].shape[0]:
        _blocks(blocks, CORRECT, parallel)
    work = blocks[5]
    for i in range(perm.size):
        out[perm[i]] = work[i]


@inner
def _scatter(data, target, position, ab, E, F, S, parallel):
    """The CSR values ``data`` into the band, ``E``, ``F`` and ``D`` (in ``S``), every
    other entry zero; on numba's threads unless ``parallel`` is None (assignments to
    distinct places: the same on any thread count).  ``E``, ``F``, ``S`` flat."""
    flat = (ab.ravel(), E, F, S)
    if parallel is not None:
        _scatter_parallel(data, target, position, flat)
        return
    for k in range(4):
        _fill(flat[k], 0, flat[k].size)
    _place(data, target, position, flat, 0, data.size)


#: Entries per piece of the threaded scatter.
PIECE = 16384


@threaded
def _scatter_parallel(data, target, position, flat):
    for k in range(4):
        size = flat[k].size
        for i in prange((size + PIECE - 1) // PIECE):
            _fill(flat[k], i * PIECE, min(size, (i + 1) * PIECE))
    for i in prange((data.size + PIECE - 1) // PIECE):
        _place(data, target, position, flat, i * PIECE, min(data.size, (i + 1) * PIECE))


@inner
def _fill(values, first, last):
    for p in range(first, last):
        values[p] = 0.0


@inner
def _place(data, target, position, flat, first, last):
    """Entries ``first:last`` of ``data`` to their places in the storage ``flat`` (the
    band, ``E``, ``F``, ``S`` flattened)."""
    for p in range(first, last):
        where = target[p]
        if where == 0:
            flat[0][position[p]] = data[p]
        elif where == 1:
            flat[1][position[p]] = data[p]
        elif where == 2:
            flat[2][position[p]] = data[p]
        else:
            flat[3][position[p]] = data[p]


@inner
def _factor_block(ab, ipiv, band, start, end, units, columns, X, e, f, w, direct, part):
    """The banded LU of the block ``start:end``, its ``W_j`` (``w``, from ``E_j``: ``e``)
    and its part ``F_j W_j`` (``part``, from ``F_j``: ``f``); returns LAPACK's
    ``info``."""
    n, t = end - start, direct.size
    block, pivots = ab[start:end], ipiv[start:end]
    info = band_lu(block, band, pivots)
    part[:] = 0.0
    if info > 0 or t == 0:
        return info
    x = X.reshape((units.size, n))
    for b in range(units.size):  # X = B_j^{-1} P_j: unit columns at the rows of the cover
        x[b, :] = 0.0
        x[b, units[b] - start] = 1.0
        band_substitute(block, band, pivots, x[b])
    for a in range(t):  # W = B_j^{-1} E_j: a band solve, or X E[cover rows]
        wa = w[a]
        if direct[a]:
            wa[:] = e[a]
            band_substitute(block, band, pivots, wa)
            continue
        wa[:] = 0.0
        for b in range(units.size):
            value = e[a, units[b] - start]
            if value != 0.0:
                for p in range(n):
                    wa[p] += x[b, p] * value
    for a in range(t):  # F_j W_j over the coupling columns
        for i in range(columns.size):
            p = columns[i] - start
            wp = w[a, p]
            for r in range(t):
                part[a, r] += f[p, r] * wp
    return info


@inner
def _local(blocks, j):
    """Block ``j``'s ``E_j``, ``F_j`` and ``W_j`` (views)."""
    starts, touch_ptr, E, F, W, e_ptr = (blocks[6], blocks[13], blocks[16], blocks[17],
                                         blocks[18], blocks[19])
    n, t = starts[j + 1] - starts[j], touch_ptr[j + 1] - touch_ptr[j]
    first, last = e_ptr[j], e_ptr[j + 1]
    return (E[first:last].reshape((t, n)), F[first:last].reshape((n, t)),
            W[first:last].reshape((t, n)))


@njit(cache=True, inline="always")
def _blocks(blocks, stage, parallel):
    """``_block`` of every block at ``stage``, on numba's threads unless ``parallel`` is
    None (the threaded loop is then not compiled); a solve's ``SUBSTITUTE`` on one thread
    two blocks at a time.  Inlined by numba into its callers (its branches pruned there
    the same way): compiled apart, it was six functions (three stages, two flags) whose
    LLVM optimisation of the block code linked into them was done again in each caller
    (both LUs on one and two threads, a fresh process: 5.4 s of compiling)."""
    if parallel is not None:
        _blocks_parallel(blocks, stage)
    elif stage == SUBSTITUTE:
        _substitute_pairs(blocks)
    else:
        for j in range(blocks[6].size - 1):
            _block(blocks, j, stage)


@inner
def _substitute_pairs(blocks):
    """The ``SUBSTITUTE`` stage on one thread, two blocks at a time (``pair_substitute``),
    the last alone if their number is odd."""
    lower, upper, ipiv, band, work, starts = (blocks[23], blocks[24], blocks[2], blocks[3],
                                              blocks[5], blocks[6])
    nblocks = starts.size - 1
    for j in range(0, nblocks - 1, 2):
        a, m, b = starts[j], starts[j + 1], starts[j + 2]
        pair_substitute(lower[a:m], upper[a:m], ipiv[a:m], work[a:m],
                        lower[m:b], upper[m:b], ipiv[m:b], work[m:b], band)
    if nblocks % 2:
        _block(blocks, nblocks - 1, SUBSTITUTE)


@threaded
def _blocks_parallel(blocks, stage):
    for j in prange(blocks[6].size - 1):
        _block(blocks, np.int64(j), stage)  # prange's index is unsigned: one signature


@inner
def _block(blocks, j, stage):
    """Block ``j`` at ``stage``: ``FACTOR`` (``_factor_block``, its ``info`` into
    ``infos[j]``, the factor split), ``SUBSTITUTE`` (a solve's ``y_j = B_j^{-1} x_j``)
    or ``CORRECT`` (``y_j -= W_j x_D'[T_j]``, ``x_D'`` the border's part of ``work``)."""
    (addresses, ab, ipiv, band, ints, work, starts, rows_ptr, rows, cols_ptr, cols, X,
     x_ptr, touch_ptr, touch, direct, E, F, W, e_ptr, parts, p_ptr, infos, lower,
     upper) = blocks
    start, end = starts[j], starts[j + 1]
    if stage == FACTOR:
        e, f, w = _local(blocks, j)
        t = touch_ptr[j + 1] - touch_ptr[j]
        infos[j] = _factor_block(
            ab, ipiv, band, start, end, rows[rows_ptr[j]:rows_ptr[j + 1]],
            cols[cols_ptr[j]:cols_ptr[j + 1]], X[x_ptr[j]:x_ptr[j + 1]], e, f, w,
            direct[touch_ptr[j]:touch_ptr[j + 1]], parts[p_ptr[j]:p_ptr[j + 1]].reshape((t, t)))
        if infos[j] == 0:
            split(ab[start:end], band, lower[start:end], upper[start:end])
    elif stage == SUBSTITUTE:
        split_substitute(lower[start:end], upper[start:end], band, ipiv[start:end],
                         work[start:end])
    else:  # over slices: an index from 0 needs no wrap-around test, and LLVM vectorises
        y, g = work[start:end], work[ab.shape[0]:]  # the loop (the E-sail rig's 12
        n, first = end - start, e_ptr[j]  # blocks: 4.8 -> 2.2 us); W_j (t, n_j) flat
        for a in range(touch_ptr[j + 1] - touch_ptr[j]):
            ga = g[touch[touch_ptr[j] + a]]
            wa = W[first + a * n: first + (a + 1) * n]
            for i in range(n):
                y[i] -= wa[i] * ga
