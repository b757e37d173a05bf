"""Numba kernel of the Lorentz force on a current-carrying line body (``electrodynamic``).

The force at a point depends on the whole line (the current of the motional EMF, (3)), so
the load runs the two array passes of ``kernels.line`` with its own work between them:
``gather`` (``line.points``: the points' positions, slopes and velocities, made absolute),
the field at the points (``dipole_points``, or a Python field), and ``finish`` (the EMF,
the current, the force and its derivatives at the points, scattered by ``line.assemble``).

At every point of the line body (``lines.LinePoints``), with ``x = R + S q`` the absolute
position (``R`` the reference point of the system's orbit, zero without one),
``a = r_x = S_x q`` the slope and ``B = B(x)`` the magnetic field, a current ``I`` along the
line (positive towards increasing arc length) feels the force per unit *reference* length

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

from . import line


@njit(cache=True)
def offset(motion, X, U):
    """Add the reference point's position and velocity ``motion = [R, V]`` (2, 3) to the
    points' positions ``X`` and velocities ``U`` (ne, nq, 3) of ``line.points``: the
    absolute ``x = R + S q`` and ``u = V + S v`` (``v`` is zero in statics:
    ``contract.Evaluation``)."""
    ne, nq = X.shape[:2]
    for e in range(ne):
        for g in range(nq):
            for i in range(3):
                X[e, g, i] += motion[0, i]
                U[e, g, i] += motion[1, i]


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
    """The motional EMF (3) of the cable (V) from the points' absolute positions ``X``,
    slopes ``A`` and velocities ``U`` (``gather``) and the field ``B``; ``plasma`` (3,) is
    ``Omega``."""
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
def forces(currents, want, A, B, dB, F, Fx, Fa):
    """The force (1) ``F`` (ne, nq, 3) at the points of slopes ``A`` in the fields ``B``
    (ne, nq, 3) of gradients ``dB`` (ne, nq, 3, 3) carrying the ``currents`` (ne, nq),
    and if ``want`` its derivatives (2) at fixed currents: ``Fx`` and ``Fa`` (ne, nq, 3,
    3)."""
    ne, nq = F.shape[:2]
    for e in range(ne):
        for g in range(nq):
            a, b, db, current = A[e, g], B[e, g], dB[e, g], currents[e, g]
            F[e, g, 0] = current * (a[1] * b[2] - a[2] * b[1])
            F[e, g, 1] = current * (a[2] * b[0] - a[0] * b[2])
            F[e, g, 2] = current * (a[0] * b[1] - a[1] * b[0])
            if not want:
                continue
            Hx, Ha = Fx[e, g], Fa[e, g]
            for j in range(3):
                # I [a]_x dB/dx, column j: I a x (dB[:, j])
                Hx[0, j] = current * (a[1] * db[2, j] - a[2] * db[1, j])
                Hx[1, j] = current * (a[2] * db[0, j] - a[0] * db[2, j])
                Hx[2, j] = current * (a[0] * db[1, j] - a[1] * db[0, j])
            # -I [B]_x
            Ha[0, 0], Ha[0, 1], Ha[0, 2] = 0.0, current * b[2], -current * b[1]
            Ha[1, 0], Ha[1, 1], Ha[1, 2] = -current * b[2], 0.0, current * b[0]
            Ha[2, 0], Ha[2, 1], Ha[2, 2] = current * b[1], -current * b[0], 0.0


@njit(cache=True)
def gather(pack, ev):
    """The first pass: the absolute positions, slopes and velocities of the points into
    the scratch ``X``, ``A``, ``U`` of ``pack`` (``kernel``), by ``line.points``."""
    points, motion, source, drive, plasma, scratch, out = pack
    edofs, S, Sx, w = points
    X, A, U, B, dB, F, Fx, Fa, Fv, I = scratch
    line.points(edofs, S, Sx, ev[0], ev[1], X, A, U)
    offset(motion, X, U)


@njit(cache=True)
def finish(pack, index, ev):
    """The second pass, with the fields ``B``, ``dB`` at the points in ``pack``: the
    current ``I = I_0 + G E`` (``drive = [I_0, G]``; ``E`` by (3), the open-circuit EMF,
    whatever the current) into ``out = [I, E]``, the force (1) at the points and, at fixed
    ``I``, its derivatives (2), scattered by ``line.assemble`` into ``ev``'s external
    forces and matrix values at ``index`` (ne, 3 nf, 3 nf)."""
    points, motion, source, drive, plasma, scratch, out = pack
    edofs, S, Sx, w = points
    X, A, U, B, dB, F, Fx, Fa, Fv, I = scratch
    q, v, s, f, f_ext, fd, data, energy, power = ev
    E = motional_emf(w, plasma, X, A, U, B)
    current = drive[0] + drive[1] * E
    out[0], out[1] = current, E
    want = data.size > 0
    I[:] = current
    forces(I, want, A, B, dB, F, Fx, Fa)
    line.assemble(edofs, S, Sx, w, F, Fx, Fa, Fv, s[1], 0.0, f_ext, data, index)


@njit(cache=True)
def kernel(pack, index, ev):
    """The compiled hook of the evaluation contract (``contract.Term.kernels``) for a
    uniform field plus a dipole: ``pack = ((edofs, S, Sx, w), motion (2, 3), source
    (2, 3), drive (2,), plasma (3,), scratch, out (2,))`` with the line body's points
    (``lines.LinePoints``), ``scratch = (X, A, U, B (ne, nq, 3), dB, F (ne, nq, 3),
    Fx, Fa, Fv (ne, nq, 3, 3), I (ne, nq))`` (``Fv`` zero: the force does not depend on
    the velocity at fixed current; ``I`` the current at the points) and ``out``
    receiving ``[I, E]``: ``gather``, the field (4) at the points, ``finish``."""
    gather(pack, ev)
    points, motion, source, drive, plasma, scratch, out = pack
    dipole_points(source, scratch[0], scratch[3], scratch[4])
    finish(pack, index, ev)
