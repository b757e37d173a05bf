"""Closed-form reference solutions used by the validation tests, demos and benchmarks.

Examples
--------
>>> from skfem_cable.analytic import elastica_tip_load, string_frequency
>>> [round(x, 4) for x in elastica_tip_load(2.0)]   # u/L, w/L at k = P L^2 / EI = 2
[0.1606, 0.4935]
>>> string_frequency(length=1.0, tension=100.0, mass_per_length=0.01)   # Hz
50.0
"""

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq
from scipy.special import ellipe, ellipeinc, ellipk, ellipkinc


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
    >>> from skfem_cable.analytic import elastica_tip_load
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
    >>> from skfem_cable.analytic import compound_pendulum_period
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
