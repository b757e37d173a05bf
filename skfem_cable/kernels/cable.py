"""Numba kernel: elastic force and tangent of all cable elements in one pass.

Same mathematics as ``kernels.reference`` (the chain rule through the Hermite-function
derivatives of the densities in ``kernels.density``), written as loops over elements and
Gauss points that gather from the global coordinate vector and scatter straight into the
global force vector and the CSR data array of a fixed sparsity pattern.
"""

import numpy as np
from numba import njit

from .density import SLOPE_FLOOR


@njit(cache=True)
def _axial(a, EA, Wa, Waa):
    p = a[0] * a[0] + a[1] * a[1] + a[2] * a[2]
    eps = 0.5 * (p - 1.0)
    for i in range(3):
        Wa[i] += EA * eps * a[i]
        for j in range(3):
            Waa[i, j] += EA * a[i] * a[j]
        Waa[i, i] += EA * eps
    return 0.5 * EA * eps * eps


@njit(cache=True)
def _bending(a, b, EI, Wa, Wb, Waa, Wab, Wbb):
    p = max(a[0] * a[0] + a[1] * a[1] + a[2] * a[2], SLOPE_FLOOR)
    c = a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
    bb = b[0] * b[0] + b[1] * b[1] + b[2] * b[2]
    g = p * bb - c * c
    h = 0.5 * EI
    p3 = 1.0 / (p * p * p)
    p4 = p3 / p
    p5 = p4 / p
    ga = np.empty(3)
    gb = np.empty(3)
    for i in range(3):
        ga[i] = 2.0 * bb * a[i] - 2.0 * c * b[i]
        gb[i] = 2.0 * p * b[i] - 2.0 * c * a[i]
    for i in range(3):
        Wa[i] += h * (ga[i] * p3 - 6.0 * g * p4 * a[i])
        Wb[i] += h * gb[i] * p3
        for j in range(3):
            d = 1.0 if i == j else 0.0
            gaa = 2.0 * bb * d - 2.0 * b[i] * b[j]
            gab = 4.0 * a[i] * b[j] - 2.0 * b[i] * a[j] - 2.0 * c * d
            gbb = 2.0 * p * d - 2.0 * a[i] * a[j]
            Waa[i, j] += h * (gaa * p3 - 6.0 * p4 * (ga[i] * a[j] + a[i] * ga[j])
                              - 6.0 * g * p4 * d + 48.0 * g * p5 * a[i] * a[j])
            Wab[i, j] += h * (gab * p3 - 6.0 * p4 * a[i] * gb[j])
            Wbb[i, j] += h * gbb * p3
    return h * g * p3


@njit(cache=True)
def force_tangent(q, edofs, Sx, Sxx, w, EA, EI, f, data, scatter, cK, energy):
    """Add the elastic force ``dU/dq`` to ``f`` and ``cK * d2U/dq2`` to ``data``.

    Parameters
    ----------
    q : ndarray (n,)
        Global coordinates.
    edofs : int ndarray (ne, 12)
        Global DOF of each element coordinate (Eq. 8).
    Sx, Sxx, w : ndarray (ne, nq, 4), (ne, nq, 4), (ne, nq)
        Shape-function derivative tables and weights.
    EA, EI : float
        Stiffnesses; ``EI = 0`` skips bending (truss).
    f : ndarray (n,)
        Force accumulator.
    data : ndarray
        CSR data accumulator; ignored when ``scatter`` has no rows.
    scatter : int ndarray (ne, 12, 12) or (0, 12, 12)
        Index of each element-matrix entry in ``data``; empty to skip the tangent.
    cK : float
        Factor applied to the tangent.
    energy : ndarray (2,)
        Accumulates the axial and the bending energy.
    """
    ne, nq = w.shape
    want_matrix = scatter.shape[0] == ne
    qe = np.empty((4, 3))
    a = np.empty(3)
    b = np.empty(3)
    Wa = np.empty(3)
    Wb = np.empty(3)
    Waa = np.empty((3, 3))
    Wab = np.empty((3, 3))
    Wbb = np.empty((3, 3))
    fe = np.empty(12)
    Ke = np.empty((12, 12))
    for e in range(ne):
        for A in range(4):
            for i in range(3):
                qe[A, i] = q[edofs[e, 3 * A + i]]
        fe[:] = 0.0
        Ke[:] = 0.0
        for g in range(nq):
            a[:] = 0.0
            b[:] = 0.0
            for A in range(4):
                for i in range(3):
                    a[i] += Sx[e, g, A] * qe[A, i]
                    b[i] += Sxx[e, g, A] * qe[A, i]
            Wa[:] = 0.0
            Wb[:] = 0.0
            Waa[:] = 0.0
            Wab[:] = 0.0
            Wbb[:] = 0.0
            wg = w[e, g]
            energy[0] += wg * _axial(a, EA, Wa, Waa)
            if EI > 0.0:
                energy[1] += wg * _bending(a, b, EI, Wa, Wb, Waa, Wab, Wbb)
            for A in range(4):
                sa = Sx[e, g, A]
                ta = Sxx[e, g, A]
                for i in range(3):
                    fe[3 * A + i] += wg * (sa * Wa[i] + ta * Wb[i])
            if want_matrix:
                for A in range(4):
                    sa = wg * Sx[e, g, A]
                    ta = wg * Sxx[e, g, A]
                    for B in range(4):
                        sb = Sx[e, g, B]
                        tb = Sxx[e, g, B]
                        for i in range(3):
                            for j in range(3):
                                Ke[3 * A + i, 3 * B + j] += (
                                    sa * sb * Waa[i, j] + sa * tb * Wab[i, j]
                                    + ta * sb * Wab[j, i] + ta * tb * Wbb[i, j])
        for k in range(12):
            f[edofs[e, k]] += fe[k]
        if want_matrix:
            for k in range(12):
                for m in range(12):
                    data[scatter[e, k, m]] += cK * Ke[k, m]
