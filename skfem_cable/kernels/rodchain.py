"""Numba kernels of the rod-chain tether (``skfem_cable.rodchain``): the recursive
factorisation and O(n) solve of the constant mass matrix (Eqs. 27-30), the right-hand
side of the equations of motion (Eqs. 12, 16, 18) and fixed-step RK4 loops, for the
anchored chain and for a free chain with end bodies in orbit (the differential gravity
as the distributed load of Eq. 14).

Arrays of rod vectors have shape ``(n, 3)``, rod ``i`` (0-based) running from joint
``O_i`` to ``O_{i+1}`` (the paper's rod ``i + 1``).  ``b[i]`` is the paper's ``b_{i+1}``,
the entry ``B[i + 1, i]`` of the lower-bidiagonal factor; ``b[n - 1] = 0``.
"""

import numpy as np
from numba import njit

from .central import differential_acceleration

#: ``load_vector``'s ``elastic`` from the kernels: a bool as the Python callers' (a
#: literal ``True`` is typed as its value, a second signature).
ELASTIC = np.bool_(True)


@njit(cache=True, error_model="numpy")
def factor_mass(m, p):
    """Bidiagonal factor ``B`` of ``G = B^T B`` (Eqs. 25-27), bottom-up.

    ``m`` are the rod masses and ``p`` point masses at the joints ``O_1 .. O_n`` (zeros for
    the paper's chain): a point mass at ``O_{i+1}`` adds ``p[i]`` to ``G[i, i]``, since its
    kinetic energy is ``p[i] |U_{i+1}|^2 / 2`` in the joint velocities ``U = Phi q'``.

    Returns the diagonal ``a`` and the subdiagonal ``b`` (``b[n-1] = 0``).
    """
    n = m.size
    a = np.empty(n)
    b = np.zeros(n)
    a[n - 1] = np.sqrt(m[n - 1] / 3.0 + p[n - 1])
    for i in range(n - 2, -1, -1):
        b[i] = m[i + 1] / (6.0 * a[i + 1])
        a[i] = np.sqrt((m[i] + m[i + 1]) / 3.0 + p[i] - b[i] * b[i])
    return a, b


@njit(cache=True, error_model="numpy")
def solve_mass(a, b, rhs, out):
    """``out = M^{-1} rhs`` column by column (Eqs. 28-30); ``rhs`` and ``out`` are
    ``(n, k)`` and must not alias.

    Loop 1 runs from the free end: ``gamma = (I - eps^T) rhs`` and ``B^T lam = gamma``;
    loop 2 from the fixed end: ``B eta = lam`` and ``out = (I - eps) eta``.
    """
    n, k = rhs.shape
    lam = np.zeros(k)
    for i in range(n - 1, -1, -1):
        for c in range(k):
            gamma = rhs[i, c] - rhs[i + 1, c] if i < n - 1 else rhs[i, c]
            lam[c] = (gamma - b[i] * lam[c]) / a[i]
            out[i, c] = lam[c]
    eta = np.zeros(k)
    for i in range(n):
        bi = b[i - 1] if i > 0 else 0.0
        for c in range(k):
            new = (out[i, c] - bi * eta[c]) / a[i]
            out[i, c] = new - eta[c]
            eta[c] = new


@njit(cache=True, error_model="numpy")
def axial_factor(l, l0, EA, compression):
    """``k_i`` of Eq. 12, ``EA/l0 - EA/l``; zero for a slack rod when ``compression`` is off."""
    if not compression and l < l0:
        return 0.0
    return EA / l0 - EA / l


@njit(cache=True, error_model="numpy")
def load_vector(q, masses, l0, EA, compression, elastic, geff, w, tip, Fx, Fxs, max_strain,
                out):
    """``out = Q - K q`` (right-hand side of Eq. 18; ``Q`` alone unless ``elastic``) in one
    pass from the free end.

    ``Q_i = F*_i + sum_{j>i} F_j + P`` (Eq. 16) with, per rod, ``F_i = m_i g_eff + w l_i +
    Fx_i`` and ``F*_i = m_i g_eff / 2 + w l_i / 2 + Fxs_i`` (Eq. 14 for a mass-proportional
    field ``g_eff``, a uniform load ``w`` per current length and precomputed extra loads),
    and ``P`` the point force at ``O_n``.

    Returns the index of the first rod (from the free end) whose length is not finite or
    outside ``(0, (1 + max_strain) l0]``, or -1.
    """
    n = q.shape[0]
    bad = -1
    tail = tip.copy()
    for i in range(n - 1, -1, -1):
        l = np.sqrt(q[i, 0] * q[i, 0] + q[i, 1] * q[i, 1] + q[i, 2] * q[i, 2])
        if bad < 0 and not (0.0 < l <= (1.0 + max_strain) * l0[i]):
            bad = i
        k = axial_factor(l, l0[i], EA[i], compression) if elastic else 0.0
        for d in range(3):
            F = masses[i] * geff[d] + w[d] * l + Fx[i, d]
            Fs = 0.5 * masses[i] * geff[d] + 0.5 * w[d] * l + Fxs[i, d]
            out[i, d] = Fs + tail[d] - k * q[i, d]
            tail[d] += F
    return bad


@njit(cache=True, error_model="numpy")
def derivative(q, masses, l0, EA, compression, a, b, geff, w, tip, Fx, Fxs, max_strain,
               work, out):
    """Rod-vector accelerations ``M^{-1} (Q - K q)`` (Eq. 21); returns ``load_vector``'s flag."""
    bad = load_vector(q, masses, l0, EA, compression, ELASTIC, geff, w, tip, Fx, Fxs, max_strain,
                      work)
    solve_mass(a, b, work, out)
    return bad


@njit(cache=True, error_model="numpy")
def rk4_stage(q, v, h, rate, acc, q_out, v_out):
    """One RK4 stage state: ``q_out = q + h rate``, ``v_out = v + h acc``."""
    for i in range(q.shape[0]):
        for d in range(3):
            q_out[i, d] = q[i, d] + h * rate[i, d]
            v_out[i, d] = v[i, d] + h * acc[i, d]


@njit(cache=True, error_model="numpy")
def rk4_update(q, v, dt, v2, v3, v4, a1, a2, a3, a4):
    """The RK4 step in place: ``q += dt/6 (v + 2 v2 + 2 v3 + v4)``, likewise ``v``."""
    c = dt / 6.0
    for i in range(q.shape[0]):
        for d in range(3):
            q[i, d] += c * (v[i, d] + 2.0 * v2[i, d] + 2.0 * v3[i, d] + v4[i, d])
            v[i, d] += c * (a1[i, d] + 2.0 * a2[i, d] + 2.0 * a3[i, d] + a4[i, d])


@njit(cache=True, error_model="numpy")
def rk4_block(q, v, dt, nsteps, stride, masses, l0, EA, compression, a, b, gtab, w, tip,
              max_strain, out_q, out_v):
    """Advance ``(q, v)`` in place by ``nsteps`` classical RK4 steps of size ``dt``.

    ``gtab[j]`` is the mass-proportional field ``g - a_anchor`` at ``t_start + j dt / 2``
    (``2 nsteps + 1`` rows).  Every ``stride``-th state is written to ``out_q[j]``,
    ``out_v[j]`` (``j = 0, 1, ...``).  Returns ``(step, rod)`` of the first state that
    failed the length check of ``load_vector`` (``step = -1`` when all passed).
    """
    n = q.shape[0]
    zero = np.zeros((n, 3))
    work = np.empty((n, 3))
    a1 = np.empty((n, 3))
    a2 = np.empty((n, 3))
    a3 = np.empty((n, 3))
    a4 = np.empty((n, 3))
    qs = np.empty((n, 3))
    v2 = np.empty((n, 3))
    v3 = np.empty((n, 3))
    v4 = np.empty((n, 3))
    h = 0.5 * dt
    for s in range(nsteps):
        bad = derivative(q, masses, l0, EA, compression, a, b, gtab[2 * s], w, tip, zero,
                         zero, max_strain, work, a1)
        if bad >= 0:
            return s, bad
        rk4_stage(q, v, h, v, a1, qs, v2)
        derivative(qs, masses, l0, EA, compression, a, b, gtab[2 * s + 1], w, tip, zero, zero,
                   max_strain, work, a2)
        rk4_stage(q, v, h, v2, a2, qs, v3)
        derivative(qs, masses, l0, EA, compression, a, b, gtab[2 * s + 1], w, tip, zero, zero,
                   max_strain, work, a3)
        rk4_stage(q, v, dt, v3, a3, qs, v4)
        derivative(qs, masses, l0, EA, compression, a, b, gtab[2 * s + 2], w, tip, zero, zero,
                   max_strain, work, a4)
        rk4_update(q, v, dt, v2, v3, v4, a1, a2, a3, a4)
        if (s + 1) % stride == 0:
            j = (s + 1) // stride - 1
            out_q[j] = q
            out_v[j] = v
    bad = load_vector(q, masses, l0, EA, compression, ELASTIC, gtab[2 * nsteps], w, tip, zero,
                      zero, max_strain, work)
    if bad >= 0:
        return nsteps, bad
    return -1, -1


@njit(cache=True, error_model="numpy")
def orbit_loads(x, masses, ends, R, mu, xi, wq, F, Fs):
    """``F_i``, ``F*_i`` (Eq. 14) of the differential gravity on a free chain in orbit.

    ``x = (r_0, q_1 .. q_n)`` (n + 1, 3): the offset of ``O_0`` from the reference point
    ``R`` and the rod vectors.  Row 0 holds the force on the end body at ``O_0`` (mass
    ``ends[0]``), rows ``1 .. n`` the rods: ``F_i = m_i sum_g w_g a(r_g)``, ``F*_i = m_i
    sum_g w_g s_g a(r_g)`` at the Gauss points ``s_g`` (``xi``, weights ``wq`` on [0, 1]).
    The end body at ``O_n`` (mass ``ends[1]``) is a point load at ``s = 1`` of the last rod,
    added to both its ``F_n`` and ``F*_n``.
    """
    n = x.shape[0] - 1
    R2 = R[0] * R[0] + R[1] * R[1] + R[2] * R[2]
    px, py, pz = x[0, 0], x[0, 1], x[0, 2]
    ax, ay, az, _, _ = differential_acceleration(mu, R, R2, px, py, pz)
    F[0, 0], F[0, 1], F[0, 2] = ends[0] * ax, ends[0] * ay, ends[0] * az
    Fs[0, 0], Fs[0, 1], Fs[0, 2] = F[0, 0], F[0, 1], F[0, 2]
    for i in range(1, n + 1):
        m = masses[i - 1]
        for d in range(3):
            F[i, d] = 0.0
            Fs[i, d] = 0.0
        for g in range(xi.size):
            s = xi[g]
            ax, ay, az, _, _ = differential_acceleration(
                mu, R, R2, px + s * x[i, 0], py + s * x[i, 1], pz + s * x[i, 2])
            F[i, 0] += m * wq[g] * ax
            F[i, 1] += m * wq[g] * ay
            F[i, 2] += m * wq[g] * az
            Fs[i, 0] += m * wq[g] * s * ax
            Fs[i, 1] += m * wq[g] * s * ay
            Fs[i, 2] += m * wq[g] * s * az
        px, py, pz = px + x[i, 0], py + x[i, 1], pz + x[i, 2]
    ax, ay, az, _, _ = differential_acceleration(mu, R, R2, px, py, pz)
    F[n, 0] += ends[1] * ax
    F[n, 1] += ends[1] * ay
    F[n, 2] += ends[1] * az
    Fs[n, 0] += ends[1] * ax
    Fs[n, 1] += ends[1] * ay
    Fs[n, 2] += ends[1] * az


@njit(cache=True, error_model="numpy")
def orbit_derivative(x, masses, l0, EA, compression, ends, a, b, R, mu, xi, wq, max_strain,
                     zero, F, Fs, work, out):
    """Accelerations ``x''`` of a free chain in orbit (``x`` as in ``orbit_loads``).

    Rows ``1 .. n``: ``Q_i - k_i q_i`` with ``Q_i = F*_i + sum_{j>i} F_j`` (Eqs. 12, 16,
    ``load_vector`` without field, uniform load or tip force); row 0, the generalized force
    of ``r_0`` (which moves every point), is the resultant ``F_0 + sum_i F_i``.  Then the
    O(n) solve with the factor of the extended chain (``factor_mass``).  ``zero`` is a
    zero 3-vector (no field, uniform load or tip force).  Returns ``load_vector``'s flag
    (a rod index ``0 .. n-1``, or -1).
    """
    orbit_loads(x, masses, ends, R, mu, xi, wq, F, Fs)
    bad = load_vector(x[1:], masses, l0, EA, compression, ELASTIC, zero, zero, zero, F[1:],
                      Fs[1:], max_strain, work[1:])
    for d in range(3):
        total = F[0, d]
        for i in range(1, x.shape[0]):
            total += F[i, d]
        work[0, d] = total
    solve_mass(a, b, work, out)
    return bad


@njit(cache=True, error_model="numpy")
def rk4_orbit_block(x, v, dt, nsteps, stride, masses, l0, EA, compression, ends, a, b, rtab,
                    mu, xi, wq, max_strain, out_x, out_v):
    """``rk4_block`` for a free chain in orbit: ``rtab[j]`` is the reference point ``R`` at
    ``t_start + j dt / 2`` (``2 nsteps + 1`` rows), so every stage sees ``R`` at its own
    time.  Same outputs and return value as ``rk4_block``."""
    n1 = x.shape[0]
    zero = np.zeros(3)
    F = np.empty((n1, 3))
    Fs = np.empty((n1, 3))
    work = np.empty((n1, 3))
    a1 = np.empty((n1, 3))
    a2 = np.empty((n1, 3))
    a3 = np.empty((n1, 3))
    a4 = np.empty((n1, 3))
    xs = np.empty((n1, 3))
    v2 = np.empty((n1, 3))
    v3 = np.empty((n1, 3))
    v4 = np.empty((n1, 3))
    h = 0.5 * dt
    for s in range(nsteps):
        bad = orbit_derivative(x, masses, l0, EA, compression, ends, a, b, rtab[2 * s], mu,
                               xi, wq, max_strain, zero, F, Fs, work, a1)
        if bad >= 0:
            return s, bad
        rk4_stage(x, v, h, v, a1, xs, v2)
        orbit_derivative(xs, masses, l0, EA, compression, ends, a, b, rtab[2 * s + 1], mu, xi,
                         wq, max_strain, zero, F, Fs, work, a2)
        rk4_stage(x, v, h, v2, a2, xs, v3)
        orbit_derivative(xs, masses, l0, EA, compression, ends, a, b, rtab[2 * s + 1], mu, xi,
                         wq, max_strain, zero, F, Fs, work, a3)
        rk4_stage(x, v, dt, v3, a3, xs, v4)
        orbit_derivative(xs, masses, l0, EA, compression, ends, a, b, rtab[2 * s + 2], mu, xi,
                         wq, max_strain, zero, F, Fs, work, a4)
        rk4_update(x, v, dt, v2, v3, v4, a1, a2, a3, a4)
        if (s + 1) % stride == 0:
            j = (s + 1) // stride - 1
            out_x[j] = x
            out_v[j] = v
    bad = orbit_derivative(x, masses, l0, EA, compression, ends, a, b, rtab[2 * nsteps], mu,
                           xi, wq, max_strain, zero, F, Fs, work, a1)
    if bad >= 0:
        return nsteps, bad
    return -1, -1


@njit(cache=True, error_model="numpy")
def count_axial_below(k, m, lam):
    """Number of axial eigenvalues ``omega^2 < lam`` of the straight chain.

    In joint coordinates ``y = Phi x`` the axial problem is the pencil ``(K_y, G)``: ``K_y``
    the tridiagonal bar stiffness of springs ``k_i = E_i A_i / l_i0`` between consecutive
    joints (``y_0 = 0``) and ``G`` the tridiagonal matrix of Eq. 25.  By Sylvester's law of
    inertia the count is the number of negative pivots of ``K_y - lam G`` (Sturm sequence).
    """
    n = k.size
    count = 0
    d = 1.0
    for i in range(n):
        nxt_k = k[i + 1] if i < n - 1 else 0.0
        nxt_m = m[i + 1] if i < n - 1 else 0.0
        piv = k[i] + nxt_k - lam * (m[i] + nxt_m) / 3.0
        if i > 0:
            off = -k[i] - lam * m[i] / 6.0
            piv -= off * off / d
        if piv < 0.0:
            count += 1
        if piv == 0.0:
            piv = -1e-300
        d = piv
    return count


@njit(cache=True, error_model="numpy")
def max_axial_eigenvalue(k, m, upper):
    """Largest ``omega^2`` of ``count_axial_below`` by bisection on ``[0, upper]``, returned
    as the upper end of the final bracket (relative width 1e-14)."""
    n = k.size
    while count_axial_below(k, m, upper) < n:
        upper *= 2.0
    lo, hi = 0.0, upper
    while hi - lo > 1e-14 * hi:
        mid = 0.5 * (lo + hi)
        if count_axial_below(k, m, mid) < n:
            lo = mid
        else:
            hi = mid
    return hi
