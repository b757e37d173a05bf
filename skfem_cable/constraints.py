"""Holonomic constraints ``C(q) = 0`` imposed with Lagrange multipliers (paper Sect. 2.4).

A constraint acts on a few global coordinates ``q[dofs]`` and provides its value, its
Jacobian ``C_q`` and, when nonlinear, the Hessian term ``d(C_q^T lambda)/dq`` of Eq. 15.
"""

import numpy as np

from .cable import Node


def _unit(v, name):
    v = np.asarray(v, dtype=float)
    n = np.linalg.norm(v)
    if v.shape != (3,) or not np.isfinite(n) or n == 0:
        raise ValueError(f"{name} must be a non-zero finite 3-vector, got {v!r}")
    return v / n


def orthonormal_complement(d):
    """Two unit vectors spanning the plane orthogonal to the unit vector ``d``."""
    seed = np.eye(3)[np.argmin(np.abs(d))]
    n1 = np.cross(d, seed)
    n1 /= np.linalg.norm(n1)
    return n1, np.cross(d, n1)


class LinearConstraint:
    """``C(q) = J q[dofs] - c``: clamps and spherical joints between ANCF nodes, ground
    points and natural-coordinate bodies are all linear (Eqs. 53-55).

    Parameters
    ----------
    dofs : callable
        ``dofs(system) -> int ndarray``: the global coordinates involved.
    J : ndarray, shape (n_eq, len(dofs))
    c : ndarray, shape (n_eq,)
    name : str
    labels : list of str
        One label per equation (names the multipliers, e.g. reaction components).
    """

    linear = True

    def __init__(self, dofs, J, c, name, labels):
        self._dofs = dofs
        self.J = np.atleast_2d(np.asarray(J, dtype=float))
        self.c = np.asarray(c, dtype=float)
        self.name = name
        self.labels = list(labels)

    @property
    def n_eq(self):
        return self.J.shape[0]

    def dofs(self, system):
        return self._dofs(system)

    def value(self, qc):
        return self.J @ qc - self.c

    def jacobian(self, qc):
        return self.J

    def hessian(self, qc, lam):
        return None


def clamp(node, direction=None, position=None):
    """Clamp ``node``: its position and the *direction* of its slope are fixed.

    Fixing the slope's direction (two equations ``n_k . r_x = 0`` with ``n_k`` orthogonal to
    ``direction``) rather than the whole slope vector leaves the axial stretch at the root
    free.  Five equations: ``r - position = 0`` and the two slope-direction equations.
    """
    if not isinstance(node, Node):
        raise TypeError(f"clamp expects a Node (cable.node(i)), got {type(node).__name__}")
    q0 = node.body.q0[node.body.node_dofs(node.index)]
    p = q0[:3] if position is None else np.asarray(position, dtype=float)
    d = _unit(q0[3:] if direction is None else direction, "direction")
    n1, n2 = orthonormal_complement(d)
    J = np.zeros((5, 6))
    J[:3, :3] = np.eye(3)
    J[3, 3:] = n1
    J[4, 3:] = n2
    c = np.concatenate([p, [0.0, 0.0]])
    labels = ["Fx", "Fy", "Fz", "M1", "M2"]
    return LinearConstraint(lambda s: s.dofs(node), J, c, f"clamp {node!r}", labels)


def pin(node, target=None):
    """Spherical joint (Eq. 53): the position of ``node`` equals ``target``.

    ``target`` is ``None`` (ground at the node's initial position), a 3-vector (a ground
    point), another ``Node``, or a rigid-body point (``RigidBody.point``): all linear in
    the coordinates, ``C = r_node - G(x) d``.
    """
    if not isinstance(node, Node):
        raise TypeError(f"pin expects a Node (cable.node(i)), got {type(node).__name__}")
    labels = ["Fx", "Fy", "Fz"]
    if target is None or not hasattr(target, "body"):
        if target is None:
            p = node.body.q0[node.body.node_dofs(node.index)[:3]]
        else:
            p = np.asarray(target, dtype=float)
            if p.shape != (3,) or not np.all(np.isfinite(p)):
                raise ValueError("pin target must be a finite 3-vector, a Node, a body point "
                                 f"or None, got {target!r}")
        return LinearConstraint(lambda s: s.dofs(node)[:3], np.eye(3), p, f"pin {node!r}",
                                labels)
    G = np.eye(3) if isinstance(target, Node) else target.position_matrix
    J = np.hstack([np.eye(3), -G])

    def dofs(s):
        return np.concatenate([s.position_map(node)[0], s.position_map(target)[0]])

    return LinearConstraint(dofs, J, np.zeros(3), f"pin {node!r}-{target!r}", labels)
