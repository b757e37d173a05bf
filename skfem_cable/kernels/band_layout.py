"""Where the values of a bordered matrix go in the storage of its band blocks
(``kernels.band_blocks``): the blocks, the border unknowns each touches, the places of
every CSR value, and the rows and columns of ``E_j`` its ``W_j`` takes by band solves.
Python, run once per pattern."""

import numba
import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import maximum_bipartite_matching


def blocks(pr, pc, nb):
    """The first unknowns of the independent diagonal blocks of the band (``nblocks +
    1``, ending with ``nb``): a block ends at ``p`` when no entry ``(pr, pc)`` of the band
    joins an unknown up to ``p`` with one after it."""
    reach = np.arange(nb)
    inside = (pr < nb) & (pc < nb)
    low, high = np.minimum(pr, pc)[inside], np.maximum(pr, pc)[inside]
    np.maximum.at(reach, low, high)
    ends = np.flatnonzero(np.maximum.accumulate(reach) == np.arange(nb)) + 1
    return np.concatenate([[0], ends]).astype(np.int64)


def grouped(indices, starts):
    """``(ptr, sorted unique indices)`` of band indices grouped by their block."""
    unique = np.unique(indices)
    return np.searchsorted(unique, starts).astype(np.int64), unique.astype(np.int64)


def pointers(sizes):
    """The offsets of consecutive pieces of ``sizes`` (``size + 1``, from 0)."""
    return np.concatenate([[0], np.cumsum(sizes)]).astype(np.int64)


def storage(addresses, pr, pc, n, nb, band, least, threads=1):
    """The blocks' storage for the entries ``(pr, pc)`` (in the ordering) of an ``n x n``
    matrix with ``nb`` band unknowns of half-width ``band``: ``(blocks, target, position, near,
    parallel)`` (``kernels.band_blocks``), ``position`` of the border's entries (target 3)
    left to the border's LU, ``near`` the blocks' ``Touch``.  ``least``: ``W_j`` by the
    fewest band solves (``Touch.cover``), else as the bordered band LU always took it
    (``Touch.cover_by_count``).  With ``threads > 1`` and more than one block, the blocks
    are factored and solved on numba's threads, which it launches (``launch_threads``)."""
    k = n - nb
    ldab = 3 * band + 1
    if nb * ldab >= 2**31:
        raise ValueError(f"a band of {nb} unknowns and half-width {band} exceeds 2^31 "
                         "stored entries")
    target = ((pc >= nb) + 2 * (pr >= nb)).astype(np.int8)  # 0: band, 1: E, 2: F, 3: S
    starts = blocks(pr, pc, nb)
    near = Touch(starts, pr, pc, target, k)
    position = pc * ldab + 2 * band + pr - pc
    e, f = target == 1, target == 2
    position[e] = near.e_position(pr[e], pc[e] - nb)
    position[f] = near.f_position(pc[f], pr[f] - nb)
    units = (near.cover if least else near.cover_by_count)(pr[e], pc[e] - nb)
    rows_ptr, unit_rows = grouped(units, starts)
    cols_ptr, coupling_cols = grouped(pc[f], starts)
    x_ptr = pointers(np.diff(rows_ptr) * np.diff(starts))
    nblocks = starts.size - 1
    arrays = (addresses, np.zeros((nb, ldab)), np.zeros(nb, dtype=np.int32), int(band),
              np.zeros(8, dtype=np.int32), np.zeros(n), starts,
              rows_ptr, unit_rows, cols_ptr, coupling_cols, np.zeros(x_ptr[-1]), x_ptr,
              near.ptr, near.touch, near.direct, np.zeros(near.e_ptr[-1]),
              np.zeros(near.e_ptr[-1]), np.zeros(near.e_ptr[-1]), near.e_ptr,
              np.zeros(near.p_ptr[-1]), near.p_ptr, np.zeros(nblocks, dtype=np.int64),
              np.zeros((nb, band)), np.zeros((nb, 2 * band + 1)))
    parallel = threads > 1 and nblocks > 1
    if parallel:
        launch_threads()
    return arrays, target, position.astype(np.int32), near, True if parallel else None


def launch_threads():
    """Start numba's thread pool (``numba.get_num_threads`` starts it once per process).
    numba starts it when it compiles a ``parallel=True`` kernel, and when it loads one
    from its cache, but not when it loads from its cache a kernel that calls one
    (``kernels.bordered``'s ``factor`` and ``solve`` call ``band_blocks``' threaded
    loops; numba issues 8578 and 9938): that call jumped to address 0.  A worker of the
    test suite died so (``tests/test_kernel_signatures.py``, a cache written by another
    process), and pytest-xdist then waited for it without end."""
    numba.get_num_threads()


#: The places in ``storage``'s ``arrays`` (``kernels.band_blocks``' ``blocks``) of what
#: the kernels write (the band and its factor, pivots, scratch, ``X``, ``E``, ``F``,
#: ``W``, the parts, the infos): the rest, the plan of the pattern, they only read.
WORK = (1, 2, 4, 5, 11, 16, 17, 18, 20, 22, 23, 24)


def renewed(arrays):
    """``arrays`` of ``storage`` with fresh work arrays (``WORK``, zeros as made) around
    the same plan: the storage of another solver of the same pattern, as ``storage``
    makes it, without its making."""
    return tuple(zeros(a) if k in WORK else a for k, a in enumerate(arrays))


def zeros(a):
    """Zeros of the shape and type of ``a`` (C order, as ``storage`` makes them; left to
    the system's zeroed pages, where ``np.zeros_like`` writes every one)."""
    return np.zeros(a.shape, a.dtype)


def _least_cover(graph):
    """Masks of the rows and columns of a least vertex cover of the bipartite graph of the
    CSR ``graph``'s entries (Koenig's theorem: the rows not reached from an unmatched row
    by alternating paths, and the columns reached)."""
    match = maximum_bipartite_matching(graph, perm_type="column")  # row -> column
    owner = np.full(graph.shape[1], -1)
    owner[match[match >= 0]] = np.flatnonzero(match >= 0)
    seen_rows = match < 0
    seen_cols = np.zeros(graph.shape[1], dtype=bool)
    frontier = list(np.flatnonzero(seen_rows))
    while frontier:
        row = frontier.pop()
        for col in graph.indices[graph.indptr[row]:graph.indptr[row + 1]]:
            if not seen_cols[col]:
                seen_cols[col] = True
                if owner[col] >= 0 and not seen_rows[owner[col]]:
                    seen_rows[owner[col]] = True
                    frontier.append(owner[col])
    return ~seen_rows, seen_cols


class Touch:
    """The border unknowns each block touches (``T_j``), the flat places of its ``E_j``,
    ``F_j``, ``W_j`` and of its part ``F_j W_j``, and the ``S`` entries of those parts
    (``part_keys``: ``part[a, r]`` of block ``j`` is the entry ``(T_j[r], T_j[a])``, key
    ``row * k + column``)."""

    def __init__(self, starts, pr, pc, target, k):
        nb = starts[-1]
        e, f = target == 1, target == 2
        block = np.concatenate([self._block(starts, pr[e]), self._block(starts, pc[f])])
        border = np.concatenate([pc[e], pr[f]]) - nb
        self.k, self.starts = k, starts
        self.keys = np.unique(block * k + border)
        self.ptr = np.searchsorted(self.keys // max(k, 1),
                                   np.arange(starts.size)).astype(np.int64)
        self.touch = (self.keys % max(k, 1)).astype(np.int64)
        self.t = np.diff(self.ptr)
        self.e_ptr = pointers(self.t * np.diff(starts))
        self.p_ptr = pointers(self.t**2)
        pairs = [np.add.outer(near * k, near).T.ravel() for near in
                 np.split(self.touch, self.ptr[1:-1])] if starts.size > 1 else []
        self.part_keys = np.concatenate(pairs + [np.zeros(0, dtype=np.int64)])
        self.direct = np.zeros(self.touch.size, dtype=np.int8)

    @staticmethod
    def _block(starts, p):
        return np.searchsorted(starts, p, side="right") - 1

    def _local(self, p, c):
        """Block of band unknowns ``p``, their place in it, and the place of border
        unknowns ``c`` in the block's ``T_j``."""
        j = self._block(self.starts, p)
        return j, p - self.starts[j], np.searchsorted(self.keys, j * self.k + c) - self.ptr[j]

    def cover(self, p, c):
        """The band rows of a least cover of the entries ``E[p, c]``, block by block:
        ``E_j``'s columns ``W_j`` takes by a band solve each (marked in ``direct``) and its
        rows by a band solve of their unit column each (returned), the fewest solves that
        reach every entry (a least vertex cover of the bipartite graph of rows and
        columns, from a maximum matching: Koenig's theorem).  A tether joined to the hub
        through its pin's three rows and to the ring at its tip's three coordinates: six
        solves, where rows alone take twelve and columns alone fifteen."""
        j, local, a = self._local(p, c)
        units = []
        for block in np.unique(j):
            mine = j == block
            rows, r = np.unique(p[mine], return_inverse=True)
            graph = sp.csr_matrix((np.ones(r.size), (r, a[mine])),
                                  shape=(rows.size, self.t[block]))
            left, right = _least_cover(graph)
            units.append(rows[left])
            self.direct[self.ptr[block] + np.flatnonzero(right)] = 1
        return np.concatenate(units + [np.zeros(0, dtype=np.int64)])

    def cover_by_count(self, p, c):
        """The band rows of the entries ``E[p, c]`` where a block has at most ``k`` of
        them (a band solve of each row's unit column), else every column of ``E_j`` by a
        band solve (marked in ``direct``): the bordered band LU's choice (the ring of tips
        of the two-level LU's second level, every tip joined to the hub, takes columns)."""
        j = self._block(self.starts, p)
        units = []
        for block in np.unique(j):
            rows = np.unique(p[j == block])
            if rows.size > self.k:
                self.direct[self.ptr[block]:self.ptr[block + 1]] = 1
            else:
                units.append(rows)
        return np.concatenate(units + [np.zeros(0, dtype=np.int64)])

    def e_position(self, p, c):
        """Flat places of ``E[p, c]`` in ``E_j`` (``(|T_j|, n_j)``)."""
        j, local, a = self._local(p, c)
        return self.e_ptr[j] + a * np.diff(self.starts)[j] + local

    def f_position(self, p, c):
        """Flat places of ``F[c, p]`` in ``F_j`` (``(n_j, |T_j|)``)."""
        j, local, a = self._local(p, c)
        return self.e_ptr[j] + local * self.t[j] + a
