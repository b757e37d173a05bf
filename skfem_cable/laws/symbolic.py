"""The vocabulary of element laws: what a law's density is written with.

A law receives ``a = r_x`` and ``b = r_xx`` (and, for a dissipation density, their rates
``ad``, ``bd``) as symbolic 3-vectors (``sympy.Matrix``) and its parameters as symbols; it
returns one scalar expression built from these helpers, ordinary arithmetic and the
functions re-exported here (``sqrt``, ``exp``, ``log``, ``tanh``, ``atan``, ``Abs``).  The framework
derives the gradient and Hessian from the expression exactly (``laws.law``) and prints
them as compiled code (``laws.codegen``).
"""

import sympy as sp

#: Lower bound on ``|r_x|^2`` in the curvature (``kappa2``): a cable compressed to a point is
#: given a finite (huge) bending energy instead of a division by zero.
SLOPE_FLOOR = 1e-12

#: Regularisation of the curvature rate, relative to ``1/h`` (h the element length):
#: ``kappa_dot = d(kappa^2)/dt / (2 sqrt(kappa^2 + delta^2))``, ``delta = 1e-6 / h``.
CURVATURE_RATE_DELTA = 1e-6

sqrt, exp, log, tanh, atan, Abs = sp.sqrt, sp.exp, sp.log, sp.tanh, sp.atan, sp.Abs


class floored(sp.Function):
    """``max(p, SLOPE_FLOOR)`` with the derivative of ``p``: the floor changes values only in
    a cable squeezed to a point, where it keeps them finite; the tangent stays that of the
    smooth law (printed as ``max`` by ``laws.codegen``)."""

    nargs = 1

    def fdiff(self, argindex=1):
        return sp.Integer(1)


class power(sp.Function):
    """``base**exponent`` with an exponent that depends on parameters only: differentiated as
    ``exponent base**(exponent - 1)``, where sympy's general rule ``base**exponent *
    exponent / base`` divides by zero at ``base = 0`` (e.g. ``|e_dot|^(n+1)`` at rest).
    ``CableLaw`` puts it in place of such powers before differentiating."""

    nargs = 2

    def fdiff(self, argindex=1):
        if argindex != 1:
            raise sp.ArgumentIndexError(self, argindex)
        base, exponent = self.args
        return exponent * power(base, exponent - 1)


def dot(u, v):
    """Scalar product of two 3-vectors."""
    return sum(u[i] * v[i] for i in range(3))


def cross(u, v):
    """Vector product of two 3-vectors."""
    return sp.Matrix([u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
                      u[0] * v[1] - u[1] * v[0]])


def norm(u):
    """Euclidean norm ``|u|``."""
    return sp.sqrt(dot(u, u))


def green_strain(a):
    """Green axial strain ``(|a|^2 - 1) / 2`` (Eq. 24)."""
    return (dot(a, a) - 1) / 2


def kappa2(a, b):
    """Squared curvature ``|a x b|^2 / |a|^6`` (Eq. 24 squared, Eq. 101).

    Rational in ``(a, b)`` with only ``|a|^2`` (floored at ``SLOPE_FLOOR``) in the
    denominator, so smooth at zero curvature, where ``kappa`` itself is not."""
    p = floored(dot(a, a))
    return (dot(a, a) * dot(b, b) - dot(a, b) ** 2) / p**3


def rate(expr, a, b, ad, bd):
    """Time derivative of ``expr(a, b)`` along the rates ``ad``, ``bd``:
    ``expr_a . ad + expr_b . bd``."""
    return sum(sp.diff(expr, a[i]) * ad[i] + sp.diff(expr, b[i]) * bd[i] for i in range(3))


def curvature_rate(a, b, ad, bd, h):
    """Rate of the curvature ``kappa_dot = d(kappa^2)/dt / (2 sqrt(kappa^2 + delta^2))`` with
    ``delta = CURVATURE_RATE_DELTA / h``: exact for ``kappa >> delta`` and finite at zero
    curvature, where the paper's Eq. 117 divides by zero."""
    k2 = kappa2(a, b)
    return rate(k2, a, b, ad, bd) / (2 * sp.sqrt(k2 + (CURVATURE_RATE_DELTA / h) ** 2))


def ramp(x):
    """``max(x, 0)``: the positive part, e.g. of the strain of a tension-only tether.  At
    the kink ``x = 0`` the derivatives are those of the positive side, so that an unstrained
    tether has its tensile stiffness (and a Newton solve from rest a regular tangent)."""
    return sp.Piecewise((x, x >= 0), (0, True))


def where(condition, x, y):
    """``x`` where ``condition`` holds, else ``y`` (a piecewise law)."""
    return sp.Piecewise((x, condition), (y, True))
