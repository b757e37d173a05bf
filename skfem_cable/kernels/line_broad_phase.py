"""The broad phase of line-to-line contact (``loads.contact_lines.BroadPhase``): the pairs
of segments of the lines' sampled centrelines that a time step may bring into touch, for
the narrow phase (``kernels.contact_lines``).

Each segment's axis-aligned box is inflated by half the margin and by its reach (twice
the distance its faster end travels over the step). The boxes are binned on a uniform
grid whose cell is twice the median of the boxes' largest sides (``CELL_SIDES``: a
typical box covers one to three cells along each axis), by a counting sort on a hash of
the cells; the pairs of boxes sharing a cell are tested (box overlap, once: in the cell
of the lower corner of their intersection). A sweep and prune along one axis (the first
version) is quadratic where the boxes are spread over a plane or a volume, as a radial
star of tethers is. Of the overlapping pairs it keeps those whose segments are within
the margin and both reaches (``distance``): a segment is a convex combination of its
ends, so the distance of two segments changes by at most the distances their ends move,
and a dropped pair cannot touch within the step.
"""

import math

import numpy as np
from numba import njit

from .contact_lines import closest

#: The grid's cell in medians of the boxes' largest sides: on the 12-tether sail (588
#: segments, ``benchmarks/contact_cost.py``'s state) one refresh took 0.42 ms with one
#: median (4441 box-cell entries), 0.19 ms with two (1813), 0.17 ms with four; on the
#: full-size sail (4900 segments) 4.8, 4.5 and 4.8 ms (the hub's cells, where every
#: tether's first segments meet, dominate).
CELL_SIDES = 2.0

#: The most cells along the grid's axes together (their product is a 64-bit key).
MOST_CELLS = 2**60


@njit(cache=True)
def distance(X, ends, i, j, P):
    """The distance of the segments ``i`` and ``j`` (their ends ``ends`` in ``X``);
    ``P`` (4, 3) is scratch."""
    for m in range(3):
        P[0, m], P[1, m] = X[ends[i, 0], m], X[ends[i, 1], m]
        P[2, m], P[3, m] = X[ends[j, 0], m], X[ends[j, 1], m]
    s, t = closest(P)
    d = 0.0
    for m in range(3):
        r = P[0, m] + s * (P[1, m] - P[0, m]) - P[2, m] - t * (P[3, m] - P[2, m])
        d += r * r
    return math.sqrt(d)


@njit(cache=True)
def boxes(X, V, ends, margin, dt, box):
    """Each segment's box into ``box`` (nseg, 7): its ends' box inflated by ``margin / 2``
    and its reach, which goes in the last column (module notes)."""
    for k in range(ends.shape[0]):
        a, b = ends[k, 0], ends[k, 1]
        speed = 0.0
        for m in (a, b):
            speed = max(speed, math.sqrt(V[m, 0] ** 2 + V[m, 1] ** 2 + V[m, 2] ** 2))
        box[k, 6] = 2.0 * dt * speed
        grow = 0.5 * margin + box[k, 6]
        for i in range(3):
            box[k, i] = min(X[a, i], X[b, i]) - grow
            box[k, 3 + i] = max(X[a, i], X[b, i]) + grow


@njit(cache=True)
def grid(box):
    """``(low, cell, shape)``: the grid's lower corner (3,), its cell size and its number
    of cells along each axis (3,): the cell is ``CELL_SIDES`` medians of the boxes'
    largest sides (grown until the cells number at most ``MOST_CELLS``)."""
    low, shape = np.empty(3), np.empty(3, dtype=np.int64)
    side = np.zeros(box.shape[0])
    for i in range(3):
        low[i] = box[:, i].min()
        for k in range(box.shape[0]):
            side[k] = max(side[k], box[k, 3 + i] - box[k, i])
    cell = max(CELL_SIDES * np.median(side), 1e-300)
    while True:
        total = 1.0
        for i in range(3):
            shape[i] = int((box[:, 3 + i].max() - low[i]) / cell) + 1
            total *= shape[i]
        if total <= MOST_CELLS:
            return low, cell, shape
        cell *= 2.0


@njit(cache=True, inline="always")
def index(x, low, cell, i):
    """The cell index of the coordinate ``x`` along axis ``i``."""
    return int((x - low[i]) / cell)


@njit(cache=True)
def binned(box, low, cell, shape):
    """``(keys, segments, starts, span)``: the cells (keys) each box covers and its segment,
    grouped by bucket (a counting sort on ``key mod`` a power of two at least twice the
    entries: bucket ``b`` is ``starts[b]:starts[b + 1]``; a bucket may hold several
    cells), and each box's lowest and highest cell indices ``span`` (nseg, 6)."""
    nseg = box.shape[0]
    span = np.empty((nseg, 6), dtype=np.int64)
    total = 0
    for k in range(nseg):
        n = 1
        for i in range(3):
            span[k, i] = index(box[k, i], low, cell, i)
            span[k, 3 + i] = index(box[k, 3 + i], low, cell, i)
            n *= span[k, 3 + i] - span[k, i] + 1
        total += n
    buckets = 1
    while buckets < 2 * total:
        buckets *= 2
    starts = np.zeros(buckets + 1, dtype=np.int64)
    for phase in range(2):             # count the entries of each bucket, then place them
        if phase == 1:
            starts = np.cumsum(starts)
            fill = starts[:-1].copy()
            keys, owner = np.empty(total, dtype=np.int64), np.empty(total, dtype=np.int64)
        for k in range(nseg):
            for a in range(span[k, 0], span[k, 3] + 1):
                for b in range(span[k, 1], span[k, 4] + 1):
                    for c in range(span[k, 2], span[k, 5] + 1):
                        key = (a * shape[1] + b) * shape[2] + c
                        slot = key & (buckets - 1)
                        if phase == 0:
                            starts[slot + 1] += 1
                        else:
                            keys[fill[slot]], owner[fill[slot]] = key, k
                            fill[slot] += 1
    return keys, owner, starts, span


@njit(cache=True, inline="always")
def first_shared(box, span, i, j, shape):
    """The key of the cell of the lower corner of the boxes ``i`` and ``j``'s
    intersection (the larger of their lowest cells, ``span``), or -1 if they do not
    overlap."""
    key = 0
    for m in range(3):
        if box[j, m] > box[i, 3 + m] or box[i, m] > box[j, 3 + m]:
            return -1
        key = key * shape[m] + max(span[i, m], span[j, m])
    return key


@njit(cache=True, inline="always")
def _listed(keys, key):
    """True when ``key`` is in the sorted ``keys``."""
    at = np.searchsorted(keys, key)
    return at < keys.size and keys[at] == key


@njit(cache=True)
def candidates(X, V, ends, line, arc, exclusion, excluded, margin, dt, box, pairs):
    """The pairs of segments that the step of ``dt`` may bring into touch, into
    ``pairs``; returns how many there are (more than ``len(pairs)``: only the first were
    written).

    Segment ``k`` joins the points ``ends[k]`` of ``X`` (moving at ``V``).  A pair is one
    whose boxes overlap (``boxes``, found on a grid: module notes) and whose segments are
    within ``margin`` and both reaches (``distance``).  Pairs of one line (``line``)
    closer than ``exclusion`` along it (``arc``, (nseg, 2)) are dropped;
    ``exclusion < 0``: every pair of one line is.  The pairs whose keys ``i nseg + j``
    (``i < j``) are in the sorted ``excluded`` are dropped too (next to a joint two lines
    share, ``loads.contact_joints``).  ``box`` (nseg, 7) is scratch."""
    boxes(X, V, ends, margin, dt, box)
    low, cell, shape = grid(box)
    keys, owner, starts, span = binned(box, low, cell, shape)
    P = np.empty((4, 3))
    count, nseg = 0, ends.shape[0]
    for bucket in range(len(starts) - 1):
        for u in range(starts[bucket], starts[bucket + 1]):
            for w in range(u + 1, starts[bucket + 1]):
                if keys[u] != keys[w]:
                    continue
                i, j = min(owner[u], owner[w]), max(owner[u], owner[w])
                if first_shared(box, span, i, j, shape) != keys[u]:
                    continue
                if line[i] == line[j]:
                    if exclusion < 0.0:
                        continue
                    if max(arc[i, 0] - arc[j, 1], arc[j, 0] - arc[i, 1]) < exclusion:
                        continue
                elif _listed(excluded, i * nseg + j):
                    continue
                if distance(X, ends, i, j, P) > margin + box[i, 6] + box[j, 6]:
                    continue
                if count < pairs.shape[0]:
                    pairs[count, 0], pairs[count, 1] = i, j
                count += 1
    return count
