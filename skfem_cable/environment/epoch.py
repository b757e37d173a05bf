"""Epochs and the Earth's frames: the run's ``t = 0`` as a UTC instant, and the rotation
from the inertial axes of an orbit (GCRS) to the Earth-fixed axes (ITRS), by astropy.

An orbit's coordinates are in the GCRS axes (Earth-centred, aligned with the ICRS); the
geomagnetic field, the ionosphere and the atmosphere are given in the ITRS (Earth-fixed:
longitude, latitude, height).  The rotation ``R(t)`` with ``y_ITRS = R(t) x_GCRS`` is
astropy's GCRS -> ITRS transform (IAU 2006/2000A precession-nutation through ERFA, the
Earth rotation angle from UT1 and the polar motion from the IERS tables astropy ships),
obtained once per time by transforming the three unit vectors and cached: the models of
this package evaluate it at most once per step however many points they serve.

No network access is made: astropy's automatic IERS download is switched off around the
transforms, and outside the bundled tables (about a year past the astropy-iers-data
release) astropy warns and uses degraded accuracy (UT1 = UTC, zero polar motion: errors
below 1 arcsecond in the rotation, about 5e-6 rad) instead of raising.

References
----------
1. Astropy Collaboration, "The Astropy Project: Sustaining and Growing a
   Community-oriented Open-source Project and the Latest Major Release (v5.0) of the Core
   Package", Astrophys. J. 935 (2022) 167 (coordinates: GCRS, ITRS).
2. G. Petit and B. Luzum (eds.), "IERS Conventions (2010)", IERS Technical Note 36,
   Ch. 5 (the transformation between the celestial and terrestrial systems).
"""

from collections import OrderedDict

import numpy as np

from ..space.constants import OMEGA_EARTH

CACHE_SIZE = 8
"""Number of recent times whose rotation an ``Epoch`` keeps (a step and its stages)."""


def _astropy():
    """astropy's time, units, coordinates and IERS configuration (imported on first use:
    the optional ``space`` extra)."""
    import astropy.units as u
    from astropy.coordinates import GCRS, ITRS, CartesianRepresentation, EarthLocation
    from astropy.time import Time
    from astropy.utils import iers
    return Time, u, GCRS, ITRS, CartesianRepresentation, EarthLocation, iers


class Epoch:
    """A UTC instant, the ``t = 0`` of a run, and the GCRS -> ITRS rotation at times
    ``t`` (s) after it.

    Parameters
    ----------
    value : Epoch, datetime.datetime, astropy.time.Time or str
        The instant: a datetime (UTC; a naive one is taken as UTC), an astropy ``Time``,
        an ISO 8601 string such as ``"2026-01-01T00:00:00"``, or another ``Epoch``.

    Examples
    --------
    >>> import numpy as np
    >>> import skfem_cable as sc
    >>> epoch = sc.Epoch("2026-01-01T00:00:00")
    >>> R = epoch.gcrs_to_itrs(0.0)
    >>> bool(abs(R @ R.T - np.eye(3)).max() < 1e-14)
    True
    """

    #: Attributes that cache what the epoch computes (the rotations per time), left out of
    #: a system's description (``model.fingerprint``): a run fills them.
    caches = ("_rotations",)

    def __init__(self, value):
        Time = _astropy()[0]
        try:
            self.start = Time(getattr(value, "start", value), scale="utc")
        except (TypeError, ValueError) as error:
            raise ValueError(f"epoch must be a datetime, an astropy Time, an ISO 8601 "
                             f"string or an Epoch, got {value!r} ({error})") from None
        if not self.start.isscalar:
            raise ValueError(f"epoch must be a single instant, got {value!r}")
        self._rotations = OrderedDict()

    def time(self, t=0.0):
        """The astropy ``Time`` (UTC) ``t`` seconds after the epoch."""
        u = _astropy()[1]
        return self.start + float(t) * u.s

    def datetime(self, t=0.0):
        """The ``datetime.datetime`` (UTC, naive) ``t`` seconds after the epoch."""
        return self.time(t).to_datetime()

    def gcrs_to_itrs(self, t=0.0):
        """The rotation ``R`` (3, 3) with ``y_ITRS = R x_GCRS`` at ``t`` seconds after the
        epoch: astropy's transform of the unit vectors, cached per time."""
        key = float(t)
        if key not in self._rotations:
            self._rotations[key] = _rotation(self.time(key))
            if len(self._rotations) > CACHE_SIZE:
                self._rotations.popitem(last=False)
        return self._rotations[key]

    def to_itrs(self, x, t=0.0):
        """Positions ``x`` (..., 3) in the GCRS axes expressed in the ITRS axes."""
        return np.asarray(x, dtype=float) @ self.gcrs_to_itrs(t).T

    def from_itrs(self, y, t=0.0):
        """Vectors ``y`` (..., 3) in the ITRS axes expressed in the GCRS axes."""
        return np.asarray(y, dtype=float) @ self.gcrs_to_itrs(t)

    def earth_rotation(self, t=0.0):
        """The Earth's angular velocity (3,) (rad/s) in the GCRS axes: ``OMEGA_EARTH``
        about the ITRS ``z`` axis (the pole, to the polar motion's arcseconds)."""
        return OMEGA_EARTH * self.gcrs_to_itrs(t)[2]

    def geodetic(self, x, t=0.0):
        """WGS84 geodetic longitude (deg), latitude (deg) and height (km) of GCRS
        positions ``x`` (..., 3) (m), by astropy's ``EarthLocation``."""
        u, EarthLocation = _astropy()[1], _astropy()[5]
        y = self.to_itrs(x, t)
        where = EarthLocation.from_geocentric(y[..., 0], y[..., 1], y[..., 2], unit=u.m)
        lon, lat, height = where.to_geodetic("WGS84")
        return lon.to_value(u.deg), lat.to_value(u.deg), height.to_value(u.km)

    def __repr__(self):
        return f"Epoch({self.start.isot!r})"


def _rotation(when):
    """``R`` (3, 3): the ITRS components of the GCRS unit vectors at ``when``, as
    columns."""
    _, u, GCRS, ITRS, CartesianRepresentation, _, iers = _astropy()
    with iers.conf.set_temp("auto_download", False), \
            iers.conf.set_temp("iers_degraded_accuracy", "warn"):
        axes = GCRS(CartesianRepresentation(np.eye(3) * u.m), obstime=when)
        return axes.transform_to(ITRS(obstime=when)).cartesian.xyz.to_value(u.m)


def corotation_velocity(x, omega):
    """The velocity (..., 3) (m/s) of a medium co-rotating with the Earth at positions
    ``x`` (..., 3) (m): ``omega x r``, ``omega`` (3,) its angular velocity (rad/s), e.g.
    ``Epoch.earth_rotation(t)`` or ``[0, 0, OMEGA_EARTH]``.  The relative velocity of a
    body for drag and for the motional field is ``v - omega x r``."""
    return np.cross(np.asarray(omega, dtype=float), np.asarray(x, dtype=float))
