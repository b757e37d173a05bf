"""One block loop for both banded LUs (issue 47, item 5: the test command in five
minutes): the bordered band LU (``kernels.bordered``) and the two-level Schur LU
(``kernels.schur``) hold their blocks in storage of one numba type, so the blocks'
kernels (``kernels.band_blocks``) compile once for both, and its per-stage dispatcher is
inlined by numba, not compiled as six functions."""

import numba
import numpy as np
import pytest
import scipy.sparse as sp

from skfem_cable.core.linalg import PatternSolver
from skfem_cable.kernels import band_blocks
from skfem_cable.kernels.band_layout import Touch, blocks


def arrowhead(sizes, k, seed):
    """A diagonally dominant matrix (CSR) of tridiagonal blocks of ``sizes`` and ``k``
    border unknowns last, joined to each block's first two unknowns (three rows of the
    first block: more coupling rows than border unknowns when ``k`` is 2)."""
    nb = sum(sizes)
    n = nb + k
    dense = np.zeros((n, n))
    start = 0
    for j, size in enumerate(sizes):
        for i in range(start, start + size):
            dense[i, max(i - 1, start):min(i + 2, start + size)] = 1.0
        rows = start + np.arange(3 if j == 0 else 2)
        dense[np.ix_(rows, np.arange(nb, n))] = dense[np.ix_(np.arange(nb, n), rows)] = 1.0
        start += size
    dense[nb:, nb:] = 1.0
    dense *= np.random.default_rng(seed).uniform(0.5, 1.0, dense.shape)
    dense[np.diag_indices(n)] = 10.0
    return sp.csr_matrix(dense), nb


def test_both_lus_hold_their_blocks_in_one_type():
    """Before: each LU had its own storage and its own copy of the block loops, compiled
    for each (bordered 25.9 s, schur 19.9 s of the last clean-clone suite).  Now the
    blocks' storage, ``front``, has one type: the one-level LU's, the two-level LU's and
    the two-level LU's inner (dense border) LU's."""
    A, nb = arrowhead((5, 6, 7, 4), 2, 0)
    border = np.arange(nb, A.shape[0])
    one = PatternSolver(A.indptr, A.indices, "banded", border=border)
    two = PatternSolver(A.indptr, A.indices, "banded", border=border[:1],
                        junctions=border[1:])
    assert (one.levels, two.levels) == (1, 2)
    kinds = {numba.typeof(one.lu[0]), numba.typeof(two.lu[0]), numba.typeof(two.lu[1][0])}
    assert len(kinds) == 1


def test_the_bordered_lu_keeps_its_choice_of_band_solves():
    """``W_j`` by a band solve of each coupling row's unit column where a block has at
    most ``k`` coupling rows, else by a band solve per border column (the bordered LU's
    rule, kept: its results are the same bits); the two-level LU takes a least cover."""
    A, nb = arrowhead((5, 6), 2, 1)
    coo = A.tocoo()
    pr, pc = coo.row, coo.col
    target = ((pc >= nb) + 2 * (pr >= nb)).astype(np.int8)
    e = target == 1
    starts = blocks(pr, pc, nb)
    by_count = Touch(starts, pr, pc, target, 2)
    units = by_count.cover_by_count(pr[e], pc[e] - nb)
    np.testing.assert_array_equal(units, [5, 6])  # the second block: its two rows
    np.testing.assert_array_equal(by_count.direct, [1, 1, 0, 0])  # the first: columns
    least = Touch(starts, pr, pc, target, 2)
    assert least.cover(pr[e], pc[e] - nb).size + least.direct.sum() == 4


@pytest.fixture(scope="module")
def solved():
    """A one-level solve on one thread and its error against numpy's."""
    A, nb = arrowhead((5, 6, 7), 2, 2)
    solver = PatternSolver(A.indptr, A.indices, "banded", border=np.arange(nb, A.shape[0]))
    solver.factor(A.data)
    rhs = np.arange(A.shape[0], dtype=float)
    return np.abs(solver.solve(rhs) - np.linalg.solve(A.toarray(), rhs)).max()


def test_the_stage_dispatcher_is_inlined_not_compiled(solved):
    """``_blocks`` (three stages, two ``parallel`` flags) was six compiled functions, the
    block code linked into each optimised again by LLVM; inlined by numba, it is none
    (that on one thread the threaded loop is still left out: ``test_compile_budget``)."""
    assert solved < 1e-12
    assert not band_blocks._blocks.signatures
