"""Bordered band LU: independent bands plus a few dense border rows and columns (an
arrowhead), for numba-compiled code and Python alike, its blocks on threads on request.

In the ordering ``perm`` the matrix is ``[[B, E], [F, D]]``: ``B`` (``nb x nb``) a band of
half-width ``band``, ``k`` border unknowns last (the coordinates of a hub joined to many
bodies, and the multipliers of its own constraints).  ``B`` falls apart into *blocks*,
diagonal blocks ``B_j`` that no entry couples (the tethers of an E-sail, each with its
pin's multipliers), and each block touches the border through a few *coupling* rows
``R_j`` (where ``E`` has entries) and columns ``C_j`` (where ``F`` has).  The
factorisation is, for every block (at once on numba's threads when the storage is made
with ``threads > 1``: ``prange``),

* LAPACK's banded LU of ``B_j`` (``dgbtrf``),
* ``X_j = B_j^{-1} P_j`` for the unit columns ``P_j`` of its coupling rows (a few band
  solves, not one per border column), ``W_j = B_j^{-1} E_j = X_j E[R_j]``; or, where
  the coupling rows outnumber the border (the ring of tips of ``kernels.schur``'s second
  level, every tip joined to the hub), ``W_j`` by a band solve per border column,
* and the block's part ``F_j W_j`` of the Schur
  complement, from the coupling columns alone;

then, in the order of the blocks (so that the sum, and every result, is the same whatever
the number of threads), ``S = D - sum_j F_j W_j`` and its dense LU.  A solve is one banded
solve per block, the border's dense solve, and ``x_B' = y - W x_D'``:

    y = B^{-1} x_B,   x_D' = S^{-1} (x_D - F y),   x_B' = y - W x_D'.

With ``k = 0`` it is the banded LU of the blocks alone. All storage is made once
(``storage``, for ``linalg``): ``lu = (addresses, ab, ipiv, E, F, W, S, ipiv_s, target,
position, perm, band, ints, work, starts, rows_ptr, rows, cols_ptr, cols, X, x_ptr,
parts, infos, lower, upper, parallel)``: LAPACK addresses; the band (``kernels.lapack``
layout) and its pivots (1-based within each block); ``E`` and ``F`` as ``(k, nb)`` and
``(nb, k)`` arrays whose rows are the blocks' columns; ``W`` like ``E``; ``S``
column-major ``(k, k)`` and its pivots; for every CSR value of the matrix its block
(int8; 0: band, 1: E, 2: F, 3: D) and flat position there; the ordering; the half-width;
int32 scratch, a row per block and one for ``S``; float scratch (n); the blocks' first
band unknowns (``nblocks + 1``); the coupling rows and columns of each block (CSR-like,
band indices); the ``X_j``, each ``(|R_j|, n_j)``, flat at ``x_ptr``; each block's part
of ``F W`` ``(nblocks, k, k)``; each block's LAPACK ``info``; the factor split for the
solves (``split``): the multipliers of ``L`` ``(nb, band)`` and ``U`` ``(nb, 2 band +
1)``; ``True`` if the blocks run on threads, else ``None``: numba prunes a branch on
``None`` when it compiles, so that on one thread the threaded loops (``prange``, seconds
to compile) are neither compiled nor linked into the Newton step.

**The solves read the factor in two arrays of their own.**  LAPACK's band storage of
half-width ``b`` holds a column of the factor in a row of ``3 b + 1`` values: ``2 b + 1``
of ``U`` (with the fill of the row interchanges, which a cable's iteration matrix makes
at most of its columns) then the ``b`` multipliers of ``L``. A solve's forward sweep
reads the multipliers, its backward sweep ``U``, each strided through the rows, so that
both touch most of the storage's cache lines. After a factorization ``split`` copies
``L`` and ``U`` into arrays of their own, which the solves (``split_substitute``) stream
each in one sweep: on a random band of 60,009 unknowns of half-width 13 (a 10,000-element
cable's, 19.2 MB) with interchanges at 90 % of its columns, a solve after a 40 MB stream
(out of the cache) took 1.42 ms from LAPACK's storage and 1.19 ms from the split arrays;
in the step at 10,000 elements see docs/benchmarks.md. The price: a copy of the factor
per factorization and its memory twice (LAPACK's storage is not read between
factorizations). The same operations as ``band_substitute``, bit for bit.
"""

import numpy as np
from numba import njit, prange

from .lapack import band_factor, dense_factor, dense_solve

#: The stages of a block (``_block``).  Plain ints: numba types a global int as its
#: literal value, so ``_block`` and ``_blocks`` are compiled once per stage, each with
#: the other stages' branches pruned; one int64 stage for all three compiled once, but
#: made the bordered LU of the full-size sail 1.2 to 1.3 times slower (its factor and
#: solve: a larger ``_block`` called per block, not inlined).  A needed variant.
FACTOR, SUBSTITUTE, CORRECT = 0, 1, 2

#: The multipliers' offset in ``split``'s ``lower``: an ``np.int64``, not a literal 0, so
#: that the sweeps are compiled for one type of offset, that of LAPACK's storage
#: (``band_substitute``) too.
NO_OFFSET = np.int64(0)


@njit(cache=True)
def factor(lu, data):
    """Factor the matrix with CSR values ``data``; returns the (original) unknown of a
    zero pivot (the first block's, in the ordering), or -1."""
    (addresses, ab, ipiv, E, F, W, S, ipiv_s, target, position, perm, band, ints, work,
     starts, rows_ptr, rows, cols_ptr, cols, X, x_ptr, parts, infos, lower, upper,
     parallel) = lu
    k = S.shape[0]
    nblocks = starts.size - 1
    _scatter(data, target, position, ab, E.ravel(), F.ravel(), S.ravel(), parallel)
    _blocks(lu, FACTOR, parallel)
    for j in range(nblocks):
        if infos[j] > 0:
            return perm[starts[j] + infos[j] - 1]
    if k == 0:
        return -1
    for j in range(nblocks):  # S = D - sum_j F_j W_j, in the order of the blocks
        for c in range(k):
            for r in range(k):
                S[c, r] -= parts[j, c, r]
    info = dense_factor(addresses, S, ipiv_s, ints[nblocks])
    if info > 0:
        return perm[ab.shape[0] + info - 1]
    return -1


@njit(cache=True)
def _scatter(data, target, position, ab, E, F, S, parallel):
    """The CSR values ``data`` into the band, ``E``, ``F`` and ``D`` (in ``S``), every
    other entry zero; on numba's threads unless ``parallel`` is None (assignments to distinct
    places: the same on any thread count).  ``E``, ``F``, ``S`` flat (1-D views), as
    ``kernels.schur`` passes its own: one signature for both."""
    flat = (ab.ravel(), E, F, S)
    if parallel is not None:
        _scatter_parallel(data, target, position, flat)
        return
    for k in range(4):
        _fill(flat[k], 0, flat[k].size)
    _place(data, target, position, flat, 0, data.size)


#: Entries per piece of the threaded scatter.
PIECE = 16384


@njit(cache=True, parallel=True)
def _scatter_parallel(data, target, position, flat):
    for k in range(4):
        size = flat[k].size
        for i in prange((size + PIECE - 1) // PIECE):
            _fill(flat[k], i * PIECE, min(size, (i + 1) * PIECE))
    for i in prange((data.size + PIECE - 1) // PIECE):
        _place(data, target, position, flat, i * PIECE, min(data.size, (i + 1) * PIECE))


@njit(cache=True)
def _fill(values, first, last):
    for p in range(first, last):
        values[p] = 0.0


@njit(cache=True)
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


@njit(cache=True)
def _factor_block(addresses, ab, ipiv, E, F, W, band, ints, start, end, rows, cols, X, part):
    """The banded LU of the block ``start:end``, its ``W`` columns and its part of ``F W``
    (``part``, ``(k, k)``); returns LAPACK's ``info``."""
    n = end - start
    block, pivots = ab[start:end], ipiv[start:end]
    info = band_factor(addresses, block, band, band, pivots, ints)
    part[:] = 0.0
    if info > 0 or rows.size == 0:
        return info
    k = E.shape[0]
    if rows.size > k:  # W = B_j^{-1} E_j: fewer band solves on the columns of E
        for c in range(k):
            W[c, start:end] = E[c, start:end]
            band_substitute(block, band, pivots, W[c, start:end])
    else:
        _coupling_solves(block, band, pivots, rows, start, X.reshape((rows.size, n)),
                         E[:, start:end], W[:, start:end])
    for c in range(k):  # F_j W_j over the coupling columns
        for i in range(cols.size):
            p = cols[i]
            wp = W[c, p]
            for r in range(k):
                part[c, r] += F[p, r] * wp
    return info


@njit(cache=True)
def _coupling_solves(block, band, pivots, rows, first, x, e, w):
    """``w = B^{-1} e`` (rows: border unknowns) from the banded LU of ``B`` (``block``,
    its first unknown ``first``) where ``e`` has entries in a few ``rows`` only:
    ``x = B^{-1} P`` for their unit columns ``P`` (one band solve each, into ``x``),
    then ``w = x e[:, rows - first]``."""
    n = block.shape[0]
    for b in range(rows.size):
        x[b, :] = 0.0
        x[b, rows[b] - first] = 1.0
        band_substitute(block, band, pivots, x[b])
    for c in range(e.shape[0]):
        wc = w[c]
        wc[:] = 0.0
        for b in range(rows.size):
            value = e[c, rows[b] - first]
            if value != 0.0:
                for p in range(n):
                    wc[p] += x[b, p] * value


@njit(cache=True)
def solve(lu, rhs, out):
    """``out = A^{-1} rhs`` with the last factorisation (original ordering)."""
    (addresses, ab, ipiv, E, F, W, S, ipiv_s, target, position, perm, band, ints, work,
     starts, rows_ptr, rows, cols_ptr, cols, X, x_ptr, parts, infos, lower, upper,
     parallel) = lu
    nb, k = ab.shape[0], S.shape[0]
    for i in range(perm.size):
        work[i] = rhs[perm[i]]
    _blocks(lu, SUBSTITUTE, parallel)
    if k:
        y, g = work[:nb], work[nb:]
        for i in range(cols.size):  # g = x_D - F y, over the coupling columns
            p = cols[i]
            yp = y[p]
            for r in range(k):
                g[r] -= F[p, r] * yp
        dense_solve(addresses, S, ipiv_s, g, ints[starts.size - 1])
        _blocks(lu, CORRECT, parallel)
    for i in range(perm.size):
        out[perm[i]] = work[i]


@njit(cache=True)
def _blocks(lu, stage, parallel):
    """``_block`` of every block at ``stage``, on numba's threads unless ``parallel`` is
    None (the threaded loop is then not compiled).  The blocks take the storage without
    its last member, ``parallel``: one ``_block`` per stage for both (it was compiled for
    each type of ``parallel`` too)."""
    if parallel is not None:
        _blocks_parallel(lu[:-1], stage)
    elif stage == SUBSTITUTE:
        _substitute_pairs(lu[:-1])
    else:
        for j in range(lu[14].size - 1):
            _block(lu[:-1], j, stage)


@njit(cache=True)
def _substitute_pairs(lu):
    """The ``SUBSTITUTE`` stage on one thread, two blocks at a time (``pair_substitute``),
    the last alone if their number is odd; ``lu`` the storage without ``parallel``."""
    lower, upper, ipiv, band, work, starts = lu[23], lu[24], lu[2], lu[11], lu[13], lu[14]
    nblocks = starts.size - 1
    for j in range(0, nblocks - 1, 2):
        a, m, b = starts[j], starts[j + 1], starts[j + 2]
        pair_substitute(lower[a:m], upper[a:m], ipiv[a:m], work[a:m],
                        lower[m:b], upper[m:b], ipiv[m:b], work[m:b], band)
    if nblocks % 2:
        _block(lu, nblocks - 1, SUBSTITUTE)


@njit(cache=True, parallel=True)
def _blocks_parallel(lu, stage):
    for j in prange(lu[14].size - 1):
        _block(lu, np.int64(j), stage)  # prange's index is unsigned: one signature


@njit(cache=True)
def _block(lu, j, stage):
    """Block ``j`` at ``stage``: ``FACTOR`` (``_factor_block``, its ``info`` into
    ``infos[j]``), ``SUBSTITUTE`` (a solve's ``y_j = B_j^{-1} x_j``) or ``CORRECT``
    (``y_j -= W_j x_D'``, ``x_D'`` the border's part of ``work``); ``lu`` without
    ``parallel``."""
    (addresses, ab, ipiv, E, F, W, S, ipiv_s, target, position, perm, band, ints, work,
     starts, rows_ptr, rows, cols_ptr, cols, X, x_ptr, parts, infos, lower, upper) = lu
    start, end = starts[j], starts[j + 1]
    if stage == FACTOR:
        infos[j] = _factor_block(addresses, ab, ipiv, E, F, W, band, ints[j], start, end,
                                 rows[rows_ptr[j]:rows_ptr[j + 1]],
                                 cols[cols_ptr[j]:cols_ptr[j + 1]], X[x_ptr[j]:x_ptr[j + 1]],
                                 parts[j])
        if infos[j] == 0:
            split(ab[start:end], band, lower[start:end], upper[start:end])
    elif stage == SUBSTITUTE:
        split_substitute(lower[start:end], upper[start:end], band, ipiv[start:end],
                         work[start:end])
    else:  # over slices: an index from 0 needs no wrap-around test, and LLVM vectorises
        y = work[start:end]  # the loop (the E-sail rig's 12 blocks: 4.8 -> 2.2 us)
        for c in range(S.shape[0]):
            gc = work[ab.shape[0] + c]
            wc = W[c, start:end]
            for i in range(y.size):
                y[i] -= wc[i] * gc


@njit(cache=True)
def band_substitute(ab, band, ipiv, b):
    """``b = B^{-1} b`` in place with the banded LU of ``band_factor`` (half-widths
    ``band``): LAPACK's ``dgbtrs`` for one right-hand side, as loops over contiguous
    slices.  ``dgbtrs`` makes a BLAS call per column; for the narrow bands of cables these
    loops take half its time (15 against 30 us for the E-sail's 468 band unknowns of
    half-width 13)."""
    kv = 2 * band
    _lower_sweep(ab, kv + 1, band, ipiv, b)
    _upper_sweep(ab, kv, b)


@njit(cache=True)
def split_substitute(lower, upper, band, ipiv, b):
    """``band_substitute`` from the factor split by ``split``: the same operations."""
    _lower_sweep(lower, NO_OFFSET, band, ipiv, b)
    _upper_sweep(upper, 2 * band, b)


@njit(cache=True)
def pair_substitute(lower_a, upper_a, ipiv_a, a, lower_b, upper_b, ipiv_b, b, band):
    """``split_substitute`` of two blocks at once, ``a`` and ``b`` in place (any sizes),
    each in its own order: the same operations, bit for bit.  A sweep is a chain (each
    column waits for the one before, through memory and, in ``U``, a division); two
    independent chains interleaved keep the core busy while one waits: the E-sail rig's
    blocks of 39 unknowns of half-width 13, 1.40-1.51 -> 1.04-1.21 us per pair (CPU, a
    compiled loop, load 6)."""
    na, nb = a.size, b.size
    both = min(na, nb)
    for j in range(both - 1):
        _lower_column(lower_a, NO_OFFSET, band, ipiv_a, a, j)
        _lower_column(lower_b, NO_OFFSET, band, ipiv_b, b, j)
    for j in range(both - 1, na - 1):
        _lower_column(lower_a, NO_OFFSET, band, ipiv_a, a, j)
    for j in range(both - 1, nb - 1):
        _lower_column(lower_b, NO_OFFSET, band, ipiv_b, b, j)
    width = 2 * band
    for j in range(na - 1, both - 1, -1):  # the longer block's last columns first
        _upper_column(upper_a, width, a, j)
    for j in range(nb - 1, both - 1, -1):
        _upper_column(upper_b, width, b, j)
    for j in range(both - 1, -1, -1):
        _upper_column(upper_a, width, a, j)
        _upper_column(upper_b, width, b, j)


@njit(cache=True)
def _lower_sweep(store, offset, band, ipiv, b):
    """``b = L^{-1} P b``: the row interchanges ``ipiv`` and the multipliers of column
    ``j`` at ``store[j, offset:offset + band]``."""
    for j in range(store.shape[0] - 1):
        _lower_column(store, offset, band, ipiv, b, j)


@njit(cache=True)
def _upper_sweep(store, width, b):
    """``b = U^{-1} b``, column ``j`` of ``U`` stored as ``store[j, :width + 1]``:
    ``width`` superdiagonals then the diagonal."""
    for j in range(store.shape[0] - 1, -1, -1):
        _upper_column(store, width, b, j)


@njit(cache=True, forceinline=True)
def _lower_column(store, offset, band, ipiv, b, j):
    """Column ``j`` of ``_lower_sweep``."""
    lm = min(band, store.shape[0] - j - 1)
    p = ipiv[j] - 1
    bj = b[p]
    if p != j:
        b[p] = b[j]
        b[j] = bj
    multipliers = store[j, offset: offset + lm]
    below = b[j + 1: j + 1 + lm]
    for i in range(lm):
        below[i] -= multipliers[i] * bj


@njit(cache=True, forceinline=True)
def _upper_column(store, width, b, j):
    """Column ``j`` of ``_upper_sweep``."""
    bj = b[j] / store[j, width]
    b[j] = bj
    m = min(j, width)
    column = store[j, width - m: width]
    above = b[j - m: j]
    for i in range(m):
        above[i] -= column[i] * bj


@njit(cache=True)
def split(ab, band, lower, upper):
    """Copy the banded LU ``ab`` (``band_factor``'s, half-widths ``band``) into ``lower``
    (the multipliers of each column) and ``upper`` (``U``'s ``2 band`` superdiagonals,
    with the fill of the row interchanges, and its diagonal)."""
    kv = 2 * band
    for j in range(ab.shape[0]):
        column = ab[j]
        for i in range(kv + 1):
            upper[j, i] = column[i]
        for i in range(band):
            lower[j, i] = column[kv + 1 + i]


def blocks(pr, pc, nb):
    """The first unknowns of the independent diagonal blocks of the band (``nblocks +
    1``, ending with ``nb``): a block ends at ``p`` when no entry ``(pr, pc)`` of the band
    joins an unknown up to ``p`` with one after it."""
    reach = np.arange(nb)
    inside = (pr < nb) & (pc < nb)
    low, high = np.minimum(pr, pc)[inside], np.maximum(pr, pc)[inside]
    np.maximum.at(reach, low, high)
    ends = np.flatnonzero(np.maximum.accumulate(reach) == np.arange(nb)) + 1
    return np.concatenate([[0], ends]).astype(np.int64)


def _grouped(indices, starts):
    """``(ptr, sorted unique indices)`` of band indices grouped by their block."""
    unique = np.unique(indices)
    return np.searchsorted(unique, starts).astype(np.int64), unique.astype(np.int64)


def storage(addresses, rows, cols, perm, nb, band, threads=1):
    """The ``lu`` tuple for the CSR entries ``(rows, cols)`` (original indices) of an
    ``n x n`` matrix ordered by ``perm`` with ``nb`` band unknowns of half-width
    ``band``; with ``threads > 1`` and more than one block, the blocks are factored and
    solved on numba's threads."""
    n = perm.size
    k = n - nb
    ldab = 3 * band + 1
    if max(nb * ldab, n * k) >= 2**31:
        raise ValueError(f"a band of {nb} unknowns and half-width {band} with {k} border "
                         "unknowns exceeds 2^31 stored entries")
    iperm = np.empty_like(perm)
    iperm[perm] = np.arange(n)
    pr, pc = iperm[rows], iperm[cols]
    out_r, out_c = pr >= nb, pc >= nb
    target = (out_c + 2 * out_r).astype(np.int8)  # 0: band, 1: E, 2: F, 3: D
    position = pc * ldab + 2 * band + pr - pc
    position[out_c] = ((pc - nb) * nb + pr)[out_c]
    position[out_r] = (pc * k + (pr - nb))[out_r]
    both = out_r & out_c
    position[both] = ((pc - nb) * k + (pr - nb))[both]
    starts = blocks(pr, pc, nb)
    rows_ptr, coupling_rows = _grouped(pr[(target == 1)], starts)
    cols_ptr, coupling_cols = _grouped(pc[(target == 2)], starts)
    coupling = np.diff(rows_ptr)
    sizes = np.where(coupling > k, 0, coupling) * np.diff(starts)
    x_ptr = np.concatenate([[0], np.cumsum(sizes)]).astype(np.int64)
    nblocks = starts.size - 1
    return (addresses, np.zeros((nb, ldab)), np.zeros(nb, dtype=np.int32),
            np.zeros((k, nb)), np.zeros((nb, k)), np.zeros((k, nb)), np.zeros((k, k)),
            np.zeros(k, dtype=np.int32), target, position.astype(np.int32),
            perm.astype(np.int64), int(band), np.zeros((nblocks + 1, 8), dtype=np.int32),
            np.zeros(n), starts, rows_ptr, coupling_rows, cols_ptr, coupling_cols,
            np.zeros(x_ptr[-1]), x_ptr, np.zeros((nblocks, k, k)),
            np.zeros(nblocks, dtype=np.int64), np.zeros((nb, band)),
            np.zeros((nb, 2 * band + 1)), True if threads > 1 and nblocks > 1 else None)
