"""Kepler's equation and the two-body state on a conic."""

import math

import numpy as np
from numba import njit, vectorize

KEPLER_ITERATIONS = 50
EPS = float(np.finfo(float).eps)


def _finite(name, value):
    value = float(value)
    if not np.isfinite(value):
        raise ValueError(f"Orbit: {name} must be finite, got {value}")
    return value


def _rotation(raan, inclination, argp):
    """Columns: periapsis direction P, its in-plane normal Q and the orbit normal W, in
    the inertial axes (the 3-1-3 rotation ``Rz(raan) Rx(inclination) Rz(argp)``)."""
    co, so = np.cos(raan), np.sin(raan)
    ci, si = np.cos(inclination), np.sin(inclination)
    cw, sw = np.cos(argp), np.sin(argp)
    return np.array([
        [co * cw - so * sw * ci, -co * sw - so * cw * ci, so * si],
        [so * cw + co * sw * ci, -so * sw + co * cw * ci, -co * si],
        [sw * si, cw * si, ci],
    ])


@njit(cache=True)
def solve_kepler(mean_anomaly, e):
    """Solve Kepler's equation ``E - e sin E = M`` to round-off (``0 <= e < 1``) for one
    mean anomaly (compiled: a call from Python costs under a microsecond).

    Newton's iteration on ``M`` reduced to ``[-pi, pi]``, started from Danby's
    ``E = M + 0.85 e sign(sin M)`` (convergent for every ``e < 1``).
    """
    m = mean_anomaly - 2.0 * math.pi * round(mean_anomaly / (2.0 * math.pi))
    ecc = m + 0.85 * e * math.copysign(1.0, math.sin(m)) if m != 0.0 else 0.0
    for _ in range(KEPLER_ITERATIONS):
        step = (ecc - e * math.sin(ecc) - m) / (1.0 - e * math.cos(ecc))
        ecc -= step
        if abs(step) <= 4.0 * EPS * max(1.0, abs(ecc)):
            break
    return ecc + (mean_anomaly - m)


@njit(cache=True)
def kepler_state(mu, a, e, mean_anomaly0, mean_motion, t0, axes, t, out):
    """Position and velocity at time ``t`` of the orbit of these elements (``axes``: the
    perifocal axes P, Q, W as columns) into ``out`` (6,), in scalar arithmetic."""
    ecc = solve_kepler(mean_anomaly0 + mean_motion * (t - t0), e)
    c, s = math.cos(ecc), math.sin(ecc)
    root = math.sqrt(1.0 - e * e)
    speed = math.sqrt(mu * a) / (a * (1.0 - e * c))
    x, y = a * (c - e), a * root * s
    u, w = -speed * s, speed * root * c
    for i in range(3):
        out[i] = x * axes[i, 0] + y * axes[i, 1]
        out[3 + i] = u * axes[i, 0] + w * axes[i, 1]


@vectorize(cache=True)  # compiled on first call, not at import (0.3 s)
def eccentric_anomaly(mean_anomaly, e):
    """``solve_kepler`` as a numba ufunc, for arrays of mean anomalies."""
    return solve_kepler(mean_anomaly, e)
