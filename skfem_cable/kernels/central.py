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

from . import CUBIC

#: In dynamics, a gravity-gradient tangent below this, relative to the mass, is omitted.
NEGLIGIBLE = 1e-12


@njit(cache=True)
def j2_acceleration(k, r, out):
    """``a_J2(r)`` into ``out`` (3,), ``k = 3/2 mu J2 R_e^2``."""
    r2 = r[0] * r[0] + r[1] * r[1] + r[2] * r[2]
    inv5 = r2 ** -2.5
    common = inv5 - 5.0 * r[2] * r[2] * inv5 / r2
    for i in range(3):
        out[i] = -k * r[i] * common
    out[2] -= 2.0 * k * r[2] * inv5


@njit(cache=True, inline="always")
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


@njit(cache=True, inline="always")
def differential_acceleration(mu, R, R2, x, y, z):
    """``g(R + delta) - g(R)`` at the offset ``delta = (x, y, z)`` from the reference point
    ``R`` (``R2 = |R|^2``) in Battin's cancellation-free form (``orbit.differential_gravity``),
    with ``p^(3/2) = p sqrt(p)`` (a square root is several times faster than a power):
    its three components, ``mu / |r|^3`` and ``|r|^2``.  ``kernels.rodchain`` inlines it
    too; numba's cache of that module does not notice a change here (as ``bordered``'s
    does not notice ``lapack``'s): touch that file as well."""
    q = (x * (2.0 * R[0] + x) + y * (2.0 * R[1] + y) + z * (2.0 * R[2] + z)) / R2
    p = 1.0 + q
    f = q * (3.0 + q * (3.0 + q)) / (1.0 + p * np.sqrt(p))
    r2 = R2 * p
    s = mu / (r2 * np.sqrt(r2))
    return -s * (x - f * R[0]), -s * (y - f * R[1]), -s * (z - f * R[2]), s, r2


@njit(cache=True, inline="always")
def add_j2(k, reference, base, delta, a, r, extra):
    """Add J2's difference ``a_J2(R + delta) - a_J2(R)`` to ``a`` (3,), ``base`` holding
    ``a_J2(R)``; ``r`` and ``extra`` (3,) are scratch."""
    for i in range(3):
        r[i] = reference[i] + delta[i]
    j2_acceleration(k, r, extra)
    for i in range(3):
        a[i] += extra[i] - base[i]


@njit(cache=True, inline="always")
def gradient(k, s, r2, r, T):
    """The tangent ``T = da/d delta`` (3, 3) at ``r``: ``s (3 r r^T / r^2 - I)`` with ``s =
    mu / |r|^3``, and the J2 part when ``k != 0``."""
    for i in range(3):
        for j in range(3):
            T[i, j] = 3.0 * s * r[i] * r[j] / r2
        T[i, i] -= s
    if k != 0.0:
        j2_tangent(k, r, T)


@njit(cache=True)
def kernel(pack, index, ev):
    """``_kernel`` with the number of vectors per point fixed for the cubic element and
    the rigid body (``kernels.CUBIC``), or read from ``vectors``."""
    k = pack[0].shape[1]
    if k == CUBIC:
        _kernel(pack, index, ev, CUBIC)
    else:
        _kernel(pack, index, ev, k)


@njit(cache=True, inline="always")
def _kernel(pack, index, ev, k):
    """The compiled hook of the evaluation contract (``contract.Term.kernels``): the
    generalized forces of the mass points into ``ev``'s external forces and ``-cK m (s
    s^T) (x) T`` into its matrix values at ``index`` (ng, 3 k, 3 k), one block per group
    of points sharing their ``k`` vectors, with ``pack = (vectors (np, k), coefficients
    (np, k), mass (np,), groups (ng + 1,), reference (3,), base (3,), constants = [mu,
    k_J2])`` (``orbit_gravity.MassPoints``: point ``p`` is at ``sum_j s_pj q[v_pj : v_pj +
    3]``; ``constants[2]``: a bound of the gravity gradient's norm).

    In dynamics the tangent is left out when ``cK`` times the gradient is below
    ``NEGLIGIBLE``: beside the unit mass it is added to, it would change Newton's
    contraction by less than that, and the converged step not at all (the residual is
    exact).  Far from the central body (the E-sail at 1 AU: ``cK |T|`` about 1e-14) this
    halves the load's cost; statics and modes always get it (there it may be the only
    stiffness of a libration)."""
    q, v, s, f, f_ext, fd, data, energy, power = ev
    vectors, coefficients, mass, groups, reference, base, constants = pack
    n_groups = groups.size - 1
    cK = s[1]
    want = data.size > 0 and (s[3] == 0.0 or cK * constants[2] > NEGLIGIBLE)
    mu, k2 = constants[0], constants[1]
    R2 = reference[0] ** 2 + reference[1] ** 2 + reference[2] ** 2
    delta = np.empty(3)
    a = np.empty(3)
    T = np.empty((3, 3))
    r = np.empty(3)
    extra = np.empty(3)
    K = np.empty((3 * k, 3 * k))
    for g in range(n_groups):
        if want:
            K[:] = 0.0
        for p in range(groups[g], groups[g + 1]):
            for i in range(3):
                delta[i] = 0.0
                for j in range(k):
                    delta[i] += coefficients[p, j] * q[vectors[p, j] + i]
            a[0], a[1], a[2], scale, r2 = differential_acceleration(
                mu, reference, R2, delta[0], delta[1], delta[2])
            if k2 != 0.0:
                add_j2(k2, reference, base, delta, a, r, extra)
            m = mass[p]
            for j in range(k):
                c = m * coefficients[p, j]
                for i in range(3):
                    f_ext[vectors[p, j] + i] += c * a[i]
            if not want:
                continue
            for i in range(3):
                r[i] = reference[i] + delta[i]
            gradient(k2, scale, r2, r, T)
            for j in range(k):
                for l in range(k):
                    w = m * coefficients[p, j] * coefficients[p, l]
                    for i in range(3):
                        for ii in range(3):
                            K[3 * j + i, 3 * l + ii] += w * T[i, ii]
        if want:
            for row in range(3 * k):
                for col in range(3 * k):
                    data[index[g, row, col]] -= cK * K[row, col]


@njit(cache=True)
def j2_potential(k, r):
    """J2's potential energy per unit mass at ``r``, ``k (z^2 / r^5 - 1 / (3 r^3))``
    (``k = 3/2 mu J2 R_e^2``), whose negative gradient is ``j2_acceleration``."""
    r2 = r[0] * r[0] + r[1] * r[1] + r[2] * r[2]
    return k * (r[2] * r[2] * r2 ** -2.5 - r2 ** -1.5 / 3.0)


@njit(cache=True)
def field(mu, k2, reference, base, delta, a, phi, T):
    """The differential field at the offsets ``delta`` (np, 3) from ``reference``: the
    acceleration ``a`` (np, 3), its tangent ``T`` (np, 3, 3) and the potential energy per
    unit mass ``phi`` (np,) of which ``a`` is the negative gradient, zero at the reference
    point: ``phi = V(R + delta) - V(R) + a_V(R) . delta`` with ``V`` the central body's
    potential (the point mass's part ``mu / |R| q / (sqrt(1 + q) (1 + sqrt(1 + q)))``
    free of cancellation, as ``orbit_gravity.orbital_energy``) and ``a_V(R)`` its
    acceleration at the reference point (``base`` holds J2's, ``k2 = 3/2 mu J2 R_e^2``,
    0 without J2).  For the mass a deployment moves between the reel and the tether
    (``orbit_gravity``)."""
    R2 = reference[0] ** 2 + reference[1] ** 2 + reference[2] ** 2
    R = np.sqrt(R2)
    r = np.empty(3)
    extra = np.empty(3)
    row = np.empty(3)
    for p in range(delta.shape[0]):
        x, y, z = delta[p, 0], delta[p, 1], delta[p, 2]
        a[p, 0], a[p, 1], a[p, 2], scale, r2 = differential_acceleration(
            mu, reference, R2, x, y, z)
        q = (x * (2.0 * reference[0] + x) + y * (2.0 * reference[1] + y)
             + z * (2.0 * reference[2] + z)) / R2
        root = np.sqrt(1.0 + q)
        phi[p] = mu / R * q / (root * (1.0 + root)) \
            - mu * (reference[0] * x + reference[1] * y + reference[2] * z) / (R2 * R)
        if k2 != 0.0:
            row[:] = 0.0
            add_j2(k2, reference, base, delta[p], row, r, extra)
            for i in range(3):
                a[p, i] += row[i]
            phi[p] += j2_potential(k2, r) - j2_potential(k2, reference) \
                + base[0] * x + base[1] * y + base[2] * z
        for i in range(3):
            r[i] = reference[i] + delta[p, i]
        gradient(k2, scale, r2, r, T[p])
