"""Two-level Schur LU: independent band blocks, a sparse border between them, and a dense
border last (a hub and a ring of tips), for numba-compiled code and Python alike, its
blocks on threads on request.

In the ordering ``perm`` the matrix is ``[[B, E], [F, D]]``: ``B`` (``nb x nb``) a band of
half-width ``band`` that falls apart into *blocks* ``B_j`` no entry couples (an E-sail's
tethers without their tips, each with its pin's multipliers; the auxiliary tethers of
its ring, each with its two pins' multipliers), ``k`` border unknowns last.  Block ``j``
touches only a few border unknowns, ``T_j`` (the hub's coordinates and its own tip; its
two tips): it stores ``E_j = E[R_j, T_j]``, ``F_j`` and ``W_j = B_j^{-1} E_j`` on them
alone, ``(|T_j|, n_j)``, and its part ``F_j W_j`` of the Schur complement as a
``|T_j| x |T_j|`` matrix with the places of its entries in ``S`` (precomputed).  The
factorisation is the block elimination of the bordered band (Golub & Van Loan, Matrix
Computations, 4th ed., 2013, sec. 4.5.4 (block tridiagonal/arrow systems); Saad,
Iterative Methods for Sparse Linear Systems, 2nd ed., 2003, eq. (14.9), the Schur
complement of a domain decomposition), for every block (at once on numba's threads when
the storage is made with ``threads > 1``: ``prange``)

* LAPACK's banded LU of ``B_j`` (``dgbtrf``),
* ``X_j = B_j^{-1} P_j`` for the unit columns ``P_j`` of its coupling rows ``R_j`` and
  ``W_j = X_j E_j[R_j]`` (or a band solve per column of ``E_j`` where these are fewer),
* its part ``F_j W_j``, from its coupling columns alone;

then, in the order of the blocks (the same sum whatever the number of threads),
``S = D - sum_j F_j W_j`` on S's *sparse* pattern, factored one level down by the bordered
band LU of ``kernels.bordered``: S's unknowns ordered by reverse Cuthill-McKee (a ring of
tips interleaved: a band of about two tips) with the hub's unknowns its dense border.
Without a ring (one level: an E-sail's tethers joined to the hub alone) S would be the
hub's, all dense border: ``linalg.PatternSolver`` then takes ``kernels.bordered`` itself,
whose storage (half as many arrays, none nested) the compiled Newton step unboxes in
half the time (1.7 against 4.2 us a step).  A solve:

    y = B^{-1} x_B,   x_D' = S^{-1} (x_D - F y),   x_B' = y - W x_D'.

All storage is made once (``storage``): ``lu = (blocks, perm, target, position, s_pos,
s_data, inner, parallel)``: what the blocks use, ``blocks = (addresses, ab, ipiv, band,
ints, work, starts, rows_ptr, rows, cols_ptr, cols, X, x_ptr, touch_ptr, touch, direct,
E, F, W, e_ptr, parts, p_ptr, infos)`` (LAPACK addresses; the band in the
``kernels.lapack`` layout, its pivots (1-based within each block) and half-width; int32
scratch, a row per block; float scratch (n); the blocks' first band unknowns
(``nblocks + 1``); the rows of each block's cover (CSR-like, band indices) and its
coupling columns; the ``X_j``, flat at ``x_ptr``; the border unknowns each block touches
(CSR-like, border indices) and which of them ``W_j`` takes by a band solve (int8);
``E_j`` ``(|T_j|, n_j)``, ``F_j`` ``(n_j, |T_j|)`` and ``W_j`` (like ``E_j``), flat at
``e_ptr``; the parts ``(|T_j|, |T_j|)`` flat at ``p_ptr``; each block's LAPACK
``info``); the ordering; for every CSR value of the matrix its place (int8; 0: band,
1: E, 2: F, 3: S) and flat position there; the places of the parts' entries in
``s_data``, the CSR values of ``S``; ``inner``, the ``kernels.bordered`` storage of
``S``; ``True`` if the blocks run on threads, else ``None`` (numba prunes a branch on
``None``: on one thread the threaded loops are neither compiled nor linked into the
Newton step).  The blocks take ``blocks`` alone: a call passes its arrays one by one.
"""

import numpy as np
import scipy.sparse as sp
from numba import njit, prange
from scipy.sparse.csgraph import maximum_bipartite_matching

from . import bordered
from .bordered import band_substitute
from .lapack import band_factor

#: The stages of a block (``_block``).  Plain ints: numba types a global int as its
#: literal value, so ``_block`` and ``_blocks`` are compiled once per stage, each with
#: the other stages' branches pruned; one int64 stage for all three compiled once, but
#: made the bordered LU of the full-size sail 1.2 to 1.3 times slower (its factor and
#: solve: a larger ``_block`` called per block, not inlined).  A needed variant.
FACTOR, SUBSTITUTE, CORRECT = 0, 1, 2


@njit(cache=True)
def factor(lu, data):
    """Factor the matrix with CSR values ``data``; returns the (original) unknown of a
    zero pivot (the first block's, in the ordering), or -1."""
    blocks, perm, target, position, s_pos, s_data, inner, parallel = lu
    ab, starts, E, F, parts, infos = (blocks[1], blocks[6], blocks[16], blocks[17],
                                      blocks[20], blocks[22])
    bordered._scatter(data, target, position, ab, E, F, s_data, parallel)
    _blocks(blocks, FACTOR, parallel)
    for j in range(starts.size - 1):
        if infos[j] > 0:
            return perm[starts[j] + infos[j] - 1]
    if s_data.size == 0:
        return -1
    for i in range(parts.size):  # S = D - sum_j F_j W_j, in the order of the blocks
        s_data[s_pos[i]] -= parts[i]
    at = bordered.factor(inner, s_data)
    return perm[ab.shape[0] + at] if at >= 0 else -1


@njit(cache=True)
def _factor_block(addresses, ab, ipiv, band, ints, start, end, units, columns, X, e, f, w,
                  direct, part):
    """The banded LU of the block ``start:end``, its ``W_j`` (``w``, from ``E_j``: ``e``)
    and its part ``F_j W_j`` (``part``, from ``F_j``: ``f``); returns LAPACK's
    ``info``."""
    n, t = end - start, direct.size
    block, pivots = ab[start:end], ipiv[start:end]
    info = band_factor(addresses, block, band, band, pivots, ints)
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


@njit(cache=True)
def _local(blocks, j):
    """Block ``j``'s ``E_j``, ``F_j`` and ``W_j`` (views)."""
    starts, touch_ptr, E, F, W, e_ptr = (blocks[6], blocks[13], blocks[16], blocks[17],
                                         blocks[18], blocks[19])
    n, t = starts[j + 1] - starts[j], touch_ptr[j + 1] - touch_ptr[j]
    first, last = e_ptr[j], e_ptr[j + 1]
    return (E[first:last].reshape((t, n)), F[first:last].reshape((n, t)),
            W[first:last].reshape((t, n)))


@njit(cache=True)
def solve(lu, rhs, out):
    """``out = A^{-1} rhs`` with the last factorisation (original ordering)."""
    blocks, perm, target, position, s_pos, s_data, inner, parallel = lu
    ab, work, starts, cols_ptr, cols, touch_ptr, touch, F, e_ptr = (
        blocks[1], blocks[5], blocks[6], blocks[9], blocks[10], blocks[13], blocks[14],
        blocks[17], blocks[19])
    nb = ab.shape[0]
    for i in range(perm.size):
        work[i] = rhs[perm[i]]
    _blocks(blocks, SUBSTITUTE, parallel)
    if s_data.size:
        g = work[nb:]
        for j in range(starts.size - 1):  # g = x_D - F y, in the order of the blocks
            near = touch[touch_ptr[j]:touch_ptr[j + 1]]
            f = F[e_ptr[j]:e_ptr[j + 1]].reshape((starts[j + 1] - starts[j], near.size))
            for i in range(cols_ptr[j], cols_ptr[j + 1]):
                p = cols[i]
                yp = work[p]
                fp = f[p - starts[j]]
                for a in range(near.size):
                    g[near[a]] -= fp[a] * yp
        bordered.solve(inner, g, g)
        _blocks(blocks, CORRECT, parallel)
    for i in range(perm.size):
        out[perm[i]] = work[i]


@njit(cache=True)
def _blocks(blocks, stage, parallel):
    """``_block`` of every block at ``stage``, on numba's threads unless ``parallel`` is
    None (the threaded loop is then not compiled)."""
    if parallel is not None:
        _blocks_parallel(blocks, stage)
    else:
        for j in range(blocks[6].size - 1):
            _block(blocks, j, stage)


@njit(cache=True, parallel=True)
def _blocks_parallel(blocks, stage):
    for j in prange(blocks[6].size - 1):
        _block(blocks, np.int64(j), stage)  # prange's index is unsigned: one signature


@njit(cache=True)
def _block(blocks, j, stage):
    """Block ``j`` at ``stage``: ``FACTOR`` (``_factor_block``, its ``info`` into
    ``infos[j]``), ``SUBSTITUTE`` (a solve's ``y_j = B_j^{-1} x_j``) or ``CORRECT``
    (``y_j -= W_j x_D'[T_j]``, ``x_D'`` the border's part of ``work``)."""
    (addresses, ab, ipiv, band, ints, work, starts, rows_ptr, rows, cols_ptr, cols, X,
     x_ptr, touch_ptr, touch, direct, E, F, W, e_ptr, parts, p_ptr, infos) = blocks
    start, end = starts[j], starts[j + 1]
    if stage == FACTOR:
        e, f, w = _local(blocks, j)
        t = touch_ptr[j + 1] - touch_ptr[j]
        infos[j] = _factor_block(
            addresses, ab, ipiv, band, ints[j], start, end, rows[rows_ptr[j]:rows_ptr[j + 1]],
            cols[cols_ptr[j]:cols_ptr[j + 1]], X[x_ptr[j]:x_ptr[j + 1]], e, f, w,
            direct[touch_ptr[j]:touch_ptr[j + 1]], parts[p_ptr[j]:p_ptr[j + 1]].reshape((t, t)))
    elif stage == SUBSTITUTE:
        band_substitute(ab[start:end], band, ipiv[start:end], work[start:end])
    else:
        w = _local(blocks, j)[2]
        near = touch[touch_ptr[j]:touch_ptr[j + 1]]
        y, g = work[start:end], work[ab.shape[0]:]
        for a in range(near.size):
            ga = g[near[a]]
            wa = w[a]
            for p in range(end - start):
                y[p] -= wa[p] * ga


def storage(addresses, rows, cols, perm, nb, band, order, threads=1):
    """The ``lu`` tuple for the CSR entries ``(rows, cols)`` (original indices) of an
    ``n x n`` matrix ordered by ``perm`` with ``nb`` band unknowns of half-width
    ``band``; ``order(pattern)`` gives ``(perm, nb, band)`` of the Schur complement's CSR
    ``pattern`` (over the border, in ``perm``'s order) for its own bordered band LU; with
    ``threads > 1`` and more than one block, the blocks are factored and solved on
    numba's threads."""
    n = perm.size
    k = n - nb
    ldab = 3 * band + 1
    if nb * ldab >= 2**31:
        raise ValueError(f"a band of {nb} unknowns and half-width {band} exceeds 2^31 "
                         "stored entries")
    iperm = np.empty_like(perm)
    iperm[perm] = np.arange(n)
    pr, pc = iperm[rows], iperm[cols]
    target = ((pc >= nb) + 2 * (pr >= nb)).astype(np.int8)  # 0: band, 1: E, 2: F, 3: S
    starts = bordered.blocks(pr, pc, nb)
    near = _Touch(starts, pr, pc, target, k)
    position = pc * ldab + 2 * band + pr - pc
    e, f, d = target == 1, target == 2, target == 3
    position[e] = near.e_position(pr[e], pc[e] - nb)
    position[f] = near.f_position(pc[f], pr[f] - nb)
    s_keys = np.unique(np.concatenate([(pr[d] - nb) * k + pc[d] - nb, near.part_keys]))
    position[d] = np.searchsorted(s_keys, (pr[d] - nb) * k + pc[d] - nb)
    pattern = _csr(s_keys, k)
    inner_perm, inner_nb, inner_band = order(pattern)
    inner = bordered.storage(addresses, s_keys // k, s_keys % k, inner_perm, inner_nb,
                             inner_band)
    units = near.cover(pr[e], pc[e] - nb)
    rows_ptr, unit_rows = bordered._grouped(units, starts)
    cols_ptr, coupling_cols = bordered._grouped(pc[f], starts)
    x_ptr = _pointers(np.diff(rows_ptr) * np.diff(starts))
    nblocks = starts.size - 1
    blocks = (addresses, np.zeros((nb, ldab)), np.zeros(nb, dtype=np.int32), int(band),
              np.zeros((max(nblocks, 1), 8), dtype=np.int32), np.zeros(n), starts, rows_ptr,
              unit_rows, cols_ptr, coupling_cols, np.zeros(x_ptr[-1]), x_ptr, near.ptr,
              near.touch, near.direct, np.zeros(near.e_ptr[-1]), np.zeros(near.e_ptr[-1]),
              np.zeros(near.e_ptr[-1]), near.e_ptr, np.zeros(near.p_ptr[-1]), near.p_ptr,
              np.zeros(nblocks, dtype=np.int64))
    return (blocks, perm.astype(np.int64), target, position.astype(np.int32),
            np.searchsorted(s_keys, near.part_keys).astype(np.int64), np.zeros(s_keys.size),
            inner, True if threads > 1 and nblocks > 1 else None)


def _pointers(sizes):
    return np.concatenate([[0], np.cumsum(sizes)]).astype(np.int64)


def _least_cover(graph):
    """Masks of the rows and columns of a least vertex cover of the bipartite graph of the
    CSR ``graph``'s entries (Koenig's theorem: the rows not reached from an unmatched row
    by alternating paths, and the columns reached)."""
    match = maximum_bipartite_matching(graph, perm_type="column")  # row -> column
    owner = np.full(graph.shape[1], -1)
    owner[match[match >= 0]] = np.flatnonzero(match >= 0)
    seen_rows = match < 0
    seen_cols = np.zeros(graph.shape[1], dtype=bool)
    frontier = list(np.flatnonzero(seen_rows))
    while frontier:
        row = frontier.pop()
        for col in graph.indices[graph.indptr[row]:graph.indptr[row + 1]]:
            if not seen_cols[col]:
                seen_cols[col] = True
                if owner[col] >= 0 and not seen_rows[owner[col]]:
                    seen_rows[owner[col]] = True
                    frontier.append(owner[col])
    return ~seen_rows, seen_cols


def _csr(keys, k):
    """The ``k x k`` CSR pattern of the sorted entries ``keys`` (``row * k + col``)."""
    return sp.csr_matrix((np.ones(keys.size), (keys // k, keys % k)), shape=(k, k))


class _Touch:
    """The border unknowns each block touches (``T_j``), the flat places of its ``E_j``,
    ``F_j``, ``W_j`` and of its part ``F_j W_j``, and the ``S`` entries of those parts."""

    def __init__(self, starts, pr, pc, target, k):
        nb = starts[-1]
        e, f = target == 1, target == 2
        block = np.concatenate([self._block(starts, pr[e]), self._block(starts, pc[f])])
        border = np.concatenate([pc[e], pr[f]]) - nb
        self.k, self.starts = k, starts
        self.keys = np.unique(block * k + border)
        self.ptr = np.searchsorted(self.keys // max(k, 1),
                                   np.arange(starts.size)).astype(np.int64)
        self.touch = (self.keys % max(k, 1)).astype(np.int64)
        self.t = np.diff(self.ptr)
        self.e_ptr = _pointers(self.t * np.diff(starts))
        self.p_ptr = _pointers(self.t**2)
        # part[a, r] of block j: the entry (T_j[r], T_j[a]) of S
        pairs = [np.add.outer(near * k, near).T.ravel() for near in
                 np.split(self.touch, self.ptr[1:-1])] if starts.size > 1 else []
        self.part_keys = np.concatenate(pairs + [np.zeros(0, dtype=np.int64)])

    @staticmethod
    def _block(starts, p):
        return np.searchsorted(starts, p, side="right") - 1

    def _local(self, p, c):
        """Block of band unknowns ``p``, their place in it, and the place of border
        unknowns ``c`` in the block's ``T_j``."""
        j = self._block(self.starts, p)
        return j, p - self.starts[j], np.searchsorted(self.keys, j * self.k + c) - self.ptr[j]

    def cover(self, p, c):
        """The band rows of a least cover of the entries ``E[p, c]``, block by block:
        ``E_j``'s columns ``W_j`` takes by a band solve each (marked in ``direct``) and its
        rows by a band solve of their unit column each (returned), the fewest solves that
        reach every entry (a least vertex cover of the bipartite graph of rows and
        columns, from a maximum matching: Koenig's theorem).  A tether joined to the hub
        through its pin's three rows and to the ring at its tip's three coordinates: six
        solves, where rows alone take twelve and columns alone fifteen."""
        j, local, a = self._local(p, c)
        self.direct = np.zeros(self.touch.size, dtype=np.int8)
        units = []
        for block in np.unique(j):
            mine = j == block
            rows, r = np.unique(p[mine], return_inverse=True)
            graph = sp.csr_matrix((np.ones(r.size), (r, a[mine])),
                                  shape=(rows.size, self.t[block]))
            left, right = _least_cover(graph)
            units.append(rows[left])
            self.direct[self.ptr[block] + np.flatnonzero(right)] = 1
        return np.concatenate(units + [np.zeros(0, dtype=np.int64)])

    def e_position(self, p, c):
        """Flat places of ``E[p, c]`` in ``E_j`` (``(|T_j|, n_j)``)."""
        j, local, a = self._local(p, c)
        return self.e_ptr[j] + a * np.diff(self.starts)[j] + local

    def f_position(self, p, c):
        """Flat places of ``F[c, p]`` in ``F_j`` (``(n_j, |T_j|)``)."""
        j, local, a = self._local(p, c)
        return self.e_ptr[j] + local * self.t[j] + a
