"""The independent reference of the rod-chain model: a planar chain of rigid uniform rods
in joint angles with a dense mass matrix, written without the rod-chain code.

Rod centroids are ``r_ci = sum_j J_ij e(theta_j)`` with ``e = (sin, -cos)`` (``theta_j``
from the downward vertical, gravity along ``-y``) and ``J_ij = l_j`` (``j < i``),
``l_i / 2`` (``j = i``), 0 otherwise.  The kinetic energy
``sum_i m_i |r_ci'|^2 / 2 + m_i l_i^2 theta_i'^2 / 24`` has the mass matrix
``H_jk cos(theta_j - theta_k) + I_j delta_jk`` with ``H = J^T diag(m) J`` and
``I_j = m_j l_j^2 / 12``; gravity gives ``dV/dtheta_j = g (J^T m)_j sin theta_j``.
"""

import numpy as np
from scipy.integrate import solve_ivp
from scipy.linalg import eigh


def rigid_chain_matrices(masses, lengths):
    """``H`` (n, n), ``I`` (n,) and ``J^T m`` (n,) of the rigid chain (module docstring)."""
    m, l = np.asarray(masses, float), np.asarray(lengths, float)
    J = np.tril(np.ones((m.size, m.size)), -1) * l + np.diag(l / 2)
    return J.T @ (m[:, None] * J), m * l * l / 12, J.T @ m


def rigid_chain_frequencies(masses, lengths, g=9.81):
    """Angular frequencies (rad/s, ascending) of small oscillations of the rigid chain
    hanging at rest: ``g diag(J^T m) phi = omega^2 (H + diag(I)) phi``."""
    H, inertia, moment = rigid_chain_matrices(masses, lengths)
    return np.sqrt(eigh(g * np.diag(moment), H + np.diag(inertia), eigvals_only=True))


def rigid_chain_trajectory(masses, lengths, t_end, output_dt, g=9.81, rtol=1e-11, atol=1e-12):
    """Free end of the rigid chain released at rest from horizontal (``theta = pi / 2``,
    along ``+x``).  Lagrange's equations ``sum_k H_jk (cos(th_j - th_k) th_k''
    + sin(th_j - th_k) th_k'^2) + I_j th_j'' + g (J^T m)_j sin th_j = 0`` are solved
    densely with DOP853.

    Returns ``t`` (nt,) on the grid ``output_dt`` and the free-end position (nt, 3)
    relative to ``O_0``.
    """
    l = np.asarray(lengths, float)
    n = l.size
    H, inertia, moment = rigid_chain_matrices(masses, l)

    def rhs(t, y):
        th, w = y[:n], y[n:]
        d = th[:, None] - th[None, :]
        mass = H * np.cos(d) + np.diag(inertia)
        force = -(H * np.sin(d)) @ (w * w) - g * moment * np.sin(th)
        return np.concatenate([w, np.linalg.solve(mass, force)])

    t = output_dt * np.arange(int(round(t_end / output_dt)) + 1)
    sol = solve_ivp(rhs, (0.0, t[-1]), np.concatenate([np.full(n, np.pi / 2), np.zeros(n)]),
                    method="DOP853", t_eval=t, rtol=rtol, atol=atol)
    if sol.status != 0:
        raise RuntimeError(f"rigid-chain reference failed: {sol.message}")
    th = sol.y[:n]
    xyz = np.stack([l @ np.sin(th), -(l @ np.cos(th)), np.zeros(t.size)], axis=-1)
    return t, xyz
