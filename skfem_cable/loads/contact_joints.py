"""The pairs of segments that line-to-line contact (``loads.contact_lines``) leaves out next
to a joint two of its lines share: the tethers' roots on the E-sail's hub, two lines pinned
to each other or to one tip.  There the lines meet (or leave one body side by side) by
construction, and the penalty would push apart what the joint holds together.

A line's *attachment* is a constraint on some of its coordinates (``Constraint.dofs``):
its arc range is that of the line's elements holding those coordinates (``LinePoints``:
a node's position is in the elements on either side of it), and its partners are the
other bodies the constraint holds.  Two attachments, of lines ``A`` and ``B``, are shared
when one's partners hold the other line, or their partners have a body in common (the
hub).  A pair of segments of ``A`` and ``B`` is excluded when each is within
``exclusion`` (reference arc length) of the arc range of its line's attachment.
"""

import numpy as np


def _element_arcs(points):
    """The reference arc ranges (ne, 2) of the elements of one line's ``points``."""
    ends = np.concatenate([[0.0], np.cumsum(points.w.sum(axis=1))])
    return np.column_stack([ends[:-1], ends[1:]])


def attachments(system, lines, points):
    """For each of ``lines`` (bodies of ``system``, with their ``points``), its attachments:
    a list of ``(low, high, partners)``, the arc range (m) of the elements holding the
    constrained coordinates and the set of the other bodies' positions in
    ``system.bodies`` (module notes)."""
    owner = np.full(system.n_dofs, -1, dtype=np.int64)
    for b, body in enumerate(system.bodies):
        owner[system.dofs(body)] = b
    number = {id(body): b for b, body in enumerate(system.bodies)}
    found = [[] for _ in lines]
    for constraint in system.constraints:
        dofs = np.asarray(constraint.dofs(system), dtype=np.int64)
        held = set(owner[dofs].tolist()) - {-1}
        for k, (line, p) in enumerate(zip(lines, points)):
            mine = number[id(line)]
            if mine not in held or len(held) < 2:
                continue
            elements = np.flatnonzero(np.isin(p.edofs, dofs).any(axis=1))
            if elements.size:
                arcs = _element_arcs(p)[elements]
                found[k].append((arcs[:, 0].min(), arcs[:, 1].max(), held - {mine}))
    return found, [number[id(line)] for line in lines]


def _shared(a, b, mine_a, mine_b):
    """True when the attachments ``a`` of line ``mine_a`` and ``b`` of ``mine_b`` share a
    joint (module notes)."""
    return mine_b in a[2] or mine_a in b[2] or bool((a[2] & b[2]) - {mine_a, mine_b})


def _near(arc, attachment, exclusion):
    """The segments (indices into ``arc``, (nseg, 2)) within ``exclusion`` of the arc
    range of ``attachment``."""
    low, high = attachment[0] - exclusion, attachment[1] + exclusion
    return np.flatnonzero((arc[:, 1] >= low) & (arc[:, 0] <= high))


def excluded_pairs(system, lines, points, arc, line, exclusion):
    """The sorted keys ``i * nseg + j`` (``i < j``) of the pairs of segments of different
    ``lines`` (their ``points``; the segments' arc positions ``arc`` and line numbers
    ``line``) next to a joint two lines share (module notes), int64."""
    found, numbers = attachments(system, lines, points)
    nseg, first = len(line), np.searchsorted(line, np.arange(len(lines)))
    keys = []
    for a in range(len(lines)):
        for b in range(a + 1, len(lines)):
            for one in found[a]:
                for other in found[b]:
                    if not _shared(one, other, numbers[a], numbers[b]):
                        continue
                    i = first[a] + _near(arc[line == a], one, exclusion)
                    j = first[b] + _near(arc[line == b], other, exclusion)
                    keys.append((i[:, None] * nseg + j[None, :]).ravel())
    return np.unique(np.concatenate(keys)) if keys else np.zeros(0, dtype=np.int64)
