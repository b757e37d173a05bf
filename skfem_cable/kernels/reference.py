"""Vectorised numpy evaluation of the cable's elastic energy, force and tangent.

This is the readable reference for ``kernels.cable`` (numba): both evaluate
``U = sum_e sum_g w_g W(a_g, b_g)`` with ``a = S_x e``, ``b = S_xx e`` (Eqs. 87, 96) and

``f_A = sum_g w (S_x[A] W_a + S_xx[A] W_b)``,
``K_AB = sum_g w (S_x[A] S_x[B] W_aa + S_x[A] S_xx[B] W_ab + S_xx[A] S_x[B] W_ab^T
+ S_xx[A] S_xx[B] W_bb)``,

where ``A, B`` run over the four 3-vector blocks of the element coordinates (Eq. 19).
"""

import numpy as np

from . import density


def element_force_tangent(qe, Sx, Sxx, w, EA, EI):
    """Energy, internal force ``dU/de`` and tangent ``d2U/de2`` of every element.

    Parameters
    ----------
    qe : ndarray, shape (ne, 4, 3)
        Element coordinates ``[r_i, r_x,i, r_j, r_x,j]``.
    Sx, Sxx : ndarray, shape (ne, nq, 4)
        First and second ``x``-derivatives of the Hermite functions at the Gauss points.
    w : ndarray, shape (ne, nq)
        Quadrature weights times the element Jacobian.
    EA, EI : float
        Axial and bending stiffness; ``EI = 0`` gives the truss.

    Returns
    -------
    energy : ndarray, shape (ne,)
    f : ndarray, shape (ne, 4, 3)
    K : ndarray, shape (ne, 4, 3, 4, 3)
    """
    a = np.einsum("eqA,eAi->eqi", Sx, qe)
    W, W_a, W_aa = density.axial(a, EA)
    f = np.einsum("eq,eqA,eqi->eAi", w, Sx, W_a)
    K = np.einsum("eq,eqA,eqB,eqij->eAiBj", w, Sx, Sx, W_aa)
    energy = np.einsum("eq,eq->e", w, W)
    if EI > 0:
        b = np.einsum("eqA,eAi->eqi", Sxx, qe)
        Wb, Wb_a, Wb_b, Wb_aa, Wb_ab, Wb_bb = density.bending(a, b, EI)
        energy = energy + np.einsum("eq,eq->e", w, Wb)
        f = (f + np.einsum("eq,eqA,eqi->eAi", w, Sx, Wb_a)
             + np.einsum("eq,eqA,eqi->eAi", w, Sxx, Wb_b))
        K = (K + np.einsum("eq,eqA,eqB,eqij->eAiBj", w, Sx, Sx, Wb_aa)
             + np.einsum("eq,eqA,eqB,eqij->eAiBj", w, Sx, Sxx, Wb_ab)
             + np.einsum("eq,eqA,eqB,eqji->eAiBj", w, Sxx, Sx, Wb_ab)
             + np.einsum("eq,eqA,eqB,eqij->eAiBj", w, Sxx, Sxx, Wb_bb))
    return energy, f, K
