"""The working set of a Newton iteration (issue 47, linear cost at scale): the band
solves read the factor split into ``L`` and ``U`` (``kernels.bordered.split``), with
the same results bit for bit as from LAPACK's storage; the mass matrix in the compact
form of the step (``FastCSR.strided``); the exponent's measure
(``benchmarks/step_exponent.py``)."""

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


def test_split_solve_is_the_lapack_layout_solve_bit_for_bit(factored):
    """A solve from the split factor gives the same bits as ``band_substitute`` on
    LAPACK's storage, and solves the system; with interchanges (fill in ``U``) too."""
    A, lu, pivoting = factored
    ab, ipiv, band = lu[1], lu[2], lu[11]
    assert np.any(ipiv != np.arange(1, A.shape[0] + 1)) == pivoting
    rhs = np.linspace(-1.0, 2.0, A.shape[0])
    expected = rhs.copy()
    bordered.band_substitute(ab, band, ipiv, expected)
    x = np.empty_like(rhs)
    bordered.solve(lu, rhs, x)
    assert np.array_equal(x, expected)
    assert np.allclose(A @ x, rhs, rtol=0, atol=1e-10)


def test_split_holds_the_factor(factored):
    """``lower`` holds the multipliers and ``upper`` the rest of every column of LAPACK's
    storage."""
    _, lu, _ = factored
    ab, band, lower, upper = lu[1], lu[11], lu[23], lu[24]
    assert np.array_equal(lower, ab[:, 2 * band + 1:])
    assert np.array_equal(upper, ab[:, :2 * band + 1])


def test_mass_of_cables_is_strided_and_the_same_product():
    """A pendulum's mass is ``M_s ⊗ I_3`` value for value (int32 indices, a third of the
    rows); a mass with a coupling across components stays itself (``k = 1``); the step's
    row products (``kernels.books.mass_rows``) are ``M x`` bit for bit."""
    from skfem_cable.core.linalg import FastCSR
    from skfem_cable.kernels.books import step_books
    from skfem_cable.scenes import classics

    M = classics.pendulum(n_elements=6).system.current_layout().mass
    indptr, indices, data, k = M.strided
    assert k == 3 and indices.dtype == np.int32 and indptr.size - 1 == M.shape[0] // 3
    v = np.linspace(-1.0, 1.0, M.shape[0])
    zero = np.zeros_like(v)
    kinetic = step_books(zero, (zero,) * 3, (zero,) * 3, M.strided, zero, v, v)[2]
    reference = step_books(zero, (zero,) * 3, (zero,) * 3,
                           (M.indptr, M.indices, M.data, 1), zero, v, v)[2]
    assert kinetic == reference
    assert kinetic == pytest.approx(0.5 * float(v @ (M @ v)), rel=1e-12)
    skew = M.scipy.tolil()
    skew[0, 1] = 1e-3
    assert FastCSR(skew).strided[3] == 1


def test_exponent_halves_are_the_minima_of_even_and_odd_rounds():
    """``step_exponent.exponents``: the slopes of the minima over the even and over the
    odd rounds; equal on an exact power law, apart where only the even rounds were
    slowed at the largest size all along (a spell no minimum removes)."""
    from test_benchmarks import BENCH, load

    exponent = load(BENCH / "step_exponent.py")
    sizes = np.array([1000, 3200, 10000])
    steps, chunk = 40, 20
    times = np.empty((4, sizes.size, steps // chunk))
    times[:] = (chunk * 1e-3 * (sizes / 1000) ** 1.01)[:, None]
    even, odd = exponent.exponents(sizes, times, np.full(3, 2.4 * steps), steps)["halves"]
    assert abs(even - 1.01) < 1e-12 and abs(odd - 1.01) < 1e-12
    times[0::2, -1] *= 1.2
    even, odd = exponent.exponents(sizes, times, np.full(3, 2.4 * steps), steps)["halves"]
    assert abs(odd - 1.01) < 1e-12 and even > odd + 0.05
