"""Closed-form reference solutions used by the validation tests, demos and benchmarks.

Examples
--------
>>> from skfem_cable.analysis.analytic import elastica_tip_load, string_frequency
>>> [round(x, 4) for x in elastica_tip_load(2.0)]   # u/L, w/L at k = P L^2 / EI = 2
[0.1606, 0.4935]
>>> string_frequency(length=1.0, tension=100.0, mass_per_length=0.01)   # Hz
50.0
"""

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq
from scipy.special import ellipe, ellipeinc, ellipk, ellipkinc

from ..bodies.catenary import green_stretch


def _elastica_modulus(k):
    """Parameter ``m = p^2`` of the tip-loaded elastica (Bisshopp & Drucker 1945)."""
    sk = np.sqrt(k)

    def mismatch(m):
        phi1 = np.arcsin(1.0 / np.sqrt(2.0 * m))
        return ellipk(m) - ellipkinc(phi1, m) - sk

    return brentq(mismatch, 0.5 + 1e-15, 1.0 - 1e-15, xtol=1e-15, rtol=1e-15)


def elastica_tip_load(k):
    """Tip of an inextensible cantilever under a transverse tip load ``P`` (dead load).

    With ``k = P L^2 / EI`` the tip rotation ``theta0`` follows from
    ``sqrt(k) = K(p) - F(phi1, p)``, ``p = sin(pi/4 + theta0/2)``,
    ``sin(phi1) = 1/(sqrt(2) p)`` (Bisshopp & Drucker 1945); then
    ``x_tip/L = 2 p cos(phi1) / sqrt(k)`` and ``w/L = 1 - 2 (E(p) - E(phi1, p)) / sqrt(k)``.

    Returns
    -------
    u, w : float
        Horizontal shortening ``u/L = 1 - x_tip/L`` and deflection ``w/L``.

    Examples
    --------
    >>> from skfem_cable.analysis.analytic import elastica_tip_load
    >>> u, w = elastica_tip_load(10.0)
    >>> round(u, 4), round(w, 4)
    (0.555, 0.8106)
    """
    if not k > 0:
        raise ValueError(f"k must be > 0, got {k!r}")
    sk = np.sqrt(k)
    m = _elastica_modulus(k)
    p = np.sqrt(m)
    phi1 = np.arcsin(1.0 / (np.sqrt(2.0) * p))
    u = 1.0 - 2.0 * p * np.cos(phi1) / sk
    w = 1.0 - 2.0 * (ellipe(m) - ellipeinc(phi1, m)) / sk
    return float(u), float(w)


def elastica_tip_load_angle(k, s):
    """Tangent angle ``theta(s)`` (rad, positive towards the load) along the cantilever of
    ``elastica_tip_load`` at ``s / L`` in ``[0, 1]``: the axial force there is
    ``P sin(theta)``.

    With the tip angle ``theta_L = 2 arcsin(p) - pi/2`` of the elliptic solution, the first
    integral ``theta'^2 = 2 k (sin theta_L - sin theta)`` gives the slope at the clamp, and
    ``theta'' = -k cos(theta)`` is integrated from there (``solve_ivp``, DOP853, relative
    tolerance 1e-12).
    """
    if not k > 0:
        raise ValueError(f"k must be > 0, got {k!r}")
    s = np.asarray(s, dtype=float)
    if np.any(s < 0) or np.any(s > 1):
        raise ValueError("s must lie in [0, 1] (arc length over L)")
    theta_tip = 2.0 * np.arcsin(np.sqrt(_elastica_modulus(k))) - 0.5 * np.pi
    start = [0.0, np.sqrt(2.0 * k * np.sin(theta_tip))]
    sol = solve_ivp(lambda x, y: [y[1], -k * np.cos(y[0])], (0.0, 1.0), start,
                    method="DOP853", rtol=1e-12, atol=1e-14, dense_output=True)
    return sol.sol(s)[0]


def compound_pendulum_period(length, amplitude, g=9.81):
    """Period of a uniform rigid bar pivoted at one end, released at rest at ``amplitude``
    (rad from the downward vertical): ``T = 4 K(sin^2(amplitude/2)) / omega0`` with
    ``omega0^2 = 3 g / (2 L)``.

    Examples
    --------
    >>> import numpy as np
    >>> from skfem_cable.analysis.analytic import compound_pendulum_period
    >>> round(compound_pendulum_period(1.2, np.pi / 2), 4)      # released from horizontal
    2.1179
    """
    omega0 = np.sqrt(1.5 * g / length)
    return float(4.0 * ellipk(np.sin(0.5 * amplitude) ** 2) / omega0)


def string_frequency(length, tension, mass_per_length, EI=0.0, n=1):
    """``n``-th transverse frequency (Hz) of a taut pinned string, with the first-order
    bending correction of a tensioned pinned beam:
    ``f_n = n/(2L) sqrt(T/mu) sqrt(1 + EI (n pi / L)^2 / T)``."""
    k = n * np.pi / length
    return float(n / (2 * length) * np.sqrt(tension / mass_per_length)
                 * np.sqrt(1 + EI * k * k / tension))


def rotating_string(s, length, EA, mass_per_length, tip_mass, omega, hub_radius=0.0):
    """Steady radial state of an extensible string (Green-strain law, no bending) spinning
    at ``omega`` (rad/s) about an axis, its root at ``hub_radius`` (m) from the axis and a
    point mass ``tip_mass`` (kg) at its tip.

    With ``s`` the reference arc length, the radius ``r(s)`` and the axial force ``T(s)``
    solve the two-point problem

        r' = 1 + e(T),   T' = -mu omega^2 r,   r(0) = hub_radius,   T(L) = m omega^2 r(L)

    (``e = green_stretch``): each element of length ``ds`` carries the centrifugal force
    ``mu omega^2 r ds``.  It is solved by shooting on ``T(0)`` (``brentq`` to 1e-15 relative)
    with ``solve_ivp`` (DOP853, relative tolerance 1e-13): a reference independent of the
    finite elements, accurate to about 1e-11.

    Returns
    -------
    r, T : ndarray
        Radius (m) and axial force (N) at ``s``.

    Examples
    --------
    A light stiff string: ``T(0) ~ m omega^2 L + mu omega^2 L^2 / 2 = 20 N + 0.8 N``:

    >>> from skfem_cable.analysis.analytic import rotating_string
    >>> r, T = rotating_string([0.0, 10.0], 10.0, 1e9, 4e-3, 0.5, 2.0)
    >>> [round(float(x), 4) for x in T]
    [20.8, 20.0]
    """
    s = np.asarray(s, dtype=float)
    if np.any(s < 0) or np.any(s > length):
        raise ValueError(f"s must lie in [0, length = {length}]")
    w2 = omega * omega

    def shoot(T0, dense=False):
        def rhs(x, y):
            return [1.0 + green_stretch(max(y[1], 0.0), EA), -mass_per_length * w2 * y[0]]

        sol = solve_ivp(rhs, (0.0, length), [hub_radius, T0], method="DOP853", rtol=1e-13,
                        atol=1e-14 * max(length, T0), dense_output=dense)
        return sol if dense else sol.y[1, -1] - tip_mass * w2 * sol.y[0, -1]

    rigid = tip_mass * w2 * (hub_radius + length) + mass_per_length * w2 * (
        hub_radius * length + length**2 / 2)
    T0 = brentq(shoot, 0.5 * rigid, 2.0 * rigid + 1e-300, xtol=1e-15 * rigid, rtol=1e-15)
    r, T = shoot(T0, dense=True).sol(s)
    return r, T


def elastic_catenary(s, span, height, length, w, EA):
    """Elastic catenary of the Green-strain law (no bending) hanging between ``(0, 0)``
    and ``(span, height)`` (m, ``x`` horizontal, ``z`` up) under the weight ``w`` (N per
    metre of unstretched length ``length``).

    With ``H`` the horizontal force and ``V_A`` the upward support force at the left end,
    the force in the cable at unstretched arc length ``s`` is ``(H, w s - V_A)``, of
    magnitude ``T``, and its tangent is parallel to it:

        x(s) = int_0^s (1 + e) H / T ds,   z(s) = int_0^s (1 + e) (w s - V_A) / T ds

    (Irvine, *Cable Structures*, 1981, Sect. 2.2, with the stretch ``e = green_stretch(T)``
    of this law instead of Hooke's ``T / EA``).  The inextensible part is Irvine's closed
    form in ``asinh``; the elastic part is integrated by 64-point Gauss-Legendre quadrature
    (the integrand is analytic: round-off accuracy).  ``H`` and ``V_A`` solve the closure
    ``x(L) = span, z(L) = height`` by Newton's method with a finite-difference Jacobian,
    to a residual below 1e-14 of the span.

    Returns
    -------
    xz : ndarray (len(s), 2)
        Positions (m).
    T : ndarray (len(s),)
        Axial force (N).
    H, VA : float
        Horizontal force and upward support force at the left end (N).

    Examples
    --------
    A 12 m cable hung between points 10 m apart: the two support forces carry its weight
    ``w L = 12 N`` by symmetry:

    >>> from skfem_cable.analysis.analytic import elastic_catenary
    >>> xz, T, H, VA = elastic_catenary([0.0, 6.0, 12.0], 10.0, 0.0, 12.0, 1.0, 1e6)
    >>> round(VA, 9), round(float(xz[1, 0]), 9)
    (6.0, 5.0)
    """
    chord = np.hypot(span, height)
    if not length > chord:
        raise ValueError(f"length must exceed the chord {chord} m (a slack cable), got "
                         f"{length!r}")
    s = np.atleast_1d(np.asarray(s, dtype=float))
    gx, gw = np.polynomial.legendre.leggauss(64)

    def shape(s, H, VA):
        V = w * s - VA
        x = H / w * (np.arcsinh(V / H) + np.arcsinh(VA / H))
        z = (np.hypot(H, V) - np.hypot(H, VA)) / w
        sg = 0.5 * s[:, None] * (gx + 1.0)
        wg = 0.5 * s[:, None] * gw
        Vg = w * sg - VA
        Tg = np.hypot(H, Vg)
        e = green_stretch(Tg, EA)
        return np.column_stack([x + np.sum(wg * e * H / Tg, axis=1),
                                z + np.sum(wg * e * Vg / Tg, axis=1)])

    W = w * length
    sag = np.sqrt(3.0 * span * (length - chord) / 8.0)
    u = np.array([span / (8.0 * sag), 0.5 + height / (2.0 * length)])  # H/W, VA/W
    target = np.array([span, height])

    def closure(u):
        return (shape(np.array([length]), u[0] * W, u[1] * W)[0] - target) / span

    for _ in range(100):
        f = closure(u)
        if np.max(np.abs(f)) < 1e-14:
            break
        J = np.column_stack([(closure(u + d) - f) / d[k] for k, d in
                             enumerate(np.diag(1e-7 * np.maximum(np.abs(u), 1e-3)))])
        du = np.linalg.solve(J, -f)
        u = u + du * min(1.0, 0.5 * u[0] / max(abs(du[0]), 1e-300))  # keep H > 0
    else:
        raise RuntimeError(f"catenary closure did not converge: residual {closure(u)}")
    H, VA = u * W
    return shape(s, H, VA), np.hypot(H, w * s - VA), float(H), float(VA)



def elastica_catenary(s, span, length, w, EA, EI, tol=1e-10):
    """A cable with bending stiffness hanging under its weight between two pins at the same
    height, ``(0, 0)`` and ``(span, 0)`` (m; ``x`` horizontal, ``z`` up): the planar
    elastica-catenary of the built-in law ``W = EA eps^2 / 2 + EI kappa^2 / 2`` (Green
    strain, curvature per current length), solved as a boundary-value problem.

    With ``s`` the unstretched arc length, ``theta`` the tangent angle, ``lambda`` the
    stretch and ``n = (H, V_A + w s)`` the force of the part beyond ``s`` on the part
    before it (``n' = (0, w)``: the weight ``w`` per unstretched metre), the law gives the
    moment ``m = dW/dtheta' = EI theta' / lambda^2`` and the axial force ``N = n . t =
    dW/dlambda = EA (lambda^3 - lambda) / 2 - m^2 lambda / EI`` (solved for ``lambda``),
    and Kirchhoff's equations of the planar rod read

        x' = lambda cos(theta),  z' = lambda sin(theta),  theta' = lambda^2 m / EI,
        m' = lambda (H sin(theta) - V cos(theta)),

    with ``x = z = m = 0`` at ``s = 0`` and ``x - span = z = m = 0`` at ``s = length``;
    ``H`` and ``V_A`` are unknown parameters.  ``scipy.integrate.solve_bvp`` solves it to
    the relative tolerance ``tol`` from the elastic catenary without bending
    (``elastic_catenary``), independently of the finite elements.

    Returns
    -------
    xz : ndarray (len(s), 2)
        Positions (m).
    N : ndarray (len(s),)
        Axial force (N), ``n . t`` (the tension ``Cable.tension`` reports).
    H, VA : float
        Horizontal force and the vertical force ``V_A`` of the part beyond the left
        support (N; ``-V_A`` is the upward support force there).

    Examples
    --------
    A 12 m steel wire of 2 mm radius between pins 10 m apart: the tension at a support and
    at midspan.

    >>> import numpy as np
    >>> from skfem_cable.analysis.analytic import elastica_catenary
    >>> r, E, rho = 2e-3, 2.1e11, 7850.0
    >>> A, I = np.pi * r**2, np.pi * r**4 / 4
    >>> xz, N, H, VA = elastica_catenary([0.0, 6.0], 10.0, 12.0, rho * A * 9.81, E * A, E * I)
    >>> [round(float(t), 3) for t in N]
    [7.245, 4.352]
    """
    from scipy.integrate import solve_bvp

    s = np.atleast_1d(np.asarray(s, dtype=float))
    mesh = np.linspace(0.0, length, 401)
    xz, _, H, VA = elastic_catenary(mesh, span, 0.0, length, w, EA)
    theta = np.arctan2(w * mesh - VA, H)
    guess = np.vstack([xz[:, 0], xz[:, 1], theta, np.zeros_like(mesh)])

    def stretch(N, m):
        lam = 1.0 + N / EA
        for _ in range(4):  # Newton on EA (lam^3 - lam)/2 - m^2 lam / EI = N
            f = EA * (lam**3 - lam) / 2 - m * m * lam / EI - N
            lam = lam - f / (EA * (3 * lam**2 - 1) / 2 - m * m / EI)
        return lam

    def rhs(s, y, p):
        x, z, th, m = y
        Hh, V = p[0], p[1] + w * s
        lam = stretch(Hh * np.cos(th) + V * np.sin(th), m)
        return np.vstack([lam * np.cos(th), lam * np.sin(th), lam**2 * m / EI,
                          lam * (Hh * np.sin(th) - V * np.cos(th))])

    def bc(ya, yb, p):
        return np.array([ya[0], ya[1], ya[3], yb[0] - span, yb[1], yb[3]])

    sol = solve_bvp(rhs, bc, mesh, guess, p=[H, -VA], tol=tol, max_nodes=100000)
    if not sol.success:
        raise RuntimeError(f"elastica catenary: solve_bvp failed ({sol.message})")
    x, z, th, _ = sol.sol(s)
    H, V0 = sol.p
    N = H * np.cos(th) + (V0 + w * s) * np.sin(th)
    return np.column_stack([x, z]), N, float(H), float(V0)
