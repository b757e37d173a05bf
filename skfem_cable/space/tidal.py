"""The central body's differential gravity on offsets from the reference point (Battin's
form)."""

import numpy as np


def battin_f(q):
    """``(1 + q)^(3/2) - 1`` without cancellation for small ``q``:
    ``q (3 + 3 q + q^2) / (1 + (1 + q)^(3/2))``, since ``((1 + q)^(3/2) - 1)
    ((1 + q)^(3/2) + 1) = (1 + q)^3 - 1`` (Battin's ``f(q)``, up to its sign)."""
    return q * (3.0 + q * (3.0 + q)) / (1.0 + (1.0 + q) ** 1.5)


def differential_gravity(mu, reference, delta):
    """``g(R + delta) - g(R)`` of a point mass ``mu`` at the origin, free of
    cancellation.

    With ``r = R + delta`` and ``q = delta . (2 R + delta) / |R|^2`` (so that
    ``|r|^2 = |R|^2 (1 + q)``),

    ``g(r) - g(R) = -mu / |r|^3 (delta - f(q) R)``,  ``f(q) = (1 + q)^(3/2) - 1``

    (Battin's form of Encke's method).  ``delta`` may hold many points (..., 3).
    """
    reference = np.asarray(reference, dtype=float)
    delta = np.asarray(delta, dtype=float)
    r2 = reference @ reference
    q = np.sum(delta * (2.0 * reference + delta), axis=-1) / r2
    r3 = (r2 * (1.0 + q)) ** 1.5
    return -(mu / r3)[..., None] * (delta - battin_f(q)[..., None] * reference)


def gravity_gradient(mu, r):
    """Tangent of the point-mass gravity at ``r``: ``dg/dr = mu / |r|^3 (3 r r^T / |r|^2
    - I)``, shape ``r.shape[:-1] + (3, 3)`` (also the tangent of the differential gravity
    with respect to ``delta``)."""
    r = np.asarray(r, dtype=float)
    r2 = np.sum(r * r, axis=-1)[..., None, None]
    outer = r[..., :, None] * r[..., None, :]
    return mu / r2**1.5 * (3.0 * outer / r2 - np.eye(3))
