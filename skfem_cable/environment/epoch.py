"""Epochs and the Earth's frames: the run's ``t = 0`` as a UTC instant, and the rotation
from the inertial axes of an orbit (GCRS) to the Earth-fixed axes (ITRS), by astropy.

An orbit's coordinates are in the GCRS axes (Earth-centred, aligned with the ICRS); the
geomagnetic field, the ionosphere and the atmosphere are given in the ITRS (Earth-fixed:
longitude, latitude, height).  The rotation ``R(t)`` with ``y_ITRS = R(t) x_GCRS`` is
astropy's GCRS -> ITRS transform (IAU 2006/2000A precession-nutation through ERFA, the
Earth rotation angle from UT1 and the polar motion from the IERS tables astropy ships),
obtained by transforming the three unit vectors at the knots ``t = k KNOT`` (every 600 s
after the epoch; 3.2 ms each) and, between two knots, as the rotation at constant rate
from one to the other (scipy's ``Slerp``; 0.45 ms per time with the knots' share): the
Earth turns at a constant rate about an axis that moves by precession, nutation and
polar motion at rates below 1e-11 rad/s, so the interpolation is exact at the knots and
within 3e-11 rad of astropy between them.  Both are cached: the models of this package
evaluate the rotation at most once per step however many points they serve.

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

import copy
import math
from collections import OrderedDict

import numpy as np

from ..space.constants import OMEGA_EARTH

CACHE_SIZE = 8
"""Number of recent times (and knots) whose rotation an ``Epoch`` keeps."""

KNOT = 600.0
"""Spacing (s) of the times at which astropy's transform is evaluated (module notes)."""


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

    #: Derived values a fingerprint does not describe (``model.fingerprint``): the
    #: astropy ``Time`` (described by ``utc``) and the rotations evaluated so far.
    caches = ("start", "_rotations", "_knots", "_turns")

    def __init__(self, value, name="epoch"):
        Time = _astropy()[0]
        try:
            self.start = Time(getattr(value, "start", value), scale="utc")
        except (TypeError, ValueError):
            raise ValueError(f"{name} must be a datetime, an astropy Time, an ISO 8601 "
                             f"string (2026-01-01T12:00:00, UTC) or an Epoch, got "
                             f"{value!r}") from None
        if not self.start.isscalar:
            raise ValueError(f"{name} must be a single instant, got {value!r}")
        utc = self.start.copy()
        utc.precision = 9
        self.utc = utc.isot
        self._rotations, self._knots, self._turns = OrderedDict(), OrderedDict(), OrderedDict()

    def __eq__(self, other):
        return isinstance(other, Epoch) and other.utc == self.utc

    def __hash__(self):
        return hash(self.utc)

    def time(self, t=0.0):
        """The astropy ``Time`` (UTC) ``t`` seconds after the epoch."""
        u = _astropy()[1]
        return self.start + float(t) * u.s

    def datetime(self, t=0.0):
        """The ``datetime.datetime`` (UTC, naive) ``t`` seconds after the epoch."""
        return self.time(t).to_datetime()

    def gcrs_to_itrs(self, t=0.0):
        """The rotation ``R`` (3, 3) with ``y_ITRS = R x_GCRS`` at ``t`` seconds after the
        epoch, cached per time: astropy's transform of the unit vectors at the knots
        ``t = k KNOT``, between them the rotation at constant rate from one knot's to the
        next's (scipy's ``Slerp``; module notes)."""
        key = float(t)
        if key not in self._rotations:
            self._rotations[key] = self._between_knots(key)
            if len(self._rotations) > CACHE_SIZE:
                self._rotations.popitem(last=False)
        return self._rotations[key]

    def _between_knots(self, t):
        """``R(t)`` from the knots ``k KNOT <= t < (k + 1) KNOT`` (the knot's own at a
        knot): scipy's ``Slerp`` between them, ``R_k Exp(u w_k)`` with ``u = t / KNOT -
        k`` and the rotation vector ``w_k`` of ``R_k^T R_(k+1)`` kept per interval."""
        from scipy.spatial.transform import Rotation

        k = math.floor(t / KNOT)
        first = self._knot(k)
        if t == k * KNOT:
            return first
        return first @ Rotation.from_rotvec((t / KNOT - k) * self._turn(k)).as_matrix()

    def _turn(self, k):
        """The rotation vector (3,) of ``R_k^T R_(k+1)`` (the knots' ``_knot``), cached
        (the last few)."""
        from scipy.spatial.transform import Rotation

        if k not in self._turns:
            self._turns[k] = Rotation.from_matrix(self._knot(k).T @ self._knot(k + 1)) \
                .as_rotvec()
            if len(self._turns) > CACHE_SIZE:
                self._turns.popitem(last=False)
        return self._turns[k]

    def _knot(self, k):
        """astropy's rotation at the knot ``t = k KNOT``, cached (the last few)."""
        if k not in self._knots:
            self._knots[k] = _rotation(self.time(k * KNOT))
            if len(self._knots) > CACHE_SIZE:
                self._knots.popitem(last=False)
        return self._knots[k]

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
        return itrs_geodetic(self.to_itrs(x, t))

    def geodetic_series(self, x, times):
        """``geodetic`` of the positions ``x`` (k, ..., 3) at the times ``times`` (k,)
        (row ``k`` at ``times[k]``), in one conversion: shapes (k, ...) each."""
        x = np.asarray(x, dtype=float)
        return itrs_geodetic(np.stack([self.to_itrs(xk, t) for xk, t in zip(x, times)]))

    def __repr__(self):
        return f"Epoch({self.start.isot!r})"


def as_epoch(value, name="epoch"):
    """``value`` as an ``Epoch``: an ``Epoch`` itself (its cache of rotations shared), or
    a new one of a datetime, an astropy ``Time`` or an ISO 8601 string; ``ValueError``
    naming the parameter ``name`` otherwise.

    Examples
    --------
    >>> import datetime
    >>> as_epoch(datetime.datetime(1996, 2, 26, 1, 0)).utc
    '1996-02-26T01:00:00.000000000'
    """
    return value if isinstance(value, Epoch) else Epoch(value, name)


def epoch_or_none(value, name="epoch"):
    """``as_epoch(value, name)``, or None for None (a model that takes the epoch of the
    system it is bound to: ``bound_model``)."""
    return None if value is None else as_epoch(value, name)


def model_epoch(model):
    """The ``Epoch`` of the environment ``model``, or ``ValueError`` when it has none (a
    model made without one is evaluated once bound to a system with an epoch:
    ``bound_model``)."""
    if model.epoch is None:
        raise ValueError(f"{type(model).__name__}: no epoch (give epoch=..., or use the "
                         f"model in a load of a system with one: add_orbit(orbit, "
                         f"epoch=...))")
    return model.epoch


def bound_model(model, epoch, name):
    """The environment ``model`` (an object with an attribute ``epoch``, an ``Epoch`` or
    None) at the system's ``epoch`` (an ``Epoch`` or None: ``System.add_orbit``):

    * a model without an epoch of its own takes the system's (a shallow copy: the user's
      model is left as given);
    * a model with one keeps it; a system epoch that differs is refused, naming ``name``
      (the load's parameter) and both instants;
    * neither: ``ValueError`` naming ``name`` (no ``t = 0`` for the model's time).

    A model without the attribute ``epoch`` (a number, a function of ``(x, t)``) is
    returned as it is.
    """
    own = getattr(model, "epoch", False)
    if own is False:
        return model
    if own is None:
        if epoch is None:
            raise ValueError(f"{name}: {model!r} has no epoch, and the system has none "
                             f"(give one: the model's epoch=..., or "
                             f"System.add_orbit(orbit, epoch=...))")
        model = copy.copy(model)
        model.epoch = epoch
        return model
    if epoch is not None and own != epoch:
        raise ValueError(f"{name}: the model's epoch {own.utc} differs from the system's "
                         f"{epoch.utc} (add_orbit(..., epoch=...)): t = 0 must be one "
                         f"instant")
    return model


def itrs_geodetic(y):
    """WGS84 geodetic longitude (deg), latitude (deg) and height (km) of ITRS positions
    ``y`` (..., 3) (m), by astropy's ``EarthLocation``."""
    u, EarthLocation = _astropy()[1], _astropy()[5]
    where = EarthLocation.from_geocentric(y[..., 0], y[..., 1], y[..., 2], unit=u.m)
    lon, lat, height = where.to_geodetic("WGS84")
    return lon.to_value(u.deg), lat.to_value(u.deg), height.to_value(u.km)


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
