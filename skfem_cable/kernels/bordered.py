"""Bordered band LU: a band plus a few dense border rows and columns (an arrowhead), for
numba-compiled code and Python alike.

In the ordering ``perm`` the matrix is ``[[B, E], [F, D]]``: ``B`` (``nb x nb``) a band of
half-width ``band``, ``k`` border unknowns last (the coordinates of a hub joined to many
bodies, and the multipliers of its own constraints).  The factorisation is LAPACK's banded
LU of ``B``, ``W = B^{-1} E`` and the dense LU of the Schur complement ``S = D - F W``;
a solve is one banded solve, two products with the border and one dense solve:

    y = B^{-1} x_B,   x_D' = S^{-1} (x_D - F y),   x_B' = y - W x_D'.

With ``k = 0`` it is the banded LU alone.  All storage is made once (``linalg``):

``lu = (addresses, ab, ipiv, E, F, W, S, ipiv_s, target, position, perm, band, ints,
work)``: LAPACK addresses; the band (``kernels.lapack`` layout) and its pivots; ``E``
and ``F`` column-major, as ``(k, nb)`` and ``(nb, k)`` arrays whose rows are the blocks'
columns (the products of a solve run along them); ``W`` like ``E``; ``S`` column-major
``(k, k)`` and its pivots; for every CSR value of the matrix its block (int8; 0: band,
1: E, 2: F, 3: D) and flat position there (int32: the factor's scatter reads them at every
factorization); the ordering; the half-width; int32 scratch (8) and
float scratch (n).
"""

import numpy as np
from numba import njit

from .lapack import band_factor, band_solve, dense_factor, dense_solve


@njit(cache=True)
def factor(lu, data):
    """Factor the matrix with CSR values ``data``; returns the (original) unknown of a
    zero pivot, or -1."""
    addresses, ab, ipiv, E, F, W, S, ipiv_s, target, position, perm, band, ints, work = lu
    nb, k = ab.shape[0], S.shape[0]
    ab[:] = 0.0
    E[:] = 0.0
    F[:] = 0.0
    S[:] = 0.0
    flat_ab, flat_e, flat_f, flat_s = ab.ravel(), E.ravel(), F.ravel(), S.ravel()
    for p in range(data.size):
        where = target[p]
        if where == 0:
            flat_ab[position[p]] = data[p]
        elif where == 1:
            flat_e[position[p]] = data[p]
        elif where == 2:
            flat_f[position[p]] = data[p]
        else:
            flat_s[position[p]] = data[p]
    info = band_factor(addresses, ab, band, band, ipiv, ints)
    if info > 0:
        return perm[info - 1]
    if k == 0:
        return -1
    for c in range(k):  # W = E (a loop: numba compiles a formatted error for a slice copy)
        for p in range(nb):
            W[c, p] = E[c, p]
    band_solve(addresses, ab, band, band, ipiv, W, ints)
    for c in range(k):  # S = D - F W, column c (row c of the column-major storage)
        for r in range(k):
            acc = 0.0
            for p in range(nb):
                acc += F[p, r] * W[c, p]
            S[c, r] -= acc
    info = dense_factor(addresses, S, ipiv_s, ints)
    if info > 0:
        return perm[nb + info - 1]
    return -1


@njit(cache=True)
def solve(lu, rhs, out):
    """``out = A^{-1} rhs`` with the last factorisation (original ordering)."""
    addresses, ab, ipiv, E, F, W, S, ipiv_s, target, position, perm, band, ints, work = lu
    nb, k = ab.shape[0], S.shape[0]
    for i in range(perm.size):
        work[i] = rhs[perm[i]]
    y = work[:nb]
    band_substitute(ab, band, ipiv, y)
    if k:
        g = work[nb:]
        for p in range(nb):
            yp = y[p]
            row = F[p]
            for r in range(k):
                g[r] -= row[r] * yp
        dense_solve(addresses, S, ipiv_s, g, ints)
        for c in range(k):
            for p in range(nb):
                y[p] -= W[c, p] * g[c]
    for i in range(perm.size):
        out[perm[i]] = work[i]


@njit(cache=True)
def band_substitute(ab, band, ipiv, b):
    """``b = B^{-1} b`` in place with the banded LU of ``band_factor`` (half-widths
    ``band``): LAPACK's ``dgbtrs`` for one right-hand side, as loops over contiguous
    slices.  ``dgbtrs`` makes a BLAS call per column; for the narrow bands of cables these
    loops take half its time (15 against 30 us for the E-sail's 468 band unknowns of
    half-width 13)."""
    n = ab.shape[0]
    kv = 2 * band
    for j in range(n - 1):  # L: the row interchanges and multipliers of column j
        lm = min(band, n - j - 1)
        p = ipiv[j] - 1
        bj = b[p]
        if p != j:
            b[p] = b[j]
            b[j] = bj
        multipliers = ab[j, kv + 1: kv + 1 + lm]
        below = b[j + 1: j + 1 + lm]
        for i in range(lm):
            below[i] -= multipliers[i] * bj
    for j in range(n - 1, -1, -1):  # U: 2 band superdiagonals (fill-in of the pivoting)
        bj = b[j] / ab[j, kv]
        b[j] = bj
        m = min(j, kv)
        column = ab[j, kv - m: kv]
        above = b[j - m: j]
        for i in range(m):
            above[i] -= column[i] * bj


def storage(addresses, rows, cols, perm, nb, band):
    """The ``lu`` tuple for the CSR entries ``(rows, cols)`` (original indices) of an
    ``n x n`` matrix ordered by ``perm`` with ``nb`` band unknowns of half-width
    ``band``."""
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
    return (addresses, np.zeros((nb, ldab)), np.zeros(nb, dtype=np.int32),
            np.zeros((k, nb)), np.zeros((nb, k)), np.zeros((k, nb)), np.zeros((k, k)),
            np.zeros(k, dtype=np.int32), target, position.astype(np.int32),
            perm.astype(np.int64), int(band), np.zeros(8, dtype=np.int32), np.zeros(n))
