"""Bordered band LU: independent bands plus a few dense border rows and columns (an
arrowhead), for numba-compiled code and Python alike, its blocks on threads on request.

In the ordering ``perm`` the matrix is ``[[B, E], [F, D]]``: ``B`` (``nb x nb``) a band of
half-width ``band``, ``k`` border unknowns last (the coordinates of a hub joined to many
bodies, and the multipliers of its own constraints).  ``B`` falls apart into *blocks*,
diagonal blocks ``B_j`` that no entry couples (the tethers of an E-sail, each with its
pin's multipliers), each touching the border through a few *coupling* rows ``R_j``
(where ``E`` has entries) and columns (where ``F`` has), factored and solved by
``kernels.band_blocks`` (on numba's threads when the storage is made with ``threads >
1``), which sums ``S = D - sum_j F_j W_j`` in the order of the blocks (so that every
result is the same whatever the number of threads); ``W_j = B_j^{-1} E_j = X_j E[R_j]``
from ``X_j = B_j^{-1} P_j`` for the unit columns ``P_j`` of its coupling rows (a few band
solves, not one per border column), or, where the coupling rows outnumber the border (the
ring of tips of ``kernels.schur``'s second level, every tip joined to the hub), by a band
solve per border column.  ``S`` is dense here: LAPACK's LU.  A solve:

    y = B^{-1} x_B,   x_D' = S^{-1} (x_D - F y),   x_B' = y - W x_D'.

With ``k = 0`` it is the banded LU of the blocks alone.  All storage is made once
(``storage``, for ``linalg``): ``lu = (front, S, ipiv_s, parallel)``: the blocks'
storage (``kernels.band_blocks``), whose ``s_data`` is ``S`` flat, ``S`` column-major
``(k, k)`` and its pivots, ``True`` if the blocks run on threads, else ``None``.
"""

import numpy as np
from numba import njit

from . import band_blocks, band_layout
from .band_layout import storage as blocks_storage
from .lapack import dense_factor, dense_solve


@njit(cache=True)
def factor(lu, data):
    """Factor the matrix with CSR values ``data``; returns the (original) unknown of a
    zero pivot (the first block's, in the ordering), or -1."""
    front, S, ipiv_s, parallel = lu
    at = band_blocks.factor(front, data, parallel)
    if at >= 0 or S.shape[0] == 0:
        return at
    blocks = front[0]
    info = dense_factor(blocks[0], S, ipiv_s, blocks[4])
    if info > 0:
        return front[1][blocks[1].shape[0] + info - 1]
    return -1


@njit(cache=True)
def solve(lu, rhs, out):
    """``out = A^{-1} rhs`` with the last factorisation (original ordering)."""
    front, S, ipiv_s, parallel = lu
    g = band_blocks.substitute(front, rhs, parallel)
    if S.shape[0]:
        blocks = front[0]
        dense_solve(blocks[0], S, ipiv_s, g, blocks[4])
    band_blocks.correct(front, out, parallel)


def storage(addresses, rows, cols, perm, nb, band, threads=1):
    """The ``lu`` tuple for the CSR entries ``(rows, cols)`` (original indices) of an
    ``n x n`` matrix ordered by ``perm`` with ``nb`` band unknowns of half-width
    ``band``; with ``threads > 1`` and more than one block, the blocks are factored and
    solved on numba's threads."""
    n = perm.size
    k = n - nb
    if max(nb * (3 * band + 1), n * k) >= 2**31:
        raise ValueError(f"a band of {nb} unknowns and half-width {band} with {k} border "
                         "unknowns exceeds 2^31 stored entries")
    iperm = np.empty_like(perm)
    iperm[perm] = np.arange(n)
    pr, pc = iperm[rows], iperm[cols]
    blocks, target, position, near, parallel = blocks_storage(addresses, pr, pc, n, nb,
                                                              band, least=False,
                                                              threads=threads)
    d = target == 3  # S column-major: S[c, r] the entry (r, c)
    position[d] = ((pc[d] - nb) * k + pr[d] - nb).astype(np.int32)
    keys = near.part_keys  # part[a, r] of a block: the entry (T[r], T[a])
    S = np.zeros((k, k))
    front = (blocks, perm.astype(np.int64), target, position,
             ((keys % max(k, 1)) * k + keys // max(k, 1)).astype(np.int64), S.ravel())
    return front, S, np.zeros(k, dtype=np.int32), parallel


def renewed(lu):
    """The ``lu`` of ``storage`` with fresh work arrays (``band_layout.renewed``, ``S``
    and its pivots) around the same plan: another solver's of the same pattern."""
    front, S, ipiv_s, parallel = lu
    S = band_layout.zeros(S)
    return ((band_layout.renewed(front[0]), *front[1:5], S.ravel()), S,
            band_layout.zeros(ipiv_s), parallel)
