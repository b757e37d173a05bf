"""The rod's compiled parts (``docs/rods.md``): the element loop of the energy it adds to
the cable's, ``GJ kappa3^2 / 2 + (EI_edge - EI_flat) kappa1^2 / 2``, with its exact
tangent, and the re-basing of the nodal reference frames between steps.

The density and its derivatives are generated (``rod_density``, written by
``scripts/rod_kernel.py``) in the components of ``r'``, ``r''`` along the reference frame
of the element's first node; the mismatch angle of its two nodal frames is a closed form
(``mismatch``).  The small functions of the element loop are inlined into it (numba's
``inline="always"``: the rod kernel without tangent 45 -> 26 us on 64 elements,
``benchmarks/rods.py``).  ``unit_map`` and ``through_unit`` carry derivatives in the unit
tangent to ``r'`` (``constraints.twist_tie``).

The pack of ``kernel`` (``bodies.rod.Rod.bind``) is ``(edofs, S, Sx, Sxx, w, xi, h, Sx1,
nodes, t0, d0, prm)``:

* ``edofs`` (ne, 16): the element's twelve centreline coordinates (its four 3-vectors, in
  the order of the element's functions) and then its four twist coordinates (``phi``,
  ``phi'`` at its two nodes, in the same order of functions);
* ``S``, ``Sx``, ``Sxx`` (ne, nq, 4), ``w`` (ne, nq): the functions, their arc-length
  derivatives and the weights at the Gauss points, ``xi`` (nq,) their reference
  coordinates in [0, 1] and ``h`` (ne,) the element lengths;
* ``Sx1`` (ne, 4): the slope at the element's end node ``r'(h) = sum_A Sx1[A] q_A``;
* ``nodes`` (ne, 2): its nodes; ``t0``, ``d0`` (n_nodes, 3): the reference tangents and
  directors of the nodes (changed in place between steps, ``rebase``);
* ``prm``: ``[GJ, EI_edge - EI_flat]``.
"""

from math import atan2, sqrt

import numpy as np
from numba import njit

from .rod_density import density
from .rod_density_gradient import density_gradient


@njit(cache=True)
def unit_map(A, J):
    """``t = A / |A|`` and ``s = |A|``: their first derivatives ``J`` (4, 3) in ``A``
    written (rows ``t``, ``(I - t t^T) / s``, then ``s``, whose row is ``t`` itself);
    returns ``s``."""
    s = np.sqrt(A[0] ** 2 + A[1] ** 2 + A[2] ** 2)
    for i in range(3):
        J[3, i] = A[i] / s
    t = J[3]
    for k in range(3):
        for i in range(3):
            J[k, i] = ((1.0 if k == i else 0.0) - t[k] * t[i]) / s
    return s


@njit(cache=True)
def through_unit(gy, Hy, J, s, n, gA, HAA, HJ, want):
    """The gradient ``gA`` (3,) and, if ``want``, the Hessian ``HAA`` (3, 3) in ``A`` of a
    function whose gradient ``gy`` and Hessian ``Hy`` are given in ``(t, s)`` (the first
    four entries; the first three only when ``n = 3``): the chain rule through
    ``unit_map`` (``J``, ``s = |A|``), ``HAA = J^T Hy J + sum_k gy_k d2y_k/dA2`` with the second
    derivatives of ``t`` and ``s`` contracted in closed form (``HJ`` (4, 3): scratch)."""
    t = J[3]
    gt = gy[0] * t[0] + gy[1] * t[1] + gy[2] * t[2]
    gs = gy[3] if n == 4 else 0.0
    inv_s = 1.0 / s
    for i in range(3):
        gA[i] = (gy[i] - gt * t[i]) * inv_s + gs * t[i]
    if not want:
        return
    for k in range(n):
        for j in range(3):
            v = 0.0
            for m in range(n):
                v += Hy[k, m] * J[m, j]
            HJ[k, j] = v
    for i in range(3):
        for j in range(i, 3):
            dij = 1.0 if i == j else 0.0
            v = ((3 * t[i] * t[j] * gt - gy[j] * t[i] - dij * gt - gy[i] * t[j]) * inv_s**2
                 + gs * (dij - t[i] * t[j]) * inv_s)
            for k in range(n):
                v += J[k, i] * HJ[k, j]
            HAA[i, j] = HAA[j, i] = v


@njit(cache=True, inline="always")
def point(z, R, prm, gz, Hz, work, want):
    """The density at ``z = [r', r'', th, thp]`` with its gradient ``gz`` (8,) and, if
    ``want``, its Hessian ``Hz`` (8, 8) in ``z``: ``density`` at the vectors' components
    ``x = T z`` along the rows of ``R`` (the element's reference frame ``a, d, a x d``,
    ``T = diag(R, R, 1, 1)``), ``gz = T^T gx``, ``Hz = T^T Hx T``; ``prm = [GJ, dEI]``."""
    x, gx, Hx, M = work[0], work[1], work[2], work[3]
    for v in range(0, 6, 3):
        for i in range(3):
            x[v + i] = R[i, 0] * z[v] + R[i, 1] * z[v + 1] + R[i, 2] * z[v + 2]
    x[6], x[7] = z[6], z[7]
    W = density(x, prm, gx, Hx) if want else density_gradient(x, prm, gx)
    for v in range(0, 6, 3):
        for i in range(3):
            gz[v + i] = R[0, i] * gx[v] + R[1, i] * gx[v + 1] + R[2, i] * gx[v + 2]
    gz[6], gz[7] = gx[6], gx[7]
    if not want:
        return W
    for m in range(6):  # M = Hx T in the rows of the vectors (those of the angles: Hx)
        for v in range(0, 6, 3):
            for j in range(3):
                M[m, v + j] = Hx[m, v] * R[0, j] + Hx[m, v + 1] * R[1, j] + Hx[m, v + 2] * R[2, j]
        M[m, 6], M[m, 7] = Hx[m, 6], Hx[m, 7]
    for v in range(0, 6, 3):
        for i in range(3):
            for col in range(v + i, 8):
                Hz[v + i, col] = Hz[col, v + i] = (R[0, i] * M[v, col] + R[1, i] * M[v + 1, col]
                                                   + R[2, i] * M[v + 2, col])
    Hz[6, 6], Hz[7, 7] = Hx[6, 6], Hx[7, 7]
    Hz[6, 7] = Hz[7, 6] = Hx[6, 7]
    return W


@njit(cache=True, inline="always")
def mismatch(A, ai, di, aj, dj, gA, HA, want):
    """The mismatch angle at the end node of an element, of slope ``A``: the angle about
    ``t = A / |A|`` from ``R(a_i -> t) d_i`` to ``R(a_j -> t) d_j``, with its gradient
    ``gA`` (3,) and, if ``want``, its Hessian ``HA`` (3, 3) in ``A``.

    Carried back to ``a_j`` by ``R(t -> a_j)``, the first is ``R(a_i -> a_j) d_i`` turned
    about ``a_j`` by the holonomy of the smallest rotations (parallel transport along
    great circles) around the spherical triangle ``a_i, t, a_j``, its signed solid angle
    ``Omega`` (Gauss-Bonnet), ``tan(Omega / 2) = a_i . (a_j x t) / (1 + a_i . a_j + a_j .
    t + t . a_i)`` (Van Oosterom & Strackee, *IEEE Trans. Biomed. Eng.* 30 (1983) 125,
    eq. 8).  So ``alpha = alpha_0 + 2 atan2(N, D)``, ``alpha_0`` the angle about ``a_j``
    from ``R(a_i -> a_j) d_i`` to ``d_j`` (fixed during a step), ``N = (a_i x a_j) . A``
    and ``D = (1 + a_i . a_j) |A| + (a_i + a_j) . A`` (the tangent formula times ``|A|``):
    ``N`` linear, ``D`` the only curvature."""
    c = ai[0] * aj[0] + ai[1] * aj[1] + ai[2] * aj[2]
    n0, n1, n2 = (ai[1] * aj[2] - ai[2] * aj[1], ai[2] * aj[0] - ai[0] * aj[2],
                  ai[0] * aj[1] - ai[1] * aj[0])
    nd = (n0 * di[0] + n1 * di[1] + n2 * di[2]) / (1.0 + c)
    u0 = di[0] * c + n1 * di[2] - n2 * di[1] + n0 * nd
    u1 = di[1] * c + n2 * di[0] - n0 * di[2] + n1 * nd
    u2 = di[2] * c + n0 * di[1] - n1 * di[0] + n2 * nd
    sine = (u0 * (dj[1] * aj[2] - dj[2] * aj[1]) + u1 * (dj[2] * aj[0] - dj[0] * aj[2])
            + u2 * (dj[0] * aj[1] - dj[1] * aj[0]))
    alpha0 = atan2(sine, u0 * dj[0] + u1 * dj[1] + u2 * dj[2])
    s = sqrt(A[0] ** 2 + A[1] ** 2 + A[2] ** 2)
    N = n0 * A[0] + n1 * A[1] + n2 * A[2]
    D = (1.0 + c) * s
    for k in range(3):
        D += (ai[k] + aj[k]) * A[k]
    Q = N * N + D * D
    n = (n0, n1, n2)
    b = ((1.0 + c) * A[0] / s + ai[0] + aj[0], (1.0 + c) * A[1] / s + ai[1] + aj[1],
         (1.0 + c) * A[2] / s + ai[2] + aj[2])                # the gradient of D
    for k in range(3):
        gA[k] = 2.0 * (D * n[k] - N * b[k]) / Q
    if want:
        f1, f2, f3 = 2.0 * (N * N - D * D) / Q**2, 4.0 * D * N / Q**2, 2.0 * N * (1.0 + c) / (Q * s)
        for k in range(3):
            for m in range(k, 3):
                unit = (1.0 if k == m else 0.0) - A[k] * A[m] / s**2
                HA[k, m] = HA[m, k] = (f1 * (n[k] * b[m] + b[k] * n[m])
                                       - f2 * (n[k] * n[m] - b[k] * b[m]) - f3 * unit)
    return alpha0 + 2.0 * atan2(N, D)


@njit(cache=True, inline="always")
def element_mismatch(u, Sx1, ai, di, aj, dj, grad, work, want):
    """The mismatch angle of the element with coordinates ``u`` (its end slope ``A =
    sum_A Sx1[A] u_A``, ``mismatch``) and its gradient ``grad`` (12,) in the centreline
    coordinates; if ``want``, its Hessian in ``A`` (3, 3) is ``work[6]`` (``work``: the
    scratch arrays of ``workspace``)."""
    A, gA = work[4], work[5]
    for c in range(3):
        A[c] = 0.0
        for a in range(4):
            A[c] += Sx1[a] * u[3 * a + c]
    alpha = mismatch(A, ai, di, aj, dj, gA, work[6], want)
    for a in range(4):
        for c in range(3):
            grad[3 * a + c] = Sx1[a] * gA[c]
    return alpha


@njit(cache=True, inline="always")
def point_forces(gz, Sx, Sxx, St, Spt, weight, fe):
    """``fe += weight Jz^T gz`` in the extended coordinates (``kernel``): the rows of
    ``r'`` and ``r''`` hold one function per 3-vector (``Sx``, ``Sxx``), those of the
    angles ``St``, ``Spt`` (their four functions and the mismatch's share)."""
    for a in range(4):
        for c in range(3):
            fe[3 * a + c] += weight * (Sx[a] * gz[c] + Sxx[a] * gz[3 + c])
    for j in range(5):
        fe[12 + j] += weight * (St[j] * gz[6] + Spt[j] * gz[7])


@njit(cache=True, inline="always")
def tangent_product(Hz, Sx, Sxx, St, Spt, weight, M, Ke):
    """The upper triangle of ``Ke += weight Jz^T Hz Jz`` in the extended coordinates
    (``kernel``, ``point_forces``): ``M = Hz Jz`` (8, 17) first, each of its entries two
    products (the rows of the angles only in the columns of the angles: the upper
    triangle reads no other), then each row of ``Jz`` two entries."""
    for m in range(8):
        for b in range(4 if m < 6 else 0):
            for d in range(3):
                M[m, 3 * b + d] = Hz[m, d] * Sx[b] + Hz[m, 3 + d] * Sxx[b]
        for j in range(5):
            M[m, 12 + j] = Hz[m, 6] * St[j] + Hz[m, 7] * Spt[j]
    for a in range(4):
        wx, wxx = weight * Sx[a], weight * Sxx[a]
        for c in range(3):
            k = 3 * a + c
            for col in range(k, 17):
                Ke[k, col] += wx * M[c, col] + wxx * M[3 + c, col]
    for j in range(5):
        wt, wp = weight * St[j], weight * Spt[j]
        for col in range(12 + j, 17):
            Ke[12 + j, col] += wt * M[6, col] + wp * M[7, col]


@njit(cache=True, inline="always")
def fold_mismatch(fe, Ke, ga, HA, Sx1, Kf, want):
    """Carry the extended coordinates' last one, the mismatch angle ``alpha``, to the
    centreline by ``d alpha = ga . du`` (its gradient ``ga``; its Hessian ``Sx1[A] Sx1[B]
    HA`` in the 3-vectors ``A``, ``B``): the forces ``fe`` (17,) in place and, if
    ``want``, the tangent ``Kf`` (16, 16) from the upper triangle of ``Ke`` (17, 17).
    ``alpha`` reads the end slope ``sum_A Sx1[A] u_A`` only: the rows of the 3-vectors
    ``A`` with ``Sx1[A] = 0`` (all but the end slope's, for the cubic Hermite element)
    take no share."""
    fa = fe[16]
    for k in range(12):
        fe[k] += fa * ga[k]
    if not want:
        return
    for k in range(16):
        for c in range(k, 16):
            Kf[k, c] = Kf[c, k] = Ke[k, c]
    for a in range(4):
        for k in range(3 * a, 3 * a + 3 if Sx1[a] != 0.0 else 3 * a):
            gk = ga[k]
            for c in range(16):
                Kf[k, c] += gk * Ke[c, 16]
                Kf[c, k] += gk * Ke[c, 16]
            for b in range(4):
                for c in range(3 * b, 3 * b + 3 if Sx1[b] != 0.0 else 3 * b):
                    Kf[k, c] += (gk * ga[c] * Ke[16, 16]
                                 + fa * Sx1[a] * Sx1[b] * HA[k - 3 * a, c - 3 * b])


@njit(cache=True)
def workspace():
    """The scratch arrays of ``point`` and ``element_mismatch``."""
    return (np.zeros(8), np.zeros(8), np.zeros((8, 8)), np.zeros((8, 8)), np.zeros(3),
            np.zeros(3), np.zeros((3, 3)))


@njit(cache=True)
def reference_frame(a, d, R):
    """The rows ``a``, ``d``, ``a x d`` of ``R`` (3, 3): a node's reference frame."""
    for c in range(3):
        R[0, c], R[1, c] = a[c], d[c]
    R[2, 0] = a[1] * d[2] - a[2] * d[1]
    R[2, 1] = a[2] * d[0] - a[0] * d[2]
    R[2, 2] = a[0] * d[1] - a[1] * d[0]


@njit(cache=True)
def kernel(pack, index, ev):
    """The rod term's compiled hook (``contract.Term.kernels``): forces ``f``, the bending
    and twist energy into ``energy[1]`` and ``cK`` times the tangent into ``data``.

    Each Gauss point works in 17 extended coordinates, the element's 16 and the mismatch
    angle ``alpha`` (the point's angles are ``th = S . phi + xi alpha``, ``thp = Sx . phi
    + alpha / h``): every row of the point's Jacobian then has four or five entries
    (``point_forces``, ``tangent_product``); ``alpha`` is folded into the centreline
    once per element (``fold_mismatch``).  The density is evaluated in the frame of the
    element's first node (``point``)."""
    edofs, S, Sx, Sxx, w, xi, h, Sx1, nodes, t0, d0, prm = pack
    q, v, s, f, f_ext, fd, data, energy, power = ev
    work = workspace()
    want = data.size > 0
    ne, nq, nf = S.shape
    u = np.empty(16)
    ga = np.zeros(12)
    z, gz, Hz, R = np.zeros(8), np.zeros(8), np.zeros((8, 8)), np.zeros((3, 3))
    St, Spt = np.zeros(5), np.zeros(5)
    fe, Ke, Kf, M = np.zeros(17), np.zeros((17, 17)), np.zeros((16, 16)), np.zeros((8, 17))
    for e in range(ne):
        for k in range(16):
            u[k] = q[edofs[e, k]]
        i, j = nodes[e, 0], nodes[e, 1]
        alpha = element_mismatch(u, Sx1[e], t0[i], d0[i], t0[j], d0[j], ga, work, want)
        reference_frame(t0[i], d0[i], R)
        fe[:] = 0.0
        if want:
            Ke[:] = 0.0
        We = 0.0
        for g in range(nq):
            Sg, Sxg, Sxxg = S[e, g], Sx[e, g], Sxx[e, g]
            St[4], Spt[4] = xi[g], 1.0 / h[e]
            z[6], z[7] = xi[g] * alpha, alpha / h[e]
            for c in range(3):
                z[c] = z[3 + c] = 0.0
            for a in range(nf):
                St[a], Spt[a] = Sg[a], Sxg[a]
                z[6] += Sg[a] * u[12 + a]
                z[7] += Sxg[a] * u[12 + a]
                for c in range(3):
                    z[c] += Sxg[a] * u[3 * a + c]
                    z[3 + c] += Sxxg[a] * u[3 * a + c]
            We += w[e, g] * point(z, R, prm, gz, Hz, work, want)
            point_forces(gz, Sxg, Sxxg, St, Spt, w[e, g], fe)
            if want:
                tangent_product(Hz, Sxg, Sxxg, St, Spt, w[e, g], M, Ke)
        fold_mismatch(fe, Ke, ga, work[6], Sx1[e], Kf, want)
        energy[1] += We
        for k in range(16):
            f[edofs[e, k]] += fe[k]
        if want:
            for k in range(16):
                for c in range(16):
                    data[index[e, k, c]] += s[1] * Kf[k, c]


@njit(cache=True)
def rotate(a, t, x, out):
    """``out = R(a -> t) x``: the smallest rotation taking the unit ``a`` to the unit
    ``t`` applied to ``x`` (Rodrigues' formula about ``n = a x t``: ``x (a . t) + n x x +
    n (n . x) / (1 + a . t)``); ``out`` may be ``x``."""
    c = a[0] * t[0] + a[1] * t[1] + a[2] * t[2]
    n0, n1, n2 = a[1] * t[2] - a[2] * t[1], a[2] * t[0] - a[0] * t[2], a[0] * t[1] - a[1] * t[0]
    k = (n0 * x[0] + n1 * x[1] + n2 * x[2]) / (1.0 + c)
    y0 = x[0] * c + n1 * x[2] - n2 * x[1] + n0 * k
    y1 = x[1] * c + n2 * x[0] - n0 * x[2] + n1 * k
    y2 = x[2] * c + n0 * x[1] - n1 * x[0] + n2 * k
    out[0], out[1], out[2] = y0, y1, y2


@njit(cache=True)
def smallest_rotation(a, t, x):
    """``R(a -> t) x`` (``rotate``), a new array."""
    out = np.empty(3)
    rotate(a, t, x, out)
    return out


@njit(cache=True)
def rebase(q, slopes, t0, d0):
    """Re-base the nodal reference frames in place on the current slopes ``q[slopes]``
    (n_nodes, 3): each director is carried by the smallest rotation from its reference
    tangent to the current one (the time-parallel transport of Bergou et al. 2010),
    then made unit and normal to it against round-off."""
    t, d = np.empty(3), np.empty(3)
    for i in range(t0.shape[0]):
        for c in range(3):
            t[c] = q[slopes[i, c]]
        size = np.sqrt(t[0] ** 2 + t[1] ** 2 + t[2] ** 2)
        for c in range(3):
            t[c] /= size
        rotate(t0[i], t, d0[i], d)
        dt = d[0] * t[0] + d[1] * t[1] + d[2] * t[2]
        for c in range(3):
            d[c] -= dt * t[c]
        size = np.sqrt(d[0] ** 2 + d[1] ** 2 + d[2] ** 2)
        for c in range(3):
            d0[i, c], t0[i, c] = d[c] / size, t[c]
