"""Numba kernel of the Lorentz force on a current-carrying cable (``electrodynamic``).

At every Gauss point, with ``x = R + S q`` the absolute position (``R`` the reference
point of the system's orbit, zero without one), ``a = r_x = S_x q`` the slope and
``B = B(x)`` the magnetic field, a current ``I`` along the cable (positive towards
increasing arc length) feels the force per unit *reference* length

    f = I a x B                                                        (1)

(the Lorentz force ``I dl x B`` with ``dl = a dx``: no normalisation of ``a``).  Its
derivatives at fixed ``I`` are, with ``[w]_x`` the cross-product matrix (``[w]_x y =
w x y``),

    df/da = -I [B]_x,        df/dx = I [a]_x dB/dx.                    (2)

The current is ``I = I_0 + G E`` with ``I_0`` a prescribed current and ``G = 1 / R_c``
the conductance of the circuit (short circuit: ``I_0 = 0``), ``E`` the motional EMF

    E = int (u x B) . a dx,      u = V + S v - Omega x x               (3)

(``V`` the reference point's velocity, ``v`` the offsets' velocities, zero in statics,
``Omega`` the rotation rate of the plasma, whose motional electric field in the inertial
frame is ``-(Omega x x) x B``).  ``E`` couples every coordinate of the cable to every
other; the tangent leaves that rank-one coupling out (``I`` held fixed in (2)), so the
iteration matrix keeps the cable's band: Newton converges slightly slower when ``G`` is
not zero, to the same answer, since the residual uses the current of the iterate.

The field is ``B = B_0 + B_d`` with ``B_0`` uniform and ``B_d`` a dipole of moment ``m``
(carrying the factor ``mu_0 / (4 pi)``) at the origin,

    B_d = 3 (m . x) x / |x|^5 - m / |x|^3,                             (4)
    dB_d/dx = 3 (x m^T + m x^T + (m . x) I) / |x|^5 - 15 (m . x) x x^T / |x|^7

(symmetric and traceless: the field is curl- and divergence-free outside the origin).
"""

import numpy as np
from numba import njit

from . import CUBIC


@njit(cache=True)
def gauss_points(edofs, S, Sx, q, v, motion, X, A, U):
    """At every Gauss point: the absolute position ``X = R + S q``, the slope
    ``A = S_x q`` and the absolute velocity ``U = V + S v`` (ne, nq, 3) each, with
    ``motion = [R, V]`` (2, 3) the reference point's position and velocity (``v`` is zero
    in statics: ``contract.Evaluation``)."""
    ne, nq, nf = S.shape
    for e in range(ne):
        for g in range(nq):
            for i in range(3):
                X[e, g, i] = motion[0, i]
                A[e, g, i] = 0.0
                U[e, g, i] = motion[1, i]
                for k in range(nf):
                    dof = edofs[e, 3 * k + i]
                    X[e, g, i] += S[e, g, k] * q[dof]
                    A[e, g, i] += Sx[e, g, k] * q[dof]
                    U[e, g, i] += S[e, g, k] * v[dof]


@njit(cache=True)
def dipole(source, x, B, dB):
    """The field (4) ``B`` (3,) at ``x`` (3,) and its gradient ``dB`` (3, 3), with
    ``source = [B_0, m]`` (2, 3); a zero moment leaves the uniform part alone."""
    m = source[1]
    for i in range(3):
        B[i] = source[0, i]
        for j in range(3):
            dB[i, j] = 0.0
    if m[0] == 0.0 and m[1] == 0.0 and m[2] == 0.0:
        return
    r2 = x[0] * x[0] + x[1] * x[1] + x[2] * x[2]
    mx = m[0] * x[0] + m[1] * x[1] + m[2] * x[2]
    inv3 = r2 ** -1.5
    inv5 = inv3 / r2
    for i in range(3):
        B[i] += 3.0 * mx * x[i] * inv5 - m[i] * inv3
        for j in range(3):
            dB[i, j] += (3.0 * (x[i] * m[j] + m[i] * x[j]) * inv5
                         - 15.0 * mx * x[i] * x[j] * inv5 / r2)
        dB[i, i] += 3.0 * mx * inv5


@njit(cache=True)
def dipole_points(source, X, B, dB):
    """The field (4) and its gradient at every point of ``X`` (..., 3) into ``B``
    (..., 3) and ``dB`` (..., 3, 3) (same leading shape, C-contiguous)."""
    x = X.reshape(-1, 3)
    b = B.reshape(-1, 3)
    db = dB.reshape(-1, 3, 3)
    for p in range(x.shape[0]):
        dipole(source, x[p], b[p], db[p])


@njit(cache=True)
def motional_emf(w, plasma, X, A, U, B):
    """The motional EMF (3) of the cable (V) from the Gauss-point fields of
    ``gauss_points`` and the field ``B``; ``plasma`` (3,) is ``Omega``."""
    ne, nq = w.shape
    total = 0.0
    u = np.empty(3)
    for e in range(ne):
        for g in range(nq):
            x = X[e, g]
            u[0] = U[e, g, 0] - (plasma[1] * x[2] - plasma[2] * x[1])
            u[1] = U[e, g, 1] - (plasma[2] * x[0] - plasma[0] * x[2])
            u[2] = U[e, g, 2] - (plasma[0] * x[1] - plasma[1] * x[0])
            b, a = B[e, g], A[e, g]
            total += w[e, g] * ((u[1] * b[2] - u[2] * b[1]) * a[0]
                                + (u[2] * b[0] - u[0] * b[2]) * a[1]
                                + (u[0] * b[1] - u[1] * b[0]) * a[2])
    return total


@njit(cache=True)
def assemble(edofs, S, Sx, w, drive, plasma, X, A, U, B, dB, out, index, ev):
    """``_assemble`` with the number of element functions fixed for the cubic element
    (``kernels.CUBIC``), or read from the tables."""
    nf = S.shape[2]
    if nf == CUBIC:
        _assemble(edofs, S, Sx, w, drive, plasma, X, A, U, B, dB, out, index, ev, CUBIC)
    else:
        _assemble(edofs, S, Sx, w, drive, plasma, X, A, U, B, dB, out, index, ev, nf)


@njit(cache=True, inline="always")
def _assemble(edofs, S, Sx, w, drive, plasma, X, A, U, B, dB, out, index, ev, nf):
    """The current ``I = I_0 + G E`` (``drive = [I_0, G]``; ``E`` by (3), the open-circuit
    EMF, whatever the current) into ``out = [I, E]``, the generalized force
    ``int S^T f dx`` of (1) into ``ev``'s external forces and ``-cK dF/dq`` (by (2), at
    fixed ``I``) into its matrix values at ``index`` (ne, 3 nf, 3 nf), ``nf`` functions
    per element."""
    q, v, s, f, f_ext, fd, data, energy, power = ev
    ne, nq = w.shape
    nd = 3 * nf
    E = motional_emf(w, plasma, X, A, U, B)
    current = drive[0] + drive[1] * E
    out[0], out[1] = current, E
    want = data.size > 0
    cK = s[1]
    h = np.empty(3)
    Hx = np.empty((3, 3))
    Ha = np.empty((3, 3))
    fe = np.empty(nd)
    Ke = np.empty((nd, nd))
    for e in range(ne):
        fe[:] = 0.0
        Ke[:] = 0.0
        for g in range(nq):
            a, b, db = A[e, g], B[e, g], dB[e, g]
            h[0] = current * (a[1] * b[2] - a[2] * b[1])
            h[1] = current * (a[2] * b[0] - a[0] * b[2])
            h[2] = current * (a[0] * b[1] - a[1] * b[0])
            wg = w[e, g]
            for k in range(nf):
                for i in range(3):
                    fe[3 * k + i] += wg * S[e, g, k] * h[i]
            if not want:
                continue
            for j in range(3):
                # I [a]_x dB/dx, column j: I a x (dB[:, j])
                Hx[0, j] = current * (a[1] * db[2, j] - a[2] * db[1, j])
                Hx[1, j] = current * (a[2] * db[0, j] - a[0] * db[2, j])
                Hx[2, j] = current * (a[0] * db[1, j] - a[1] * db[0, j])
            # -I [B]_x
            Ha[0, 0], Ha[0, 1], Ha[0, 2] = 0.0, current * b[2], -current * b[1]
            Ha[1, 0], Ha[1, 1], Ha[1, 2] = -current * b[2], 0.0, current * b[0]
            Ha[2, 0], Ha[2, 1], Ha[2, 2] = current * b[1], -current * b[0], 0.0
            for k in range(nf):
                sk = cK * wg * S[e, g, k]
                for m in range(nf):
                    sm, xm = S[e, g, m], Sx[e, g, m]
                    for i in range(3):
                        for j in range(3):
                            Ke[3 * k + i, 3 * m + j] -= sk * (sm * Hx[i, j] + xm * Ha[i, j])
        for k in range(nd):
            f_ext[edofs[e, k]] += fe[k]
        if want:
            for k in range(nd):
                for m in range(nd):
                    data[index[e, k, m]] += Ke[k, m]


@njit(cache=True)
def kernel(pack, index, ev):
    """The compiled hook of the evaluation contract (``contract.Term.kernels``) for a
    uniform field plus a dipole: ``pack = (edofs, S, Sx, w, motion (2, 3), source (2, 3),
    drive (2,), plasma (3,), X, A, U (ne, nq, 3), B (ne, nq, 3), dB (ne, nq, 3, 3),
    out (2,))``; ``X ... dB`` are scratch, ``out`` receives ``[I, E]``."""
    edofs, S, Sx, w, motion, source, drive, plasma, X, A, U, B, dB, out = pack
    gauss_points(edofs, S, Sx, ev[0], ev[1], motion, X, A, U)
    dipole_points(source, X, B, dB)
    assemble(edofs, S, Sx, w, drive, plasma, X, A, U, B, dB, out, index, ev)
