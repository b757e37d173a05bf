"""External loads that depend on the configuration or on time, with their tangents.

A load provides ``bind(system)``, which returns the ``(rows, cols)`` global coordinates of
its tangent entries (broadcast arrays; ``None`` when it has no tangent), and
``apply(q, t, f, data, index, coef)``, which adds its generalized force to ``f`` and, when
``data`` is given, ``coef * d f / d q`` at the CSR positions ``index`` (the shape of
``rows``).  Constant loads (point forces, gravity, line loads) are summed once into
``System.f_const`` instead.
"""

import numpy as np
import scipy.sparse as sp


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

    def bind(self, system):
        self.dofs = system.dofs(self.node)[3:]
        return self.dofs[:, None], self.dofs[None, :]

    def force(self, a):
        return np.cross(self.moment, a) / (a @ a)

    def stiffness(self, a):
        """``df/da`` (3 x 3)."""
        p = a @ a
        Mx = np.cross(self.moment, np.eye(3)).T  # Mx @ v = M x v
        return Mx / p - 2.0 * np.outer(np.cross(self.moment, a), a) / p**2

    def apply(self, q, t, f, data, index, coef):
        a = q[self.dofs]
        f[self.dofs] += self.force(a)
        if data is not None:
            np.add.at(data, index.ravel(), coef * self.stiffness(a).ravel())


class TimeLoad:
    """Time-dependent force ``force(t)`` (N) at a cable node or a rigid-body point."""

    def __init__(self, node, force):
        self.node = node
        self.fn = force
        self.force(0.0)

    def bind(self, system):
        self.dofs, self.G = system.position_map(self.node)
        return None

    def force(self, t):
        return _vector3(self.fn(t), f"force({t!r})")

    def apply(self, q, t, f, data, index, coef):
        f[self.dofs] += self.G.T @ self.force(t)


class Centrifugal:
    """Centrifugal force ``-M (Omega x (Omega x q))`` on every 3-vector of coordinates in a
    frame rotating at the constant rate ``omega`` (rad/s) about the origin.

    All coordinates (ANCF positions and slopes, natural coordinates of rigid bodies) are
    vectors that rotate with the frame, so the kinetic energy in the rotating frame gives
    this force exactly; it is linear in ``q`` with the constant tangent
    ``-M (I (x) [Omega]_x^2)``.  With it ``solve_static`` finds steady spinning states, and
    ``modes(..., spin=omega)`` their vibrations.
    """

    def __init__(self, omega):
        self.omega = _vector3(omega, "omega")

    def bind(self, system):
        C = spin_matrix(system.mass_matrix(), self.omega, 2).tocoo()
        self.matrix = C.tocsr()
        self.values = C.data
        return C.row.astype(np.int64), C.col.astype(np.int64)

    def apply(self, q, t, f, data, index, coef):
        f -= self.matrix @ q
        if data is not None:
            np.add.at(data, index, -coef * self.values)


def spin_matrix(M, omega, power):
    """``M (I (x) W^power)`` with ``W = [omega]_x`` acting on every 3-vector of coordinates
    (``power = 1``: half the gyroscopic matrix; ``2``: minus the centrifugal stiffness)."""
    W = np.linalg.matrix_power(np.cross(omega, np.eye(3)).T, power)
    n = M.shape[0]
    return (M @ sp.kron(sp.identity(n // 3), W)).tocsr()
