"""Numba kernel of a central body's differential gravity on mass points (``orbit_gravity``).

Mass point ``p`` of mass ``m_p`` sits at ``delta = G_p q[dofs_p]`` (an offset from the
reference point ``R``); it receives the generalized force ``m_p G_p^T a(R, delta)`` with
``a = g(R + delta) - g(R)`` and the tangent ``m_p G_p^T T G_p``, ``T = da/d delta``.
The point-mass part is Battin's cancellation-free form (``orbit.differential_gravity``),
its tangent the gravity gradient ``mu / r^3 (3 r r^T / r^2 - I)`` at ``r = R + delta``.

The optional J2 part (the central body's oblateness, its axis along ``z``): with
``k = 3/2 mu J2 R_e^2``,

    a_J2(r) = -k (r (r^-5 - 5 z^2 r^-7) + 2 z r^-5 e_z),
    da_J2/dr = -k ((r^-5 - 5 z^2 r^-7) I + r (35 z^2 r^-9 r - 5 r^-7 r - 10 z r^-7 e_z)^T
                   + 2 e_z (r^-5 e_z - 5 z r^-7 r)^T),

the gradient of the potential ``mu J2 R_e^2 (3 z^2 - r^2) / (2 r^5)``; its difference
``a_J2(R + delta) - a_J2(R)`` is formed by subtraction (J2 is 1e-3 of the central term,
so the digits lost are below the central term's round-off for offsets above 1e-4 m in
low Earth orbit).
"""

import numpy as np
from numba import njit


@njit(cache=True)
def j2_acceleration(k, r, out):
    """``a_J2(r)`` into ``out`` (3,), ``k = 3/2 mu J2 R_e^2``."""
    r2 = r[0] * r[0] + r[1] * r[1] + r[2] * r[2]
    inv5 = r2 ** -2.5
    common = inv5 - 5.0 * r[2] * r[2] * inv5 / r2
    for i in range(3):
        out[i] = -k * r[i] * common
    out[2] -= 2.0 * k * r[2] * inv5


@njit(cache=True)
def j2_tangent(k, r, T):
    """Add ``da_J2/dr`` to ``T`` (3, 3)."""
    r2 = r[0] * r[0] + r[1] * r[1] + r[2] * r[2]
    z = r[2]
    inv5 = r2 ** -2.5
    inv7 = inv5 / r2
    inv9 = inv7 / r2
    diag = inv5 - 5.0 * z * z * inv7
    for i in range(3):
        T[i, i] -= k * diag
        for j in range(3):
            T[i, j] -= k * r[i] * (35.0 * z * z * inv9 - 5.0 * inv7) * r[j]
        T[i, 2] += k * r[i] * 10.0 * z * inv7
    for j in range(3):
        T[2, j] += k * 10.0 * z * inv7 * r[j]
    T[2, 2] -= 2.0 * k * inv5


@njit(cache=True)
def field(mu, k, reference, base, delta, a, T, r, extra):
    """Differential acceleration ``a`` (3,) at the offset ``delta`` and its tangent ``T``
    (3, 3); ``base`` holds ``a_J2(R)`` (unused when ``k = 0``); ``r`` and ``extra`` (3,)
    are scratch."""
    R2 = reference[0] ** 2 + reference[1] ** 2 + reference[2] ** 2
    q = 0.0
    for i in range(3):
        q += delta[i] * (2.0 * reference[i] + delta[i])
        r[i] = reference[i] + delta[i]
    q /= R2
    root = np.sqrt(1.0 + q)
    fq = q * (3.0 + q * (3.0 + q)) / (1.0 + (1.0 + q) * root)
    r2 = R2 * (1.0 + q)
    s = mu / (r2 * np.sqrt(r2))
    for i in range(3):
        a[i] = -s * (delta[i] - fq * reference[i])
        for j in range(3):
            T[i, j] = 3.0 * s * r[i] * r[j] / r2
        T[i, i] -= s
    if k != 0.0:
        j2_acceleration(k, r, extra)
        for i in range(3):
            a[i] += extra[i] - base[i]
        j2_tangent(k, r, T)


@njit(cache=True)
def kernel(pack, index, ev):
    """The compiled hook of the evaluation contract (``contract.Term.kernels``): the
    generalized forces of the mass points into ``ev``'s external forces and
    ``-cK m G^T T G`` into its matrix values at ``index`` (np, n, n), with
    ``pack = (dofs (np, n), G (np, 3, n), mass (np,), reference (3,), base (3,),
    constants = [mu, k])``."""
    q, v, s, f, f_ext, fd, data, energy, power = ev
    dofs, G, mass, reference, base, constants = pack
    n_points, n = dofs.shape
    want = data.size > 0
    cK = s[1]
    mu, k = constants[0], constants[1]
    delta = np.empty(3)
    a = np.empty(3)
    T = np.empty((3, 3))
    TG = np.empty((3, n))
    r = np.empty(3)
    extra = np.empty(3)
    for p in range(n_points):
        for i in range(3):
            delta[i] = 0.0
            for c in range(n):
                delta[i] += G[p, i, c] * q[dofs[p, c]]
        field(mu, k, reference, base, delta, a, T, r, extra)
        m = mass[p]
        for c in range(n):
            f_ext[dofs[p, c]] += m * (G[p, 0, c] * a[0] + G[p, 1, c] * a[1]
                                      + G[p, 2, c] * a[2])
        if not want:
            continue
        for i in range(3):
            for c in range(n):
                TG[i, c] = T[i, 0] * G[p, 0, c] + T[i, 1] * G[p, 1, c] + T[i, 2] * G[p, 2, c]
        for c in range(n):
            for d in range(n):
                value = G[p, 0, c] * TG[0, d] + G[p, 1, c] * TG[1, d] + G[p, 2, c] * TG[2, d]
                data[index[p, c, d]] -= cK * m * value
