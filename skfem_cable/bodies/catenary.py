"""The elastic catenary: the shape of a cable hanging between two points
(``Cable.catenary``; ``analytic`` uses it as a reference)."""

import numpy as np


def green_stretch(T, EA):
    """Stretch ``lambda - 1`` of the Green-strain law at the true axial force ``T`` (N):
    the energy ``EA eps^2 / 2`` per reference length, ``eps = (lambda^2 - 1) / 2``, carries
    ``T = dW/dlambda = EA lambda (lambda^2 - 1) / 2`` (``Cable.tension`` of the built-in
    laws), i.e. ``e (1 + e) (2 + e) = 2 T / EA`` for ``e = lambda - 1``, solved by Newton's
    method in ``e`` (no cancellation in ``lambda - 1``).

    Examples
    --------
    >>> from skfem_cable.bodies.catenary import green_stretch
    >>> e = green_stretch(1e3, 1e6)
    >>> round(float(1e6 * (1 + e) * ((1 + e) ** 2 - 1) / 2), 9)
    1000.0
    """
    tau = np.asarray(T, dtype=float) / EA
    if np.any(tau < 0) or not np.all(np.isfinite(tau)):
        raise ValueError("T must be finite and >= 0 (a tension)")
    e = tau / (1.0 + 1.5 * tau)
    for _ in range(60):
        de = (e * (1 + e) * (2 + e) - 2 * tau) / (3 * e * e + 6 * e + 2)
        e = e - de
        if np.all(np.abs(de) <= 1e-16 * np.maximum(np.abs(e), 1e-300)):
            break
    return e


#: 64-point Gauss-Legendre rule on [-1, 1] of ``catenary_xz``.
_GX, _GW = np.polynomial.legendre.leggauss(64)


def stretch_minus_one(T, EA, law="green"):
    """Stretch ``e = lambda - 1`` at true tension ``T``: the element's Green-strain law
    (``green_stretch``), ``"hooke"`` (``T = EA e``, the classical law of Irvine's catenary,
    for comparison), or zero for an inextensible cable (``EA`` None)."""
    T = np.asarray(T, dtype=float)
    if EA is None:
        return np.zeros_like(T)
    return T / EA if law == "hooke" else green_stretch(T, EA)


def catenary_xz(s, H, VA, w, EA=None, law="green"):
    """Exact position of the extensible catenary hanging from the origin, given its support
    forces (``solve_catenary`` finds them from the supports; ``elastic_catenary`` does both
    for a slack cable of the Green law).

    With the horizontal force ``H`` and the upward support force ``VA`` at ``s = 0``, the
    force in the cable is ``(H, w s - VA)`` and its tangent is parallel to it, so with the
    stretch ``lambda(T)`` (``stretch_minus_one``)

        x(s) = int_0^s lambda H / T ds,   z(s) = int_0^s lambda (w s - VA) / T ds.

    The inextensible part (``lambda = 1``) is Irvine's closed form in ``asinh``; the
    elastic part ``(lambda - 1)`` is integrated by 64-point Gauss-Legendre quadrature (the
    integrand is analytic: quadrature error at round-off level).

    Parameters
    ----------
    s : array_like
        Unstretched arc length(s) from the left support.
    H, VA : float
        Horizontal force and upward support force at the left support (N).
    w : float
        Weight per unstretched length (N/m).
    EA : float or None
        Axial stiffness; ``None`` for the inextensible catenary.
    law : {"green", "hooke"}
        Material law (``stretch_minus_one``).

    Returns
    -------
    ndarray, shape (len(s), 2)
        ``(x, z)``.
    """
    s = np.atleast_1d(np.asarray(s, dtype=float))
    x = H / w * (np.arcsinh((w * s - VA) / H) + np.arcsinh(VA / H))
    z = (np.hypot(H, w * s - VA) - np.hypot(H, VA)) / w
    sg = 0.5 * s[:, None] * (_GX + 1.0)
    wg = 0.5 * s[:, None] * _GW
    V = w * sg - VA
    T = np.hypot(H, V)
    e = stretch_minus_one(T, EA, law)
    return np.column_stack([x + np.sum(wg * e * H / T, axis=1),
                            z + np.sum(wg * e * V / T, axis=1)])


def solve_catenary(span, height, L0, w, EA=None, law="green"):
    """Support forces of a catenary of unstretched length ``L0`` between ``(0, 0)`` and
    ``(span, height)``: the two closure equations ``x(L0) = span, z(L0) = height`` of
    ``catenary_xz`` solved with ``scipy.optimize.fsolve``.  Unlike ``elastic_catenary``,
    ``L0`` may be shorter than the chord (a cable that hangs only by stretching), and the
    law and ``EA = None`` (inextensible) are choices.

    Returns
    -------
    H : float
        Horizontal force (N), the same at both supports.
    VA, VB : float
        Upward support forces at the left and the right support (N), ``VA + VB = w L0``.

    Examples
    --------
    A 12 m cable hung between points 10 m apart at the same height: each support carries
    half its weight.

    >>> from skfem_cable.bodies.catenary import solve_catenary
    >>> H, VA, VB = solve_catenary(10.0, 0.0, 12.0, 1.0, 1e6)
    >>> round(float(VA), 9), round(float(VB), 9)
    (6.0, 6.0)
    """
    from scipy.optimize import fsolve

    W = w * L0
    chord = np.hypot(span, height)
    sag = np.sqrt(3 * span * max(L0 - chord, 1e-4 * span) / 8)

    def closure(u):
        return (catenary_xz(L0, u[0] * W, u[1] * W, w, EA, law)[0] - [span, height]) / span

    u, _, _, msg = fsolve(closure, [span / (8 * sag), 0.5], xtol=1e-14, full_output=True)
    # fsolve may stop with "xtol too small" at round-off: judge by the closure residual
    residual = np.max(np.abs(closure(u)))
    if not residual < 1e-13:
        raise RuntimeError(f"catenary closure did not converge: residual {residual:.1e} "
                           f"({msg})")
    return u[0] * W, u[1] * W, W - u[1] * W
