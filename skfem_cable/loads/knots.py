"""Slowly varying environment models sampled at time knots along a reference point and
interpolated in time (``ElectrodynamicForce(..., sample_every=h)``).

The geomagnetic field and the ionosphere seen by a tether in orbit change on the scale of
the orbit (minutes), while a step lasts tens of seconds and a model call costs tens of
milliseconds (``environment.IGRF`` about 21 ms, ``environment.IRI`` about 67 ms).
``OrbitKnots`` evaluates each model once per **knot** ``t_k = t_0 + k h`` at one point
``P_k`` (the reference point ``R(t_k)`` plus the tether's mean offset when the knot is
made), with its gradient there, and gives at any ``t`` the values carried to the
tether's points ``X``:

    f(X, t) ~ f(t) + grad f(t) . (X - P(t)),

where ``f(t)``, ``grad f(t)`` and ``P(t)`` are the cubic Lagrange interpolants through the
four knots around ``t`` (error ``(3 / 128) h^4 |f''''|`` at mid-interval), and the
linearisation's error is of the order of ``(|X - P| / l)^2`` for the model's length scale
``l`` (the field's ``r / 3 ~ 2300 km``; the plasma's scale height, 50 to 100 km in the
topside ionosphere, against a tether's few km).  A density is sampled and interpolated
as its logarithm (always positive, and linear in height where the profile is
exponential, as the topside's): ``n = exp(log n(t) + grad log n(t) . (X - P(t)))``, the
gradient the central difference with the step ``DENSITY_STEP`` at the knot (the seven
positions in one call).
Each knot is evaluated once, in blocks of ``BLOCK`` knots ahead (one call of each model
per block when the model evaluates several times at once, ``IGRF.field_series``,
``IRI.density_series``), whatever the step.
"""

import numpy as np

DENSITY_STEP = 1000.0
"""Step (m) of the central-difference gradient of a density at a knot."""
BLOCK = 32
"""Knots evaluated together, in one call of a model that has ``field_series`` or
``density_series`` (``environment.IGRF``, ``environment.IRI``): the coefficient files
that the libraries read at every call are read once per block."""
FLOOR = 1.0
"""The smallest density (m^-3) whose logarithm is interpolated."""
STENCIL = np.vstack([np.zeros(3), np.eye(3), -np.eye(3)])


def spacing_or_none(value):
    """``sample_every`` checked: None (models at every step) or a knot spacing (s),
    finite and > 0 (``ValueError`` naming ``sample_every``)."""
    if value is None:
        return None
    try:
        h = float(value)
    except (TypeError, ValueError):
        h = np.nan
    if isinstance(value, bool) or not (np.isfinite(h) and h > 0):
        raise ValueError(f"sample_every must be a time step (s, > 0) or None, got "
                         f"{value!r}")
    return h


def lagrange_weights(u):
    """The weights of the cubic Lagrange interpolant through uniform knots ``-1, 0, 1,
    2`` at ``u`` (in [0, 1] between knots 0 and 1): (4,)."""
    return np.array([-u * (u - 1) * (u - 2) / 6, (u + 1) * (u - 1) * (u - 2) / 2,
                     -(u + 1) * u * (u - 2) / 2, (u + 1) * u * (u - 1) / 6])


def in_series(model, name, x, times):
    """``model.<name>(x_k, t_k)`` for the positions ``x`` (k, n, 3) at the times ``times``
    (k,): the model's ``<name>_series`` in one call when it has one, else one call per
    time, stacked."""
    series = getattr(model, f"{name}_series", None)
    if callable(series):
        return series(x, times)
    parts = [getattr(model, name)(xk, t) for xk, t in zip(x, times)]
    return tuple(np.stack(p) for p in zip(*parts)) if isinstance(parts[0], tuple) \
        else np.stack(parts)


class OrbitKnots:
    """A field and a density sampled at knots every ``spacing`` seconds along a reference
    point, interpolated in time and carried to a tether's points by their gradients.

    Parameters
    ----------
    spacing : float
        The knots' spacing ``h`` (s, > 0).
    origin : float
        The time of knot 0 (s).
    centre : callable
        ``centre(t)``: the knot's point ``P`` (3,) (m, absolute) when the knot at ``t``
        is made.
    field : object with ``field(x, t) -> (B, dB)`` or None
        The field (``environment.IGRF``); None: no field is sampled.
    plasma : object with ``density(x, t)``
        The density model (m^-3, or kg/m^3 for a neutral atmosphere).
    floor : float
        The smallest density whose logarithm is interpolated (default ``FLOOR``, in
        m^-3; an atmosphere's mass density needs one below its kg/m^3).

    Attributes
    ----------
    calls : int
        Knots evaluated so far (each model is called once per ``BLOCK`` of them).
    """

    def __init__(self, spacing, origin, centre, field, plasma, floor=FLOOR):
        self.spacing, self.origin = spacing_or_none(spacing), float(origin)
        self.floor = float(floor)
        self.centre, self.field, self.plasma = centre, field, plasma
        self.knots, self.calls = {}, 0

    def _evaluate(self, first):
        """The knots ``first .. first + BLOCK - 1``: ``(P, B, dB, log n, grad log n)`` each
        (zeros for the field when there is none), the gradient by central differences
        with ``DENSITY_STEP``."""
        ks = np.arange(first, first + BLOCK)
        times = self.origin + ks * self.spacing
        P = np.array([self.centre(t) for t in times], dtype=float)
        if self.field is None:
            B, dB = np.zeros((BLOCK, 3)), np.zeros((BLOCK, 3, 3))
        else:
            B, dB = (y[:, 0] for y in in_series(self.field, "field", P[:, None], times))
        n = in_series(self.plasma, "density", P[:, None] + DENSITY_STEP * STENCIL, times)
        n = np.log(np.maximum(n, self.floor))
        dn = (n[:, 1:4] - n[:, 4:7]) / (2.0 * DENSITY_STEP)
        self.knots = {k: v for k, v in self.knots.items() if k >= first - BLOCK}
        self.knots.update((k, (P[i], B[i], dB[i], n[i, 0], dn[i]))
                          for i, k in enumerate(ks))
        self.calls += BLOCK

    def _knot(self, k):
        if k not in self.knots:
            self._evaluate(k)
        return self.knots[k]

    def at(self, X, t):
        """``(B, dB, n)`` at the points ``X`` (..., 3) at ``t``: the interpolated knot
        values carried by their gradients (module docstring); shapes (..., 3), (..., 3,
        3) and (...)."""
        u = (t - self.origin) / self.spacing
        k = int(np.floor(u))
        w = lagrange_weights(u - k)
        P, B, dB, n, dn = (sum(wi * part for wi, part in zip(w, parts)) for parts in
                           zip(*(self._knot(k + j) for j in (-1, 0, 1, 2))))
        dX = X - P
        return (B + dX @ dB.T, np.broadcast_to(dB, X.shape + (3,)), np.exp(n + dX @ dn))
