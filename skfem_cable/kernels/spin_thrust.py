"""Compiled hook of a thrust along the spin direction at points of a spinning system
(``scenes.esail.RemoteUnitThrust``): at each point ``x`` the force ``T d`` with

    d = (a x c) / |a x c|,   c = x - x_c,

``a`` the spin axis and ``x_c`` the spin centre, both linear in the coordinates of the
hub (``a = A q_h``, ``x_c = C q_h``), and ``x = G q_p`` the point's position.  ``d`` is
perpendicular to the arm ``c`` in the spin plane, the direction a point of a body turning
about ``a`` moves.  The tangent is exact:

    dd/dw = (I - d d^T) / |w|,   dw/dc = [a]_x,   dw/da = -[c]_x,

so ``dF/dq_p = T P [a]_x G`` and ``dF/dq_h = T P (-[c]_x A - [a]_x C)`` with
``P = (I - d d^T) / |w|``; the force does not depend on velocities.
"""

import numpy as np
from numba import njit


@njit(cache=True)
def _cross_matrix(u, out):
    """``out = [u]_x`` (``[u]_x y = u x y``)."""
    out[0, 0], out[0, 1], out[0, 2] = 0.0, -u[2], u[1]
    out[1, 0], out[1, 1], out[1, 2] = u[2], 0.0, -u[0]
    out[2, 0], out[2, 1], out[2, 2] = -u[1], u[0], 0.0


@njit(cache=True)
def spin_thrust(pack, index, ev):
    """``f_ext[dofs_j] += G_j^T T_j d_j`` for every point ``j``, and ``-(cK dF/dq)`` at
    ``index`` (k, m, m + nh): the columns are the point's coordinates, then the hub's.

    ``pack = (dofs (k, m), Gt (k, m, 3), hub (nh,), A (3, nh), C (3, nh), thrust (k,))``
    with ``Gt[j] = G_j^T``.
    """
    dofs, Gt, hub, A, C, thrust = pack
    q, v, s, f, f_ext, f_damping, data, energy, power = ev
    k, m = dofs.shape
    nh = hub.size
    qh = np.empty(nh)
    for i in range(nh):
        qh[i] = q[hub[i]]
    a = A @ qh
    centre = C @ qh
    ax = np.empty((3, 3))
    cx = np.empty((3, 3))
    _cross_matrix(a, ax)
    qp = np.empty(m)
    for j in range(k):
        for r in range(m):
            qp[r] = q[dofs[j, r]]
        c = qp @ Gt[j] - centre
        w = np.cross(a, c)
        nw = np.sqrt(w @ w)
        d = w / nw
        force = Gt[j] @ (thrust[j] * d)
        for r in range(m):
            f_ext[dofs[j, r]] += force[r]
        if data.size == 0:
            continue
        P = (np.eye(3) - np.outer(d, d)) * (thrust[j] / nw)
        _cross_matrix(c, cx)
        GP = Gt[j] @ P
        Kp = GP @ ax @ np.ascontiguousarray(Gt[j].T)  # G^T dF/dq_p (m, m)
        Kh = -(GP @ (cx @ A + ax @ C))  # G^T dF/dq_h (m, nh)
        for r in range(m):
            for col in range(m):
                data[index[j, r, col]] -= s[1] * Kp[r, col]
            for col in range(nh):
                data[index[j, r, m + col]] -= s[1] * Kh[r, col]
