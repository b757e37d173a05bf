"""The ``[[constraints]]`` of a scene file: joints between cable nodes, rigid-body points
and the ground.  ``CONSTRAINTS`` maps each ``type`` to its reader; a new joint is one more
entry."""

import numpy as np

from .. import constraints
from .schema import boolean, choice, direction3


def directions(value):
    """``directions = [[x, y, z], ...]``: one or two vectors."""
    if not isinstance(value, list) or not value or not all(isinstance(v, list) for v in value):
        raise ValueError("must be a list of one or two vectors [[x, y, z], ...]")
    return np.array([direction3(v) for v in value])


def pin(t, bodies, node):
    """``type = "pin"``: a spherical joint to ``target`` (ground point, another cable node
    or body point; default: the ground at the node's initial position), along
    ``directions`` only if given (a node sliding on a plane or a line)."""
    target = bodies.point(t, "target", ground=True) if "target" in t.data else None
    along = t.get("directions", directions, None)
    try:
        return [constraints.pin(node, target, directions=along)]
    except ValueError as err:  # e.g. the node itself, dependent directions
        t.fail("directions" if along is not None and "directions" in str(err) else "target",
               f"is refused: {err}")


def clamp(t, bodies, node):
    """``type = "clamp"``: position and slope direction fixed (``direction``, default the
    node's initial slope), or the whole slope vector (``slope = "full"``); on a rod's
    node its twist held (``twist = true``, the default) or free (``twist = false``)."""
    return constraints.clamp(node, t.get("direction", direction3, None),
                             slope=t.get("slope", choice("direction", "full"), "direction"),
                             twist=t.get("twist", boolean, True))


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
