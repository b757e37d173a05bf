"""Energy densities of the ANCF cable per unit reference length, as functions of the slope
``a = r_x`` and the second derivative ``b = r_xx`` at a Gauss point (vectorised numpy).

Each function returns the density ``W`` and its derivatives ``W_a, W_b`` (shape ``(..., 3)``)
and ``W_aa, W_ab, W_bb`` (shape ``(..., 3, 3)``, ``W_ab[i, j] = d2W / da_i db_j``).  The
element force and tangent follow by the chain rule through the shape-function derivatives
(``kernels.reference``), which replaces the paper's explicit Eqs. 89-107 by one formula.
"""

import numpy as np

#: Lower bound on ``|r_x|^2`` in the curvature formula: a cable compressed to a point is
#: given a finite (huge) bending energy instead of a division by zero.
SLOPE_FLOOR = 1e-12


def _outer(u, v):
    return u[..., :, None] * v[..., None, :]


def axial(a, EA):
    """Axial density ``W = EA/2 eps^2`` with Green strain ``eps = (a.a - 1)/2`` (Eqs. 23-24).

    ``W_a = EA eps a`` and ``W_aa = EA (a a^T + eps I)`` reproduce Eqs. 86-93.
    """
    eps = 0.5 * (np.einsum("...i,...i", a, a) - 1.0)
    W = 0.5 * EA * eps**2
    W_a = EA * eps[..., None] * a
    W_aa = EA * (_outer(a, a) + eps[..., None, None] * np.eye(3))
    return W, W_a, W_aa


def bending(a, b, EI):
    """Bending density ``W = EI/2 kappa^2`` with the squared curvature
    ``kappa^2 = (|a|^2 |b|^2 - (a.b)^2) / |a|^6`` (Eqs. 24 and 97, squared).

    Unlike ``kappa`` itself (paper Eqs. 97-107), ``kappa^2`` is a smooth function of
    ``(a, b)``: a straight cable (``a x b = 0``) has finite force and tangent.
    """
    I3 = np.eye(3)
    p = np.maximum(np.einsum("...i,...i", a, a), SLOPE_FLOOR)
    c = np.einsum("...i,...i", a, b)
    bb = np.einsum("...i,...i", b, b)
    g = p * bb - c**2
    pe = p[..., None]
    pm = p[..., None, None]
    g_a = 2 * bb[..., None] * a - 2 * c[..., None] * b
    g_b = 2 * pe * b - 2 * c[..., None] * a
    g_aa = 2 * bb[..., None, None] * I3 - 2 * _outer(b, b)
    g_ab = 4 * _outer(a, b) - 2 * _outer(b, a) - 2 * c[..., None, None] * I3
    g_bb = 2 * pm * I3 - 2 * _outer(a, a)
    k2 = g / p**3
    k2_a = g_a / pe**3 - 6 * g[..., None] * a / pe**4
    k2_b = g_b / pe**3
    k2_aa = (g_aa / pm**3 - 6 / pm**4 * (_outer(g_a, a) + _outer(a, g_a))
             - 6 * g[..., None, None] / pm**4 * I3 + 48 * g[..., None, None] / pm**5 * _outer(a, a))
    k2_ab = g_ab / pm**3 - 6 / pm**4 * _outer(a, g_b)
    k2_bb = g_bb / pm**3
    h = 0.5 * EI
    return h * k2, h * k2_a, h * k2_b, h * k2_aa, h * k2_ab, h * k2_bb
