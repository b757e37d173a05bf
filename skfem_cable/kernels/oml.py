"""Numba solver of the OML current and bias along a bare tether on a fixed mesh
(``environment.oml`` states the problem; ``loads.oml_circuit`` builds the mesh).

Unknowns ``y_k = (I_k, dV_k)`` at the nodes ``z_0 = 0 < z_1 < ... < z_K = L`` (the
tether's stations, its ends and the insulated interval's edges), with the right-hand side
of ``environment.oml``

    f(y) = (g(dV), E - I / (sigma A)),
    g(dV) = -c_e N sqrt(dV) (dV >= 0),  c_i N sqrt(-dV) (dV < 0),  0 when insulated,

and on every interval ``[z_k, z_k+1]`` (length ``h``) the three-point Lobatto IIIA
collocation (the Hermite-Simpson rule, fourth order: scipy's ``solve_bvp`` uses the same)

    y_m = (y_k + y_k+1) / 2 + h / 8 (f_k - f_k+1),
    y_k+1 - y_k - h / 6 (f_k + 4 f_m + f_k+1) = 0,

the fields ``E``, ``N`` linear on the interval (as ``OMLProblem``'s ``sampled``) and the
interval's own collecting flag at its three points (the right-hand side jumps at an
insulated edge, which is a node).  With the cathode's condition ``dV_0 + V_C + R_L I_0 -
V_s = 0`` first and ``I_K = 0`` last, the rows of the intervals between them, the Newton
matrix is banded (two sub- and two super-diagonals), solved by LAPACK's banded LU with
partial pivoting (``dgbtrf``/``dgbtrs``, ``kernels.lapack``).  Newton's iteration starts from the
previous solution (a warm start) and halves its step while the scaled residual grows; the
derivative ``g'`` is evaluated with ``|dV|`` at least ``FLOOR`` (``sqrt`` has an infinite
slope at zero bias; the residual is exact).
"""

import numpy as np
from numba import njit

from . import lapack

FLOOR = 1e-12
"""Smallest ``|dV|`` (V) in the collection's derivative."""
TOL = 1e-11
"""Newton stops when its step is below ``TOL`` times the scales of current and bias."""
MAX_ITER = 60
"""Newton iterations before the solver reports failure (``iterations = -1``)."""
KL = np.int64(2)
"""Sub-diagonals of the Newton matrix (``KU`` super-diagonals; LAPACK's band storage
keeps ``KL`` more rows for the fill of the row exchanges).  ``np.int64``: numba types a
global int as its literal value, and ``kernels.lapack``'s band LU would be compiled
again for it (``kernels.bordered`` passes an int64)."""
KU = np.int64(2)


@njit(cache=True)
def collection(V, N, c_e, c_i, on):
    """``(g, dg/dV)``: the conventional current entering per unit length (A/m) at bias
    ``V`` and density ``N``, and its derivative (``|V| >= FLOOR`` in it)."""
    if on == 0.0:
        return 0.0, 0.0
    if V >= 0.0:
        return -c_e * N * np.sqrt(V), -0.5 * c_e * N / np.sqrt(max(V, FLOOR))
    return c_i * N * np.sqrt(-V), -0.5 * c_i * N / np.sqrt(max(-V, FLOOR))


@njit(cache=True)
def interval(h, y, E, N, on, c, R, J):
    """The residual ``R`` (2,) of the collocation on one interval and its Jacobian ``J``
    (2, 4) with respect to ``(I_k, dV_k, I_k+1, dV_k+1)``: ``y`` those four values,
    ``E``, ``N`` (2,) the fields at the ends, ``c = (c_e, c_i, 1 / (sigma A))``."""
    c_e, c_i, r = c[0], c[1], c[2]
    g0, d0 = collection(y[1], N[0], c_e, c_i, on)
    g1, d1 = collection(y[3], N[1], c_e, c_i, on)
    f0I, f0V = g0, E[0] - r * y[0]
    f1I, f1V = g1, E[1] - r * y[2]
    Im = 0.5 * (y[0] + y[2]) + h / 8.0 * (f0I - f1I)
    Vm = 0.5 * (y[1] + y[3]) + h / 8.0 * (f0V - f1V)
    gm, dm = collection(Vm, 0.5 * (N[0] + N[1]), c_e, c_i, on)
    fmI, fmV = gm, 0.5 * (E[0] + E[1]) - r * Im
    R[0] = y[2] - y[0] - h / 6.0 * (f0I + 4.0 * fmI + f1I)
    R[1] = y[3] - y[1] - h / 6.0 * (f0V + 4.0 * fmV + f1V)
    # d y_m / d y_k = 1/2 + h/8 Jf_k, d y_m / d y_k+1 = 1/2 - h/8 Jf_k+1, with
    # Jf = [[0, g'], [-r, 0]]; then dR = +-1 - h/6 (Jf_end + 4 Jf_m dy_m)
    for side in range(2):
        sgn = 1.0 if side == 0 else -1.0
        d = d0 if side == 0 else d1
        M00, M01, M10, M11 = 0.5, sgn * h / 8.0 * d, -sgn * h / 8.0 * r, 0.5
        e = -1.0 if side == 0 else 1.0
        col = 2 * side
        J[0, col] = e - h / 6.0 * (4.0 * dm * M10)
        J[0, col + 1] = -h / 6.0 * (d + 4.0 * dm * M11)
        J[1, col] = -h / 6.0 * (-r + 4.0 * (-r) * M00)
        J[1, col + 1] = e - h / 6.0 * (4.0 * (-r) * M01)


@njit(cache=True)
def node_fields(stations, nodes, E, N):
    """The fields at the nodes ``E``, ``N`` (K + 1,) from their values at the stations
    ``stations = (E_st, N_st)`` and ``nodes = (z, i0, i1, wt, on, at)``: linear between
    stations (``(1 - wt) x[i0] + wt x[i1]``), constant beyond the first and last."""
    E_st, N_st = stations
    z, i0, i1, wt = nodes[0], nodes[1], nodes[2], nodes[3]
    for k in range(z.shape[0]):
        E[k] = (1.0 - wt[k]) * E_st[i0[k]] + wt[k] * E_st[i1[k]]
        N[k] = (1.0 - wt[k]) * N_st[i0[k]] + wt[k] * N_st[i1[k]]


@njit(cache=True)
def residual(x, z, on, E, N, c, bc, F, AB):
    """The residual ``F`` (2 K + 2,) at the unknowns ``x = (I_0, dV_0, I_1, ...)`` and,
    unless ``AB`` is empty, the Newton matrix in LAPACK's band storage ``AB``
    (``kernels.lapack``: ``A[i, j]`` at ``AB[j, KL + KU + i - j]``); ``bc = (V_C, R_L,
    V_s)``.  (A flag passed as ``True`` or ``False`` would be typed as its literal value:
    two signatures.)"""
    want = AB.shape[0] > 0
    K = z.shape[0] - 1
    y, R, J = np.empty(4), np.empty(2), np.empty((2, 4))
    Ek, Nk = np.empty(2), np.empty(2)
    if want:
        AB[:] = 0.0
    F[0] = x[1] + bc[0] + bc[1] * x[0] - bc[2]
    if want:
        AB[0, KL + KU] = bc[1]
        AB[1, KL + KU - 1] = 1.0
    for k in range(K):
        for i in range(4):
            y[i] = x[2 * k + i]
        Ek[0], Ek[1], Nk[0], Nk[1] = E[k], E[k + 1], N[k], N[k + 1]
        interval(z[k + 1] - z[k], y, Ek, Nk, on[k], c, R, J)
        for m in range(2):
            row = 1 + 2 * k + m
            F[row] = R[m]
            if want:
                for i in range(4):
                    AB[2 * k + i, KL + KU + row - 2 * k - i] = J[m, i]
    F[2 * K + 1] = x[2 * K]
    if want:
        AB[2 * K, KL + KU + 1] = 1.0


@njit(cache=True)
def scaled_norm(F, I_scale, V_scale):
    """The largest entry of the residual ``F`` scaled: current rows by ``I_scale``, bias
    rows by ``V_scale`` (the cathode's row 0 and the even rows are bias rows; the odd
    rows and the last, ``I_K = 0``, current rows)."""
    n = F.shape[0]
    worst = abs(F[0]) / V_scale
    for row in range(1, n - 1):
        scale = I_scale if row % 2 == 1 else V_scale
        worst = max(worst, abs(F[row]) / scale)
    return max(worst, abs(F[n - 1]) / I_scale)


@njit(cache=True)
def cold_start(x, z, E, bc):
    """``I = 0``, ``dV = dV_0 + int_0^z E`` (trapezoidal): ``OMLProblem.guess``."""
    V = bc[2] - bc[0]
    x[0], x[1] = 0.0, V
    for k in range(1, z.shape[0]):
        V += 0.5 * (z[k] - z[k - 1]) * (E[k] + E[k - 1])
        x[2 * k], x[2 * k + 1] = 0.0, V


@njit(cache=True)
def solve(nodes, E, N, c, bc, work):
    """Newton's iteration for the nodal unknowns ``work[0]`` (2 K + 2,), from their
    values (a warm start) when ``work[5][0]`` is 1, else from ``cold_start``; ``work =
    (x, F, AB, dx, trial, flag, ipiv, ints, addresses)`` (the last three LAPACK's,
    ``kernels.lapack``).  Returns the number of iterations, -1 if it did not converge
    within ``MAX_ITER``, met a non-finite value or a singular matrix."""
    z, on = nodes[0], nodes[4]
    x, F, AB, dx, trial, flag, ipiv, ints, addresses = work
    if flag[0] == 0.0:
        cold_start(x, z, E, bc)
    E_max = 0.0
    for k in range(E.shape[0]):
        E_max = max(E_max, abs(E[k]))
    I_scale = max(E_max, 1e-30) / c[2]
    V_scale = E_max * z[-1] + abs(bc[0]) + abs(bc[2]) + 1.0
    for it in range(MAX_ITER):
        residual(x, z, on, E, N, c, bc, F, AB)
        norm = scaled_norm(F, I_scale, V_scale)
        for i in range(F.shape[0]):
            dx[i] = -F[i]
        if lapack.band_factor(addresses, AB, KL, KU, ipiv, ints) != 0:
            break
        lapack.band_solve(addresses, AB, KL, KU, ipiv, dx, ints)
        step = 0.0
        for i in range(dx.shape[0]):
            size = abs(dx[i]) / (I_scale if i % 2 == 0 else V_scale)
            if not size <= step:  # a NaN too
                step = size
        if not np.isfinite(step):
            break
        lam = 1.0
        for _ in range(30):
            for i in range(x.shape[0]):
                trial[i] = x[i] + lam * dx[i]
            residual(trial, z, on, E, N, c, bc, F, AB[:0])
            if scaled_norm(F, I_scale, V_scale) <= norm or step * lam < TOL:
                break
            lam *= 0.5
        x[:] = trial
        if step * lam < TOL:
            flag[0] = 1.0
            return it + 1
    flag[0] = 0.0
    return -1
