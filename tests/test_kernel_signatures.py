"""One compiled signature per package kernel where the variants are not needed (issue 47,
item 5: the test command in five minutes).  numba compiles a kernel again for every new
tuple of argument types: a global int passed as an argument is typed as its literal value,
``prange``'s index is unsigned, an array of another dimension or layout is another type.
The bordered band LU of two different systems, one of them on threads, holds one
signature of each kernel per stage of a block (literal: the other stages pruned) and per
``parallel`` flag (None or True: the threaded loop pruned on one thread), the variants
that are needed."""

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import scipy.sparse as sp
from numba.core import types

from skfem_cable.core.contract import NO_INDEX, Term
from skfem_cable.kernels import band_blocks, bordered, lapack, oml

ROOT = Path(__file__).resolve().parents[1]


def arrowhead(sizes, k, seed):
    """A diagonally dominant matrix of tridiagonal blocks of ``sizes`` and ``k`` border
    unknowns joined to every block's first and last unknowns (CSR, the border last)."""
    nb = sum(sizes)
    n = nb + k
    dense = np.zeros((n, n))
    start = 0
    for size in sizes:
        for i in range(start, start + size):
            dense[i, max(i - 1, start):min(i + 2, start + size)] = 1.0
        for b in range(nb, n):
            dense[[start, start + size - 1], b] = dense[b, [start, start + size - 1]] = 1.0
        start += size
    dense[nb:, nb:] = 1.0
    rng = np.random.default_rng(seed)
    dense *= rng.uniform(0.5, 1.0, dense.shape)
    dense[np.diag_indices(n)] = 10.0
    return sp.csr_matrix(dense), nb


def compiled(kernel):
    """The signatures ``kernel`` was compiled for: this process's and those in numba's
    cache index (a kernel linked into a caller loaded from the cache is not compiled
    again, and holds none in ``signatures``)."""
    cached = kernel._cache._cache_file._load_index()
    return {str(key[0]) for key in cached} | {str(s) for s in kernel.signatures}


@pytest.fixture(scope="module")
def solved():
    """The solution errors of two arrowheads, one factored and solved on threads."""
    errors = []
    for sizes, k, threads in (((5, 6), 2, 1), ((4, 5, 6), 3, 2)):
        A, nb = arrowhead(sizes, k, seed=len(sizes))
        coo = A.tocoo()
        lu = bordered.storage(lapack.ADDRESSES, coo.row, coo.col, np.arange(A.shape[0]),
                              nb, 1, threads=threads)
        assert bordered.factor(lu, coo.data) == -1
        rhs = np.arange(A.shape[0], dtype=float)
        out = np.empty_like(rhs)
        bordered.solve(lu, rhs, out)
        errors.append(np.abs(A @ out - rhs).max())
    return errors


def test_the_bordered_lu_solves_both(solved):
    assert max(solved) < 1e-12


def test_a_block_is_compiled_per_stage_and_thread_flag_alone(solved):
    """``_block``: one signature per stage (a literal: the other stages pruned, a needed
    variant, faster), the same for both ``parallel`` flags (it takes the storage without
    the flag; before, one per flag too: six); its index int64 from a loop and from a
    ``prange`` (unsigned, cast) alike."""
    signatures = compiled(band_blocks._block)
    assert all(", int64, Literal[int](" in s for s in signatures)
    assert len(signatures) == 3


def test_the_scatter_takes_flat_arrays_from_either_lu(solved):
    """``_scatter``: ``E``, ``F``, ``S`` flat, as both LUs' blocks
    (``kernels.band_blocks``) hold them; one signature per ``parallel`` flag."""
    signatures = compiled(band_blocks._scatter)
    assert len(signatures) == 2
    assert all(s.count("Array(float64, 1, 'C'") == 4 for s in signatures)


def test_the_band_lu_of_lapack_takes_int64_half_widths(solved):
    """Not a literal 2 (``kernels.oml``'s ``KL``, ``KU``): numba types a global as its
    literal value when ``types.maybe_literal`` gives one (``typeinfer.typeof_global``), and
    does not for an ``np.int64``.  The signatures compiled in this process, not the cache
    index's: an index outlives the code that wrote it while its source file keeps its
    stamp (a CI machine that keeps its checkout and cache held ``Literal[int](2)`` from
    the previous commit's ``KL = 2``)."""
    assert types.maybe_literal(2) is not None  # the rule, checked where it bites
    assert types.maybe_literal(oml.KL) is None and types.maybe_literal(oml.KU) is None
    assert all("Literal" not in str(s) for s in lapack.band_factor.signatures)


def test_an_evaluation_without_the_tangent_has_the_index_dimensions():
    """``Term.evaluate(ev, None)``: an empty index of the term's own dimensions, not a
    1-D one that would compile its kernels again."""
    rows = np.zeros((4, 6, 6), dtype=np.int64)
    assert Term(kernels=(), rows=rows, cols=rows).no_index().shape == (0, 6, 6)
    assert Term(kernels=(), rows=rows[:, :, :1].reshape(4, 6), cols=np.zeros(
        (1, 6), dtype=np.int64)).no_index().shape == (0, 6)
    assert Term(kernels=()).no_index() is NO_INDEX


#: A fresh process: numba's threading layer before and after a threaded storage of two
#: blocks (unknowns 0-1 and 2-3) and one border unknown (4).
LAUNCH = """
import numba, numpy as np
from skfem_cable.kernels import bordered, lapack
def layer():
    try:
        return numba.threading_layer()
    except ValueError:
        return None
before = layer()
A = 4.0 * np.eye(5)
A[0, 1] = A[1, 0] = A[2, 3] = A[3, 2] = 1.0
A[4, :4] = A[:4, 4] = 1.0
rows, cols = np.nonzero(A)
lu = bordered.storage(lapack.ADDRESSES, rows, cols, np.arange(5), 4, 1, threads=2)
print(before, lu[3], layer())
"""


def test_a_threaded_storage_starts_numbas_threads():
    """``band_layout.launch_threads``: a storage on threads starts numba's thread pool
    before any kernel runs on it.  A kernel loaded from numba's cache that calls a
    threaded one does not start it (numba issues 8578, 9938), and called it at address 0:
    with a cache written by other processes, the first test of this module segfaulted."""
    out = subprocess.run([sys.executable, "-c", LAUNCH], cwd=ROOT, check=True,
                         capture_output=True, text=True).stdout.split()
    assert out[0] == "None" and out[1] == "True" and out[2] != "None"
