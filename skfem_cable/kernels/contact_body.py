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
    (module notes); ``work`` (12, 9) scratch."""
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
    H6, J, r, y, n = work[:6, :6], work[6:9, :6], work[9, :3], work[10, :3], work[11, :3]
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
    for i in range(3):
        g[i] = n[i] - alpha * cyl * a[i]
        g[3 + i] = -g[i]
        g[6 + i] = -cyl * (alpha * r[i] + beta * n[i])
        for j in range(3):
            J[i, j] = (1.0 if i == j else 0.0) - cyl * a[i] * a[j]
            J[i, 3 + j] = -cyl * (a[i] * r[j] + (beta if i == j else 0.0))
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
def dissipative(coef, N, kp, p, g, Hs, v, f, Fz, Fv, work):
    """The normal damping and friction ``f`` (3) on the line at the slip velocity ``v``
    and their derivatives ``Fz`` (3, 9), ``Fv`` (3, 3) (``kernels.contact``'s, with the
    normal ``n = g[:3]`` and ``dn/dz = Hs[:3]``); ``work`` (9, 9) scratch."""
    dvn, vt, phi = work[0], work[1, :3], work[2, :3]
    D, Pn = work[3:6, :3], work[6:9, :3]
    c, mu, onset = coef[DAMPING], coef[FRICTION], coef[ONSET]
    if p < onset:
        u = 1.0 - p / onset
        ramp, dramp = 1.0 - u * u, 2.0 * u / onset
    else:
        ramp, dramp = 1.0, 0.0
    vn = g[0] * v[0] + g[1] * v[1] + g[2] * v[2]
    for m in range(9):
        dvn[m] = 0.0
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
    for i in range(3):
        vt[i] = v[i] - vn * g[i]
    sigma = math.sqrt(vt[0] ** 2 + vt[1] ** 2 + vt[2] ** 2 + coef[SLIP] ** 2)
    for i in range(3):
        phi[i] = vt[i] / sigma
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
    for i in range(3):
        for k in range(3):
            W[i, k] = Ed[i, 0] * Einv[0, k] + Ed[i, 1] * Einv[1, k] + Ed[i, 2] * Einv[2, k]


@njit(cache=True)
def coefficients(S, e, gp, nf, x, rA, Einv, ell):
    """``ell`` (nf + 4): ``Lrel = ell^T (x) I`` (module notes), the element's functions at
    point ``gp`` of element ``e`` and minus ``G(c)``'s coefficients ``(1 - sum c, c)`` of
    the body's material point at ``x`` (``c = E^-1 (x - r_A)``)."""
    total = 0.0
    for a in range(nf):
        ell[a] = S[e, gp, a]
    for k in range(3):
        c = 0.0
        for i in range(3):
            c += Einv[k, i] * (x[i] - rA[i])
        ell[nf + 1 + k] = -c
        total += c
    ell[nf] = total - 1.0


@njit(cache=True)
def scratch(nd):
    """The scratch arrays of ``element`` for ``nd`` coordinates, allocated once per
    evaluation."""
    return (np.empty((3, 3)), np.empty((3, 3)), np.empty((3, 3)), np.empty(9), np.empty(9),
            np.empty((9, 9)), np.empty((12, 9)), np.empty(nd // 3), np.empty(3),
            np.empty((3, 9)), np.empty((3, 3)), np.empty(3), np.empty(nd), np.empty((9, 12)),
            np.empty((3, nd)), np.empty((9, 9)), np.empty((9, 9)))


@njit(cache=True)
def element(e, pack, u, ud, dynamic, want, cK, cC, fe, fde, Ke, tmp):
    """The element ``e``'s internal force ``fe``, dissipative force ``fde`` (applied,
    ``Q``) and, if ``want``, iteration matrix ``Ke`` (nd, nd) over its coordinates ``u``
    (velocities ``ud``; the body's last 12), with the scratch ``tmp`` (``scratch``);
    returns ``Pi`` (J).  ``L`` is block diagonal (the functions for ``x``, ``B`` for
    ``(o, a)``) and ``Lrel = ell^T (x) I``: the products are written by blocks."""
    udofs, S, w, scale, B, kind, coef = pack[:7]
    nf = S.shape[2]
    nl, nd = 3 * nf, 3 * nf + 12
    d, dd = u[nl:], ud[nl:]
    E, Einv, W, z, g, Hs, work, ell, f, Fz, Fv, v, gL, MB, T, dwork, M = tmp
    body_frame(d, dd, E, Einv, W)
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
        coefficients(S, e, gp, nf, z[:3], d[:3], Einv, ell)
        for a in range(nf):
            for i in range(3):
                gL[3 * a + i] = ell[a] * g[i]
        for c in range(12):
            gL[nl + c] = 0.0
            for m in range(6):
                gL[nl + c] += g[3 + m] * B[m, c]
        for a in range(nd):
            fe[a] -= wg * N * gL[a]
        if want:
            for m in range(9):
                for j in range(9):
                    M[m, j] = kp * g[m] * g[j] - N * Hs[m, j]
            sandwich(S, e, gp, nf, B, M, cK * wg, MB, Ke)
        if not dis:
            continue
        for i in range(3):
            v[i] = 0.0
            for a in range(nf + 4):
                v[i] += ell[a] * ud[3 * a + i]
        dissipative(coef, N, kp, p, g, Hs, v, f, Fz, Fv, dwork)
        for a in range(nf + 4):
            for i in range(3):
                fde[3 * a + i] += wg * ell[a] * f[i]
        if want:
            dissipative_tangent(nf, B, wg, cK, cC, f, Fz, Fv, W, Einv, ell, T, dwork, Ke)
    return energy


@njit(cache=True)
def sandwich(S, e, gp, nf, B, M, c, MB, Ke):
    """``Ke += c L^T M L`` at point ``gp`` of element ``e`` (``M`` (9, 9) symmetric, ``L``
    block diagonal: the element's functions for ``x``, ``B`` for ``(o, a)``); ``MB`` (9,
    12) scratch."""
    nl = 3 * nf
    for m in range(9):
        for k in range(12):
            MB[m, k] = 0.0
            for j in range(6):
                MB[m, k] += M[m, 3 + j] * B[j, k]
    for a in range(nf):
        sa = c * S[e, gp, a]
        for b in range(nf):
            sab = sa * S[e, gp, b]
            for i in range(3):
                for j in range(3):
                    Ke[3 * a + i, 3 * b + j] += sab * M[i, j]
        for i in range(3):
            for k in range(12):
                Ke[3 * a + i, nl + k] += sa * MB[i, k]
                Ke[nl + k, 3 * a + i] += sa * MB[i, k]
    for k in range(12):
        for m in range(12):
            acc = 0.0
            for j in range(6):
                acc += B[j, k] * MB[3 + j, m]
            Ke[nl + k, nl + m] += c * acc


@njit(cache=True)
def dissipative_tangent(nf, B, wg, cK, cC, f, Fz, Fv, W, Einv, ell, T, work, Ke):
    """Subtract ``wg (cK dQ/du + cC dQ/du_dot)`` of the dissipative force ``Q = wg Lrel^T
    f`` from ``Ke`` (module notes), with ``Lrel = ell^T (x) I``: ``dQ/du = Lrel^T T + Z
    E^-1 Lrel`` with ``T = F_z L - F_v W Lrel``, ``dQ/du_dot = (ell ell^T) (x) F_v``;
    ``T`` (3, nd) and ``work`` (9, 9) scratch."""
    nl = 3 * nf
    FW = work[:3, :3]
    for i in range(3):
        for j in range(3):
            FW[i, j] = Fv[i, 0] * W[0, j] + Fv[i, 1] * W[1, j] + Fv[i, 2] * W[2, j]
    for i in range(3):
        for a in range(nf):
            for j in range(3):
                T[i, 3 * a + j] = Fz[i, j] * ell[a]
        for k in range(12):
            T[i, nl + k] = 0.0
            for m in range(6):
                T[i, nl + k] += Fz[i, 3 + m] * B[m, k]
        for b in range(nf + 4):
            for j in range(3):
                T[i, 3 * b + j] -= FW[i, j] * ell[b]
    for a in range(nf + 4):
        for i in range(3):
            sa = wg * ell[a]
            for col in range(T.shape[1]):
                Ke[3 * a + i, col] -= sa * cK * T[i, col]
            for b in range(nf + 4):
                for j in range(3):
                    Ke[3 * a + i, 3 * b + j] -= sa * cC * ell[b] * Fv[i, j]
    for b in range(nf + 4):          # Z E^-1 Lrel: d(-G(c)^T f)/dc_k dc_k
        for j in range(3):
            total = (Einv[0, j] + Einv[1, j] + Einv[2, j]) * ell[b]
            for i in range(3):
                Ke[nl + i, 3 * b + j] -= wg * cK * f[i] * total
                for k in range(3):
                    Ke[nl + 3 * (k + 1) + i, 3 * b + j] += wg * cK * f[i] * Einv[k, j] * ell[b]


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
    tmp = scratch(nd)
    for e in range(udofs.shape[0]):
        if scale[e] == 0.0:
            continue
        for k in range(nd):
            u[k], ud[k] = q[udofs[e, k]], v[udofs[e, k]]
        fe[:] = 0.0
        fde[:] = 0.0
        Ke[:] = 0.0
        energy[0] += element(e, pack, u, ud, dynamic, want, cK, cC, fe, fde, Ke, tmp)
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
