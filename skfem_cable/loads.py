"""External loads: constant generalized forces (point forces, gravity, line loads) and
configuration-dependent ones (point moments) with their tangent."""

import numpy as np


def _vector3(v, name):
    v = np.asarray(v, dtype=float)
    if v.shape != (3,) or not np.all(np.isfinite(v)):
        raise ValueError(f"{name} must be a finite 3-vector, got {v!r}")
    return v


class PointMoment:
    """Moment ``M`` (N m, fixed in space) at a cable node.

    From the virtual work ``dW = M . (t x dt)`` with ``t = r_x / |r_x|``, the generalized
    force on the node's slope is ``f = M x r_x / |r_x|^2`` and its derivative is
    ``df/dr_x = ([M]_x |r_x|^2 - 2 (M x r_x) r_x^T) / |r_x|^4``.
    """

    def __init__(self, node, moment):
        self.node = node
        self.moment = _vector3(moment, "moment")

    def dofs(self, system):
        return system.dofs(self.node)[3:]

    def force(self, a):
        return np.cross(self.moment, a) / (a @ a)

    def stiffness(self, a):
        """``df/da`` (3 x 3)."""
        p = a @ a
        Mx = np.cross(self.moment, np.eye(3)).T  # Mx @ v = M x v
        return Mx / p - 2.0 * np.outer(np.cross(self.moment, a), a) / p**2


class TimeLoad:
    """Time-dependent force ``force(t)`` (N) on three position coordinates ``dofs``."""

    def __init__(self, dofs, force):
        self.dofs = dofs
        self.fn = force
        self.force(0.0)

    def force(self, t):
        return _vector3(self.fn(t), f"force({t!r})")
