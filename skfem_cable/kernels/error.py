"""Numba kernel of the local error control's ratio (``GeneralizedAlpha`` with ``rtol``
and ``atol``): one pass over the coordinates, where the array expressions it replaces
took about a twentieth of the full-size E-sail's step."""

import numpy as np
from numba import njit


@njit(cache=True)
def error_ratio(q0, q1, abar1, abar, factor, vectors, scalars, atol, rtol):
    """The largest ratio of the estimated local error of a step from ``q0`` to ``q1`` to
    its tolerance: the error ``e = factor (abar1 - abar)`` (``GeneralizedAlpha.local_error``,
    ``factor = (beta - 1/6 + (alpha_m - alpha_f)/2) h^2``) against ``atol + rtol
    max(|q0|, |q1|)`` per coordinate, ``|.|`` the length of the 3-vector for the
    coordinates of ``vectors`` (int (nb, 3): positions, slopes) and the coordinate's own
    size for those of ``scalars`` (int (ns,)); ``atol`` (n,) holds the same value within a
    3-vector."""
    ratio = 0.0
    for b in range(vectors.shape[0]):
        e2 = m0 = m1 = 0.0
        for c in range(3):
            i = vectors[b, c]
            d = factor * (abar1[i] - abar[i])
            e2 += d * d
            m0 += q0[i] * q0[i]
            m1 += q1[i] * q1[i]
        tol = atol[vectors[b, 0]] + rtol * np.sqrt(max(m0, m1))
        ratio = max(ratio, np.sqrt(e2) / tol)
    for i in scalars:
        d = abs(factor * (abar1[i] - abar[i]))
        ratio = max(ratio, d / (atol[i] + rtol * max(abs(q0[i]), abs(q1[i]))))
    return ratio
