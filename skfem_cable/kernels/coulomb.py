"""The solar-wind Coulomb force at a point of a line (paper Eqs. 29-35): the point function
of a pointwise load (``kernels.line``), whose generated module is the force's kernel.

At every point ``f = c s(rho) u_perp`` with ``u_perp = (I - t t^T) i_R`` (Eqs. 29-30),
``t = r_x / |r_x|`` the tether tangent, ``i_R = (r - r_sun) / rho`` the radial direction
from the Sun (Eq. 32) at the heliocentric distance ``rho = |r - r_sun|``, and
``s(rho) = (d0 / rho)^p`` the scaling of the thrust with solar distance (``d0`` the distance
of the wind's data, 1 AU; ``p = 7/6`` after Janhunen et al. 2010, see ``coulomb``).  The
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


@njit(cache=True, inline="always")
def point(params, e, t, x, a, xd, want, f, Fx, Fa, Fv, work):
    """``f = s(rho) u_perp`` at the point ``x`` of slope ``a`` and, if ``want``, its
    derivatives ``Fx``, ``Fa`` (``Fv`` stays zero), with ``params = (sun, scaling)``: the
    Sun's position (3,) and ``scaling = (d0, p)`` (2,) (``kernels.line`` for the
    signature; ``work[0, 0]``, ``work[0, 1]`` hold ``i_R`` and ``t``, ``work[1]``,
    ``work[2]`` the projections).  Inlined into the generated loop, as before the loop
    was generic (its CPU time per evaluation is the hand-written loop's)."""
    sun, scaling = params
    _wind(sun, scaling[0], scaling[1], True, x, a, want, f, Fx, Fa, work)


@njit(cache=True, inline="always")
def point_uniform(params, e, t, x, a, xd, want, f, Fx, Fa, Fv, work):
    """``point`` of a wind that does not scale with the distance (``p = 0``: ``s = 1``,
    the paper's force law), without the power and its derivative at every point: the
    same numbers, bit for bit."""
    sun, scaling = params
    _wind(sun, 1.0, 0.0, False, x, a, want, f, Fx, Fa, work)


@njit(cache=True, inline="always")
def _wind(sun, d0, power, scaled, x, a, want, f, Fx, Fa, work):
    """The force and its derivatives of ``point``; ``scaled``: a constant of the inlined
    copy, False when ``power`` is 0 (``s = 1``).  The force is computed in scalars (the
    radial direction and the tangent in registers: 15 % of the kernel's time on the E-sail
    rig against the scratch arrays it went through before, the same operations in the
    same order); the tangent's projections take them from ``work``."""
    r0, r1, r2 = x[0] - sun[0], x[1] - sun[1], x[2] - sun[2]
    a0, a1, a2 = a[0], a[1], a[2]
    rho = math.sqrt(r0 * r0 + r1 * r1 + r2 * r2)
    p = math.sqrt(a0 * a0 + a1 * a1 + a2 * a2)
    r0, r1, r2 = r0 / rho, r1 / rho, r2 / rho
    u0, u1, u2 = a0 / p, a1 / p, a2 / p
    ti = r0 * u0 + r1 * u1 + r2 * u2
    s = (d0 / rho) ** power if scaled else 1.0
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
