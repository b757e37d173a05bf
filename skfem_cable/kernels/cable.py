"""Numba kernel: elastic and damping forces and tangents of all cable elements in one pass.

Same mathematics as ``kernels.reference`` (densities of ``kernels.density`` pulled back by
one chain rule through ``S6 = [S_x; S_xx]``), written as loops over elements and Gauss
points that gather from the global coordinate and velocity vectors and scatter straight
into the global force vector and the CSR data array of a fixed sparsity pattern.
"""

import math

import numpy as np
from numba import njit

from .density import CURVATURE_RATE_DELTA, SLOPE_FLOOR


@njit(cache=True, inline="always")
def _squared_curvature(x, grad, hess, want_hess):
    """``kappa^2`` of ``x = (a, b)``; writes its gradient (6,) and, if ``want_hess``, its
    Hessian (6, 6)."""
    a0, a1, a2, b0, b1, b2 = x[0], x[1], x[2], x[3], x[4], x[5]
    p = max(a0 * a0 + a1 * a1 + a2 * a2, SLOPE_FLOOR)
    c = a0 * b0 + a1 * b1 + a2 * b2
    bb = b0 * b0 + b1 * b1 + b2 * b2
    g = p * bb - c * c
    p3 = 1.0 / (p * p * p)
    p4 = p3 / p
    p5 = p4 / p
    a = x[:3]
    b = x[3:]
    for i in range(3):
        gai = 2.0 * bb * a[i] - 2.0 * c * b[i]
        grad[i] = gai * p3 - 6.0 * g * p4 * a[i]
        grad[3 + i] = (2.0 * p * b[i] - 2.0 * c * a[i]) * p3
    if want_hess:
        for i in range(3):
            gai = 2.0 * bb * a[i] - 2.0 * c * b[i]
            for j in range(3):
                gaj = 2.0 * bb * a[j] - 2.0 * c * b[j]
                gbj = 2.0 * p * b[j] - 2.0 * c * a[j]
                d = 1.0 if i == j else 0.0
                gaa = 2.0 * bb * d - 2.0 * b[i] * b[j]
                gab = 4.0 * a[i] * b[j] - 2.0 * b[i] * a[j] - 2.0 * c * d
                gbb = 2.0 * p * d - 2.0 * a[i] * a[j]
                hess[i, j] = (gaa * p3 - 6.0 * p4 * (gai * a[j] + a[i] * gaj)
                              - 6.0 * g * p4 * d + 48.0 * g * p5 * a[i] * a[j])
                kab = gab * p3 - 6.0 * p4 * a[i] * gbj
                hess[i, 3 + j] = kab
                hess[3 + j, i] = kab
                hess[3 + i, 3 + j] = gbb * p3
    return g * p3


@njit(cache=True)
def force_tangent(state, elements, law, out, coef):
    """Add elastic and damping forces to ``f`` and ``cK K + cC C`` into ``data``.

    Parameters
    ----------
    state : tuple ``(q, v)``
        Global coordinates and velocities, ndarray (n,) each (``v`` unused without
        damping).
    elements : tuple ``(edofs, Sx, Sxx, w, h)``
        Global DOF of each element coordinate, int (ne, 12) (Eq. 8); shape-function
        derivative tables (ne, nq, 4) and weights (ne, nq); element lengths (ne,) (for the
        curvature-rate regularisation).
    law : tuple ``(EA, EI, gamma_a, gamma_b)``
        Stiffnesses (``EI = 0``: truss) and damping coefficients (0: off).
    out : tuple ``(f, fd, data, scatter, energy, power)``
        Force accumulator ``dU/dq + dD/dv`` (n,); its damping part ``dD/dv`` alone (n,);
        CSR data accumulator and the index of each element-matrix entry in it, int
        (ne, 12, 12), or (0, 12, 12) to skip the tangents; axial and bending energy (2,)
        and dissipated power (2,).
    coef : tuple ``(cK, cC)``
        Factors of the stiffness ``df/dq`` and damping ``df/dv`` tangents.
    """
    q, v = state
    edofs, Sx, Sxx, w, h = elements
    EA, EI, gamma_a, gamma_b = law
    f, fd, data, scatter, energy, power = out
    cK, cC = coef
    ne, nq = w.shape
    want_matrix = scatter.shape[0] == ne
    damped = gamma_a > 0.0 or (gamma_b > 0.0 and EI > 0.0)
    qe = np.empty((4, 3))
    ve = np.zeros((4, 3))
    x = np.empty(6)
    xd = np.empty(6)
    G = np.empty(6)
    H = np.empty((6, 6))
    Hc = np.empty((6, 6))
    kg = np.empty(6)
    kh = np.empty((6, 6))
    dkd = np.empty(6)
    fe = np.empty(12)
    fde = np.empty(12)
    Gd = np.empty(6)
    Ke = np.empty((12, 12))
    S6 = np.empty((2, 4))
    for e in range(ne):
        for A in range(4):
            for i in range(3):
                qe[A, i] = q[edofs[e, 3 * A + i]]
                if damped:
                    ve[A, i] = v[edofs[e, 3 * A + i]]
        fe[:] = 0.0
        fde[:] = 0.0
        Ke[:] = 0.0
        delta2 = (CURVATURE_RATE_DELTA / h[e]) ** 2
        for g in range(nq):
            for A in range(4):
                S6[0, A] = Sx[e, g, A]
                S6[1, A] = Sxx[e, g, A]
            for U in range(2):
                for i in range(3):
                    sx = 0.0
                    sv = 0.0
                    for A in range(4):
                        sx += S6[U, A] * qe[A, i]
                        sv += S6[U, A] * ve[A, i]
                    x[3 * U + i] = sx
                    xd[3 * U + i] = sv
            G[:] = 0.0
            Gd[:] = 0.0
            if want_matrix:
                H[:] = 0.0
                Hc[:] = 0.0
            wg = w[e, g]
            # axial energy (Eqs. 86-94)
            p = x[0] * x[0] + x[1] * x[1] + x[2] * x[2]
            eps = 0.5 * (p - 1.0)
            energy[0] += wg * 0.5 * EA * eps * eps
            for i in range(3):
                G[i] += EA * eps * x[i]
            if want_matrix:
                for i in range(3):
                    for j in range(3):
                        H[i, j] += EA * x[i] * x[j]
                    H[i, i] += EA * eps
            if gamma_a > 0.0:
                # axial damping (Eqs. 108-112)
                c = gamma_a * EA
                edot = x[0] * xd[0] + x[1] * xd[1] + x[2] * xd[2]
                power[0] += wg * c * edot * edot
                for i in range(3):
                    Gd[i] += c * edot * x[i]
                if want_matrix:
                    for i in range(3):
                        for j in range(3):
                            Hc[i, j] += c * x[i] * x[j]
                            H[i, j] += c * x[i] * xd[j]
                        H[i, i] += c * edot
            if EI > 0.0:
                # bending energy through the squared curvature (Eqs. 95-107)
                k2 = _squared_curvature(x, kg, kh, want_matrix)
                energy[1] += wg * 0.5 * EI * k2
                for i in range(6):
                    G[i] += 0.5 * EI * kg[i]
                    if want_matrix:
                        for j in range(6):
                            H[i, j] += 0.5 * EI * kh[i, j]
                if gamma_b > 0.0:
                    # bending damping with the regularised curvature rate (Eqs. 113-127)
                    c = gamma_b * EI
                    s = math.sqrt(k2 + delta2)
                    k2dot = 0.0
                    for i in range(6):
                        k2dot += kg[i] * xd[i]
                    kdot = k2dot / (2.0 * s)
                    power[1] += wg * c * kdot * kdot
                    for i in range(6):
                        Gd[i] += c * kdot * kg[i] / (2.0 * s)
                    if want_matrix:
                        for i in range(6):
                            hx = 0.0
                            for j in range(6):
                                hx += kh[i, j] * xd[j]
                            dkd[i] = hx / (2.0 * s) - k2dot * kg[i] / (4.0 * s**3)
                        for i in range(6):
                            gi = kg[i] / (2.0 * s)
                            for j in range(6):
                                gj = kg[j] / (2.0 * s)
                                Hc[i, j] += c * gi * gj
                                H[i, j] += c * (gi * dkd[j] + kdot * (
                                    kh[i, j] / (2.0 * s) - kg[i] * kg[j] / (4.0 * s**3)))
            for A in range(4):
                for i in range(3):
                    fd_i = wg * (S6[0, A] * Gd[i] + S6[1, A] * Gd[3 + i])
                    fde[3 * A + i] += fd_i
                    fe[3 * A + i] += wg * (S6[0, A] * G[i] + S6[1, A] * G[3 + i]) + fd_i
            if want_matrix:
                for A in range(4):
                    for B in range(4):
                        for U in range(2):
                            for V in range(2):
                                sab = wg * S6[U, A] * S6[V, B]
                                for i in range(3):
                                    for j in range(3):
                                        Ke[3 * A + i, 3 * B + j] += sab * (
                                            cK * H[3 * U + i, 3 * V + j]
                                            + cC * Hc[3 * U + i, 3 * V + j])
        for k in range(12):
            f[edofs[e, k]] += fe[k]
            if damped:
                fd[edofs[e, k]] += fde[k]
        if want_matrix:
            for k in range(12):
                for m in range(12):
                    data[scatter[e, k, m]] += Ke[k, m]
