"""Linear solves on the fixed sparsity pattern of the KKT (iteration) matrix.

The pattern is reordered once by reverse Cuthill-McKee.  A single cable (with its
multipliers interleaved by the ordering) is a band of half-width about 11, factored by
LAPACK's banded LU (``dgbtrf``, through ``kernels.lapack`` so that the compiled Newton step
uses the same factor) in O(n); wider patterns fall back to SuperLU.  All index maps from
the CSR data array into the factor's storage, and the storage itself, are made once.
"""

import numpy as np
import scipy.sparse as sp
from numba import njit
from scipy.sparse.csgraph import reverse_cuthill_mckee
from scipy.sparse.linalg import splu

from .kernels.lapack import ADDRESSES, band_factor, load_band, permuted_solve

#: Banded LU is used while the band half-width stays below this.
MAX_BANDWIDTH = 64

#: Largest band storage (entries) used to locate where a sparse factorization found the
#: matrix singular (160 MB).
MAX_LOCATE_ENTRIES = 2e7


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
    """

    def __init__(self, indptr, indices, method="auto"):
        n = len(indptr) - 1
        self.n = n
        self.pattern = sp.csr_matrix((np.ones(len(indices)), indices, indptr), shape=(n, n))
        rows = np.repeat(np.arange(n), np.diff(indptr))
        perm = reverse_cuthill_mckee(self.pattern, symmetric_mode=True).astype(np.int64)
        iperm = np.empty_like(perm)
        iperm[perm] = np.arange(n)
        pr, pc = iperm[rows], iperm[indices]
        band = int(np.max(np.abs(pr - pc))) if n else 0
        if method == "auto":
            method = "banded" if band <= MAX_BANDWIDTH else "sparse"
        if method not in ("banded", "sparse"):
            raise ValueError(f"method must be 'auto', 'banded' or 'sparse', got {method!r}")
        self.method = method
        self.perm, self.iperm, self.band = perm, iperm, band
        self._pr, self._pc = pr, pc
        self.ints = np.zeros(8, dtype=np.int32)
        if method == "banded":
            self.kl = self.ku = band
            self.ab, self.band_index = self._band_storage()
            self.ipiv = np.zeros(n, dtype=np.int32)
            self.work = np.empty(n)
        self.factorizations = 0
        self._lu = None

    def _band_storage(self):
        """LAPACK band storage of the reordered matrix (``kernels.lapack``) and the
        position of every CSR value in it."""
        band = self.band
        ldab = 3 * band + 1
        return np.zeros((self.n, ldab)), self._pc * ldab + 2 * band + self._pr - self._pc

    def _band_factor(self, ab, band_index, ipiv, data):
        """Banded LU of the values ``data`` into ``ab``, ``ipiv``; returns the unknown of
        a zero pivot, or -1."""
        load_band(ab, band_index, data)
        info = band_factor(ADDRESSES, ab, self.band, self.band, ipiv, self.ints)
        return int(self.perm[info - 1]) if info > 0 else -1

    def factor(self, data):
        """LU-factor the matrix with CSR values ``data``."""
        self.factorizations += 1
        if self.method == "banded":
            idx = self._band_factor(self.ab, self.band_index, self.ipiv, data)
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
        band = self.band
        if self.n * (3 * band + 1) > MAX_LOCATE_ENTRIES:
            return -1
        ab, band_index = self._band_storage()
        return self._band_factor(ab, band_index, np.zeros(self.n, dtype=np.int32), data)

    def solve(self, rhs):
        """Solve with the last factorization; ``rhs`` of shape ``(n,)`` or ``(n, k)``."""
        if self.method == "sparse":
            return self._lu.solve(rhs)
        rhs = np.asarray(rhs, dtype=float)
        out = np.empty_like(rhs)
        for k in np.ndindex(rhs.shape[1:]):
            col = (slice(None), *k)
            permuted_solve(ADDRESSES, self.ab, self.band, self.band, self.ipiv, self.perm,
                           np.ascontiguousarray(rhs[col]), self.work, out[col], self.ints)
        return out


@njit(cache=True)
def _csr_matvec(indptr, indices, data, x, out):
    for i in range(len(indptr) - 1):
        acc = 0.0
        for k in range(indptr[i], indptr[i + 1]):
            acc += data[k] * x[indices[k]]
        out[i] = acc
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

    def __matmul__(self, x):
        return _csr_matvec(self.indptr, self.indices, self.data, np.ascontiguousarray(x),
                           np.empty(self.shape[0]))
