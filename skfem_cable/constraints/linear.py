"""Linear constraints ``A q = b(t)`` and the fixed slope direction of a cable node."""

import numpy as np

from .prescribed import Motion, time_derivatives


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
    """``C(q, t) = J q[dofs] - c(t)``: clamps and spherical joints between ANCF nodes, ground
    points (fixed or moving) and natural-coordinate bodies are all linear (Eqs. 53-55).

    Parameters
    ----------
    dofs : callable
        ``dofs(system) -> int ndarray``: the global coordinates involved.
    J : ndarray, shape (n_eq, len(dofs))
    c : ndarray (n_eq,) or Motion
        Constant offset, or a prescribed ``Motion`` (a driven joint).
    name : str
    labels : list of str
        One label per equation (names the multipliers, e.g. reaction components).
    """

    linear = True

    def __init__(self, dofs, J, c, name, labels):
        self._dofs = dofs
        self.J = np.atleast_2d(np.asarray(J, dtype=float))
        self.motion = c if isinstance(c, Motion) else None
        self.c = None if self.motion is not None else np.asarray(c, dtype=float)
        self.name = name
        self.labels = list(labels)

    @property
    def n_eq(self):
        return self.J.shape[0]

    @property
    def driven(self):
        return self.motion is not None and self.motion.driven

    def dofs(self, system):
        return self._dofs(system)

    def offset(self, t, order=0):
        """``c(t)`` (or its derivative of the given order)."""
        if self.motion is None:
            return self.c if order == 0 else np.zeros_like(self.c)
        return self.motion(t, order)

    def value(self, qc, t=0.0):
        return self.J @ qc - self.offset(t)

    def jacobian(self, qc, t=0.0):
        return self.J

    def hessian(self, qc, lam, t=0.0):
        return None

    def velocity_term(self, qc, t=0.0):
        return -self.offset(t, 1)

    def accel_term(self, qc, vc, t=0.0):
        return -self.offset(t, 2)


class SlopeDirection:
    """The slope of a node keeps the direction ``d(t)``: ``n_k(t) . r_x = 0`` for the two
    unit vectors ``n_k(t)`` orthogonal to ``d(t)``.

    ``n_k(t) = R(t) n_k0`` with ``R(t)`` the smallest rotation from ``d(t0)`` to ``d(t)``
    (continuous while ``d`` does not turn by 180 degrees).  The Jacobian depends on time
    only, so the constraint's Hessian is zero; its time derivatives come from
    ``time_derivatives`` of ``n_k(t)``.
    """

    linear = False
    n_eq = 2

    def __init__(self, node, direction, t0=0.0):
        self.node = node
        self.direction = direction
        self.d0 = _unit(direction(t0), "direction(t0)")
        self.n0 = np.array(orthonormal_complement(self.d0))
        self.name = f"slope direction {node!r}"
        self.labels = ["M1", "M2"]

    def normals(self, t):
        """``n_1(t), n_2(t)`` as rows (2, 3)."""
        d = _unit(self.direction(t), f"direction({t!r})")
        axis = np.cross(self.d0, d)
        s, c = np.linalg.norm(axis), self.d0 @ d
        if c <= -1 + 1e-12:
            raise ValueError(f"direction(t) turned by 180 degrees at t = {t}: the clamp "
                             "frame is undefined")
        K = np.cross(axis, np.eye(3)).T  # K @ x = axis x x
        R = np.eye(3) + K + K @ K / (1 + c) if s > 0 else np.eye(3)
        return self.n0 @ R.T

    def dofs(self, system):
        return system.dofs(self.node)[3:6]

    def value(self, qc, t=0.0):
        return self.normals(t) @ qc

    def jacobian(self, qc, t=0.0):
        return self.normals(t)

    def hessian(self, qc, lam, t=0.0):
        return None

    def velocity_term(self, qc, t=0.0):
        return time_derivatives(self.normals, t, 1) @ qc

    def accel_term(self, qc, vc, t=0.0):
        return (2 * time_derivatives(self.normals, t, 1) @ vc
                + time_derivatives(self.normals, t, 2) @ qc)
