"""The point function of quadratic fluid drag on line bodies (``drag``: Morison and
free-molecular), for the one loop of the line loads (``kernels.line.module``).

At every point of a line body (``lines.LinePoints``), with ``r = S q`` the position,
``a = r_x = S_x q`` the slope, ``p = |a|``, ``t = a / p`` the tangent,
``u = c(r, t) - r_dot`` the velocity of the flow relative to the line, ``s = t . u`` and
``u_n = u - s t`` (``m = |u_n|``), the force per unit length is

    h = k_n m u_n + k_t |s| s t + k_x m s t,

times ``lam = p`` (per unit deformed length) or ``lam = 1`` (per unit reference length).
Morison drag has ``k_n = rho d C_dn / 2``, ``k_t = rho pi d C_dt / 2``, ``k_x = 0``;
free-molecular drag ``k_n = k_x = rho d C_D / 2``, ``k_t = 0`` (``m u`` with
``m = |u x t|``).  The flow is ``c(r, t) = c_0 + W r + sigma U(e . r)``: a uniform part,
a linear part (a co-rotating atmosphere: ``W = [omega]_x``) and a piecewise-linear
profile ``U`` in the elevation ``z = e . r`` (held constant outside its table) scaled by
``sigma``; ``c_0`` and ``sigma`` depend on time only (refreshed by ``Term.prepare``).

Exact derivatives (``G(w) = |w| I + w w^T / |w|``, ``P = I - t t^T``, ``u^T P = u_n^T``):

    dh/du   = k_n (m P + u_n u_n^T / m) + 2 k_t |s| t t^T + k_x (s t u_n^T / m + m t t^T)
    p dh/da = -k_n (m t u_n^T + m s P + s u_n u_n^T / m) + k_t |s| (2 t u_n^T + s P)
              + k_x (m t u_n^T + m s P - s^2 t u_n^T / m)

(terms divided by ``m`` are dropped at ``m = 0``, their limit or a subgradient), and
``df/du = lam dh/du``, ``df/da = lam dh/da + [deformed] h t^T``,
``df/dr = df/du (W + sigma U'(z) e^T)``, ``df/dr_dot = -df/du``; the loop of
``kernels.line`` integrates them into the generalized force and its tangent.
"""

import math

import numpy as np
from numba import njit

from .line import point_function


@njit(cache=True, inline="always")
def flow(x, uniform, W, vertical, heights, velocities, sigma, c, dc, slope):
    """The flow velocity ``c`` (3,) at ``x`` and its gradient ``dc = dc/dx`` (3, 3);
    ``slope`` (3,) is scratch."""
    z = vertical[0] * x[0] + vertical[1] * x[1] + vertical[2] * x[2]
    nz = heights.size
    for i in range(3):
        slope[i] = 0.0
        c[i] = uniform[i] + W[i, 0] * x[0] + W[i, 1] * x[1] + W[i, 2] * x[2]
    if nz > 0:
        if z <= heights[0]:
            for i in range(3):
                c[i] += sigma * velocities[0, i]
        elif z >= heights[nz - 1]:
            for i in range(3):
                c[i] += sigma * velocities[nz - 1, i]
        else:
            k = np.searchsorted(heights, z) - 1
            dz = heights[k + 1] - heights[k]
            xi = (z - heights[k]) / dz
            for i in range(3):
                c[i] += sigma * ((1.0 - xi) * velocities[k, i] + xi * velocities[k + 1, i])
                slope[i] = sigma * (velocities[k + 1, i] - velocities[k, i]) / dz
    for i in range(3):
        for j in range(3):
            dc[i, j] = W[i, j] + slope[i] * vertical[j]


@njit(cache=True, inline="always")
def point_force(a, u, coef, want, h, Hu, Ha, t, un):
    """Force ``lam h`` per unit length (into ``h``) and, if ``want``, its derivatives
    ``df/du`` (``Hu``) and ``df/da`` (``Ha``) at one point;
    ``coef = [k_n, k_t, k_x, deformed]``; ``t``, ``un`` (3,) are scratch (they receive the
    tangent and the normal relative flow)."""
    kn, kt, kx, deformed = coef[0], coef[1], coef[2], coef[3]
    p = math.sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2])
    for i in range(3):
        t[i] = a[i] / p
    s = t[0] * u[0] + t[1] * u[1] + t[2] * u[2]
    for i in range(3):
        un[i] = u[i] - s * t[i]
    m = math.sqrt(un[0] * un[0] + un[1] * un[1] + un[2] * un[2])
    inv_m = 1.0 / m if m > 0.0 else 0.0
    lam = p if deformed != 0.0 else 1.0
    for i in range(3):
        h[i] = kn * m * un[i] + (kt * abs(s) + kx * m) * s * t[i]
    for i in range(3 if want else 0):
        for j in range(3):
            d = 1.0 if i == j else 0.0
            P = d - t[i] * t[j]
            tt = t[i] * t[j]
            nn = un[i] * un[j] * inv_m
            tn = t[i] * un[j]
            du = (kn * (m * P + nn) + 2.0 * kt * abs(s) * tt
                  + kx * (s * tn * inv_m + m * tt))
            da = (-kn * (m * tn + m * s * P + s * nn) + kt * abs(s) * (2.0 * tn + s * P)
                  + kx * (m * tn + m * s * P - s * s * tn * inv_m)) / p
            Hu[i, j] = lam * du
            Ha[i, j] = lam * da + (h[i] * t[j] if deformed != 0.0 else 0.0)
    for i in range(3):
        h[i] *= lam


@point_function
def point(params, e, t, x, a, xd, want, f, Fx, Fa, Fv, work):
    """The drag's point function for the loop of ``kernels.line.module``: the force ``f``
    per unit length at the position ``x``, slope ``a`` and velocity ``xd``, with
    ``Fa = df/da``, ``Fv = df/dxd = -df/du`` and ``Fx = df/du dc/dx`` (the flow's
    gradient); ``params = (coef, uniform, W, vertical, heights, velocities, sigma)``
    (``sigma`` of shape (1,)); the derivatives only if ``want``."""
    coef, uniform, W, vertical, heights, velocities, sigma = params
    c, u, dc, Hu = work[0, 0], work[0, 1], work[1], work[2]
    flow(x, uniform, W, vertical, heights, velocities, sigma[0], c, dc, work[0, 2])
    for i in range(3):
        u[i] = c[i] - xd[i]
    point_force(a, u, coef, want, f, Hu, Fa, work[3, 0], work[3, 1])
    if not want:
        return
    for i in range(3):
        for j in range(3):
            Fx[i, j] = Hu[i, 0] * dc[0, j] + Hu[i, 1] * dc[1, j] + Hu[i, 2] * dc[2, j]
            Fv[i, j] = -Hu[i, j]


@njit(cache=True)
def body_drag(pack, index, ev):
    """The quadratic drag ``f = k rho |u| u`` (``u = c(x, t) - xd``, the flow relative to
    the point; ``c`` of ``flow``) at a point of position ``x = G q[dofs]``: the
    generalized force ``G^T f`` and, with a tangent, minus ``G^T (cK df/dx + cC df/dxd)
    G`` at ``index`` (nd, nd), with ``df/du = k rho (|u| I + u u^T / |u|)``,
    ``df/dx = df/du dc/dx`` and ``df/dxd = -df/du`` (exact for a density ``rho`` frozen
    over the step).  ``pack = (dofs (nd,), G (3, nd), coef (1,) = [k], rho (1,),
    uniform, W, vertical, heights, velocities, sigma)``: the flow's arrays
    (``loads.drag.Flow.arrays``)."""
    dofs, G, coef, rho, uniform, W, vertical, heights, velocities, sigma = pack
    q, v, s, f, f_ext, fd, data, energy, power = ev
    nd = dofs.size
    work = np.zeros((5, 3))
    x, xd, c, u, slope = work[0], work[1], work[2], work[3], work[4]
    mats = np.empty((3, 3, 3))
    dc, H, K = mats[0], mats[1], mats[2]
    for i in range(3):
        for a in range(nd):
            x[i] += G[i, a] * q[dofs[a]]
            xd[i] += G[i, a] * v[dofs[a]]
    flow(x, uniform, W, vertical, heights, velocities, sigma[0], c, dc, slope)
    for i in range(3):
        u[i] = c[i] - xd[i]
    m = math.sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2])
    k = coef[0] * rho[0]
    for a in range(nd):
        f_ext[dofs[a]] += k * m * (G[0, a] * u[0] + G[1, a] * u[1] + G[2, a] * u[2])
    if data.size == 0:
        return
    inv_m = 1.0 / m if m > 0.0 else 0.0
    for i in range(3):
        for j in range(3):
            H[i, j] = k * ((m if i == j else 0.0) + u[i] * u[j] * inv_m)
    cK, cC = s[1], s[2] if s[3] != 0.0 else 0.0
    for i in range(3):
        for j in range(3):
            K[i, j] = cK * (H[i, 0] * dc[0, j] + H[i, 1] * dc[1, j]
                            + H[i, 2] * dc[2, j]) - cC * H[i, j]
    for a in range(nd):
        for b in range(nd):
            acc = 0.0
            for i in range(3):
                for j in range(3):
                    acc += G[i, a] * K[i, j] * G[j, b]
            data[index[a, b]] -= acc
