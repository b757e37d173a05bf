"""The ``[[constraints]]`` of a scene file: joints between cable nodes, rigid-body points
and the ground.  ``CONSTRAINTS`` maps each ``type`` to its reader; a new joint is one more
entry."""

from .. import constraints
from .schema import choice, direction3


def pin(t, bodies, node):
    """``type = "pin"``: a spherical joint to ``target`` (ground point, another cable node
    or body point; default: the ground at the node's initial position)."""
    target = bodies.point(t, "target", ground=True) if "target" in t.data else None
    try:
        return [constraints.pin(node, target)]
    except ValueError as err:  # e.g. the node itself
        t.fail("target", f"is refused: {err}")


def clamp(t, bodies, node):
    """``type = "clamp"``: position and slope direction fixed (``direction``, default the
    node's initial slope)."""
    return constraints.clamp(node, t.get("direction", direction3, None))


#: Readers of the constraint types: ``reader(t, bodies, node)`` returns the constraints.
CONSTRAINTS = {"pin": pin, "clamp": clamp}


def read_constraint(t, bodies, system):
    """One ``[[constraints]]`` table, added to ``system``: a constraint that repeats
    another's equations (the node pinned or clamped twice) is refused, naming both."""
    kind = t.get("type", choice(*CONSTRAINTS))
    node = bodies.point(t, "node", body_points=False)
    for joint in CONSTRAINTS[kind](t, bodies, node):
        try:
            system.add_constraint(joint)
        except ValueError as err:
            t.fail("node", f"is refused: {err}")
    t.finish()
