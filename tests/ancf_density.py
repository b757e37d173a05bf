"""Hand-derived energy and dissipation densities of the paper's ANCF cable (the oracle of
the generated ``laws.green``; see ``ancf_reference``) per unit reference length, as
functions of ``x = (a, b)`` with ``a = r_x`` and ``b = r_xx`` at a Gauss point (numpy,
vectorised over leading axes).

Derivatives are returned as 6-vectors and 6x6 matrices in the ``(a, b)`` ordering.  The
element force and tangent follow by one chain rule through the shape-function derivatives
(``ancf_reference``), which replaces the paper's explicit Eqs. 86-127.
"""

import numpy as np

from skfem_cable.laws import SLOPE_FLOOR


def _outer(u, v):
    return u[..., :, None] * v[..., None, :]


def axial(a, EA):
    """Axial density ``W = EA/2 eps^2``, Green strain ``eps = (a.a - 1)/2`` (Eqs. 23-24).

    Returns ``W, W_a, W_aa`` with ``W_a = EA eps a`` and ``W_aa = EA (a a^T + eps I)``
    (Eqs. 86-93).
    """
    eps = 0.5 * (np.einsum("...i,...i", a, a) - 1.0)
    return (0.5 * EA * eps**2, EA * eps[..., None] * a,
            EA * (_outer(a, a) + eps[..., None, None] * np.eye(3)))


def squared_curvature(a, b):
    """``kappa^2 = (|a|^2 |b|^2 - (a.b)^2) / |a|^6`` (Eq. 24 squared, Eq. 101) with its
    gradient (6,) and Hessian (6, 6) with respect to ``(a, b)``.

    ``kappa^2`` is rational in ``(a, b)`` with only ``|a|^2`` in the denominator, so it is
    smooth at zero curvature, where ``kappa`` itself (Eqs. 97-107) is not differentiable.
    """
    I3 = np.eye(3)
    p = np.maximum(np.einsum("...i,...i", a, a), SLOPE_FLOOR)
    c = np.einsum("...i,...i", a, b)
    bb = np.einsum("...i,...i", b, b)
    g = p * bb - c**2
    pe, pm = p[..., None], p[..., None, None]
    g_a = 2 * bb[..., None] * a - 2 * c[..., None] * b
    g_b = 2 * pe * b - 2 * c[..., None] * a
    g_aa = 2 * bb[..., None, None] * I3 - 2 * _outer(b, b)
    g_ab = 4 * _outer(a, b) - 2 * _outer(b, a) - 2 * c[..., None, None] * I3
    g_bb = 2 * pm * I3 - 2 * _outer(a, a)
    k2 = g / p**3
    grad = np.concatenate([g_a / pe**3 - 6 * g[..., None] * a / pe**4, g_b / pe**3], axis=-1)
    k_aa = (g_aa / pm**3 - 6 / pm**4 * (_outer(g_a, a) + _outer(a, g_a))
            - 6 * g[..., None, None] / pm**4 * I3 + 48 * g[..., None, None] / pm**5 * _outer(a, a))
    k_ab = g_ab / pm**3 - 6 / pm**4 * _outer(a, g_b)
    k_bb = g_bb / pm**3
    hess = np.concatenate([np.concatenate([k_aa, k_ab], axis=-1),
                           np.concatenate([np.swapaxes(k_ab, -1, -2), k_bb], axis=-1)], axis=-2)
    return k2, grad, hess


def axial_damping(a, adot, EA, gamma):
    """Axial Rayleigh dissipation (Eqs. 36, 108-112): ``D = gamma EA/2 eps_dot^2`` with
    ``eps_dot = a . a_dot``.

    Returns the dissipated power density ``2 D``, the force density ``D_adot``, and its
    derivatives ``D_adot,adot`` and ``D_adot,a`` (3x3 each).
    """
    edot = np.einsum("...i,...i", a, adot)
    c = gamma * EA
    return (c * edot**2, c * edot[..., None] * a, c * _outer(a, a),
            c * (_outer(a, adot) + edot[..., None, None] * np.eye(3)))


def bending_damping(x, xdot, k2, grad, hess, EI, gamma, delta):
    """Bending Rayleigh dissipation (Eqs. 36, 113-127): ``D = gamma EI/2 kappa_dot^2``.

    ``kappa_dot = k2_dot / (2 s)``, ``s = sqrt(kappa^2 + delta^2)``, ``k2_dot = grad . xdot``:
    exact for ``kappa >> delta`` and finite at zero curvature (the paper's Eq. 117 divides
    by ``Phi_1^(1/2) = 0`` there).  Returns the power density ``2 D``, ``D_xdot`` (6,),
    ``D_xdot,xdot`` and ``D_xdot,x`` (6x6).
    """
    s = np.sqrt(k2 + delta**2)[..., None]
    k2dot = np.einsum("...i,...i", grad, xdot)[..., None]
    kdot = k2dot / (2 * s)
    g = grad / (2 * s)
    dkdot_dx = np.einsum("...ij,...j->...i", hess, xdot) / (2 * s) - k2dot * grad / (4 * s**3)
    dg_dx = hess / (2 * s[..., None]) - _outer(grad, grad) / (4 * s[..., None] ** 3)
    c = gamma * EI
    return (c * kdot[..., 0] ** 2, c * kdot * g, c * _outer(g, g),
            c * (_outer(g, dkdot_dx) + kdot[..., None] * dg_dx))
