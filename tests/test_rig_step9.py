"""The windless E-sail rig's step made cheaper bit for bit (issue 47, item 2).

The band solve's border correction vectorised (``kernels.bordered._block``), the mass
of a system with point masses in the strided form of the step (``FastCSR.strided``
leaves stored zeros out), and what else the step lost: each check here is of the
arithmetic (the same bits as before), on small matrices and no compiled step."""

import numpy as np
import scipy.sparse as sp

from skfem_cable.core.linalg import FastCSR
from skfem_cable.kernels.books import csr_product, step_books


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
    books = step_books(zero, (zero,) * 3, (zero,) * 3, M.strided, zero, x, x, zero.copy())
    reference = step_books(zero, (zero,) * 3, (zero,) * 3, (M.indptr, M.indices, M.data, 1),
                           zero, x, x, zero.copy())
    mv = np.empty_like(x)
    step_books(zero, (zero,) * 3, (zero,) * 3, M.strided, zero, x, x, mv)
    assert np.array_equal(mv.view(np.int64), general.view(np.int64))
    assert books == reference
