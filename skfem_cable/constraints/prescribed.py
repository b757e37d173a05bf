"""Constraints driven in time: the prescribed ``Motion`` and the time derivatives of a
prescribed function."""

import numpy as np

#: Step of the time differences of driven joints, relative to ``max(1, |t|)`` seconds.
TIME_STEP = 1e-3


def time_derivatives(fn, t, order):
    """First (``order=1``) or second derivative of ``fn`` at ``t`` by central differences
    with Richardson extrapolation (fourth order; step ``TIME_STEP * max(1, |t|)``): relative
    error about ``(w h)^4 / 30`` for a motion of angular frequency ``w``, 1e-7 at
    ``w = 100 rad/s``.  Give the derivatives explicitly for faster motions.

    Examples
    --------
    >>> import numpy as np
    >>> from skfem_cable.constraints.prescribed import time_derivatives
    >>> round(float(time_derivatives(np.sin, 0.0, 1)), 12)
    1.0
    >>> round(float(time_derivatives(np.cos, 0.0, 2)), 9)
    -1.0
    """
    h = TIME_STEP * max(1.0, abs(t))

    def central(step):
        if order == 1:
            return (np.asarray(fn(t + step)) - np.asarray(fn(t - step))) / (2 * step)
        return (np.asarray(fn(t + step)) - 2 * np.asarray(fn(t))
                + np.asarray(fn(t - step))) / step**2

    return (4 * central(0.5 * h) - central(h)) / 3


def _point(p, name, size=3):
    p = np.asarray(p, dtype=float)
    if p.shape != (size,) or not np.all(np.isfinite(p)):
        raise ValueError(f"{name} must be a finite vector of length {size}, got {p!r}")
    return p


class Motion:
    """A prescribed vector ``x(t)`` with its first two time derivatives.

    Parameters
    ----------
    fn : callable or array_like
        ``fn(t)`` (a constant vector is a motion at rest).
    velocity, acceleration : callable, optional
        Exact derivatives; else ``time_derivatives``.
    name : str
        Parameter name used in error messages.
    size : int
        Length of the vector.
    """

    def __init__(self, fn, velocity=None, acceleration=None, name="target", size=3):
        self.name, self.size = name, size
        if callable(fn):
            self.fn = fn
            self.driven = True
        else:
            value = _point(fn, name, size)
            self.fn = lambda t: value
            self.driven = False
        self.derivatives = (velocity, acceleration)
        for label, d in zip(("velocity", "acceleration"), self.derivatives):
            if d is not None and not callable(d):
                raise TypeError(f"{label} must be a callable of time, got {d!r}")
        self(0.0)

    def __call__(self, t, order=0):
        if order and not self.driven:
            return np.zeros(self.size)
        exact = self.derivatives[order - 1] if order else self.fn
        if exact is not None:
            label = f"{self.name} derivative {order}" if order else self.name
            return _point(exact(t), f"{label} at t={t!r}", self.size)
        return time_derivatives(
            lambda s: _point(self.fn(s), f"{self.name} at t={s!r}", self.size), t, order)
