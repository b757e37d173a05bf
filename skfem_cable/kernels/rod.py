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
def unit_map(A, J, T2):
    """``t = A / |A|`` and ``s = |A|``: their first derivatives ``J`` (4, 3) (rows ``t``
    then ``s``) and second derivatives ``T2`` (4, 3, 3) in ``A`` written; returns ``s``."""
    s = np.sqrt(A[0] ** 2 + A[1] ** 2 + A[2] ** 2)
    t = A / s
    for i in range(3):
        J[3, i] = t[i]
        for j in range(3):
            dij = 1.0 if i == j else 0.0
            T2[3, i, j] = (dij - t[i] * t[j]) / s
            for k in range(3):
                dki = 1.0 if k == i else 0.0
                dkj = 1.0 if k == j else 0.0
                T2[k, i, j] = (3 * t[i] * t[j] * t[k] - dkj * t[i] - dij * t[k]
                               - dki * t[j]) / s**2
        for k in range(3):
            J[k, i] = ((1.0 if k == i else 0.0) - t[k] * t[i]) / s
    return s


@njit(cache=True)
def through_unit(gy, Hy, J, T2, n, gA, HAA, want):
    """The gradient ``gA`` (3,) and, if ``want``, the Hessian ``HAA`` (3, 3) in ``A`` of a
    function whose gradient ``gy`` and Hessian ``Hy`` are given in ``(t, s)`` (the first
    four entries; the first three only when ``n = 3``): the chain rule through
    ``unit_map``."""
    for i in range(3):
        gA[i] = 0.0
        for k in range(n):
            gA[i] += gy[k] * J[k, i]
        for j in range(3 if want else 0):
            v = 0.0
            for k in range(n):
                v += gy[k] * T2[k, i, j]
                for m in range(n):
                    v += J[k, i] * Hy[k, m] * J[m, j]
            HAA[i, j] = v


@njit(cache=True)
def point(z, p, gz, Hz, work, want):
    """The density at ``z = [r', r'', th, thp]`` with its gradient ``gz`` (8,) and, if
    ``want``, its Hessian ``Hz`` (8, 8) in ``z`` (``density`` in ``y = [t, s, r'', th,
    thp]`` and ``through_unit``)."""
    y, gy, Hy, J, T2, gA, HAA = work[:7]
    s = unit_map(z[:3], J, T2)
    y[:3] = z[:3] / s
    y[3] = s
    y[4:] = z[3:]
    W = density(y, p, gy, Hy) if want else density_gradient(y, p, gy)
    through_unit(gy, Hy, J, T2, 4, gA, HAA, want)
    gz[:3] = gA
    gz[3:] = gy[4:]
    if not want:
        return W
    Hz[:3, :3] = HAA
    for i in range(3):
        for m in range(5):
            v = 0.0
            for k in range(4):
                v += J[k, i] * Hy[k, 4 + m]
            Hz[i, 3 + m] = v
            Hz[3 + m, i] = v
    Hz[3:, 3:] = Hy[4:, 4:]
    return W


@njit(cache=True)
def element_mismatch(u, Sx1, ai, di, aj, dj, grad, hess, work, want):
    """The mismatch angle of the element with coordinates ``u`` (its end slope ``sum_A
    Sx1[A] u_A``), its gradient ``grad`` (12,) and, if ``want``, its Hessian ``hess``
    (12, 12) in the centreline coordinates (``work``: the scratch arrays of
    ``workspace``)."""
    y, gy, Hy, J, T2, gA, HAA, A, pm = work
    A[:] = 0.0
    for a in range(4):
        for c in range(3):
            A[c] += Sx1[a] * u[3 * a + c]
    s = unit_map(A, J, T2)
    pm[:3], pm[3:6], pm[6:9], pm[9:] = ai, di, aj, dj
    for c in range(3):
        y[c] = A[c] / s
    alpha = mismatch(y[:3], pm, gy, Hy) if want else mismatch_gradient(y[:3], pm, gy)
    through_unit(gy, Hy, J, T2, 3, gA, HAA, want)
    for a in range(4):
        for c in range(3):
            grad[3 * a + c] = Sx1[a] * gA[c]
            for b in range(4 if want else 0):
                for d in range(3):
                    hess[3 * a + c, 3 * b + d] = Sx1[a] * Sx1[b] * HAA[c, d]
    return alpha


@njit(cache=True)
def tangent_product(Jz, Hz, Sx, Sxx, weight, M, Ke):
    """``Ke += weight Jz^T Hz Jz`` with the sparsity of ``Jz``: its rows of ``r'`` and
    ``r''`` hold one function's value per 3-vector (``Sx``, ``Sxx``), those of the angles
    are full (``kernel``)."""
    nf = Sx.shape[0]
    M[:] = 0.0
    for m in range(8):
        for n in range(6):
            hmn = Hz[m, n]
            table = Sx if n < 3 else Sxx
            for a in range(nf):
                M[m, 3 * a + n % 3] += hmn * table[a]
        for n in range(6, 8):
            for k in range(16):
                M[m, k] += Hz[m, n] * Jz[n, k]
    for m in range(6):
        table = Sx if m < 3 else Sxx
        for a in range(nf):
            jv = weight * table[a]
            k = 3 * a + m % 3
            for c in range(16):
                Ke[k, c] += jv * M[m, c]
    for m in range(6, 8):
        for k in range(16):
            jv = weight * Jz[m, k]
            if jv != 0.0:
                for c in range(16):
                    Ke[k, c] += jv * M[m, c]


@njit(cache=True)
def workspace():
    """The scratch arrays of ``point`` and ``element_mismatch``."""
    return (np.zeros(9), np.zeros(9), np.zeros((9, 9)), np.zeros((4, 3)), np.zeros((4, 3, 3)),
            np.zeros(3), np.zeros((3, 3)), np.zeros(3), np.zeros(12))


@njit(cache=True)
def kernel(pack, index, ev):
    """The rod term's compiled hook (``contract.Term.kernels``): forces ``f``, the bending
    and twist energy into ``energy[1]`` and ``cK`` times the tangent into ``data``."""
    edofs, S, Sx, Sxx, w, xi, h, Sx1, nodes, t0, d0, prm = pack
    q, v, s, f, f_ext, fd, data, energy, power = ev
    work = workspace()
    want = data.size > 0
    ne, nq, nf = S.shape
    u = np.empty(16)
    ga, Ha = np.zeros(12), np.zeros((12, 12))
    Jz, z, gz, Hz = np.zeros((8, 16)), np.zeros(8), np.zeros(8), np.zeros((8, 8))
    fe, Ke, M = np.zeros(16), np.zeros((16, 16)), np.zeros((8, 16))
    p = np.zeros(8)
    p[6], p[7] = prm[0], prm[1]
    for e in range(ne):
        for k in range(16):
            u[k] = q[edofs[e, k]]
        i, j = nodes[e, 0], nodes[e, 1]
        alpha = element_mismatch(u, Sx1[e], t0[i], d0[i], t0[j], d0[j], ga, Ha, work, want)
        p[:3] = t0[i]
        p[3:6] = d0[i]
        fe[:] = 0.0
        Ke[:] = 0.0
        We = coef = 0.0
        for g in range(nq):
            Jz[:] = 0.0
            for a in range(nf):
                for c in range(3):
                    Jz[c, 3 * a + c] = Sx[e, g, a]
                    Jz[3 + c, 3 * a + c] = Sxx[e, g, a]
                Jz[6, 12 + a] = S[e, g, a]
                Jz[7, 12 + a] = Sx[e, g, a]
            for k in range(12):
                Jz[6, k] = xi[g] * ga[k]
                Jz[7, k] = ga[k] / h[e]
            for m in range(6):
                z[m] = 0.0
                for k in range(12):
                    z[m] += Jz[m, k] * u[k]
            z[6] = xi[g] * alpha
            z[7] = alpha / h[e]
            for a in range(nf):
                z[6] += S[e, g, a] * u[12 + a]
                z[7] += Sx[e, g, a] * u[12 + a]
            We += w[e, g] * point(z, p, gz, Hz, work, want)
            for k in range(16):
                for m in range(8):
                    fe[k] += w[e, g] * Jz[m, k] * gz[m]
            if want:
                tangent_product(Jz, Hz, Sx[e, g], Sxx[e, g], w[e, g], M, Ke)
                coef += w[e, g] * (gz[6] * xi[g] + gz[7] / h[e])
        if want:  # the mismatch's curvature, weighted by the forces on the angles
            for k in range(12):
                for c in range(12):
                    Ke[k, c] += coef * Ha[k, c]
        energy[1] += We
        for k in range(16):
            f[edofs[e, k]] += fe[k]
        if want:
            for k in range(16):
                for c in range(16):
                    data[index[e, k, c]] += s[1] * Ke[k, c]


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
