"""The working set of a Newton iteration (issue 47, linear cost at scale): the band
solves read a compact copy of the factor (``kernels.bordered.compact``), with the same
results bit for bit as from LAPACK's storage."""

import numpy as np
import pytest
import scipy.sparse as sp

from skfem_cable.core.linalg import ADDRESSES
from skfem_cable.kernels import bordered


def _band_matrix(n, band, pivoting, seed=0):
    """A random band matrix of half-width ``band``; with ``pivoting`` its first rows
    have tiny diagonals (LAPACK interchanges rows there), else it is diagonally
    dominant (no interchanges)."""
    rng = np.random.default_rng(seed)
    diagonals = [rng.standard_normal(n - abs(k)) for k in range(-band, band + 1)]
    A = sp.diags(diagonals, list(range(-band, band + 1)), format="lil")
    A.setdiag(A.diagonal() + 4.0 * band)
    if pivoting:
        for i in range(3):
            A[i, i] = 1e-3
    return A.tocsr()


@pytest.fixture(scope="module", params=[False, True], ids=["no interchanges", "pivoting"])
def factored(request):
    """A factored bordered storage of a band of 40 unknowns, half-width 3, no border."""
    n, band = 40, 3
    A = _band_matrix(n, band, request.param)
    rows = np.repeat(np.arange(n), np.diff(A.indptr))
    lu = bordered.storage(ADDRESSES, rows, A.indices, np.arange(n), n, band)
    assert bordered.factor(lu, A.data) == -1
    return A, lu, request.param


def test_compact_solve_is_the_lapack_layout_solve_bit_for_bit(factored):
    """A solve from the compact copy gives the same bits as ``band_substitute`` on
    LAPACK's storage, and solves the system; the fill of the pivoting is found in the
    first columns only (none without interchanges)."""
    A, lu, pivoting = factored
    ab, ipiv, band, fills = lu[1], lu[2], lu[11], lu[26]
    assert (fills[0] > 0) == pivoting and fills[0] < A.shape[0] // 2
    rhs = np.linspace(-1.0, 2.0, A.shape[0])
    expected = rhs.copy()
    bordered.band_substitute(ab, band, ipiv, expected)
    x = np.empty_like(rhs)
    bordered.solve(lu, rhs, x)
    assert np.array_equal(x, expected)
    assert np.allclose(A @ x, rhs, rtol=0, atol=1e-10)


def test_compact_copy_holds_the_factor_without_the_fill(factored):
    """``lower`` holds the multipliers and ``upper`` the diagonal and ``band``
    superdiagonals of every column of LAPACK's storage."""
    _, lu, _ = factored
    ab, band, lower, upper = lu[1], lu[11], lu[24], lu[25]
    assert np.array_equal(lower, ab[:, 2 * band + 1:])
    assert np.array_equal(upper, ab[:, band:2 * band + 1])
