"""The solar-wind Coulomb force at a point of a line (paper Eqs. 29-35): the point function
of a pointwise load (``kernels.line``), whose generated module is the force's kernel.

At every point ``f = c s(rho) u_perp`` with ``u_perp = (I - t t^T) i_R`` (Eqs. 29-30),
``t = r_x / |r_x|`` the tether tangent, ``i_R = (r - r_sun) / rho`` the radial direction
from the Sun (Eq. 32) at the heliocentric distance ``rho = |r - r_sun|``, and
``s(rho) = (d0 / rho)^p`` the scaling of the thrust with solar distance (``d0`` the distance
of the wind's data, 1 AU; ``p = 7/6`` after Janhunen et al. 2010, see ``coulomb``), taken
from its series about the distance of the system's origin where the point is close to it
(``expansion``: the power once per time step instead of once per point).  The
per-element coefficient ``c`` (N/m: the force coefficient of Eq. 29 times the wind speed,
times a deploying tether's stretch) is the loop's ``scale``; ``point`` gives
``s(rho) u_perp``.  With ``ds/dr = -p s i_R^T / rho`` the tangent has the two parts

``df/dr = c s (I - t t^T)(I - (1 + p) i_R i_R^T) / rho``,
``df/dr_x = -c s (t i_R^T + (t . i_R) I)(I - t t^T) / |r_x|``

(Eq. 35 and the dependence of ``i_R`` and ``s`` on the position, negligible at 1 AU but kept
exact); the force does not depend on the velocity (the wind blows at ``u i_R`` whatever the
tether's motion, as in the paper's force law).
"""

import math

from numba import njit

from .line import point_function


@point_function
def point(params, e, t, x, a, xd, want, f, Fx, Fa, Fv, work):
    """``f = s(rho) u_perp`` at the point ``x`` of slope ``a`` and, if ``want``, its
    derivatives ``Fx``, ``Fa`` (``Fv`` stays zero), with ``params = (sun, scaling)``: the
    Sun's position (3,) and ``scaling`` (7 numbers: ``(d0, p)`` and their
    expansion about the origin's distance, ``expansion``) (``kernels.line`` for the
    signature; ``work[0, 0]``, ``work[0, 1]`` hold ``i_R`` and ``t``, ``work[1]``,
    ``work[2]`` the projections).  Inlined by LLVM into the generated loop
    (``line.point_function``; its CPU time per evaluation is the hand-written loop's)."""
    sun, scaling = params
    _wind(sun, scaling, True, x, a, want, f, Fx, Fa, work)


@point_function
def point_uniform(params, e, t, x, a, xd, want, f, Fx, Fa, Fv, work):
    """``point`` of a wind that does not scale with the distance (``p = 0``: ``s = 1``,
    the paper's force law), without the power and its derivative at every point: the
    same numbers, bit for bit."""
    sun, scaling = params
    _wind(sun, scaling, False, x, a, want, f, Fx, Fa, work)


#: The bound on the relative truncation error of the expansion (``expansion``): a
#: hundredth of the rounding of a double.
TRUNCATION = 1e-18


def expansion(d0, power, sun):
    """The kernel's ``scaling`` (7 numbers) of the law ``s(rho) = (d0 /
    rho)^p`` about the distance ``R = |sun|`` of the system's origin from the Sun:
    ``(d0, p, 1 / R, s(R), c1, c2, q_max)``, with which a point at the distance ``rho``,
    ``q = rho / R - 1``, has

    ``s(rho) = s(R) (1 + q)^(-p) = s(R) (1 + c1 q + c2 q^2) + E``,
    ``c1 = -p``, ``c2 = p (p + 1) / 2``,  ``|E| <= s(R) c3 |q|^3 (1 + xi)^(-p - 3)``,
    ``c3 = |p (p + 1) (p + 2)| / 6``

    (the binomial series and its Lagrange remainder, ``xi`` between 0 and ``q``).
    ``q_max = min(1e-3, (TRUNCATION / c3)^(1/3))``: where ``|q| <= q_max`` the kernel
    takes the series, whose truncation stays below ``TRUNCATION`` relative (to the factor
    ``(1 + xi)^(-p - 3)``, within ``1e-3 |p + 3|`` of 1), elsewhere the power.  A sail of
    tethers of 20 km at 1 AU has ``|q| <= 1.4e-7`` against ``q_max = 9.1e-7`` of the
    paper's ``p = 7/6``: one power per time step instead of one per Gauss point; the
    series agrees with the power to the rounding of the two (``(1 + p)`` units of 2.2e-16
    relative, ``tests/test_step_speed.py``).

    Parameters
    ----------
    d0, power : float
        The law's reference distance (m) and exponent ``p``.
    sun : sequence of 3 floats
        The Sun's position in the system's coordinates (m); at the origin (``R = 0``)
        the kernel takes the power everywhere (``q_max = -1``).

    Returns
    -------
    tuple of 7 floats
        ``(d0, p, 1 / R, s(R), c1, c2, q_max)``.
    """
    R = math.hypot(*sun)
    c3 = abs(power * (power + 1.0) * (power + 2.0)) / 6.0
    q_max = min(1e-3, (TRUNCATION / c3) ** (1.0 / 3.0)) if c3 > 0.0 else 1e-3
    if not R > 0.0:  # the Sun at the origin: the power everywhere
        return (d0, power, 0.0, 0.0, 0.0, 0.0, -1.0)
    return (d0, power, 1.0 / R, (d0 / R) ** power, -power,
            0.5 * power * (power + 1.0), q_max)


@njit(cache=True, inline="always")
def _scale(scaling, rho):
    """``s(rho) = (d0 / rho)^p`` of the kernel's ``scaling`` (``expansion``): its series
    about the origin's distance where the point is close enough, else the power."""
    q = rho * scaling[2] - 1.0
    if abs(q) <= scaling[6]:
        return scaling[3] * (1.0 + q * (scaling[4] + q * scaling[5]))
    return (scaling[0] / rho) ** scaling[1]


@njit(cache=True, inline="always")
def _wind(sun, scaling, scaled, x, a, want, f, Fx, Fa, work):
    """The force and its derivatives of ``point``; ``scaled``: a constant of the inlined
    copy, False when the exponent is 0 (``s = 1``: ``scaling`` unread).  The force is
    computed in scalars (the radial direction and the tangent in registers: 15 % of the
    kernel's time on the E-sail rig against the scratch arrays it went through before,
    the same operations in the same order); the tangent's projections take them from ``work``."""
    power = scaling[1] if scaled else 0.0
    r0, r1, r2 = x[0] - sun[0], x[1] - sun[1], x[2] - sun[2]
    a0, a1, a2 = a[0], a[1], a[2]
    rho = math.sqrt(r0 * r0 + r1 * r1 + r2 * r2)
    p = math.sqrt(a0 * a0 + a1 * a1 + a2 * a2)
    r0, r1, r2 = r0 / rho, r1 / rho, r2 / rho
    u0, u1, u2 = a0 / p, a1 / p, a2 / p
    ti = r0 * u0 + r1 * u1 + r2 * u2
    s = _scale(scaling, rho) if scaled else 1.0
    f[0] = s * (r0 - ti * u0)
    f[1] = s * (r1 - ti * u1)
    f[2] = s * (r2 - ti * u2)
    if not want:
        return
    r = work[0, 0]
    u = work[0, 1]
    r[0], r[1], r[2] = r0, r1, r2
    u[0], u[1], u[2] = u0, u1, u2
    Pt = work[1]
    Pr = work[2]
    for i in range(3):
        for j in range(3):
            d = 1.0 if i == j else 0.0
            Pt[i, j] = d - u[i] * u[j]
            Pr[i, j] = d - (1.0 + power) * r[i] * r[j]
    for i in range(3):
        for j in range(3):
            sr = 0.0
            sa = 0.0
            for k in range(3):
                sr += Pt[i, k] * Pr[k, j]
                d = 1.0 if i == k else 0.0
                sa += (u[i] * r[k] + ti * d) * Pt[k, j]
            Fx[i, j] = s * sr / rho
            Fa[i, j] = -s * sa / p
