"""Hand-derived numpy evaluation of the paper's cable law (forces and tangents): the
independent oracle of the generated built-in law (``laws.green``; ``tests/test_kernels.py``).

It evaluates, with
``x = (a, b) = (S_x e, S_xx e)`` (Eqs. 87, 96) at every Gauss point and the 2x4 table
``S6 = [S_x; S_xx]``,

``f_A = sum_g w S6[U, A] G_U``,  ``K_AB = sum_g w S6[U, A] S6[V, B] H_UV``,

where ``G = W_x + D_xdot`` and ``H = W_xx + D_xdot,x`` (or ``D_xdot,xdot`` for the damping
matrix) come from ``ancf_density`` (derived by hand) and ``A, B`` run over the four
3-vector blocks of the element coordinates (Eq. 19).
"""

import ancf_density as density
import numpy as np

from skfem_cable.laws import CURVATURE_RATE_DELTA


def element_forces(qe, ve, Sx, Sxx, w, h, EA, EI, gamma_axial=0.0, gamma_bending=0.0):
    """Energies, dissipated powers, forces and tangents of every element.

    Parameters
    ----------
    qe, ve : ndarray, shape (ne, 4, 3)
        Element coordinates ``[r_i, r_x,i, r_j, r_x,j]`` and their velocities.
    Sx, Sxx : ndarray, shape (ne, nq, 4)
        First and second ``x``-derivatives of the Hermite functions at the Gauss points.
    w : ndarray, shape (ne, nq)
        Quadrature weights times the element length.
    h : ndarray, shape (ne,)
        Element lengths (set the curvature-rate regularisation).
    EA, EI : float
        Axial and bending stiffness; ``EI = 0`` gives the truss.
    gamma_axial, gamma_bending : float
        Damping coefficients of Eq. 36.

    Returns
    -------
    energy, power : ndarray, shape (ne, 2)
        Axial and bending elastic energy; axial and bending dissipated power.
    f : ndarray, shape (ne, 12)
        Elastic plus damping force ``dU/de + dD/de_dot``.
    K, C : ndarray, shape (ne, 12, 12)
        ``d f / d e`` and ``d f / d e_dot``.
    """
    ne, nq = w.shape
    S6 = np.stack([Sx, Sxx], axis=2)
    x = np.einsum("eqUA,eAi->eqUi", S6, qe).reshape(ne, nq, 6)
    xdot = np.einsum("eqUA,eAi->eqUi", S6, ve).reshape(ne, nq, 6)
    a, adot = x[..., :3], xdot[..., :3]
    G = np.zeros((ne, nq, 6))
    H = np.zeros((ne, nq, 6, 6))
    Hc = np.zeros((ne, nq, 6, 6))
    energy = np.zeros((ne, nq, 2))
    power = np.zeros((ne, nq, 2))
    energy[..., 0], G[..., :3], H[..., :3, :3] = density.axial(a, EA)
    if gamma_axial > 0:
        P, Dv, Dvv, Dvx = density.axial_damping(a, adot, EA, gamma_axial)
        power[..., 0] = P
        G[..., :3] += Dv
        Hc[..., :3, :3] += Dvv
        H[..., :3, :3] += Dvx
    if EI > 0:
        k2, grad, hess = density.squared_curvature(a, x[..., 3:])
        energy[..., 1] = 0.5 * EI * k2
        G += 0.5 * EI * grad
        H += 0.5 * EI * hess
        if gamma_bending > 0:
            delta = (CURVATURE_RATE_DELTA / h)[:, None]
            P, Dv, Dvv, Dvx = density.bending_damping(x, xdot, k2, grad, hess, EI,
                                                      gamma_bending, delta)
            power[..., 1] = P
            G += Dv
            Hc += Dvv
            H += Dvx
    G = G.reshape(ne, nq, 2, 3)
    f = np.einsum("eq,eqUA,eqUi->eAi", w, S6, G).reshape(ne, 12)

    def chain(M):
        M = M.reshape(ne, nq, 2, 3, 2, 3)
        return np.einsum("eq,eqUA,eqVB,eqUiVj->eAiBj", w, S6, S6, M).reshape(ne, 12, 12)

    return (np.einsum("eq,eqk->ek", w, energy), np.einsum("eq,eqk->ek", w, power), f,
            chain(H), chain(Hc))


def cable_forces(cable, q, v=None):
    """``element_forces`` of a built-in ``cable`` (law ``"cable"`` or ``"truss"``) at ``q``
    (and ``v``: with damping)."""
    sec = cable.section
    qe = q[cable.element_dofs].reshape(-1, 4, 3)
    ve = np.zeros_like(qe) if v is None else v[cable.element_dofs].reshape(-1, 4, 3)
    EI = sec.EI if cable.bending else 0.0
    damping = (0.0, 0.0) if v is None else (sec.gamma_axial,
                                             sec.gamma_bending if cable.bending else 0.0)
    return element_forces(qe, ve, cable.Sx, cable.Sxx, cable.weights, cable.h, sec.EA, EI,
                          *damping)
