"""Post-processing of time histories: crossing times, periods and decay rates."""

import numpy as np


def zero_crossings(t, x, v):
    """Times where ``x(t)`` crosses zero, located on the cubic Hermite interpolant of the
    samples ``x`` and their derivatives ``v`` (fourth-order accurate in the sampling step).

    Parameters
    ----------
    t, x, v : ndarray (nt,)
        Sample times, values and time derivatives.

    Returns
    -------
    ndarray
        Crossing times in increasing order.
    """
    t, x, v = (np.asarray(a, dtype=float) for a in (t, x, v))
    out = []
    for i in np.flatnonzero(x[:-1] * x[1:] < 0):
        h = t[i + 1] - t[i]
        c = np.array([x[i], h * v[i], x[i + 1], h * v[i + 1]])
        s = x[i] / (x[i] - x[i + 1])
        for _ in range(50):
            H = np.array([2 * s**3 - 3 * s**2 + 1, s**3 - 2 * s**2 + s, 3 * s**2 - 2 * s**3,
                          s**3 - s**2])
            dH = np.array([6 * s**2 - 6 * s, 3 * s**2 - 4 * s + 1, 6 * s - 6 * s**2,
                           3 * s**2 - 2 * s])
            step = (H @ c) / (dH @ c)
            s = min(max(s - step, 0.0), 1.0)
            if abs(step) < 1e-15:
                break
        out.append(t[i] + s * h)
    return np.array(out)


def period(t, x, v):
    """Mean period from every other zero crossing of an oscillating signal."""
    c = zero_crossings(t, x, v)
    if len(c) < 3:
        raise ValueError("the signal must cross zero at least three times")
    return float(np.mean(c[2:] - c[:-2]))


def decay_rate(t, x):
    """Exponential decay rate ``sigma`` of ``x ~ exp(-sigma t) cos(...)``, fitted to the
    logarithm of the positive peaks."""
    t, x = np.asarray(t, float), np.asarray(x, float)
    i = np.flatnonzero((x[1:-1] > x[:-2]) & (x[1:-1] >= x[2:]) & (x[1:-1] > 0)) + 1
    if len(i) < 2:
        raise ValueError("need at least two positive peaks")
    return float(-np.polyfit(t[i], np.log(x[i]), 1)[0])
