"""LAPACK's banded LU and its solves of one right-hand side as loops, for numba-compiled
code: the factorization (``band_lu``, LAPACK's ``dgbtf2``), the solves from LAPACK's storage
(``band_substitute``) or from the factor split into its multipliers and ``U``
(``split``, ``split_substitute``), which the band LUs of ``kernels.band_blocks`` read, one
block or two interleaved (``pair_substitute``).  All the same operations as LAPACK's, bit
for bit.

**The factorization is LAPACK's own, without its calls.**  ``dgbtrf`` factors a band
narrower than its block size (32) column by column (``dgbtf2``): per column a BLAS call
to find the pivot, one to swap the rows, one to scale the multipliers and a rank-one
update (``dger``), which OpenBLAS runs as one ``daxpy`` per column of the update, with
fused multiply-adds (its kernels for x86-64 with FMA).  For a cable's band of half-width
11 the calls cost more than their arithmetic: ``band_lu`` does the same operations in the
same order (the update with fused multiply-adds, ``_fma``), scipy's factor and pivots bit
for bit where its OpenBLAS fuses (elsewhere the same factor up to round-off, and the
same on every machine; ``tests/test_compiled.py`` checks the pivots and the factor to
round-off), 2.2 times faster (the flexible
pendulum's 105 unknowns: 19.5 -> 8.8 us; CPU, a compiled loop).

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
factorizations).
"""

import numpy as np
from llvmlite import ir
from numba import njit, types
from numba.extending import intrinsic

#: The multipliers' offset in ``split``'s ``lower``: an ``np.int64``, not a literal 0, so
#: that the sweeps are compiled for one type of offset, that of LAPACK's storage
#: (``band_substitute``) too.
NO_OFFSET = np.int64(0)


@intrinsic
def _fma(typingctx, x, y, z):
    """``x * y + z`` rounded once (LLVM's ``fma``: the instruction where the machine has
    it), as OpenBLAS's ``daxpy``."""
    def codegen(context, builder, signature, args):
        double = ir.DoubleType()
        fma = builder.module.declare_intrinsic("llvm.fma", [double],
                                               ir.FunctionType(double, [double] * 3))
        return builder.call(fma, args)

    return types.float64(types.float64, types.float64, types.float64), codegen


@njit(cache=True)
def band_lu(ab, band, ipiv):
    """LU-factor the band ``ab`` (half-widths ``band``, the ``kernels.lapack`` layout: row
    ``j`` holds column ``j`` of LAPACK's storage) in place with row interchanges, as
    ``dgbtf2``, the same operations in the same order; ``ipiv`` its pivots (1-based).
    Returns LAPACK's ``info`` (``> 0``: the first zero pivot's 1-based column).

    Indices as ``np.uint64`` where they are not a ``range``'s from 0: numba tests a signed
    index for wrap-around at every read (the update's loop 30 % slower)."""
    n = ab.shape[0]
    kv = 2 * band
    for j in range(band + 1, min(kv, n)):  # the fill-in of the first columns zero
        for i in range(kv - j, band):
            ab[j, i] = 0.0
    last = info = 0  # the last column the eliminations so far reached
    for j in range(n):
        if j + kv < n:
            for i in range(band):
                ab[j + kv, i] = 0.0
        below = min(band, n - 1 - j)
        column = ab[j]
        p = 0  # the pivot: the first largest magnitude (idamax)
        for i in range(1, below + 1):
            if abs(column[np.uint64(kv + i)]) > abs(column[np.uint64(kv + p)]):
                p = i
        ipiv[j] = p + j + 1
        if column[np.uint64(kv + p)] == 0.0:
            info = info or j + 1
            continue
        last = max(last, min(j + band + p, n - 1))
        if p != 0:  # swap rows j and j + p over columns j..last (dswap)
            for c in range(last - j + 1):
                row, a, b = ab[j + c], np.uint64(kv + p - c), np.uint64(kv - c)
                row[a], row[b] = row[b], row[a]
        if below == 0:
            continue
        scale = 1.0 / column[np.uint64(kv)]  # the multipliers (dscal)
        for i in range(1, below + 1):
            column[np.uint64(kv + i)] *= scale
        for c in range(1, last - j + 1):  # the rank-one update (dger), column by column
            row, top = ab[j + c], np.uint64(kv - c)
            y = -row[top]
            if y != 0.0:  # the reference BLAS's test (OpenBLAS adds 0 x: the same values)
                for i in range(1, below + 1):
                    u = np.uint64(i)
                    row[top + u] = _fma(column[np.uint64(kv) + u], y, row[top + u])
    return info


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
