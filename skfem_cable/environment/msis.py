"""The neutral atmosphere: NRLMSIS 2.1 (pymsis) at inertial positions.

``MSIS(epoch, f107=..., f107a=..., ap=...).density(x, t)`` is the total neutral mass
density (kg/m^3) at GCRS positions ``x`` (..., 3) (m), ``t`` seconds after the epoch:
the positions are turned into WGS84 geodetic longitude, latitude and height
(``Epoch.geodetic``) and handed to ``pymsis.calculate`` with the space-weather indices.

The indices are arguments, never downloaded: pymsis fetches them from a space-weather
file over the network when they are missing, which a run must not do.  ``f107`` is the
daily F10.7 solar radio flux of the previous day, ``f107a`` its 81-day centred mean (both
in solar flux units, 1e-22 W m^-2 Hz^-1) and ``ap`` the daily geomagnetic Ap index;
each is a number or a function of ``t`` (s after the epoch) for a long run that crosses
days.  Typical values: solar minimum ``f107 = f107a = 70``, moderate 150, maximum 250;
quiet ``ap = 4``, storm 100 and above.

References
----------
1. J. T. Emmert et al., "NRLMSIS 2.0: A whole-atmosphere empirical model of temperature
   and neutral species densities", Earth Space Sci. 8 (2021) e2020EA001321; NRLMSIS 2.1
   (Emmert et al., 2022, the nitric-oxide update): the default of pymsis.
2. G. Lucas et al., pymsis: a Python interface to the NRLMSIS models.
"""

import numpy as np

from .epoch import epoch_or_none, model_epoch

VERSION = 2.1
"""The NRLMSIS version pymsis evaluates."""


def index(name, value, low, high):
    """A space-weather index ``value(t)``: a number in ``[low, high]`` or a callable of
    ``t`` (s), checked at ``t = 0``."""
    function = value if callable(value) else (lambda t: value)
    sample = function(0.0)
    try:
        sample = float(sample)
    except (TypeError, ValueError):
        sample = np.nan
    if not low <= sample <= high:
        raise ValueError(f"{name} must be a number in [{low}, {high}] or a function of t "
                         f"giving one, got {value!r}")
    return function


class MSIS:
    """The NRLMSIS 2.1 neutral mass density at inertial positions.

    Parameters
    ----------
    epoch : Epoch, datetime, astropy Time, str or None
        The instant of ``t = 0``; None: the epoch of the system whose load the model
        serves (``System.add_orbit(orbit, epoch=...)``; ``epoch.bound_model``).
    f107, f107a : float or callable
        Daily F10.7 of the previous day and its 81-day centred mean (sfu, in [0, 500]),
        or functions of ``t`` (s).
    ap : float or callable
        Daily Ap index (in [0, 400]) or a function of ``t``.

    Notes
    -----
    A load evaluates the density once per step (its ``Term.prepare(t)``, at the step's
    positions) and keeps it through the Newton iterations: one pymsis call per step for
    all the points.

    Examples
    --------
    >>> import skfem_cable as sc
    >>> msis = sc.environment.MSIS("2026-01-01", f107=150.0, f107a=150.0, ap=4.0)
    >>> rho = msis.density([[sc.R_EARTH + 400e3, 0.0, 0.0]])
    >>> bool(1e-13 < rho[0] < 1e-10)
    True
    """

    def __init__(self, epoch=None, f107=None, f107a=None, ap=None):
        self.epoch = epoch_or_none(epoch)
        self.f107 = index("f107", f107, 0.0, 500.0)
        self.f107a = index("f107a", f107a, 0.0, 500.0)
        self.ap = index("ap", ap, 0.0, 400.0)

    def density(self, x, t=0.0):
        """The neutral mass density (kg/m^3) at GCRS positions ``x`` (..., 3) (m):
        shape (...)."""
        x = np.asarray(x, dtype=float)
        return self.density_series(x[None], [t])[0]

    def density_series(self, x, times):
        """``density`` at several times in one pymsis call: positions ``x`` (k, ..., 3)
        at the times ``times`` (k,) (s), each time its own indices: shape (k, ...)
        (``loads.knots``, the drag's density at knots)."""
        import pymsis
        x, times = np.asarray(x, dtype=float), np.asarray(times, dtype=float)
        epoch = model_epoch(self)
        lon, lat, height = (np.ravel(c) for c in epoch.geodetic_series(x, times))
        per_time = np.prod(x.shape[1:-1], dtype=int)

        def at_points(values):
            return np.repeat(np.asarray(values), per_time)

        dates = at_points([np.datetime64(epoch.datetime(t), "ns") for t in times])
        indices = [at_points([float(index(t)) for t in times])
                   for index in (self.f107, self.f107a, self.ap)]
        out = pymsis.calculate(dates, lon, lat, height, indices[0], indices[1],
                               np.repeat(indices[2][:, None], 7, axis=1), version=VERSION)
        return out[:, pymsis.Variable.MASS_DENSITY].reshape(x.shape[:-1])

    def __repr__(self):
        return f"MSIS({self.epoch!r})"
