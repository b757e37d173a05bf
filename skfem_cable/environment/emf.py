"""The open-circuit EMF of a straight tether along an orbit at an epoch: the motional field
of the co-rotating ionosphere integrated along the tether.

A straight, rigid tether of length ``L`` stands along the local vertical from the point
``R(t)`` of a Keplerian orbit (towards the zenith, or the nadir) and turns with the
orbiting frame.  Its point at distance ``s`` is at ``r = R + s u`` (``u = +-R / |R|``),
moving at ``v = V + omega_o x (s u)`` (``omega_o = R x V / |R|^2``, the rate of the
orbiting frame); the plasma there co-rotates with the Earth, ``v_p = omega_E x r``. The
open-circuit EMF (no current: no ohmic drop, no sheath) is

    EMF = int_0^L ((v - v_p) x B(r, t)) . u ds

(e.g. Cosmo & Lorenzini, Tethers in Space Handbook, Ch. 4), by Gauss-Legendre
quadrature in ``s`` (``POINTS`` points: the field varies on the scale ``|R| / 3``, so
four points are exact to far below the model's accuracy for tethers of tens of km).  It
is positive when the motional field drives a current towards the tether's far end
(``u``): for an eastward orbit and a zenith tether, the far (upper) end is the anode.

References
----------
1. B. E. Gilchrist et al., "Enhanced electrodynamic tether currents due to electron
   emission from a neutral gas discharge: Results from the TSS-1R mission", Geophys.
   Res. Lett. 25(4) (1998) 437-440, doi:10.1029/97GL03023 (19.7 km deployed, an EMF of
   3482 V just before the tether broke).
2. M. L. Cosmo and E. C. Lorenzini (eds.), "Tethers in Space Handbook", 3rd ed., NASA
   Marshall Space Flight Center, 1997.
"""

import numpy as np

from ..bodies.section import check_positive
from .epoch import as_epoch, bound_model
from .igrf import IGRF

#: Gauss-Legendre points along the tether.
POINTS = 4

#: The directions of the tether from the orbit's point.
DIRECTIONS = {"zenith": 1.0, "nadir": -1.0}


def open_circuit_emf(orbit, epoch, length, t, field=None, direction="zenith"):
    """The open-circuit EMF (V) of a straight tether along the local vertical of ``orbit``
    at the times ``t`` (s after ``epoch``) (module notes).

    Parameters
    ----------
    orbit : Orbit
        The orbit of the tether's end at the orbit's point (its ``position(t)``,
        ``velocity(t)``: GCRS axes, m, m/s); in the GCRS axes of ``epoch``.
    epoch : Epoch, datetime, astropy Time or str
        The instant of ``t = 0``.
    length : float
        The tether's length (m, > 0).
    t : float or array_like
        Times (s after the epoch).
    field : object with ``__call__(x, t) -> B`` or None
        The geomagnetic field (T) at GCRS positions (..., 3); None: ``IGRF(epoch)``
        (a model without an epoch takes ``epoch``).
    direction : {"zenith", "nadir"}
        Where the tether points from the orbit's point.

    Returns
    -------
    ndarray
        The EMF (V), of the shape of ``t``.

    Examples
    --------
    >>> import numpy as np, skfem_cable as sc
    >>> orbit = sc.Orbit(sc.MU_EARTH, sc.R_EARTH + 296e3, inclination=np.radians(28.5))
    >>> emf = sc.environment.open_circuit_emf(orbit, "1996-02-26T01:30", 19.7e3, 0.0)
    >>> bool(1e3 < abs(float(emf)) < 6e3)
    True
    """
    epoch = as_epoch(epoch)
    length = check_positive("length", length)
    if direction not in DIRECTIONS:
        raise ValueError(f"direction must be one of {sorted(DIRECTIONS)}, got {direction!r}")
    field = bound_model(IGRF() if field is None else field, epoch, "field")
    nodes, weights = np.polynomial.legendre.leggauss(POINTS)
    s, w = 0.5 * length * (nodes + 1.0), 0.5 * length * weights
    times = np.asarray(t, dtype=float)
    out = np.array([_emf(orbit, epoch, field, float(ti), DIRECTIONS[direction], s, w)
                    for ti in times.ravel()])
    return out.reshape(times.shape)


def _emf(orbit, epoch, field, t, sign, s, w):
    """The EMF at one time ``t``: the quadrature of the motional field at the points
    ``s`` (k,) with the weights ``w`` (k,)."""
    R, V = np.asarray(orbit.position(t), float), np.asarray(orbit.velocity(t), float)
    u = sign * R / np.linalg.norm(R)
    offsets = s[:, None] * u
    x = R + offsets
    rate = np.cross(R, V) / (R @ R)
    relative = V + np.cross(rate, offsets) - np.cross(epoch.earth_rotation(t), x)
    B = field(x, t)
    return float(w @ (np.cross(relative, B) @ u))
