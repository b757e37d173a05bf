"""Labels of the coordinates, points and multipliers of a system, as a run store writes
them (``io.schema``, ``docs/output.md``): what makes ``xarray.open_zarr`` show labelled
data without this library.

Everything here follows the body contract (``docs/extending.md``): ``name``, ``n_dofs``,
``position_mask``, ``describe_dof`` and the system's 3-vectors (``System.vectors``,
``System.vector_is_position``, from the bodies' optional ``vector_mask``).  A body's
*points* are its position 3-vectors, in order: a cable's nodes, a rigid body's base
points.  A vector that is not a position (a slope) belongs to the point before it; a
scalar coordinate (a reel's length) to no point.
"""

from collections import Counter

import numpy as np

from ..core.protocols import SystemView

#: Names of the components of a position vector and of another vector (a slope).
POSITION = ("x", "y", "z")
DIRECTION = ("dx", "dy", "dz")


def body_labels(system: SystemView):
    """One label per body: its name, made unique by ``#k`` on the ``k``-th repetition
    (``cable``, ``cable#2``); a body without a name is ``body<i>``."""
    seen, labels = Counter(), []
    for i, body in enumerate(system.bodies):
        name = getattr(body, "name", None) or f"body{i}"
        seen[name] += 1
        labels.append(name if seen[name] == 1 else f"{name}#{seen[name]}")
    return labels


def _vectors_of(system, body):
    """``(blocks, is_position)`` of the 3-vectors of ``body`` (global coordinates)."""
    inside = np.isin(system.vectors[:, 0], system.dofs(body))
    return system.vectors[inside], system.vector_is_position[inside]


def dof_labels(system: SystemView):
    """Labels of the coordinates ``q`` (arrays of ``n_dofs``): ``body`` (``body_labels``),
    ``node`` (index of the body's point; -1 for a coordinate of no point), ``component``
    (``x y z`` of a position, ``dx dy dz`` of another vector, the body's
    ``describe_dof`` for a scalar) and ``label`` (the body's ``describe_dof``)."""
    body, node, component, label = [], [], [], []
    for name, b in zip(body_labels(system), system.bodies):
        local = [str(b.describe_dof(i)) for i in range(b.n_dofs)]
        first = system.dofs(b)[0] if b.n_dofs else 0
        points, parts = np.full(b.n_dofs, -1), list(local)
        point = -1
        blocks, is_position = _vectors_of(system, b)
        for block, position in zip(blocks - first, is_position):
            point += bool(position)
            points[block] = point
            for k, names in zip(block, POSITION if position else DIRECTION):
                parts[k] = names
        body += [name] * b.n_dofs
        node.append(points)
        component += parts
        label += local
    return {"body": np.array(body, dtype=str), "node": np.concatenate(node).astype(np.int64),
            "component": np.array(component, dtype=str), "label": np.array(label, dtype=str)}


def multiplier_labels(system: SystemView):
    """Labels of the multipliers ``lam`` (arrays of ``n_constraints``): ``constraint``
    (its name) and ``equation`` (its label of the equation, else its index)."""
    constraint, equation = [], []
    for c in system.constraints:
        labels = list(getattr(c, "labels", []))
        constraint += [str(c.name)] * c.n_eq
        equation += [str(labels[k]) if k < len(labels) else str(k) for k in range(c.n_eq)]
    return {"constraint": np.array(constraint, dtype=str),
            "equation": np.array(equation, dtype=str)}


class Points:
    """The points of the bodies that have any, as a store writes their positions
    ``r(time, body, node, component)``: bodies without points (a reel) are left out, and
    bodies with fewer points than the most are padded with NaN.

    Attributes
    ----------
    bodies : list of str
        The labels (``body_labels``) of the bodies with points.
    index : int ndarray (n_bodies, n_nodes, 3)
        Global coordinate of each component of each point; -1 where padded.
    arc_length : ndarray (n_bodies, n_nodes)
        Reference arc length (m) of a cable's nodes (``mesh.p[0]`` of the bodies in
        ``System.cables``); NaN for other bodies' points and where padded.
    """

    def __init__(self, system: SystemView):
        cables = {id(c) for c in system.cables()}
        rows = []
        for name, body in zip(body_labels(system), system.bodies):
            blocks, is_position = _vectors_of(system, body)
            if is_position.any():
                s = body.mesh.p[0] if id(body) in cables else None
                rows.append((name, blocks[is_position], s))
        n = max((len(blocks) for _, blocks, _ in rows), default=0)
        self.bodies = [name for name, _, _ in rows]
        self.index = np.full((len(rows), n, 3), -1, dtype=np.int64)
        self.arc_length = np.full((len(rows), n), np.nan)
        for i, (_, blocks, s) in enumerate(rows):
            self.index[i, :len(blocks)] = blocks
            if s is not None and len(s) == len(blocks):
                self.arc_length[i, :len(s)] = s

    def __bool__(self):
        return bool(self.bodies)

    def positions(self, q):
        """The positions ``(nt, n_bodies, n_nodes, 3)`` in the coordinates ``q``
        ``(nt, n_dofs)`` (NaN where padded)."""
        q = np.asarray(q, dtype=float)
        out = q[:, np.maximum(self.index, 0)]
        out[:, self.index < 0] = np.nan
        return out
