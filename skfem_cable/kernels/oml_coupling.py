"""Numba kernel of the OML current's coupling in the tangent of
``ElectrodynamicForce(current="oml")`` (``kernels.oml_force``).

The profile ``y = (I_k, dV_k)`` at the solver's nodes solves ``R(y, E_n) = 0``
(``kernels.oml``), with ``E_n = P E`` the nodes' motional fields, linear in the
stations' ``E_s = ((u - u_p) x B) . a`` (``kernels.oml_force`` (1); ``P`` the
interpolation of ``kernels.oml.node_fields``).  The density and the plasma's velocity are
held over the step, as the force holds them.  At the converged profile, by the implicit
function theorem,

    dy/dE_s = -(dR/dy)^-1 (dR/dE_n) P                                   (1)

with ``dR/dy`` the Newton matrix the solver has factored (LAPACK's band solve, one
right-hand side per node).  The interval ``[z_k, z_k+1]`` (length ``h``) of the
Hermite-Simpson collocation depends on the fields through its midpoint bias ``V_m``
(``dV_m/dE_k = h / 8 = -dV_m/dE_k+1``) and the bias equation:

    dR_I/dE_k = -h^2 g'(V_m) / 12 = -dR_I/dE_k+1,   dR_V/dE_k = dR_V/dE_k+1 = -h / 2.  (2)

The station's field depends on its absolute position ``x``, slope ``a`` and velocity
``u`` (``u' = u - u_p``; ``dB`` the field's gradient as the force evaluates it):

    dE/dx = dB^T (a x u'),   dE/da = u' x B,   dE/du = B x a.             (3)

The force at station ``g``, ``f_g = I_g a_g x B_g``, then has beyond its derivatives at
fixed current (``kernels.electrodynamic`` (2)) the coupling

    dF_A/dq = sum_g w_g S_A (a_g x B_g) sum_k G_gk dE_k/dq,   G = dI_s/dE_s   (4)

(``G`` the station rows of (1)), and the same in ``v`` through ``dE/du``: a block dense
over the line body's coordinates, the magnetic damping of the current in ``v``.
"""

import numpy as np
from numba import njit

from . import lapack
from .oml import KL, KU, collection


@njit(cache=True)
def node_sensitivities(nodes, E, N, c, work, dy):
    """``dy`` (K + 1, 2 K + 2): row ``m`` the derivative (1) of the nodal unknowns in the
    node field ``E_m``, from the factored Newton matrix in ``work`` (``kernels.oml.
    solve``'s, at convergence); ``E``, ``N`` the nodes' fields, ``c`` the circuit's
    coefficients."""
    z, on = nodes[0], nodes[4]
    x, AB, ipiv, ints, addresses = work[0], work[2], work[6], work[7], work[8]
    c_e, c_i, r = c[0], c[1], c[2]
    dy[:] = 0.0
    for k in range(z.shape[0] - 1):
        h = z[k + 1] - z[k]
        Vm = 0.5 * (x[2 * k + 1] + x[2 * k + 3]) + h / 8.0 * (
            E[k] - r * x[2 * k] - E[k + 1] + r * x[2 * k + 2])
        dm = collection(Vm, 0.5 * (N[k] + N[k + 1]), c_e, c_i, on[k])[1]
        row = 1 + 2 * k                      # -dR/dE (2): the right-hand sides
        dy[k, row] += h * h * dm / 12.0
        dy[k + 1, row] -= h * h * dm / 12.0
        dy[k, row + 1] += 0.5 * h
        dy[k + 1, row + 1] += 0.5 * h
    lapack.band_solve(addresses, AB, KL, KU, ipiv, dy.ravel(), ints)  # 1-D: one signature


@njit(cache=True)
def station_sensitivities(nodes, dy, G):
    """``G`` (ns, ns): the derivative of the current at station ``g`` in the field at
    station ``k`` (4), from the nodes' ``dy`` (``node_sensitivities``) through the
    interpolation ``P`` (``nodes = (z, i0, i1, wt, on, at)``)."""
    i0, i1, wt, at = nodes[1], nodes[2], nodes[3], nodes[5]
    G[:] = 0.0
    for m in range(dy.shape[0]):
        for g in range(G.shape[0]):
            d = dy[m, 2 * at[g]]
            G[g, i0[m]] += (1.0 - wt[m]) * d
            G[g, i1[m]] += wt[m] * d


@njit(cache=True)
def field_derivatives(S, Sx, X, A, U, Up, B, dB, cK, cC, D):
    """``D`` (ns, 3 nf): ``cK dE_k/dq_e + cC dE_k/dv_e`` of every station ``k`` in the
    coordinates of its element ``e`` (3); ``X``, ``A``, ``U``, ``Up``, ``B`` (ne, nq, 3)
    and ``dB`` (ne, nq, 3, 3) at the points."""
    ne, nq, nf = S.shape
    c, dx, da, du = np.empty(3), np.empty(3), np.empty(3), np.empty(3)
    u = np.empty(3)
    for e in range(ne):
        for g in range(nq):
            a, b, db = A[e, g], B[e, g], dB[e, g]
            for i in range(3):
                u[i] = U[e, g, i] - Up[e, g, i]
            cross(a, u, c)
            cross(u, b, da)
            cross(b, a, du)
            for j in range(3):
                dx[j] = db[0, j] * c[0] + db[1, j] * c[1] + db[2, j] * c[2]
            k = e * nq + g
            for F in range(nf):
                s, sx = S[e, g, F], Sx[e, g, F]
                for j in range(3):
                    D[k, 3 * F + j] = cK * (s * dx[j] + sx * da[j]) + cC * s * du[j]


@njit(cache=True, inline="always")
def cross(p, q, out):
    """``out = p x q`` (3,)."""
    out[0] = p[1] * q[2] - p[2] * q[1]
    out[1] = p[2] * q[0] - p[0] * q[2]
    out[2] = p[0] * q[1] - p[1] * q[0]


@njit(cache=True)
def assemble(points, A, B, G, D, local, H, data, index):
    """Minus the coupling (4) (``cK`` in ``q``, ``cC`` in ``v``: ``D``) into ``data`` at
    ``index`` (nc, nc), the line body's coordinates numbered by ``local`` (ne, 3 nf);
    ``H`` (ns, nc) scratch: ``H_g = sum_k G_gk D_k`` over the coordinates."""
    S, w = points[1], points[3]
    ne, nq, nf = S.shape
    nd = 3 * nf
    H[:] = 0.0
    for k in range(G.shape[0]):
        row = local[k // nq]
        for g in range(G.shape[0]):
            Ggk = G[g, k]
            if Ggk == 0.0:
                continue
            for d in range(nd):
                H[g, row[d]] += Ggk * D[k, d]
    unit = np.empty(3)
    for e in range(ne):
        for g in range(nq):
            cross(A[e, g], B[e, g], unit)
            Hg = H[e * nq + g]
            for F in range(nf):
                sA = w[e, g] * S[e, g, F]
                for i in range(3):
                    at = index[local[e, 3 * F + i]]
                    c = sA * unit[i]
                    for col in range(Hg.shape[0]):
                        data[at[col]] -= c * Hg[col]
