"""The crossing guard of line-to-line contact (``loads.contact_lines``): a step whose
converged state has carried two lines (or two parts of one) through each other is refused,
with the reason naming the contact, the lines, their arc positions and when in the step;
the step control then halves the step, or the run stops with that reason
(``docs/contact.md``, "Lines that cross").

It is the contact term's ``check`` (``contract.Term``): the integrator calls it once per
attempted step on the converged candidate (``solvers.guard.refusal``), never per Newton
iteration.  It tests the candidate pairs of the step's broad phase
(``contact_lines.BroadPhase``, found from the step's start) with the compiled swept test
of ``kernels.contact_crossing``; without pairs it returns at once.
"""

import numpy as np

from ..kernels import contact_crossing as kernel

#: Closest distance of two centrelines (in units of the sum of the radii) at a time their
#: ends are coplanar, below which the segments met (``kernels.contact_crossing``): at a
#: true crossing it is round-off.
CROSSING_GAP = 1e-3


def crossing_check(contact, tables, broad):
    """The ``check(q0, q1)`` of the term of ``contact`` (``LineLineContact``) over the
    lines' ``tables`` (``LineLineContact.tables``) and the candidate pairs of its
    ``broad`` phase: None, or the reason the step from ``q0`` to ``q1`` is refused (the
    first crossing pair and how many pairs crossed)."""
    points, rows, arc, line = tables[:4]
    names = [body.name for body in contact.lines]
    gap = CROSSING_GAP * contact.sum_radii
    found = np.empty(4)

    def check(q0, q1):
        if broad.count[0] == 0:
            return None
        n = kernel.crossed(points.edofs, points.S, rows, broad.pairs, broad.count, gap,
                           np.ascontiguousarray(q0, float),
                           np.ascontiguousarray(q1, float), found)
        if n == 0:
            return None
        pair = broad.pairs[int(found[kernel.PAIR])]
        ends = arc[pair]
        along = ends[:, 0] + found[[kernel.ON_A, kernel.ON_B]] * (ends[:, 1] - ends[:, 0])
        first, second = (names[k] for k in line[pair])
        return (f"{contact.name}: lines {first!r} and {second!r} pass through each other "
                f"at {along[0]:.4g} m along {first!r} and {along[1]:.4g} m along "
                f"{second!r} (reference arc lengths), {found[kernel.TAU]:.3g} of the way "
                f"through the step ({n} pair{'s' if n > 1 else ''} of segments crossed): "
                "the penalty cannot hold them at this step (a smaller step, a stiffer "
                "contact or the exact tangent may)")
    return check
