"""The compiled term of a line body's contact with a surface carried by a rigid body
(``loads.contact_body``): the penalty as a potential of the line's and the body's
coordinates, and the normal damping and friction on the velocity relative to the body.

The body's natural coordinates ``d`` (12: the base points ``r_A .. r_D``, ``bodies.rigid``,
paper Eqs. 39-41, 131-132) carry the surface's point ``o = B_o d`` and direction
``a = B_a d`` linearly (``B = [B_o; B_a]``, 6 x 12, fixed at binding).  With ``z = (x, o,
a)`` (9) at a point ``x`` of the line, the signed distance ``s(z)``, its gradient ``g =
ds/dz`` and Hessian ``Hs`` are in closed form (``geometry``), with ``r = x - o``:

* plane (``PLANE``): ``s = a . r``, ``g = (a, -a, r)``, ``d2s/dx da = I``,
  ``d2s/do da = -I``;
* cylinder (``CYLINDER``; ``a = 0``: the sphere, ``SPHERE``): ``y = r - beta a``,
  ``beta = a . r``, ``s = |y| - R``, ``n = y / |y|``, ``alpha = a . n``:
  ``ds/dr = n - alpha a``, ``ds/da = -(alpha r + beta n)``; over ``(r, a)`` the Hessian is
  ``J^T (I - n n^T) J / |y| + Q`` with ``J = [I - a a^T, -(a r^T + beta I)]``,
  ``Q_ra = -(alpha I + a n^T)``, ``Q_aa = -(r n^T + n r^T)``, ``Q_rr = 0``.

On a rigid body ``|a| = 1`` and ``alpha = 0``: these are the fixed surfaces' distances
(``kernels.contact``), and they hold exactly off it too (a Newton iterate, a difference
check), so the tangent is exact everywhere.

**Penalty: a potential.**  ``Pi = sum w Phi(p)``, ``p = r_c - s``, ``Phi' = N`` the
penalty of ``kernels.contact`` (``Phi = k p^3 / (6 p_0)`` within the onset, ``k (p^2 / 2
- p_0 p / 2 + p_0^2 / 6)`` beyond).  With ``L`` the map of the element's and the body's
coordinates ``u`` to ``z`` (the line's shape functions for ``x``, ``B`` for ``(o, a)``),
the internal force is ``dPi/du = -w N L^T g`` and its tangent ``w L^T (N' g g^T - N Hs)
L`` (symmetric).  The force on the line is ``N g_x = N n``; the one on the body is
``-dPi/dd``, equal and opposite with its moment for every rigid motion of the two (``Pi``
does not change under them); ``Pi`` is booked as stored energy (``contract.AXIAL``).

**Damping and friction: relative to the body.**  The body's material point at ``x`` has
the edge coefficients ``c = E^-1 (x - r_A)`` (``E = [r_B - r_A, r_C - r_A, r_D -
r_A]``), so ``x = G(c) d`` (Eq. 132, ``G(c) = [(1 - sum c) I, c_1 I, c_2 I, c_3 I]``)
and its velocity is ``G(c) d_dot``.  The slip velocity is ``v = xd - G(c) d_dot =
Lrel u_dot`` with ``Lrel = [S_A I, -G(c)]``; with ``n = g_x`` the force on the line is
``f = N_d n + f_t`` (``kernels.contact``: ``N_d = -c_n v_n r(p)``, ``f_t = -mu N v_t /
sqrt(|v_t|^2 + eps^2)``) and ``-f`` acts on the body at the same material point: the
generalized force is ``Q = w Lrel^T f`` (no resultant, no moment), its power ``f . v``
(<= 0) is booked as dissipation.  Derivatives: ``dc/du = E^-1 Lrel``, ``dv/du = -W Lrel``
(``W = E_dot E^-1``), ``dv/du_dot = Lrel``, so

    dQ/du = w (Lrel^T (F_z L - F_v W Lrel) + Z E^-1 Lrel),   dQ/du_dot = w Lrel^T F_v Lrel,

with ``F_z``, ``F_v`` the derivatives of ``f`` in ``z`` and ``v`` (those of
``kernels.contact`` with ``H`` replaced by ``dn/dz``, the rows of ``Hs`` for ``x``) and
``Z`` (12, 3), ``Z[:, k] = d(-G(c)^T f)/dc_k``.
"""

import math

import numpy as np
from numba import njit

from .contact import (
    CYLINDER,
    DAMPING,
    FRICTION,
    ONSET,
    PLANE,
    RADIUS,
    SLIP,
    STIFFNESS,
)


@njit(cache=True)
def geometry(kind, R, x, o, a, g, Hs, work):
    """The signed distance ``s(x, o, a)`` of the surface of kind ``kind`` (radius ``R``);
    its gradient into ``g`` (9,) and Hessian into ``Hs`` (9, 9) over ``z = (x, o, a)``
    (module notes); ``work`` (6, 6) scratch."""
    g[:] = 0.0
    Hs[:] = 0.0
    if kind == PLANE:
        s = 0.0
        for i in range(3):
            r = x[i] - o[i]
            s += a[i] * r
            g[i], g[3 + i], g[6 + i] = a[i], -a[i], r
            Hs[i, 6 + i] = Hs[6 + i, i] = 1.0
            Hs[3 + i, 6 + i] = Hs[6 + i, 3 + i] = -1.0
        return s
    cyl = 1.0 if kind == CYLINDER else 0.0
    r, y, n = np.empty(3), np.empty(3), np.empty(3)
    beta = 0.0
    for i in range(3):
        r[i] = x[i] - o[i]
        beta += cyl * a[i] * r[i]
    for i in range(3):
        y[i] = r[i] - beta * a[i]
    rho = math.sqrt(y[0] * y[0] + y[1] * y[1] + y[2] * y[2])
    inv = 1.0 / rho if rho > 0.0 else 0.0
    alpha = 0.0
    for i in range(3):
        n[i] = y[i] * inv
        alpha += cyl * a[i] * n[i]
    J = np.zeros((3, 6))
    for i in range(3):
        g[i] = n[i] - alpha * cyl * a[i]
        g[3 + i] = -g[i]
        g[6 + i] = -cyl * (alpha * r[i] + beta * n[i])
        for j in range(3):
            J[i, j] = (1.0 if i == j else 0.0) - cyl * a[i] * a[j]
            J[i, 3 + j] = -cyl * (a[i] * r[j] + (beta if i == j else 0.0))
    H6 = work
    for p in range(6):
        for m in range(6):
            acc = 0.0
            for i in range(3):
                ni = 0.0
                for j in range(3):
                    ni += ((1.0 if i == j else 0.0) - n[i] * n[j]) * J[j, m]
                acc += J[i, p] * ni
            H6[p, m] = acc * inv
    for i in range(3):
        for j in range(3):
            H6[i, 3 + j] -= cyl * ((alpha if i == j else 0.0) + a[i] * n[j])
            H6[3 + j, i] -= cyl * ((alpha if i == j else 0.0) + a[i] * n[j])
            H6[3 + i, 3 + j] -= cyl * (r[i] * n[j] + n[i] * r[j])
    for i in range(3):      # r = x - o: (x, o, a) from (r, a)
        for j in range(3):
            h = H6[i, j]
            Hs[i, j], Hs[i, 3 + j], Hs[3 + i, j], Hs[3 + i, 3 + j] = h, -h, -h, h
            h = H6[i, 3 + j]
            Hs[i, 6 + j], Hs[3 + i, 6 + j] = h, -h
            Hs[6 + j, i], Hs[6 + j, 3 + i] = h, -h
            Hs[6 + i, 6 + j] = H6[3 + i, 3 + j]
    return rho - R


@njit(cache=True)
def penalty(p, k, onset):
    """``(Phi, N, N')``: the penalty's potential, force and slope at the penetration
    ``p > 0`` (module notes)."""
    if p < onset:
        return k * p ** 3 / (6.0 * onset), 0.5 * k * p * p / onset, k * p / onset
    return k * (0.5 * p * p - 0.5 * onset * p + onset * onset / 6.0), \
        k * (p - 0.5 * onset), k


@njit(cache=True)
def dissipative(coef, N, kp, p, g, Hs, v, f, Fz, Fv):
    """The normal damping and friction ``f`` (3) on the line at the slip velocity ``v``
    and their derivatives ``Fz`` (3, 9), ``Fv`` (3, 3) (``kernels.contact``'s, with the
    normal ``n = g[:3]`` and ``dn/dz = Hs[:3]``)."""
    c, mu, onset = coef[DAMPING], coef[FRICTION], coef[ONSET]
    if p < onset:
        u = 1.0 - p / onset
        ramp, dramp = 1.0 - u * u, 2.0 * u / onset
    else:
        ramp, dramp = 1.0, 0.0
    vn = g[0] * v[0] + g[1] * v[1] + g[2] * v[2]
    dvn = np.zeros(9)
    for m in range(9):
        for i in range(3):
            dvn[m] += v[i] * Hs[i, m]
    Nd = -c * vn * ramp
    for i in range(3):
        f[i] = Nd * g[i]
        for m in range(9):
            dNd = -c * (ramp * dvn[m] - vn * dramp * g[m])    # dp/dz = -g
            Fz[i, m] = g[i] * dNd + Nd * Hs[i, m]
        for j in range(3):
            Fv[i, j] = -c * ramp * g[i] * g[j]
    if mu == 0.0:
        return
    vt = np.empty(3)
    for i in range(3):
        vt[i] = v[i] - vn * g[i]
    sigma = math.sqrt(vt[0] ** 2 + vt[1] ** 2 + vt[2] ** 2 + coef[SLIP] ** 2)
    phi = vt / sigma
    D = np.empty((3, 3))
    Pn = np.empty((3, 3))
    for i in range(3):
        f[i] -= mu * N * phi[i]
        for j in range(3):
            D[i, j] = ((1.0 if i == j else 0.0) - phi[i] * phi[j]) / sigma
            Pn[i, j] = (1.0 if i == j else 0.0) - g[i] * g[j]
    for i in range(3):
        for m in range(9):
            dvt = 0.0
            for j in range(3):
                dvt += D[i, j] * -(g[j] * dvn[m] + vn * Hs[j, m])
            Fz[i, m] -= mu * (phi[i] * kp * -g[m] + N * dvt)
        for j in range(3):
            acc = 0.0
            for m in range(3):
                acc += D[i, m] * Pn[m, j]
            Fv[i, j] -= mu * N * acc


@njit(cache=True)
def product(A, B, out, transpose):
    """``out = A B`` (``transpose`` False) or ``A^T B`` (True), by loops: the kernel's
    matrices are small, and loops compile faster than the BLAS bindings of ``@``."""
    rows = A.shape[1] if transpose else A.shape[0]
    inner = A.shape[0] if transpose else A.shape[1]
    for i in range(rows):
        for j in range(B.shape[1]):
            acc = 0.0
            for m in range(inner):
                acc += (A[m, i] if transpose else A[i, m]) * B[m, j]
            out[i, j] = acc


@njit(cache=True)
def body_frame(d, dd, E, Einv, W):
    """The edges ``E`` (3, 3: columns ``r_B - r_A``, ...) of the body's coordinates ``d``,
    their inverse ``Einv`` (by cofactors) and ``W = E_dot E^-1`` from the velocities
    ``dd``."""
    Ed = np.empty((3, 3))
    for i in range(3):
        for k in range(3):
            E[i, k] = d[3 * (k + 1) + i] - d[i]
            Ed[i, k] = dd[3 * (k + 1) + i] - dd[i]
    for i in range(3):
        for k in range(3):
            a, b = (k + 1) % 3, (k + 2) % 3
            c, e = (i + 1) % 3, (i + 2) % 3
            Einv[i, k] = E[a, c] * E[b, e] - E[a, e] * E[b, c]
    det = E[0, 0] * Einv[0, 0] + E[0, 1] * Einv[1, 0] + E[0, 2] * Einv[2, 0]
    for i in range(3):
        for k in range(3):
            Einv[i, k] /= det
    product(Ed, Einv, W, False)


@njit(cache=True)
def point_maps(S, e, gp, nf, B, x, rA, Einv, L, Lrel, cvec):
    """The maps ``L`` (9, nd) and ``Lrel`` (3, nd) of the element's and the body's
    coordinates at point ``gp`` of element ``e`` at ``x`` (module notes), and the edge
    coefficients ``cvec`` (3) of the body's material point there."""
    nl = 3 * nf
    L[:] = 0.0
    Lrel[:] = 0.0
    for A in range(nf):
        for i in range(3):
            L[i, 3 * A + i] = Lrel[i, 3 * A + i] = S[e, gp, A]
    for m in range(6):
        for j in range(12):
            L[3 + m, nl + j] = B[m, j]
    for k in range(3):
        cvec[k] = 0.0
        for i in range(3):
            cvec[k] += Einv[k, i] * (x[i] - rA[i])
    c0 = 1.0 - cvec[0] - cvec[1] - cvec[2]
    for i in range(3):
        Lrel[i, nl + i] = -c0
        for k in range(3):
            Lrel[i, nl + 3 * (k + 1) + i] = -cvec[k]


@njit(cache=True)
def element(e, pack, u, ud, dynamic, want, cK, cC, fe, fde, Ke):
    """The element ``e``'s internal force ``fe``, dissipative force ``fde`` (applied,
    ``Q``) and, if ``want``, iteration matrix ``Ke`` (nd, nd) over its coordinates ``u``
    (velocities ``ud``; the body's last 12); returns ``Pi`` (J)."""
    udofs, S, w, scale, B, kind, coef = pack[:7]
    nf = S.shape[2]
    nl, nd = 3 * nf, 3 * nf + 12
    d, dd = u[nl:], ud[nl:]
    E, Einv, W = np.empty((3, 3)), np.empty((3, 3)), np.empty((3, 3))
    body_frame(d, dd, E, Einv, W)
    z, g, Hs, work = np.empty(9), np.empty(9), np.empty((9, 9)), np.empty((6, 6))
    L, Lrel, cvec = np.empty((9, nd)), np.empty((3, nd)), np.empty(3)
    f, Fz, Fv, v = np.empty(3), np.empty((3, 9)), np.empty((3, 3)), np.empty(3)
    gL, HL, LHL = np.empty(nd), np.empty((9, nd)), np.empty((nd, nd))
    WL, EL, FL, A3 = np.empty((3, nd)), np.empty((3, nd)), np.empty((3, nd)), np.empty((3, nd))
    for m in range(6):
        z[3 + m] = 0.0
        for j in range(12):
            z[3 + m] += B[m, j] * d[j]
    dis = dynamic and (coef[DAMPING] > 0.0 or coef[FRICTION] > 0.0)
    energy = 0.0
    for gp in range(S.shape[1]):
        for i in range(3):
            z[i] = 0.0
            for a in range(nf):
                z[i] += S[e, gp, a] * u[3 * a + i]
        p = coef[RADIUS] - geometry(kind, coef[7], z[:3], z[3:6], z[6:], g, Hs, work)
        if p <= 0.0:
            continue
        wg = scale[e] * w[e, gp]
        Phi, N, kp = penalty(p, coef[STIFFNESS], coef[ONSET])
        energy += wg * Phi
        point_maps(S, e, gp, nf, B, z[:3], d[:3], Einv, L, Lrel, cvec)
        for a in range(nd):
            gL[a] = 0.0
            for m in range(9):
                gL[a] += g[m] * L[m, a]
            fe[a] -= wg * N * gL[a]
        if want:
            product(Hs, L, HL, False)
            product(L, HL, LHL, True)
            for a in range(nd):
                for b in range(nd):
                    Ke[a, b] += cK * wg * (kp * gL[a] * gL[b] - N * LHL[a, b])
        if not dis:
            continue
        for i in range(3):
            v[i] = 0.0
            for a in range(nd):
                v[i] += Lrel[i, a] * ud[a]
        dissipative(coef, N, kp, p, g, Hs, v, f, Fz, Fv)
        for a in range(nd):
            for i in range(3):
                fde[a] += wg * Lrel[i, a] * f[i]
        if want:
            dissipative_tangent(nl, wg, cK, cC, f, Fz, Fv, W, Einv, L, Lrel, WL, EL, FL,
                                A3, LHL, Ke)
    return energy


@njit(cache=True)
def dissipative_tangent(nl, wg, cK, cC, f, Fz, Fv, W, Einv, L, Lrel, WL, EL, FL, A3, K,
                        Ke):
    """Subtract ``wg (cK dQ/du + cC dQ/du_dot)`` of the dissipative force ``Q = wg Lrel^T
    f`` from ``Ke`` (module notes); ``WL``, ``EL``, ``FL``, ``A3`` (3, nd) and ``K`` (nd,
    nd) are scratch."""
    nd = L.shape[1]
    product(W, Lrel, WL, False)
    product(Einv, Lrel, EL, False)
    product(Fv, Lrel, FL, False)
    product(Fz, L, A3, False)
    for i in range(3):
        for b in range(nd):
            acc = 0.0
            for j in range(3):
                acc += Fv[i, j] * WL[j, b]
            A3[i, b] -= acc
    product(Lrel, A3, K, True)
    for a in range(nd):
        for b in range(nd):
            Ke[a, b] -= wg * cK * K[a, b]
    product(Lrel, FL, K, True)
    for a in range(nd):
        for b in range(nd):
            Ke[a, b] -= wg * cC * K[a, b]
    for b in range(nd):              # Z E^-1 Lrel: d(-G(c)^T f)/dc_k dc_k
        total = EL[0, b] + EL[1, b] + EL[2, b]
        for i in range(3):
            Ke[nl + i, b] -= wg * cK * f[i] * total
            for k in range(3):
                Ke[nl + 3 * (k + 1) + i, b] += wg * cK * f[i] * EL[k, b]


@njit(cache=True)
def kernel(pack, index, ev):
    """The hook of the evaluation contract (``contract.Term.kernels``): ``pack = (udofs,
    S, w, scale, B, kind, coef)`` with ``udofs`` (ne, nd) each element's coordinates and
    the body's, ``coef`` the one of ``kernels.contact`` and the surface's radius;
    ``index`` (ne, nd, nd).  Elements with ``scale[e] = 0`` are skipped (the broad phase,
    ``loads.surface_broad_phase``)."""
    q, v, s, f, f_ext, fd, data, energy, power = ev
    udofs, scale = pack[0], pack[3]
    cK, dynamic = s[1], s[3] != 0.0
    cC = s[2] if dynamic else 0.0
    want = data.size > 0
    flat = index.ravel()
    nd = udofs.shape[1]
    u, ud = np.empty(nd), np.empty(nd)
    fe, fde, Ke = np.empty(nd), np.empty(nd), np.empty((nd, nd))
    for e in range(udofs.shape[0]):
        if scale[e] == 0.0:
            continue
        for k in range(nd):
            u[k], ud[k] = q[udofs[e, k]], v[udofs[e, k]]
        fe[:] = 0.0
        fde[:] = 0.0
        Ke[:] = 0.0
        energy[0] += element(e, pack, u, ud, dynamic, want, cK, cC, fe, fde, Ke)
        for k in range(nd):
            f[udofs[e, k]] += fe[k] - fde[k]
            fd[udofs[e, k]] -= fde[k]
            if want:
                for m in range(nd):
                    data[flat[(e * nd + k) * nd + m]] += Ke[k, m]


@njit(cache=True)
def relative_velocities(d, dd, X, V, out):
    """The velocities ``out`` (m, 3) of the points ``X`` (m, 3) moving at ``V`` relative
    to the body's material points there (``xd - r_A_dot - W (x - r_A)``)."""
    E, Einv, W = np.empty((3, 3)), np.empty((3, 3)), np.empty((3, 3))
    body_frame(d, dd, E, Einv, W)
    for m in range(X.shape[0]):
        for i in range(3):
            acc = V[m, i] - dd[i]
            for j in range(3):
                acc -= W[i, j] * (X[m, j] - d[j])
            out[m, i] = acc
