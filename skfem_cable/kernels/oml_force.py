"""Numba kernel of the Lorentz force on a bare tether carrying its OML current
(``ElectrodynamicForce(current="oml")``, ``loads.oml_circuit``).

Per evaluation: ``gather`` the points' absolute positions, slopes and velocities
(``kernels.electrodynamic.gather``), the field at the points (the compiled dipole, or the
per-step field linearised about the step's positions, ``linearised_field``), the motional
field per unit reference length at every point

    E(s) = ((u - u_p) x B) . a                                          (1)

(``u_p`` the plasma's velocity there, held over the step), the OML current and bias on the
fixed mesh of the stations (``kernels.oml.solve``, warm-started from the previous
evaluation), and the force ``f = I(s) a x B`` with its derivatives at fixed current
(``kernels.electrodynamic.forces``), scattered by ``line.assemble``, and, unless the
term leaves it out, the current's coupling (``kernels.oml_coupling``: a block dense over
the line body's coordinates).  The term's tangent index is flat: the element blocks
(ne, 3 nf, 3 nf) first, then the coupling's block (nc, nc).
"""

import numpy as np
from numba import njit

from . import line
from . import oml_coupling as coupled
from .electrodynamic import dipole_points, forces, offset
from .lapack import ADDRESSES
from .oml import KL, KU, node_fields, solve


@njit(cache=True)
def linearised_field(cache, X, B, dB):
    """``B = B_0 + dB_0 (X - X_0)``, ``dB = dB_0``: the field and gradient ``(X_0, B_0,
    dB_0) = cache[:3]`` evaluated once per step (``Term.prepare``) at the step's
    positions ``X_0``, carried to the iterate's positions ``X`` (ne, nq, 3)."""
    X0, B0, dB0 = cache[0], cache[1], cache[2]
    ne, nq = X.shape[:2]
    for e in range(ne):
        for g in range(nq):
            for i in range(3):
                b = B0[e, g, i]
                for j in range(3):
                    b += dB0[e, g, i, j] * (X[e, g, j] - X0[e, g, j])
                    dB[e, g, i, j] = dB0[e, g, i, j]
                B[e, g, i] = b


@njit(cache=True)
def motional_fields(X, A, U, B, Up, E):
    """The motional field (1) (V per metre of reference length) at every point into
    ``E`` (ne * nq,), in the points' order; ``Up`` (ne, nq, 3) the plasma's velocity."""
    ne, nq = X.shape[:2]
    for e in range(ne):
        for g in range(nq):
            u0 = U[e, g, 0] - Up[e, g, 0]
            u1 = U[e, g, 1] - Up[e, g, 1]
            u2 = U[e, g, 2] - Up[e, g, 2]
            b, a = B[e, g], A[e, g]
            E[e * nq + g] = ((u1 * b[2] - u2 * b[1]) * a[0] + (u2 * b[0] - u0 * b[2]) * a[1]
                             + (u0 * b[1] - u1 * b[0]) * a[2])


@njit(cache=True)
def finish(pack, index, ev):
    """The motional field (1), the OML profile, the force and its tangent: at fixed
    current, plus the current's coupling when ``coupling``'s ``local`` is not empty
    (``kernels.oml_coupling``); ``out = [I(0), EMF, motional power int I E ds, mean
    current, Newton iterations, dV(L)]``.  When the profile's Newton iteration fails
    (twice, the second from a cold start) the iterations are -1 and the force NaN: the
    integrator refuses the step (a non-finite residual) and retries a shorter one."""
    points, _, _, cache, mesh, circuit, work, scratch, coupling, out = pack
    edofs, S, Sx, w = points
    X, A, U, B, dB, F, Fx, Fa, Fv, I, V = scratch
    nodes, E_st, E_nodes, N_nodes = mesh
    Up, N_st = cache[3], cache[4]
    q, v, s, f, f_ext, fd, data, energy, power = ev
    motional_fields(X, A, U, B, Up, E_st)
    node_fields((E_st, N_st), nodes, E_nodes, N_nodes)
    iterations = solve(nodes, E_nodes, N_nodes, circuit[0], circuit[1], work)
    if iterations < 0:  # a fresh start, once, before giving up
        iterations = solve(nodes, E_nodes, N_nodes, circuit[0], circuit[1], work)
    if iterations < 0:  # a non-finite force: the step is refused and retried shorter
        out[4] = -1.0
        f_ext[edofs[0, 0]] = np.nan
        return
    x, at = work[0], nodes[5]
    ne, nq = w.shape
    emf, motional, mean = 0.0, 0.0, 0.0
    for e in range(ne):
        for g in range(nq):
            k = at[e * nq + g]
            I[e, g], V[e, g] = x[2 * k], x[2 * k + 1]
            emf += w[e, g] * E_st[e * nq + g]
            motional += w[e, g] * I[e, g] * E_st[e * nq + g]
            mean += w[e, g] * I[e, g]
    out[0], out[1], out[2] = x[0], emf, motional
    out[3], out[4], out[5] = mean / nodes[0][-1], iterations, x[-1]
    want = data.size > 0
    forces(I, want, A, B, dB, F, Fx, Fa)
    nd = edofs.shape[1]
    blocks = ne * nd * nd if want else 0
    line.assemble(edofs, S, Sx, w, F, Fx, Fa, Fv, s[1], 0.0, f_ext, data,
                  index[:blocks].reshape((-1, nd, nd)))
    local, dy, G, D, H = coupling
    if want and local.shape[0] > 0:
        coupled.node_sensitivities(nodes, E_nodes, N_nodes, circuit[0], work, dy)
        coupled.station_sensitivities(nodes, dy, G)
        coupled.field_derivatives(S, Sx, X, A, U, Up, B, dB, s[1], s[2], D)
        nc = H.shape[1]
        coupled.assemble(points, A, B, G, D, local, H, data,
                         index[blocks:blocks + nc * nc].reshape((nc, nc)))


@njit(cache=True)
def gather(pack, ev):
    """The points' absolute positions, slopes and velocities (``line.points``)."""
    points, motion = pack[0], pack[1]
    scratch = pack[7]
    line.points(points[0], points[1], points[2], ev[0], ev[1], scratch[0], scratch[1],
                scratch[2])
    offset(motion, scratch[0], scratch[2])


@njit(cache=True)
def kernel_dipole(pack, index, ev):
    """The hook (``contract.Term.kernels``) for a uniform field plus a dipole (``source =
    [B_0, m]``, ``kernels.electrodynamic.dipole``) evaluated at every iterate.

    ``pack = ((edofs, S, Sx, w), motion (2, 3), source (2, 3), cache, mesh, circuit,
    work, scratch, coupling, out (6,))`` with ``cache = (X_0, B_0, dB_0, U_p, N (ne
    nq,), offsets (ne, nq, 3))`` (``Term.prepare``), ``mesh = (nodes, E (ne nq,),
    E_nodes, N_nodes)``, ``nodes = (z, i0, i1, wt, on, at)`` (``kernels.oml``),
    ``circuit = (c, bc)``,
    ``work = (x, F, AB, dx, trial, flag, ipiv, ints, addresses)`` and ``scratch = (X,
    A, U, B, dB, F, Fx, Fa, Fv, I, V)``, ``coupling = (local (ne, 3 nf), dy (K + 1, 2 K +
    2), G (ns, ns), D (ns, 3 nf), H (ns, nc))`` (``kernels.oml_coupling``; ``local``
    empty: the coupling left out)."""
    gather(pack, ev)
    scratch = pack[7]
    dipole_points(pack[2], scratch[0], scratch[3], scratch[4])
    finish(pack, index, ev)


@njit(cache=True)
def kernel_cached(pack, index, ev):
    """The hook for a field evaluated once per step (``linearised_field``); ``pack`` as
    ``kernel_dipole``'s."""
    gather(pack, ev)
    scratch = pack[7]
    linearised_field(pack[3], scratch[0], scratch[3], scratch[4])
    finish(pack, index, ev)


def empty_work(K):
    """The solver's arrays for ``K`` intervals (``kernels.oml.solve``), with LAPACK's
    pivots, integer scratch and addresses (``kernels.lapack``)."""
    n = 2 * (K + 1)
    return (np.zeros(n), np.zeros(n), np.zeros((n, 2 * KL + KU + 1)), np.zeros(n), np.zeros(n),
            np.zeros(1), np.zeros(n, dtype=np.int32), np.zeros(8, dtype=np.int32),
            ADDRESSES)
