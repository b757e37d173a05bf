"""The ``[[constraints]]`` of a scene file: joints between cable nodes, rigid-body points
and the ground.  ``CONSTRAINTS`` maps each ``type`` to its reader; a new joint is one more
entry."""

from .schema import choice, vector3


def pin(t, bodies, system, node):
    """``type = "pin"``: a spherical joint to ``target`` (ground point, cable node or body
    point; default: the ground at the node's initial position)."""
    target = bodies.point(t, "target", ground=True) if "target" in t.data else None
    system.pin(node, target)


def clamp(t, bodies, system, node):
    """``type = "clamp"``: position and slope direction fixed (``direction``, default the
    node's initial slope)."""
    system.clamp(node, t.get("direction", vector3, None))


#: Readers of the constraint types: ``reader(t, bodies, system, node)``.
CONSTRAINTS = {"pin": pin, "clamp": clamp}


def read_constraint(t, bodies, system):
    """One ``[[constraints]]`` table, added to ``system``."""
    kind = t.get("type", choice(*CONSTRAINTS))
    node = bodies.point(t, "node", body_points=False)
    CONSTRAINTS[kind](t, bodies, system, node)
    t.finish()
