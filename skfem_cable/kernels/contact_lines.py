"""The narrow phase of line-to-line contact (``loads.contact_lines``): the closest points
of two segments of the lines' sampled centrelines, a penalty on their gap and regularised
Coulomb friction, with exact tangents, over the candidate pairs of the broad phase.

A segment joins two consecutive points ``P0, P1`` of a line's quadrature (each a linear
combination of one element's 3-vectors, ``lines.LinePoints``); the other segment is
``P2, P3``.  With ``u = P1 - P0``, ``w = P3 - P2``, the closest points
``x_a = P0 + s u`` and ``x_b = P2 + t w`` (``s, t`` in ``[0, 1]``, Ericson, *Real-Time
Collision Detection*, 2005, Sect. 5.1.9) give ``delta = x_a - x_b = sum_j c_j P_j``,
``c = (1 - s, s, -(1 - t), -t)``, the distance ``d = |delta|``, the normal
``n = delta / d`` and the penetration ``p = r_a + r_b - d``.  Where ``p > 0`` the force on
line a at ``x_a`` is

    f = N n + f_t,    f_t = -mu N v_t / sqrt(|v_t|^2 + eps^2),

with ``N`` the penalty of ``kernels.contact`` (``k (p - p_0 / 2)``, ``k p^2 / (2 p_0)``
within the onset ``p_0``; here a force, N), ``v_r = sum_j c_j V_j`` the relative
velocity and ``v_t = v_r - (n . v_r) n`` its slip; line b gets ``-f`` at ``x_b``: the
generalized force on ``P_j`` is ``c_j f`` (equal and opposite by construction).

Exact tangents.  Where ``s`` (or ``t``) is inside ``(0, 1)`` it is stationary,
``G_s = delta . u = 0`` (``G_t = -delta . w = 0``); the implicit function theorem gives
``d(s, t)/dq = -H_ss^-1 dG/dq`` over the free parameters (``H_ss = [[u.u, -u.w],
[-u.w, w.w]]``), a clamped parameter has zero derivative.  Then
``d delta/dP_j = c_j I + u ds/dP_j - w dt/dP_j``, ``dn = (I - n n^T) d delta / d``,
``dd = n^T d delta``, ``dN = -N' dd``, ``dv_r/dq = (V1 - V0) ds - (V3 - V2) dt``,
``dv_t = P_n dv_r - n (v_r^T dn) - v_n dn`` and, with ``phi = v_t / sigma``,
``D = (I - phi phi^T) / sigma``: ``df_t = -mu (phi dN^T + N D dv_t)``,
``df_t/dV_k = -mu N D P_n c_k``, ``d(c_j f) = f dc_j^T + c_j df``.  The penalty part is
conservative, ``-dPi/dP_j = c_j N n`` (the envelope theorem) with ``Pi = int N dp``
(``k p^3 / (6 p_0)`` within the onset): an internal force of the two lines, its ``Pi``
booked as stored energy (``contract.AXIAL``); the friction as dissipation.

A pair counts where each closest point is inside its segment or at an end of its line:
a closest point at a joint of two segments of one line is the other segment's (no force
counted twice where the contact crosses a joint).

The own tangent (``own`` 1 in the pack): of ``d(c_j f)/dP_k`` only the blocks where the
points ``P_j`` and ``P_k`` are in one element enter the iteration matrix, so the term adds
no entry the lines' own elements do not have (the E-sail's tethers stay band blocks of
their own).  The residual is unchanged: Newton converges to the same state, linearly
while two lines touch, by the spectral radius of ``J_own^-1 (J - J_own)``, below 1 only
where the penalty is below the touching points' mass term (``docs/contact.md``).  With a
record (``tangent="woodbury"``) the kernel also writes ``J - J_own`` pair by pair, and the
compiled step adds it back to the factored own matrix (``kernels.woodbury``): Newton is
exact again on the own pattern.
"""

import math

import numpy as np
from numba import njit

#: Positions in ``coef = [k, mu, eps, r_a + r_b, p_0]``.
STIFFNESS, FRICTION, SLIP, RADII, ONSET = range(5)
#: Rows of the scratch ``work`` of ``pair``.
WORK = 18
#: Columns of a segment's row in ``segments``: the element and point of its two ends and
#: whether each end is an end of its line (1) or a joint (0).
E0, G0, E1, G1, END0, END1 = range(6)


@njit(cache=True, inline="always")
def _clamp(x):
    return min(1.0, max(0.0, x))


@njit(cache=True)
def closest(P):
    """``(s, t)``: the parameters of the closest points of the segments ``P[0] P[1]`` and
    ``P[2] P[3]`` (Ericson's algorithm; module notes)."""
    a = b = c = e = f = 0.0
    for i in range(3):
        u, w, r = P[1, i] - P[0, i], P[3, i] - P[2, i], P[0, i] - P[2, i]
        a += u * u
        b += u * w
        c += u * r
        e += w * w
        f += w * r
    denom = a * e - b * b
    s = _clamp((b * f - c * e) / denom) if denom > 1e-12 * a * e else 0.0
    t = (b * s + f) / e
    if t < 0.0:
        t, s = 0.0, _clamp(-c / a)
    elif t > 1.0:
        t, s = 1.0, _clamp((b - c) / a)
    return s, t


@njit(cache=True)
def pair(P, V, s, t, coef, dynamic, want, F, Fd, K, Kd, Cd, work):
    """The contact of the segments ``P[0] P[1]`` and ``P[2] P[3]`` (points (4, 3) moving at
    ``V``) at their closest points ``s``, ``t`` (``closest``): the penalty's generalized
    forces on the four points ``F`` (12,) and, if ``want``, ``K = dF/dP`` (12, 12); with
    friction and ``dynamic``, the friction's ``Fd`` and ``Kd = dFd/dP``, ``Cd = dFd/dV``.
    ``work`` (WORK, 12) is scratch.  Returns the penetration (<= 0: no contact, nothing
    written) and leaves the normal force ``N`` in ``work[17, 0]`` and its potential
    ``Pi`` in ``work[17, 1]`` (module notes)."""
    c = work[17, 4:8]
    c[0], c[1], c[2], c[3] = 1.0 - s, s, -(1.0 - t), -t
    delta, n, u, w = work[0, :3], work[0, 3:6], work[0, 6:9], work[0, 9:12]
    for i in range(3):
        u[i] = P[1, i] - P[0, i]
        w[i] = P[3, i] - P[2, i]
        delta[i] = c[0] * P[0, i] + c[1] * P[1, i] + c[2] * P[2, i] + c[3] * P[3, i]
    d = math.sqrt(delta[0] ** 2 + delta[1] ** 2 + delta[2] ** 2)
    p = coef[RADII] - d
    if p <= 0.0:
        return p
    k, p0 = coef[STIFFNESS], coef[ONSET]
    if p < p0:
        N, kp, Pi = 0.5 * k * p * p / p0, k * p / p0, k * p ** 3 / (6.0 * p0)
    else:
        N, kp = k * (p - 0.5 * p0), k
        Pi = k * (p0 * p0 / 6.0 + 0.5 * (p * p - p0 * p0) - 0.5 * p0 * (p - p0))
    work[17, 0], work[17, 1] = N, Pi
    for i in range(3):
        n[i] = delta[i] / d
    for j in range(4):
        for i in range(3):
            F[3 * j + i] = c[j] * N * n[i]
    mu = coef[FRICTION]
    friction = mu > 0.0 and dynamic
    vr, vt = work[16, :3], work[16, 3:6]
    vn, sigma = 0.0, 1.0
    if friction:
        for i in range(3):
            vr[i] = c[0] * V[0, i] + c[1] * V[1, i] + c[2] * V[2, i] + c[3] * V[3, i]
        vn = n[0] * vr[0] + n[1] * vr[1] + n[2] * vr[2]
        for i in range(3):
            vt[i] = vr[i] - vn * n[i]
        sigma = math.sqrt(vt[0] ** 2 + vt[1] ** 2 + vt[2] ** 2 + coef[SLIP] ** 2)
        for j in range(4):
            for i in range(3):
                Fd[3 * j + i] = -c[j] * mu * N * vt[i] / sigma
    if not want:
        return p
    _tangents(P, V, s, t, c, d, N, kp, mu, friction, vn, sigma, K, Kd, Cd, work)
    return p


@njit(cache=True)
def _parameter_rates(P, s, t, c, a, b, e, work):
    """``ds/dP`` and ``dt/dP`` (12,) into ``work[1]``, ``work[2]``: the implicit function
    theorem on the free parameters, zero for a clamped one (module notes)."""
    delta, u, w = work[0, :3], work[0, 6:9], work[0, 9:12]
    Gs, Gt, ds, dt = work[3], work[4], work[1], work[2]
    for j in range(4):
        for i in range(3):
            Gs[3 * j + i] = c[j] * u[i]
            Gt[3 * j + i] = -c[j] * w[i]
    for i in range(3):
        Gs[i] -= delta[i]
        Gs[3 + i] += delta[i]
        Gt[6 + i] += delta[i]
        Gt[9 + i] -= delta[i]
    free_s, free_t = 0.0 < s < 1.0, 0.0 < t < 1.0
    for m in range(12):
        if free_s and free_t:
            det = a * e - b * b
            ds[m] = -(e * Gs[m] + b * Gt[m]) / det
            dt[m] = -(b * Gs[m] + a * Gt[m]) / det
        else:
            ds[m] = -Gs[m] / a if free_s else 0.0
            dt[m] = -Gt[m] / e if free_t else 0.0


@njit(cache=True)
def _tangents(P, V, s, t, c, d, N, kp, mu, friction, vn, sigma, K, Kd, Cd, work):
    """The tangents of ``pair`` (module notes) into ``K`` and, with ``friction``, ``Kd``
    and ``Cd``."""
    n, u, w = work[0, 3:6], work[0, 6:9], work[0, 9:12]
    a, b, e = u @ u, u @ w, w @ w
    _parameter_rates(P, s, t, c, a, b, e, work)
    ds, dt = work[1], work[2]
    Jd, Jn = work[3:6], work[6:9]          # d delta/dP, dn/dP (3, 12)
    dd, dN, dc = work[9], work[10], work[11:15, :]   # dd/dP, dN/dP, dc_j/dP
    for m in range(12):
        for i in range(3):
            Jd[i, m] = u[i] * ds[m] - w[i] * dt[m]
        Jd[m % 3, m] += c[m // 3]
        dd[m] = n[0] * Jd[0, m] + n[1] * Jd[1, m] + n[2] * Jd[2, m]
        dN[m] = -kp * dd[m]
        for i in range(3):
            Jn[i, m] = (Jd[i, m] - n[i] * dd[m]) / d
        dc[0, m], dc[1, m], dc[2, m], dc[3, m] = -ds[m], ds[m], dt[m], -dt[m]
    for j in range(4):
        for i in range(3):
            fi = N * n[i]
            for m in range(12):
                K[3 * j + i, m] = dc[j, m] * fi + c[j] * (n[i] * dN[m] + N * Jn[i, m])
    if not friction:
        return
    vr, vt = work[16, :3], work[16, 3:6]
    phi = vt / sigma
    D = (np.eye(3) - np.outer(phi, phi)) / sigma
    Pn = np.eye(3) - np.outer(n, n)
    dvr = np.outer(V[1] - V[0], ds) - np.outer(V[3] - V[2], dt)
    dvt = Pn @ dvr - np.outer(n, vr @ Jn) - vn * Jn
    dft = -mu * (np.outer(phi, dN) + N * (D @ dvt))
    ft = -mu * N * phi
    dftv = -mu * N * (D @ Pn)
    for j in range(4):
        for i in range(3):
            for m in range(12):
                Kd[3 * j + i, m] = dc[j, m] * ft[i] + c[j] * dft[i, m]
            for k in range(4):
                for l in range(3):
                    Cd[3 * j + i, 3 * k + l] = c[j] * c[k] * dftv[i, l]


@njit(cache=True)
def gather(edofs, S, seg, x, P):
    """The two end points (2, 3) of the segment ``seg`` (a row of ``segments``) of the
    global vector ``x`` into ``P``."""
    nf = S.shape[2]
    for end in range(2):
        e, g = seg[2 * end], seg[2 * end + 1]
        for i in range(3):
            acc = 0.0
            for A in range(nf):
                acc += S[e, g, A] * x[edofs[e, 3 * A + i]]
            P[end, i] = acc


@njit(cache=True)
def gather_pair(edofs, S, sa, sb, x, P):
    """The four points (4, 3) of the segments ``sa`` and ``sb`` of a pair (``gather``) of
    the global vector ``x`` into ``P``: ``sa``'s ends, then ``sb``'s."""
    gather(edofs, S, sa, x, P[:2])
    gather(edofs, S, sb, x, P[2:])


@njit(cache=True)
def _ends_count(seg_a, seg_b, s, t):
    """False where a closest point sits at a joint of two segments (module notes)."""
    if (s == 0.0 and seg_a[4] == 0) or (s == 1.0 and seg_a[5] == 0):
        return False
    return not ((t == 0.0 and seg_b[4] == 0) or (t == 1.0 and seg_b[5] == 0))


@njit(cache=True)
def _scatter(edofs, S, sa, sb, vec, out, sign):
    """``out[dof] += sign S vec`` of the 12 point forces ``vec`` onto the global
    coordinates of the segments ``sa``, ``sb``."""
    nf = S.shape[2]
    for j in range(4):
        seg = sa if j < 2 else sb
        e, g = seg[2 * (j % 2)], seg[2 * (j % 2) + 1]
        for A in range(nf):
            for i in range(3):
                out[edofs[e, 3 * A + i]] += sign * S[e, g, A] * vec[3 * j + i]


@njit(cache=True)
def _scatter_tangent(edofs, S, sa, sb, local, own, index, G, data):
    """``data -= S_jA S_kB G[j i, k l]`` at the positions ``index`` (flat) of the pairs of
    coordinates: with ``own`` 0, of the dense block over ``local``; with ``own`` 1, of
    the blocks of the lines' elements (``edofs``), leaving out the entries that couple
    points of different elements (module notes)."""
    nf, nde = S.shape[2], edofs.shape[1]
    nd = 0 if own else int(round(math.sqrt(index.size)))
    for j in range(4):
        sj = sa if j < 2 else sb
        ej, gj = sj[2 * (j % 2)], sj[2 * (j % 2) + 1]
        for k in range(4):
            sk = sa if k < 2 else sb
            ek, gk = sk[2 * (k % 2)], sk[2 * (k % 2) + 1]
            if own and ej != ek:
                continue
            for A in range(nf):
                for B in range(nf):
                    w = S[ej, gj, A] * S[ek, gk, B]
                    if w == 0.0:
                        continue
                    for i in range(3):
                        for m in range(3):
                            if own:
                                at = (ej * nde + 3 * A + i) * nde + 3 * B + m
                            else:
                                at = local[edofs[ej, 3 * A + i]] * nd \
                                    + local[edofs[ek, 3 * B + m]]
                            data[index[at]] -= w * G[3 * j + i, 3 * k + m]


@njit(cache=True)
def _record(sa, sb, G, record):
    """The entries of the pair's tangent ``-G`` that the own pattern leaves out (points
    of different elements) as the next record of ``kernels.woodbury`` (``record =
    (count, points, values)``), if it has room; counts the pair either way."""
    count, points, values = record
    k = count[0]
    count[0] = k + 1
    if k >= points.shape[0]:
        return
    for j in range(4):
        seg = sa if j < 2 else sb
        points[k, j, 0], points[k, j, 1] = seg[2 * (j % 2)], seg[2 * (j % 2) + 1]
    for j in range(4):
        for m in range(4):
            cross = points[k, j, 0] != points[k, m, 0]
            for i in range(3):
                for l in range(3):
                    values[k, 3 * j + i, 3 * m + l] = -G[3 * j + i, 3 * m + l] if cross \
                        else 0.0


@njit(cache=True)
def kernel(pack, index, ev):
    """The hook of the evaluation contract (``contract.Term.kernels``) of a line-to-line
    contact: ``pack = (edofs, S, segments, pairs, count, coef, local, own, record)``, the
    candidate pairs ``pairs[:count[0]]`` of rows of ``segments`` (refreshed by the broad
    phase, ``loads.contact_lines``); ``index`` the dense block over ``local`` (``own``
    0: the exact tangent) or the blocks (ne, (3 nf)^2) of the lines' elements, row-major
    (``own`` 1: the points' own elements only, module notes).  Both are 2-D: the two
    patterns share one compiled signature.  With the tangent, on the own pattern and a
    ``record`` of ``kernels.woodbury`` with room (``tangent="woodbury"``), the entries
    left out are written there for the step's correction; ``record[0] = [pairs
    recorded, most pairs in contact at one evaluation]``."""
    q, v, s, f, f_ext, fd, data, energy, power = ev
    edofs, S, segments, pairs, count, coef, local, own, record = pack
    want = data.size > 0
    recording = want and own == 1 and record[1].shape[0] > 0
    if recording:
        record[0][0] = 0
    if count[0] == 0:
        return
    cK, cC, dynamic = s[1], s[2] if s[3] != 0.0 else 0.0, s[3] != 0.0
    flat = index.ravel()
    P, V = np.empty((4, 3)), np.zeros((4, 3))
    F, Fd = np.zeros(12), np.zeros(12)
    K, Kd, Cd = np.zeros((12, 12)), np.zeros((12, 12)), np.zeros((12, 12))
    G = np.empty((12, 12))
    work = np.zeros((WORK, 12))
    friction = coef[FRICTION] > 0.0 and dynamic
    for m in range(count[0]):
        sa, sb = segments[pairs[m, 0]], segments[pairs[m, 1]]
        gather_pair(edofs, S, sa, sb, q, P)
        if friction:
            gather_pair(edofs, S, sa, sb, v, V)
        st = closest(P)
        if not _ends_count(sa, sb, st[0], st[1]):
            continue
        if pair(P, V, st[0], st[1], coef, dynamic, want, F, Fd, K, Kd, Cd, work) <= 0.0:
            continue
        _scatter(edofs, S, sa, sb, F, f, -1.0)
        energy[0] += work[17, 1]
        if friction:
            _scatter(edofs, S, sa, sb, Fd, f, -1.0)
            _scatter(edofs, S, sa, sb, Fd, fd, -1.0)
        if not want:
            continue
        for i in range(12):
            for j in range(12):
                G[i, j] = cK * K[i, j]
                if friction:
                    G[i, j] += cK * Kd[i, j] + cC * Cd[i, j]
        _scatter_tangent(edofs, S, sa, sb, local, own, flat, G, data)
        if recording:
            _record(sa, sb, G, record)
    if recording:
        record[0][1] = max(record[0][1], record[0][0])


@njit(cache=True)
def resolve(edofs, S, segments, pairs, count, coef, q, v, out):
    """The active contacts at ``q``, ``v``: rows ``[pair, N, p, x_a (3), x_b (3),
    f_t (3), v_t (3), s, t]`` of ``out`` (capacity, 17), ``f_t`` the friction on line a,
    ``v_t`` its slip on line b and ``s``, ``t`` the closest points' parameters on the
    segments; returns how many (for outputs, ``loads.contact_lines``)."""
    P, V = np.empty((4, 3)), np.zeros((4, 3))
    F, Fd = np.zeros(12), np.zeros(12)
    K = np.zeros((12, 12))
    work = np.zeros((WORK, 12))
    active = 0
    for m in range(count[0]):
        sa, sb = segments[pairs[m, 0]], segments[pairs[m, 1]]
        gather_pair(edofs, S, sa, sb, q, P)
        gather_pair(edofs, S, sa, sb, v, V)
        st = closest(P)
        if not _ends_count(sa, sb, st[0], st[1]):
            continue
        Fd[:] = 0.0
        s, t = st
        # flags as bool values, not literals: ``kernel``'s signature of ``pair``
        p = pair(P, V, s, t, coef, np.bool_(True), np.bool_(False), F, Fd, K, K, K, work)
        if p <= 0.0:
            continue
        row = out[active]
        row[0], row[1], row[2] = m, work[17, 0], p
        for i in range(3):
            row[3 + i] = P[0, i] + s * (P[1, i] - P[0, i])
            row[6 + i] = P[2, i] + t * (P[3, i] - P[2, i])
            row[9 + i] = Fd[i] / (1.0 - s) if s < 1.0 else Fd[3 + i] / s
            row[12 + i] = work[16, 3 + i] if coef[FRICTION] > 0.0 else 0.0
        row[15], row[16] = s, t
        active += 1
    return active
