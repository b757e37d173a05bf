"""Linear solves on the fixed sparsity pattern of the KKT (iteration) matrix.

The pattern is reordered once by reverse Cuthill-McKee, its light unknowns (a pin's
multipliers) placed apart where that narrows the band (``core.ordering``).  A single cable
(with a pin's multipliers at its end) is a band of half-width 11, factored by
LAPACK's banded LU (``dgbtrf``, through ``kernels.lapack`` so that the compiled Newton step
uses the same factor) in O(n).  A hub joined to many cables (the E-sail's) is ordered last
as a dense border eliminated by its Schur complement (``kernels.bordered``), so the band
stays that of one cable, and each cable is a block of its own, factored apart (on threads with
``SKFEM_CABLE_THREADS``); where cables are joined to each other too (the ring of an
E-sail's tips) the junctions join the border, and the Schur complement, sparse, is
factored as a band with the hub as its dense border: two levels (``kernels.schur``).
Patterns no band fits fall back to SuperLU.  All index maps from
the CSR data array into the factor's storage, and the storage itself, are made once.
"""

import copy
import functools
import os

import numba
import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import splu

from ..kernels import bordered as bordered_lu
from ..kernels import schur
from ..kernels.books import csr_product
from ..kernels.lapack import ADDRESSES
from .ordering import band_ordering

#: The environment variable of the number of threads of the bordered LU's blocks
#: (``threads`` of ``PatternSolver``) and of the element loops (``kernels.chunks``).
THREADS = "SKFEM_CABLE_THREADS"

#: Banded LU is used while the band half-width stays below this.
MAX_BANDWIDTH = 64

#: Largest band storage (entries) used to locate where a sparse factorization found the
#: matrix singular (160 MB).
MAX_LOCATE_ENTRIES = 2e7


def thread_count(threads=None):
    """The threads of the bordered LU and of the element loops: ``threads``, else
    ``SKFEM_CABLE_THREADS``, else 1,
    at most numba's ``NUMBA_NUM_THREADS`` (numba is told, for the calling thread);
    ``ValueError`` naming the source for anything but an integer >= 1."""
    source = "threads" if threads is not None else THREADS
    value = threads if threads is not None else os.environ.get(THREADS, "1")
    try:
        count = int(value)
    except (TypeError, ValueError):
        count = 0
    if count < 1 or str(count) != str(value).strip():
        raise ValueError(f"{source} must be an integer >= 1, got {value!r}")
    count = min(count, numba.config.NUMBA_NUM_THREADS)
    if count > 1:
        numba.set_num_threads(count)
    return count


def _unknowns(indices):
    """Sorted unique int64 unknowns of ``indices`` (None: none)."""
    return np.unique(np.asarray([] if indices is None else indices, dtype=np.int64))


def _pattern(indptr, indices):
    """The square CSR matrix of ones on the pattern ``(indptr, indices)``."""
    n = len(indptr) - 1
    return sp.csr_matrix((np.ones(len(indices)), indices, indptr), shape=(n, n))


def choose_ordering(pattern, border, junctions):
    """``(perm, nb, band, dense)`` of the square CSR ``pattern``: the narrowest band of
    the orderings with nothing, the ``border``, and (if there is a border) the
    ``border`` with the ``junctions`` last (each only if strictly narrower), and the
    unknowns the Schur complement keeps dense (the ``border``'s; the junctions make its
    own band) (``PatternSolver.ordering``)."""
    perm, nb, band = band_ordering(pattern, np.zeros(0, dtype=np.int64))
    dense = np.zeros(0, dtype=np.int64)
    two = border.size and junctions.size  # under a hub only: the rest keep their LU
    for last in [border] + ([np.union1d(border, junctions)] if two else []):
        if last.size:
            candidate = band_ordering(pattern, last)
            if candidate[2] < band:
                (perm, nb, band), dense = candidate, border
    return perm, nb, band, dense


def ordering_of(indptr, indices, border=None, junctions=None):
    """``PatternSolver(indptr, indices, border=border, junctions=junctions).ordering``,
    without the solver's storage."""
    return choose_ordering(_pattern(indptr, indices), _unknowns(border), _unknowns(junctions))


class SingularMatrixError(np.linalg.LinAlgError):
    """The iteration matrix is singular; ``index`` is the unknown where it was detected."""

    def __init__(self, message, index):
        super().__init__(message)
        self.index = index


class PatternSolver:
    """Factor and solve matrices that share one CSR pattern.

    Parameters
    ----------
    indptr, indices : ndarray
        CSR pattern of a structurally symmetric square matrix.
    method : {"auto", "banded", "sparse"}
        ``"banded"``: LAPACK's banded LU of the pattern reordered by reverse
        Cuthill-McKee (its light unknowns placed apart where that narrows the band:
        ``core.ordering.band_ordering``), with the ``border`` unknowns (if any) last,
        eliminated by a Schur
        complement (``kernels.bordered``, or with ``junctions`` ``kernels.schur``);
        ``"sparse"``: SuperLU; ``"auto"``: banded while
        the half-width stays within ``MAX_BANDWIDTH``.
    border : int array_like, optional
        Unknowns coupled to many others (a hub's coordinates and its own constraints'
        multipliers, ``Layout.border``): ordered last, they keep the band of the rest
        narrow; used when they make the band narrower.
    threads : int, optional
        Threads on which the independent blocks of the band (an E-sail's tethers) are
        factored and solved (``kernels.bordered``, ``kernels.schur``; numba's, at most
        ``NUMBA_NUM_THREADS``); the results are the same for any number.  Default: the
        environment variable ``SKFEM_CABLE_THREADS``, else 1.  Give a process more than
        one only where it has the cores to itself: numba's OpenMP threads wait by
        spinning, and beside other busy processes (test workers, a Dask cluster on the
        same cores) each factorization can wait for a time slice.
    junctions : int array_like, optional
        Unknowns where bodies outside the ``border`` meet (``Layout.junctions``: the tips
        of an E-sail's tethers joined by its ring): with a ``border``, ordered last too
        when that makes the band narrower still, they make the Schur complement's band,
        the ``border`` its dense border (two levels, ``kernels.schur``).
    ordering : tuple, optional
        The ``ordering`` of another solver of the same pattern, ``border`` and
        ``junctions`` (computed when None).

    Attributes
    ----------
    method : str
    band : int
        Half-width of the band (of the unknowns outside the border).
    border : int
        Number of border unknowns (0: a plain band).
    levels : int
        1: the border is dense (or there is none), factored by ``kernels.bordered``; 2:
        the border's Schur complement is a band with a dense border of its own
        (``kernels.schur``).
    kernels : module
        ``kernels.bordered`` or ``kernels.schur``: the ``factor``, ``solve`` and storage
        (``lu``) of the banded method; the compiled Newton step calls the same.
    ordering : tuple
        ``(perm, nb, band, dense)`` of ``choose_ordering``: the reordering of the pattern (its
        reverse Cuthill-McKee orderings take most of a solver's making).
    """

    def __init__(self, indptr, indices, method="auto", border=None, threads=None,
                 junctions=None, ordering=None):
        if method not in ("auto", "banded", "sparse"):
            raise ValueError(f"method must be 'auto', 'banded' or 'sparse', got {method!r}")
        self.threads = thread_count(threads)
        n = len(indptr) - 1
        self.n = n
        self.pattern = _pattern(indptr, indices)
        self._rows = np.repeat(np.arange(n), np.diff(indptr))
        if ordering is None:
            ordering = choose_ordering(self.pattern, _unknowns(border), _unknowns(junctions))
        self.ordering = ordering
        perm, nb, band, dense = ordering
        if method == "auto":
            method = "banded" if band <= MAX_BANDWIDTH else "sparse"
        self.method = method
        self.perm, self.band, self.border = perm, band, n - nb
        hub = np.isin(perm[nb:], dense)
        self.levels = 1 + bool(not hub.all())
        self.kernels = schur if self.levels == 2 else bordered_lu
        if method == "banded" and self.levels == 2:
            self.lu = schur.storage(ADDRESSES, self._rows, self.pattern.indices, perm, nb,
                                    band, lambda s: band_ordering(s, np.flatnonzero(hub)),
                                    self.threads)
        elif method == "banded":
            self.lu = bordered_lu.storage(ADDRESSES, self._rows, self.pattern.indices, perm,
                                          nb, band, self.threads)
        self.factorizations = 0
        self._lu = None

    def renewed(self):
        """A solver of the same pattern, ordering and storage plan as this one, with work
        arrays of its own (as made: ``kernels.bordered.renewed``, ``kernels.schur.renewed``)
        and no factorization: what a solver's making derives from its pattern alone (its
        storage's plan, most of the making of the E-sail rig's) made once."""
        other = copy.copy(self)
        if self.method == "banded":
            other.lu = self.kernels.renewed(self.lu)
        other.factorizations, other._lu = 0, None
        return other

    def factor(self, data):
        """LU-factor the matrix with CSR values ``data``."""
        self.factorizations += 1
        if self.method == "banded":
            idx = int(self.kernels.factor(self.lu, data))
            if idx >= 0:
                raise SingularMatrixError(f"singular iteration matrix at unknown {idx}", idx)
        else:
            A = sp.csr_matrix((data, self.pattern.indices, self.pattern.indptr),
                              shape=(self.n, self.n))
            try:
                self._lu = splu(A.tocsc())
            except RuntimeError as err:
                idx = self._locate_singular(data)
                at = f"at unknown {idx}" if idx >= 0 else f"({err})"
                raise SingularMatrixError(f"singular iteration matrix {at}", idx) from None

    def _locate_singular(self, data):
        """The unknown where a singular matrix with CSR values ``data`` loses rank, found
        by a banded LU of its bandwidth-reduced form (as the banded method does); -1 if
        that band would exceed ``MAX_LOCATE_ENTRIES`` (too large to locate)."""
        perm, nb, band = band_ordering(self.pattern, np.zeros(0, dtype=np.int64))
        if self.n * (3 * band + 1) > MAX_LOCATE_ENTRIES:
            return -1
        lu = bordered_lu.storage(ADDRESSES, self._rows, self.pattern.indices, perm, nb, band)
        return int(bordered_lu.factor(lu, data))

    def solve(self, rhs):
        """Solve with the last factorization; ``rhs`` of shape ``(n,)`` or ``(n, k)``."""
        if self.method == "sparse":
            return self._lu.solve(rhs)
        rhs = np.asarray(rhs, dtype=float)
        out = np.empty_like(rhs)
        for k in np.ndindex(rhs.shape[1:]):
            col = (slice(None), *k)
            column = np.empty(self.n)
            self.kernels.solve(self.lu, np.ascontiguousarray(rhs[col]), column)
            out[col] = column
        return out


class FastCSR:
    """A CSR matrix whose product with a vector skips scipy's per-call overhead (it
    dominates for the small matrices multiplied at every Newton iteration)."""

    def __init__(self, matrix):
        m = sp.csr_matrix(matrix)
        m.sort_indices()
        self.shape = m.shape
        self.indptr = m.indptr.astype(np.int64)
        self.indices = m.indices.astype(np.int64)
        self.data = m.data.astype(float)
        self.scipy = m

    @functools.cached_property
    def strided(self):
        """The matrix in the form the compiled step and its books read
        (``kernels.books.mass_product``): ``(indptr, indices, data, k)`` of the CSR matrix
        ``M_s`` (int32 indices) with ``M = M_s ⊗ I_k`` value for value, ``k = 3`` where
        that holds (a cable's mass: a node's position and slope vectors, their three
        components coupled alike), else ``M`` itself and ``k = 1``.  At 10,000 cable
        elements 1.5 MB instead of the 6.2 MB of the CSR with int64 indices, read at every
        Newton iteration; a row of ``M_s`` holds row ``k r + c`` of ``M`` in the same order
        (columns ``k j + c``), so that ``M x`` is the same sums.

        Stored zeros are left out first (a point mass's ``m I_3`` block stores six, which
        made the E-sail rig's mass fail the test): a sum that starts at ``+0`` never holds
        ``-0``, so adding ``0 x`` (``x`` finite) leaves every bit of it as it is."""
        k = 3
        kept = self.data != 0.0
        indptr = np.concatenate([[0], np.cumsum(kept)])[self.indptr]
        indices, data = self.indices[kept], self.data[kept]
        counts = np.diff(indptr)
        n = counts.size
        rows = np.repeat(np.arange(n), counts)
        if n % k == 0 and np.all(counts.reshape(-1, k) == counts[::k, None]) and \
                np.array_equal(indices % k, rows % k):
            first = rows % k == 0
            same = all(np.array_equal(indices[rows % k == c] // k, indices[first] // k)
                       and np.array_equal(data[rows % k == c].view(np.int64),
                                          data[first].view(np.int64)) for c in range(1, k))
            if same:
                return (np.concatenate([[0], np.cumsum(counts[::k])]).astype(np.int32),
                        (indices[first] // k).astype(np.int32), data[first].copy(), k)
        return indptr.astype(np.int32), indices.astype(np.int32), data, 1

    def __matmul__(self, x):
        return csr_product(self.indptr, self.indices, self.data, np.ascontiguousarray(x),
                           np.empty(self.shape[0]))
