"""The rod's compiled parts (``docs/rods.md``): the element loop of the energy it adds to
the cable's, ``GJ kappa3^2 / 2 + (EI_edge - EI_flat) kappa1^2 / 2``, with its exact
tangent, and the re-basing of the nodal reference frames between steps.

The densities and their derivatives are generated (``rod_density``, ``rod_mismatch``,
written by ``scripts/rod_kernel.py``) in the unit tangent ``t`` and the stretch ``s =
|r'|``; ``unit_map`` carries them to ``r'`` by the chain rule, exactly.

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

import numpy as np
from numba import njit

from .rod_density import density
from .rod_density_gradient import density_gradient
from .rod_mismatch import mismatch
from .rod_mismatch_gradient import mismatch_gradient


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


@njit(cache=True)
def point(z, p, gz, Hz, work, want):
    """The density at ``z = [r', r'', th, thp]`` with its gradient ``gz`` (8,) and, if
    ``want``, its Hessian ``Hz`` (8, 8) in ``z`` (``density`` in ``y = [t, s, r'', th,
    thp]`` and ``through_unit``)."""
    y, gy, Hy, J, HJ, gA, HAA = work[:7]
    s = unit_map(z[:3], J)
    for c in range(3):
        y[c] = J[3, c]
    y[3] = s
    for m in range(5):
        y[4 + m] = z[3 + m]
    W = density(y, p, gy, Hy) if want else density_gradient(y, p, gy)
    through_unit(gy, Hy, J, s, 4, gA, HAA, HJ, want)
    for c in range(3):
        gz[c] = gA[c]
    for m in range(5):
        gz[3 + m] = gy[4 + m]
    if not want:
        return W
    for i in range(3):
        for j in range(3):
            Hz[i, j] = HAA[i, j]
        for m in range(5):
            v = 0.0
            for k in range(4):
                v += J[k, i] * Hy[k, 4 + m]
            Hz[i, 3 + m] = Hz[3 + m, i] = v
    for m in range(5):
        for k in range(5):
            Hz[3 + m, 3 + k] = Hy[4 + m, 4 + k]
    return W


@njit(cache=True)
def element_mismatch(u, Sx1, ai, di, aj, dj, grad, hess, work, want):
    """The mismatch angle of the element with coordinates ``u`` (its end slope ``sum_A
    Sx1[A] u_A``), its gradient ``grad`` (12,) and, if ``want``, its Hessian ``hess``
    (12, 12) in the centreline coordinates (``work``: the scratch arrays of
    ``workspace``)."""
    y, gy, Hy, J, HJ, gA, HAA, A, pm = work
    for c in range(3):
        A[c] = 0.0
        for a in range(4):
            A[c] += Sx1[a] * u[3 * a + c]
        pm[c], pm[3 + c], pm[6 + c], pm[9 + c] = ai[c], di[c], aj[c], dj[c]
    s = unit_map(A, J)
    t = J[3]
    alpha = mismatch(t, pm, gy, Hy) if want else mismatch_gradient(t, pm, gy)
    through_unit(gy, Hy, J, s, 3, gA, HAA, HJ, want)
    for a in range(4):
        for c in range(3):
            grad[3 * a + c] = Sx1[a] * gA[c]
            for b in range(4 if want else 0):
                for d in range(3):
                    hess[3 * a + c, 3 * b + d] = Sx1[a] * Sx1[b] * HAA[c, d]
    return alpha


@njit(cache=True)
def point_forces(gz, Sx, Sxx, St, Spt, weight, fe):
    """``fe += weight Jz^T gz`` in the extended coordinates (``kernel``): the rows of
    ``r'`` and ``r''`` hold one function per 3-vector (``Sx``, ``Sxx``), those of the
    angles ``St``, ``Spt`` (their four functions and the mismatch's share)."""
    for a in range(4):
        for c in range(3):
            fe[3 * a + c] += weight * (Sx[a] * gz[c] + Sxx[a] * gz[3 + c])
    for j in range(5):
        fe[12 + j] += weight * (St[j] * gz[6] + Spt[j] * gz[7])


@njit(cache=True)
def tangent_product(Hz, Sx, Sxx, St, Spt, weight, M, Ke):
    """The upper triangle of ``Ke += weight Jz^T Hz Jz`` in the extended coordinates
    (``kernel``, ``point_forces``): ``M = Hz Jz`` (8, 17) first, each of its entries two
    products, then each row of ``Jz`` two entries."""
    for m in range(8):
        for b in range(4):
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


@njit(cache=True)
def fold_mismatch(fe, Ke, ga, Ha, Sx1, Kf, want):
    """Carry the extended coordinates' last one, the mismatch angle ``alpha``, to the
    centreline by ``d alpha = ga . du`` (its gradient ``ga``, Hessian ``Ha``): the forces
    ``fe`` (17,) in place and, if ``want``, the tangent ``Kf`` (16, 16) from the upper
    triangle of ``Ke`` (17, 17).  ``alpha`` reads the end slope ``sum_A Sx1[A] u_A``
    only: the rows of the 3-vectors ``A`` with ``Sx1[A] = 0`` (all but the end slope's,
    for the cubic Hermite element) take no share."""
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
                    Kf[k, c] += gk * ga[c] * Ke[16, 16] + fa * Ha[k, c]


@njit(cache=True)
def workspace():
    """The scratch arrays of ``point`` and ``element_mismatch``."""
    return (np.zeros(9), np.zeros(9), np.zeros((9, 9)), np.zeros((4, 3)), np.zeros((4, 3)),
            np.zeros(3), np.zeros((3, 3)), np.zeros(3), np.zeros(12))


@njit(cache=True)
def kernel(pack, index, ev):
    """The rod term's compiled hook (``contract.Term.kernels``): forces ``f``, the bending
    and twist energy into ``energy[1]`` and ``cK`` times the tangent into ``data``.

    Each Gauss point works in 17 extended coordinates, the element's 16 and the mismatch
    angle ``alpha`` (the point's angles are ``th = S . phi + xi alpha``, ``thp = Sx . phi
    + alpha / h``): every row of the point's Jacobian then has four or five entries
    (``point_forces``, ``tangent_product``); ``alpha`` is folded into the centreline
    once per element (``fold_mismatch``)."""
    edofs, S, Sx, Sxx, w, xi, h, Sx1, nodes, t0, d0, prm = pack
    q, v, s, f, f_ext, fd, data, energy, power = ev
    work = workspace()
    want = data.size > 0
    ne, nq, nf = S.shape
    u = np.empty(16)
    ga, Ha = np.zeros(12), np.zeros((12, 12))
    z, gz, Hz = np.zeros(8), np.zeros(8), np.zeros((8, 8))
    St, Spt = np.zeros(5), np.zeros(5)
    fe, Ke, Kf, M = np.zeros(17), np.zeros((17, 17)), np.zeros((16, 16)), np.zeros((8, 17))
    p = np.zeros(8)
    p[6], p[7] = prm[0], prm[1]
    for e in range(ne):
        for k in range(16):
            u[k] = q[edofs[e, k]]
        i, j = nodes[e, 0], nodes[e, 1]
        alpha = element_mismatch(u, Sx1[e], t0[i], d0[i], t0[j], d0[j], ga, Ha, work, want)
        for c in range(3):
            p[c], p[3 + c] = t0[i, c], d0[i, c]
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
            We += w[e, g] * point(z, p, gz, Hz, work, want)
            point_forces(gz, Sxg, Sxxg, St, Spt, w[e, g], fe)
            if want:
                tangent_product(Hz, Sxg, Sxxg, St, Spt, w[e, g], M, Ke)
        fold_mismatch(fe, Ke, ga, Ha, Sx1[e], Kf, want)
        energy[1] += We
        for k in range(16):
            f[edofs[e, k]] += fe[k]
        if want:
            for k in range(16):
                for c in range(16):
                    data[index[e, k, c]] += s[1] * Kf[k, c]


@njit(cache=True)
def smallest_rotation(a, t, x):
    """``R(a -> t) x``: the smallest rotation taking the unit ``a`` to the unit ``t``
    applied to ``x`` (Rodrigues' formula about ``a x t``)."""
    c = a[0] * t[0] + a[1] * t[1] + a[2] * t[2]
    n = np.cross(a, t)
    return x * c + np.cross(n, x) + n * (n[0] * x[0] + n[1] * x[1] + n[2] * x[2]) / (1 + c)


@njit(cache=True)
def rebase(q, slopes, t0, d0):
    """Re-base the nodal reference frames in place on the current slopes ``q[slopes]``
    (n_nodes, 3): each director is carried by the smallest rotation from its reference
    tangent to the current one (the time-parallel transport of Bergou et al. 2010),
    then made unit and normal to it against round-off."""
    for i in range(t0.shape[0]):
        a = np.empty(3)
        for c in range(3):
            a[c] = q[slopes[i, c]]
        t = a / np.sqrt(a[0] ** 2 + a[1] ** 2 + a[2] ** 2)
        d = smallest_rotation(t0[i], t, d0[i])
        d -= (d[0] * t[0] + d[1] * t[1] + d[2] * t[2]) * t
        d0[i] = d / np.sqrt(d[0] ** 2 + d[1] ** 2 + d[2] ** 2)
        t0[i] = t
