"""Band orderings of the KKT (iteration) matrix's pattern for the banded LU.

Reverse Cuthill-McKee (George & Liu, *Computer Solution of Large Sparse Positive Definite
Systems*, 1981, Sect. 4.3) numbers a graph level by level from a peripheral unknown.  On
the iteration matrix of a cable it numbers the cable node by node (half-width 11 for six
coordinates a node), but the multipliers of a constraint join the level of their
coordinates: a pin's three, interleaved between the pinned node's unknowns, widen the
band to 13 (``docs/benchmarks.md``, the exponent on the shared machine).  A factor's
storage and work grow as the half-width (``3 b + 1`` values a column for LAPACK's
``dgbtrf``; at 10,000 elements 16.3 MB instead of 19.2 and a factorization 28 % cheaper
at 11).

``band_ordering`` therefore also orders the *light* unknowns apart (``light``: coupled to
at most ``LIGHT`` others, none of them light, as a point constraint's multipliers are):
reverse Cuthill-McKee of the rest, then each light unknown put at the cut of that
ordering where it widens the band least (``_cuts``: a cut at an end of a cable is crossed
by no coupling, so a pin's multipliers there leave the cable's half-width), and keeps
this ordering where its band is strictly narrower than that of reverse Cuthill-McKee of
all (elsewhere the orderings, and the results, stay those of reverse Cuthill-McKee).
"""

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import reverse_cuthill_mckee

#: An unknown coupled to at most this many others (outside the border), none of them
#: light too, is ordered after the rest (``light``): a point constraint's multipliers (a
#: pin's or a spherical joint's on a cable: 3 coordinates), a distance's between two
#: points (6).
LIGHT = 6


def half_width(pattern, perm):
    """The half-width of the square CSR ``pattern`` ordered by ``perm``."""
    iperm = np.empty_like(perm)
    iperm[perm] = np.arange(perm.size)
    coo = pattern.tocoo()
    return int(np.max(np.abs(iperm[coo.row] - iperm[coo.col]), initial=0))


def light(pattern):
    """Boolean mask of the light unknowns of the square CSR ``pattern``: coupled to at
    least one and at most ``LIGHT`` other unknowns, none of which is light too (so that
    each is placed among unknowns ordered without it)."""
    off = sp.csr_matrix(pattern, dtype=bool, copy=True)
    off.setdiag(False)
    off.eliminate_zeros()
    degree = np.diff(off.indptr)
    few = (degree >= 1) & (degree <= LIGHT)
    return few & (off @ few.astype(np.int64) == 0)


def _crossing(pattern, rank):
    """``w[c]`` for every cut ``c`` (before position ``c``, ``0 <= c <= m``) of the
    ``m`` unknowns of the square CSR ``pattern`` at positions ``rank``: the longest
    coupling ``(i, j)``, ``i < c <= j`` in positions, that crosses it (0: none)."""
    m = rank.size
    reach = np.arange(m)
    rows = np.flatnonzero(np.diff(pattern.indptr))
    if rows.size:
        top = np.maximum.reduceat(rank[pattern.indices], pattern.indptr[rows])
        reach[rank[rows]] = np.maximum(top, rank[rows])
    span = reach - np.arange(m)
    w = np.zeros(m + 1, dtype=np.int64)
    for s in range(1, int(np.max(span, initial=0)) + 1):
        np.maximum(w[s:], np.where(span[:m + 1 - s] >= s, span[:m + 1 - s], 0), out=w[s:])
    return w


def _cuts(first, last, w):
    """The cut of each light unknown among ``w.size - 1`` ordered ones, given the first
    and last positions of its neighbours (``first``, ``last``) and the crossing widths
    ``w`` (``_crossing``): the cut of least half-width, where it makes ``w[c] + k + 1``
    (the couplings crossing it, over the ``k`` light unknowns already there and itself)
    and ``max(c - first, last + 1 - c) + k`` (its own couplings); of equals the nearest
    to its neighbours, then the first."""
    cuts = np.empty(first.size, dtype=np.int64)
    placed = np.zeros(w.size, dtype=np.int64)
    reach = int(np.max(w, initial=0)) + 1
    for u in np.argsort(first + last, kind="stable"):
        c = np.arange(max(0, min(first[u], last[u] - reach)),
                      min(w.size, max(last[u], first[u] + reach) + 1))
        own = np.maximum(c - first[u], last[u] + 1 - c)
        cost = np.maximum(w[c] + 1, own) + placed[c]
        cuts[u] = c[np.lexsort((own, cost))[0]]
        placed[cuts[u]] += 1
    return cuts


def light_last(pattern):
    """The ordering of the square CSR ``pattern`` that puts its light unknowns (``light``)
    at the cuts of the reverse Cuthill-McKee ordering of the rest where they widen the
    band least (``_cuts``); None if there are none."""
    mask = light(pattern)
    if not mask.any() or mask.all():
        return None
    heavy, few = np.flatnonzero(~mask), np.flatnonzero(mask)
    rest = pattern[heavy][:, heavy]
    order = heavy[reverse_cuthill_mckee(rest, symmetric_mode=True)]
    rank = np.full(mask.size, -1)
    rank[order] = np.arange(order.size)
    coo = pattern[few].tocoo()
    at = rank[coo.col]
    coupled = at >= 0
    first = np.full(few.size, order.size)
    last = np.full(few.size, -1)
    np.minimum.at(first, coo.row[coupled], at[coupled])
    np.maximum.at(last, coo.row[coupled], at[coupled])
    cuts = _cuts(first, last, _crossing(rest, rank[heavy]))
    # a cut c comes before the unknown at position c: keys 2 c (light) and 2 c + 1; the
    # light unknowns at one cut in the order of their neighbours, so that those of the
    # bodies on either side of a free cut stay on their side (blocks stay apart)
    keys = np.concatenate([2 * np.arange(order.size) + 1, 2 * cuts])
    near = np.concatenate([np.zeros(order.size, dtype=np.int64), first + last])
    return np.concatenate([order, few])[np.lexsort((near, keys))]


def band_ordering(pattern, border):
    """``(perm, nb, band)`` of the square CSR ``pattern``: the unknowns outside ``border``
    ordered by reverse Cuthill-McKee, or with their light unknowns placed apart
    (``light_last``) where that band is strictly narrower, then the ``border``; ``nb``
    band unknowns of half-width ``band``."""
    n = pattern.shape[0]
    rest = np.setdiff1d(np.arange(n), border)
    sub = pattern[rest][:, rest] if border.size else pattern
    order = reverse_cuthill_mckee(sub, symmetric_mode=True) if rest.size else rest
    band = half_width(sub, order)
    other = light_last(sub) if rest.size else None
    if other is not None:
        narrower = half_width(sub, other)
        if narrower < band:
            order, band = other, narrower
    perm = np.concatenate([rest[order], border]).astype(np.int64)
    return perm, rest.size, band
