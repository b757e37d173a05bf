"""Numba kernel of the solar-wind Coulomb force on cables (paper Eqs. 29-35).

At every Gauss point ``f = c s(rho) u_perp`` with ``u_perp = (I - t t^T) i_R``
(Eqs. 29-30), ``t = r_x / |r_x|`` the tether tangent, ``i_R = (r - r_sun) / rho`` the radial
direction from the Sun (Eq. 32) at the heliocentric distance ``rho = |r - r_sun|``, and
``s(rho) = (d0 / rho)^p`` the scaling of the thrust with solar distance (``d0`` the distance
of the wind's data, 1 AU; ``p = 7/6`` after Janhunen et al. 2010, see ``coulomb``); ``c``
(N/m) is the per-element product of the force coefficient of Eq. 29 and the wind speed.
With ``ds/dr = -p s i_R^T / rho`` the tangent has the two parts

``df/dr = c s (I - t t^T)(I - (1 + p) i_R i_R^T) / rho``,
``df/dr_x = -c s (t i_R^T + (t . i_R) I)(I - t t^T) / |r_x|``

(Eq. 35 and the dependence of ``i_R`` and ``s`` on the position, negligible at 1 AU but kept
exact).  With ``p = 0`` the force and tangent are the paper's, bit for bit.
"""

import math

import numpy as np
from numba import njit, prange

from . import CUBIC
from .chunks import CHUNK


@njit(cache=True)
def force_tangent(q, elements, wind, out, cK):
    """Add the generalized Coulomb force ``int S^T f dx`` (Eq. 34) of all elements to
    ``f`` and ``cK d/dq`` of it into ``data`` (``_span`` for the arguments), one chunk of
    elements after the other (``kernels.chunks``)."""
    acc = np.zeros(((elements[3].shape[0] + CHUNK - 1) // CHUNK + 1, 3))
    for c in range(acc.shape[0] - 1):
        _chunk(c, q, elements, wind, out, cK, acc)
    _close(q, elements, wind, out, cK, acc)


@njit(cache=True, parallel=True)
def force_tangent_parallel(q, elements, wind, out, cK):
    """``force_tangent`` with the chunks on numba's threads: the same sums in the same
    order."""
    acc = np.zeros(((elements[3].shape[0] + CHUNK - 1) // CHUNK + 1, 3))
    for c in prange(acc.shape[0] - 1):
        _chunk(c, q, elements, wind, out, cK, acc)
    _close(q, elements, wind, out, cK, acc)


@njit(cache=True)
def _range(first, last, step, q, elements, wind, out, cK, acc):
    """``_span`` with the number of element functions fixed for the cubic element
    (``kernels.CUBIC``), or read from the tables."""
    nf = elements[1].shape[2]
    if nf == CUBIC:
        _span(first, last, step, q, elements, wind, out, cK, CUBIC, acc)
    else:
        _span(first, last, step, q, elements, wind, out, cK, nf, acc)


@njit(cache=True, inline="always")
def _chunk(c, q, elements, wind, out, cK, acc):
    """The elements of chunk ``c`` but its first (for ``c > 0``), their force resultant
    into ``acc[c]``."""
    first = c * CHUNK + (1 if c > 0 else 0)
    _range(first, min(elements[3].shape[0], (c + 1) * CHUNK), 1, q, elements, wind, out, cK,
           acc[c])


@njit(cache=True)
def _close(q, elements, wind, out, cK, acc):
    """The first elements of the chunks after the first (their resultant into the last row
    of ``acc``), then the rows of ``acc`` added in order."""
    _range(CHUNK, elements[3].shape[0], CHUNK, q, elements, wind, out, cK, acc[-1])
    resultant = out[3]
    for c in range(acc.shape[0]):
        for i in range(3):
            resultant[i] += acc[c, i]


@njit(cache=True, inline="always")
def _span(first, last, step, q, elements, wind, out, cK, nf, acc):
    """Add the generalized Coulomb force ``int S^T f dx`` (Eq. 34) of the elements
    ``range(first, last, step)`` to ``f`` and ``cK d/dq`` of it into ``data`` through
    ``scatter`` (skipped when empty); adds their force resultant ``int f dx`` to ``acc``
    (3,).

    Parameters
    ----------
    first, last, step : int
        The elements ``range(first, last, step)``.
    q : ndarray (n,)
        Global coordinates.
    elements : tuple ``(edofs, S, Sx, w)``
        Global DOF of each element coordinate (ne, 3 nf), shape functions and their
        derivatives at the Gauss points (ne, nq, nf), weights (ne, nq).
    wind : tuple ``(coef, sun, scaling)``
        Force per unit length of a perpendicular tether per element at the distance ``d0``
        (ne,) (N/m), the Sun's position (3,) and ``scaling = (d0, p)`` (2,): the force
        scales as ``(d0 / rho)^p`` with the heliocentric distance ``rho``.
    out : tuple ``(f, data, scatter, resultant)``
        Force accumulator (n,), CSR data and the index (ne, 3 nf, 3 nf) of each element-matrix
        entry in it ((0, 3 nf, 3 nf): no tangent), force resultant (3,) (the loop's
        total).
    cK : float
        Factor of the tangent.
    nf : int
        Functions per element (the tables' last dimension).
    acc : ndarray (3,)
    """
    edofs, S, Sx, w = elements
    coef, sun, scaling = wind
    d0, power = scaling[0], scaling[1]
    f, data, scatter, resultant = out
    ne, nq = w.shape
    nd = 3 * nf
    want = scatter.shape[0] == ne
    qe = np.empty((nf, 3))
    r = np.empty(3)
    a = np.empty(3)
    fr = np.empty((3, 3))
    fa = np.empty((3, 3))
    Pt = np.empty((3, 3))
    Pr = np.empty((3, 3))
    fe = np.empty(nd)
    Ke = np.empty((nd, nd))
    for e in range(first, last, step):
        c = coef[e]
        if c == 0.0:
            continue
        for A in range(nf):
            for i in range(3):
                qe[A, i] = q[edofs[e, 3 * A + i]]
        fe[:] = 0.0
        Ke[:] = 0.0
        for g in range(nq):
            for i in range(3):
                r[i] = 0.0
                a[i] = 0.0
                for A in range(nf):
                    r[i] += S[e, g, A] * qe[A, i]
                    a[i] += Sx[e, g, A] * qe[A, i]
                r[i] -= sun[i]
            rho = math.sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2])
            p = math.sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2])
            for i in range(3):
                r[i] /= rho
                a[i] /= p
            ti = r[0] * a[0] + r[1] * a[1] + r[2] * a[2]
            cs = c * (d0 / rho) ** power
            wg = w[e, g]
            for i in range(3):
                fi = cs * (r[i] - ti * a[i])
                acc[i] += wg * fi
                for A in range(nf):
                    fe[3 * A + i] += wg * S[e, g, A] * fi
            if want:
                for i in range(3):
                    for j in range(3):
                        d = 1.0 if i == j else 0.0
                        Pt[i, j] = d - a[i] * a[j]
                        Pr[i, j] = d - (1.0 + power) * r[i] * r[j]
                for i in range(3):
                    for j in range(3):
                        sr = 0.0
                        sa = 0.0
                        for k in range(3):
                            sr += Pt[i, k] * Pr[k, j]
                            d = 1.0 if i == k else 0.0
                            sa += (a[i] * r[k] + ti * d) * Pt[k, j]
                        fr[i, j] = cs * sr / rho
                        fa[i, j] = -cs * sa / p
                for A in range(nf):
                    sA = wg * S[e, g, A]
                    for B in range(nf):
                        sB = S[e, g, B]
                        xB = Sx[e, g, B]
                        for i in range(3):
                            for j in range(3):
                                Ke[3 * A + i, 3 * B + j] += sA * (sB * fr[i, j] + xB * fa[i, j])
        for k in range(nd):
            f[edofs[e, k]] += fe[k]
        if want:
            for k in range(nd):
                for m in range(nd):
                    data[scatter[e, k, m]] += cK * Ke[k, m]


@njit(cache=True, inline="always")
def _arguments(pack, index, ev):
    """The arguments of ``force_tangent`` for the packed evaluation ``ev``, with ``pack =
    (edofs, S, Sx, w, coef, sun, scaling, resultant)`` (the last a scratch accumulator
    (3,)) and the tangent entries at ``index``, int (ne, 3 nf, 3 nf): the force into the
    external forces."""
    q, v, s, f, f_ext, fd, data, energy, power = ev
    edofs, S, Sx, w, coef, sun, scaling, resultant = pack
    scatter = index if data.size else index[:0]
    return (q, (edofs, S, Sx, w), (coef, sun, scaling), (f_ext, data, scatter, resultant),
            -s[1])


@njit(cache=True)
def kernel(pack, index, ev):
    """The solar wind's compiled hook of the evaluation contract
    (``contract.Term.kernels``): ``force_tangent`` on the packed evaluation ``ev``
    (``_arguments``)."""
    q, elements, wind, out, cK = _arguments(pack, index, ev)
    force_tangent(q, elements, wind, out, cK)


@njit(cache=True)
def kernel_parallel(pack, index, ev):
    """``kernel`` on numba's threads (``force_tangent_parallel``)."""
    q, elements, wind, out, cK = _arguments(pack, index, ev)
    force_tangent_parallel(q, elements, wind, out, cK)
