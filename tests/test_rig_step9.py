"""The windless E-sail rig's step made cheaper bit for bit (issue 47, item 2).

The band solve's blocks substituted two at a time (``kernels.band_sweeps.pair_substitute``)
and its border correction vectorised (``kernels.band_blocks._block``), the mass
of a system with point masses in the strided form of the step (``FastCSR.strided``
leaves stored zeros out), the mass and CSR products without wrap-around tests
(``kernels.books``) and the constraint forces scattered from the rows of ``C``
(``kernels.step._constraints``): each check here is of the arithmetic (the same bits as
before), on small matrices and three steps of three joined cables."""

import numpy as np
import pytest
import scipy.sparse as sp
from scipy.linalg import lapack

import skfem_cable as sc
from skfem_cable.core.linalg import FastCSR
from skfem_cable.kernels import band_sweeps
from skfem_cable.kernels.books import csr_product, step_books
from skfem_cable.solvers.galpha import GeneralizedAlpha


def _mass_with_stored_zeros():
    """A cable-like ``M_s ⊗ I_3`` plus a point mass on its last node stored as a dense
    ``m I_3`` block (six stored zeros), as ``System.mass_matrix`` gives a tip mass."""
    rng = np.random.default_rng(3)
    coarse = sp.random(6, 6, density=0.5, random_state=rng)
    cable = sp.kron(coarse + coarse.T + 2.0 * sp.eye(6), sp.eye(3)).tocoo()
    tip = np.arange(15, 18)
    rows, cols = np.repeat(tip, 3), np.tile(tip, 3)
    values = 1.5 * np.eye(3).ravel()
    coo = sp.coo_matrix((np.concatenate([cable.data, values]),
                         (np.concatenate([cable.row, rows]), np.concatenate([cable.col, cols]))),
                        shape=cable.shape)
    return FastCSR(coo.tocsr())


def test_stored_zeros_leave_the_mass_strided_and_its_products_the_same_bits():
    """A point mass stored with its zeros no longer keeps the general form (``k = 1``):
    the strided form leaves them out, and ``M x`` and the books' ``v . M v`` are the
    general CSR's bit for bit (a sum from ``+0`` never holds ``-0``: ``0 x`` changes no
    bit of it), signed zeros in ``x`` included."""
    M = _mass_with_stored_zeros()
    assert (M.data == 0.0).sum() > 0
    indptr, indices, data, k = M.strided
    assert k == 3 and indptr.size - 1 == M.shape[0] // 3 and (data != 0.0).all()
    x = np.linspace(-1.0, 1.0, M.shape[0])
    x[::4] = -0.0
    general = csr_product(M.indptr, M.indices, M.data, x, np.empty(M.shape[0]))
    zero = np.zeros_like(x)
    written = (True, True)  # the damping and external forces read
    books = step_books(zero, (zero,) * 3, (zero,) * 3, M.strided, zero, x, x, zero.copy(),
                       written)
    reference = step_books(zero, (zero,) * 3, (zero,) * 3, (M.indptr, M.indices, M.data, 1),
                           zero, x, x, zero.copy(), written)
    mv = np.empty_like(x)
    step_books(zero, (zero,) * 3, (zero,) * 3, M.strided, zero, x, x, mv, written)
    assert np.array_equal(mv.view(np.int64), general.view(np.int64))
    assert books == reference


def _split_factor(n, band, seed):
    """The split banded LU (``band_sweeps.split``) of a random band of ``n`` unknowns and
    half-width ``band`` with tiny first diagonals (row interchanges there)."""
    rng = np.random.default_rng(seed)
    storage = np.zeros((3 * band + 1, n), order="F")
    storage[band:] = rng.standard_normal((2 * band + 1, n))
    storage[2 * band, :3] = 1e-3
    lu, pivots, info = lapack.dgbtrf(storage, band, band)
    assert info == 0
    ab, ipiv = np.ascontiguousarray(lu.T), (pivots + 1).astype(np.int32)
    assert np.any(ipiv != np.arange(1, n + 1))
    lower, upper = np.zeros((n, band)), np.zeros((n, 2 * band + 1))
    band_sweeps.split(ab, band, lower, upper)
    return lower, upper, ipiv


@pytest.mark.parametrize("sizes", [(40, 40), (40, 27), (9, 33)])
def test_two_blocks_substituted_together_are_each_alone_bit_for_bit(sizes):
    """``pair_substitute`` interleaves the sweeps of two blocks (equal sizes, the longer
    first or second); each block's result is its ``split_substitute`` byte for byte."""
    band = 3
    (la, ua, pa), (lb, ub, pb) = (_split_factor(n, band, n) for n in sizes)
    a, b = np.linspace(-1.0, 2.0, sizes[0]), np.cos(np.arange(sizes[1]))
    expected_a, expected_b = a.copy(), b.copy()
    band_sweeps.split_substitute(la, ua, band, pa, expected_a)
    band_sweeps.split_substitute(lb, ub, band, pb, expected_b)
    band_sweeps.pair_substitute(la, ua, pa, a, lb, ub, pb, b, band)
    assert np.array_equal(a.view(np.int64), expected_a.view(np.int64))
    assert np.array_equal(b.view(np.int64), expected_b.view(np.int64))


def test_constraint_forces_scattered_from_the_rows_are_the_transpose_product():
    """``kernels.step._constraints`` scatters ``C_q^T lam`` from the rows of ``C``; on
    three cables pinned together at one node (its coordinates take terms from two rows
    each) the step's ``f_con`` is the transpose's row-by-row product (``FastCSR @``, the
    sums as the step made them before) byte for byte."""
    sec = sc.Section.circular(radius=0.01, E=7e10, rho=7800.0)
    a = sc.Cable.straight([0, 0, 0], [1.0, 0, 0], 2, sec, name="a")
    b = sc.Cable.straight([1.0, 0, 0], [1.0, -1.0, 0], 2, sec, name="b")
    c = sc.Cable.straight([1.0, 0, 0], [2.0, 0, 0], 2, sec, name="c")
    system = sc.System([a, b, c]).pin(a.node(0)).add_gravity([0, -9.81, 0])
    system.pin(b.node(0), a.node(-1)).pin(c.node(0), a.node(-1))
    g = GeneralizedAlpha(system, rho_inf=0.8)
    g.initialize(system.q0, np.zeros(system.n_dofs), 0.0)
    for _ in range(3):
        assert g.step(1e-3)[0]
    lay, arrays = g.lay, g.compiled.arrays
    assert np.diff(lay.C_lin_T.indptr).max() >= 2  # sums of several terms
    expected = lay.C_lin_T @ arrays["lam1"][lay.lin_rows]
    assert np.any(expected != 0.0)
    assert np.array_equal(arrays["f_con"].view(np.int64), expected.view(np.int64))
