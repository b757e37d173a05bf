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
``|T_j| x |T_j|`` matrix with the places of its entries in ``S`` (precomputed): the
block elimination of the bordered band (Golub & Van Loan, Matrix Computations, 4th ed.,
2013, sec. 4.5.4 (block tridiagonal/arrow systems); Saad, Iterative Methods for Sparse
Linear Systems, 2nd ed., 2003, eq. (14.9), the Schur complement of a domain
decomposition) of ``kernels.band_blocks``, the blocks at once on numba's threads when the
storage is made with ``threads > 1``;
then, in the order of the blocks (the same sum whatever the number of threads),
``S = D - sum_j F_j W_j`` on S's *sparse* pattern, factored one level down by the bordered
band LU of ``kernels.bordered``: S's unknowns ordered by reverse Cuthill-McKee (a ring of
tips interleaved: a band of about two tips) with the hub's unknowns its dense border.
Without a ring (one level: an E-sail's tethers joined to the hub alone) S would be the
hub's, all dense border: ``linalg.PatternSolver`` then takes ``kernels.bordered`` itself.
A solve:

    y = B^{-1} x_B,   x_D' = S^{-1} (x_D - F y),   x_B' = y - W x_D'.

All storage is made once (``storage``): ``lu = (front, inner, parallel)``: the blocks'
storage (``kernels.band_blocks``, the same type as ``kernels.bordered``'s: the blocks'
kernels compile once for both), ``W_j`` by the fewest band solves
(``band_layout.Touch.cover``), ``s_data`` the CSR values of ``S``; ``inner``, the
``kernels.bordered`` storage of ``S``; ``True`` if the blocks run on threads, else
``None`` (numba prunes a branch on ``None``: on one thread the threaded loops are
neither compiled nor linked into the Newton step).
"""

import numpy as np
import scipy.sparse as sp
from numba import njit

from . import band_blocks, band_layout, bordered
from .band_layout import storage as blocks_storage


@njit(cache=True)
def factor(lu, data):
    """Factor the matrix with CSR values ``data``; returns the (original) unknown of a
    zero pivot (the first block's, in the ordering), or -1."""
    front, inner, parallel = lu
    at = band_blocks.factor(front, data, parallel)
    s_data = front[5]
    if at >= 0 or s_data.size == 0:
        return at
    at = bordered.factor(inner, s_data)
    return front[1][front[0][1].shape[0] + at] if at >= 0 else -1


@njit(cache=True)
def solve(lu, rhs, out):
    """``out = A^{-1} rhs`` with the last factorisation (original ordering)."""
    front, inner, parallel = lu
    g = band_blocks.substitute(front, rhs, parallel)
    if g.size:
        bordered.solve(inner, g, g)
    band_blocks.correct(front, out, parallel)


def storage(addresses, rows, cols, perm, nb, band, order, threads=1):
    """The ``lu`` tuple for the CSR entries ``(rows, cols)`` (original indices) of an
    ``n x n`` matrix ordered by ``perm`` with ``nb`` band unknowns of half-width
    ``band``; ``order(pattern)`` gives ``(perm, nb, band)`` of the Schur complement's CSR
    ``pattern`` (over the border, in ``perm``'s order) for its own bordered band LU; with
    ``threads > 1`` and more than one block, the blocks are factored and solved on
    numba's threads."""
    n = perm.size
    k = n - nb
    iperm = np.empty_like(perm)
    iperm[perm] = np.arange(n)
    pr, pc = iperm[rows], iperm[cols]
    blocks, target, position, near, parallel = blocks_storage(addresses, pr, pc, n, nb,
                                                              band, least=True,
                                                              threads=threads)
    d = target == 3
    s_keys = np.unique(np.concatenate([(pr[d] - nb) * k + pc[d] - nb, near.part_keys]))
    position[d] = np.searchsorted(s_keys, (pr[d] - nb) * k + pc[d] - nb)
    inner_perm, inner_nb, inner_band = order(_csr(s_keys, k))
    inner = bordered.storage(addresses, s_keys // k, s_keys % k, inner_perm, inner_nb,
                             inner_band)
    front = (blocks, perm.astype(np.int64), target, position,
             np.searchsorted(s_keys, near.part_keys).astype(np.int64), np.zeros(s_keys.size))
    return front, inner, parallel


def renewed(lu):
    """The ``lu`` of ``storage`` with fresh work arrays (``band_layout.renewed``, the
    values of ``S``, the inner LU's, ``bordered.renewed``) around the same plan: another
    solver's of the same pattern."""
    front, inner, parallel = lu
    return ((band_layout.renewed(front[0]), *front[1:5], band_layout.zeros(front[5])),
            bordered.renewed(inner), parallel)


def _csr(keys, k):
    """The ``k x k`` CSR pattern of the sorted entries ``keys`` (``row * k + col``)."""
    return sp.csr_matrix((np.ones(keys.size), (keys // k, keys % k)), shape=(k, k))
