"""The working set of a Newton iteration (issue 47, linear cost at scale): the band
solves read the factor split into ``L`` and ``U`` (``kernels.band_sweeps.split``), with
the same results bit for bit as from LAPACK's storage; the mass matrix in the compact
form of the step (``FastCSR.strided``); the forces no term writes, left alone
(``Term.writes``); the exponent's measure (``benchmarks/step_exponent.py``)."""

import numpy as np
import pytest
import scipy.sparse as sp
from scipy.linalg import lapack

import skfem_cable as sc
from skfem_cable.core.contract import Term
from skfem_cable.core.linalg import FastCSR
from skfem_cable.kernels import band_sweeps
from skfem_cable.kernels.books import step_books
from skfem_cable.scenes import classics
from skfem_cable.solvers.galpha import GeneralizedAlpha


@pytest.fixture(scope="module", params=[False, True], ids=["no interchanges", "pivoting"])
def factored(request):
    """LAPACK's banded LU (``dgbtrf``, in ``kernels.lapack``'s layout: a row per column)
    of a random band of 40 unknowns and half-width 3: diagonally dominant (no row
    interchanges), or with tiny first diagonals (interchanges there), and its split."""
    n, band = 40, 3
    rng = np.random.default_rng(0)
    storage = np.zeros((3 * band + 1, n), order="F")
    storage[band:] = rng.standard_normal((2 * band + 1, n))
    storage[2 * band] += 0.0 if request.param else 4.0 * band
    if request.param:
        storage[2 * band, :3] = 1e-3
    A = sp.dia_matrix((storage[band:], np.arange(band, -band - 1, -1)), shape=(n, n))
    lu, pivots, info = lapack.dgbtrf(storage, band, band)
    assert info == 0
    ab, ipiv = np.ascontiguousarray(lu.T), (pivots + 1).astype(np.int32)
    lower, upper = np.zeros((n, band)), np.zeros((n, 2 * band + 1))
    band_sweeps.split(ab, band, lower, upper)
    return A.tocsr(), ab, ipiv, band, lower, upper, request.param


def test_split_solve_is_the_lapack_layout_solve_bit_for_bit(factored):
    """A solve from the split factor (``split_substitute``, what ``bordered.solve`` runs
    per block) gives the same bits as ``band_substitute`` on LAPACK's storage, and
    solves the system; with row interchanges (fill in ``U``) too."""
    A, ab, ipiv, band, lower, upper, pivoting = factored
    assert np.any(ipiv != np.arange(1, A.shape[0] + 1)) == pivoting
    rhs = np.linspace(-1.0, 2.0, A.shape[0])
    expected, x = rhs.copy(), rhs.copy()
    band_sweeps.band_substitute(ab, band, ipiv, expected)
    band_sweeps.split_substitute(lower, upper, band, ipiv, x)
    assert np.array_equal(x, expected)
    assert np.allclose(A @ x, rhs, rtol=0, atol=1e-10)


def test_split_holds_the_factor(factored):
    """``lower`` holds the multipliers and ``upper`` the rest of every column of LAPACK's
    storage."""
    _, ab, _, band, lower, upper, _ = factored
    assert np.array_equal(lower, ab[:, 2 * band + 1:])
    assert np.array_equal(upper, ab[:, :2 * band + 1])


def test_mass_of_three_alike_components_is_strided_and_the_same_product():
    """A mass ``M_s ⊗ I_3`` (a cable's: its nodes' vectors' components coupled alike) is
    found value for value (int32 indices, a third of the rows); a coupling across
    components keeps ``M`` itself (``k = 1``); the books' ``v . M v`` from the strided
    form (``kernels.books.mass_product``) is the CSR's bit for bit."""
    rng = np.random.default_rng(1)
    coarse = sp.random(8, 8, density=0.4, random_state=rng) + sp.eye(8)
    M = FastCSR(sp.kron(coarse + coarse.T, sp.eye(3)))
    indptr, indices, data, k = M.strided
    assert k == 3 and indices.dtype == np.int32 and indptr.size - 1 == M.shape[0] // 3
    v = np.linspace(-1.0, 1.0, M.shape[0])
    zero = np.zeros_like(v)
    written = (True, True)  # the damping and external forces read
    kinetic = step_books(zero, (zero,) * 3, (zero,) * 3, M.strided, zero, v, v, zero.copy(),
                         written)[2]
    reference = step_books(zero, (zero,) * 3, (zero,) * 3,
                           (M.indptr, M.indices, M.data, 1), zero, v, v, zero.copy(), written)[2]
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


def _pendulum_run(poison, steps=20):
    """An undamped pendulum of 8 elements (pinned, under gravity) after ``steps`` steps of
    1 ms; with ``poison``, NaN first in the step's arrays of the forces no term writes
    (``fd``, ``f_ext``)."""
    scene = classics.pendulum(n_elements=8)
    g = GeneralizedAlpha(scene.system, rho_inf=0.8)
    g.initialize(scene.initial.q, scene.initial.v, 0.0)
    arrays = g.compiled.arrays
    if poison:
        arrays["fd"][:] = arrays["f_ext"][:] = np.nan
    for _ in range(steps):
        assert g.step(1e-3)[0]
    return g, arrays


def test_the_step_leaves_alone_the_forces_no_term_writes():
    """The undamped cable's term declares ``writes=("f",)`` and gravity is a constant
    force: the compiled step neither clears nor reads ``fd`` and ``f_ext``
    (``Layout.writes``): NaN put there stays, and the state and the books after 20 steps
    are the same bits as without it (two passes fewer over a vector per iteration, four
    reads and two copies per step); the state's damping and external forces of the books
    stay zero.  ``C_q^T lam`` is cleared only where a constraint holds the coordinate
    (``Layout.constrained``) and stays zero elsewhere."""
    clean, _ = _pendulum_run(False)
    g, arrays = _pendulum_run(True)
    assert g.lay.writes == {"f"} and g.lay.constrained.tolist() == [0, 1, 2]
    assert np.isnan(arrays["fd"]).all() and np.isnan(arrays["f_ext"]).all()
    for name in ("q", "v", "a", "lam", "abar"):
        assert np.array_equal(getattr(g, name).view(np.int64),
                              getattr(clean, name).view(np.int64)), name
    assert g.energies() == clean.energies()
    assert not (g.fd.any() or g.fnc.any() or g.fcon[3:].any()) and g.fcon[:3].any()


def test_terms_declare_the_forces_they_write():
    """A damped cable writes ``f`` and ``f_damping``, an undamped rod (its cable's term
    and its twist kernel) ``f`` alone, a point load that varies in time ``f_ext`` alone
    (``Term.writes``): the layout takes their union; a term naming another accumulator is
    refused, with the accepted names."""
    damped = classics.pendulum(n_elements=4, gamma_axial=0.01).system
    assert damped.current_layout().writes == {"f", "f_damping"}
    section = sc.Section(E=1e3, A=1e-4, I=1e-6, rho=1e3, G=2e3, J=3e-6, I_edge=4e-6)
    rod = sc.Rod.straight([0, 0, 0], [1, 0, 0], 3, section, normal=[0, 0.3, 1])
    assert sc.System([rod]).current_layout().writes == {"f"}
    pushed = classics.pendulum(n_elements=4).system
    cable = pushed.bodies[0]
    pushed.add_load(sc.PointLoad(cable.node(-1), lambda t: [0.0, 0.0, np.sin(t)]))
    assert pushed.current_layout().writes == {"f", "f_ext"}
    with pytest.raises(ValueError, match=r"writes must name accumulators of \('f', "
                                         r"'f_damping', 'f_ext'\), got \('f', 'force'\)"):
        Term(add=lambda ev, index: None, writes=("f", "force"), name="bad")
