"""The ionosphere: the International Reference Ionosphere's electron density (PyIRI) at
inertial positions, a plasma of the protocol of ``environment.plasma``.

``IRI(epoch, f107=...)`` evaluates PyIRI (``edp_update.IRI_density_1day``: the CCIR
F2-peak coefficients, the monthly means interpolated to the day and in solar activity)
at the WGS84 geodetic longitude, latitude and height of each point (``Epoch.geodetic``).
PyIRI 0.1.7 models the electron density only: the electron temperature is the argument
``temperature`` (K), uniform (the OML electron current does not depend on it; it sets the
validity of the OML regime through the Debye length).  The ionosphere co-rotates with the
Earth: ``velocity = omega_E x r`` with ``omega_E = Epoch.earth_rotation(t)``.

References
----------
1. V. Forsythe et al., "PyIRI: Whole-Globe Approach to the International Reference
   Ionosphere Modeling Implemented in Python", Space Weather 22 (2024) e2023SW003739.
2. D. Bilitza et al., "The International Reference Ionosphere model: A review and
   description of an ionospheric benchmark", Rev. Geophys. 60 (2022) e2022RG000792.
"""

import numpy as np

from ..bodies.section import check_positive
from .coefficients import read_once
from .epoch import corotation_velocity, epoch_or_none, model_epoch
from .msis import index
from .plasma import OXYGEN_ION_MASS

BLOCK = 64
"""Points per PyIRI profile build: the profile is built on a (heights x points) grid, of
which the diagonal is kept, so blocks bound the work to ``BLOCK`` times the points."""


def pyiri():
    """PyIRI's ``edp_update``, its CCIR/URSI coefficient files read once per month and
    folder in a process.  ``IRI_density_1day`` reads two months' files (fortranformat,
    about 30 ms each) on every call, three quarters of a call's CPU for tens of points,
    and a load evaluates it once per step; the memo (``coefficients.read_once``) replaces
    ``main_library.read_ccir_ursi_coeff``, which ``edp_update`` looks up at each call."""
    from PyIRI import edp_update, main_library
    read_once(main_library, "read_ccir_ursi_coeff", 24, kept=_read_only)
    return edp_update


def _read_only(arrays):
    """PyIRI's coefficient arrays made read-only (PyIRI only reads them: a write would
    raise instead of changing the coefficients of later calls)."""
    for array in arrays:
        array.flags.writeable = False
    return arrays


def pyiri_density(when, lon, lat, height, f107):
    """PyIRI's electron density (m^-3) at the datetime ``when`` (UTC) at longitudes,
    latitudes (deg) and heights (km) ``(n,)`` each, for the F10.7 index ``f107``."""
    return pyiri_series([when], lon[None], lat[None], height[None], f107)[0]


def pyiri_series(whens, lon, lat, height, f107):
    """PyIRI's electron density (m^-3) at the datetimes ``whens`` (k,) (UTC, one day) at
    longitudes, latitudes (deg) and heights (km) ``(k, n)`` each (the points of time
    ``k`` in row ``k``), for the F10.7 index ``f107``: one call (PyIRI builds the
    parameters on the grid of the times and all the points, the rows' own are kept)."""
    import PyIRI
    edp_update = pyiri()
    day = whens[0]
    if any(when.date() != day.date() for when in whens):
        raise ValueError("pyiri_series: the times must lie in one UTC day")
    hours = np.array([(when - when.replace(hour=0, minute=0, second=0, microsecond=0))
                      .total_seconds() / 3600.0 for when in whens])
    k, n = lon.shape
    F2, F1, E, *_ = edp_update.IRI_density_1day(
        day.year, day.month, day.day, hours, lon.ravel(), lat.ravel(), np.array([300.0]),
        f107, PyIRI.coeff_dir)
    density = np.empty((k, n))
    for row in range(k):
        for start in range(0, n, BLOCK):
            block = slice(row * n + start, row * n + min(start + BLOCK, n))
            layers = [{key: value[row:row + 1, block] for key, value in layer.items()
                       if np.ndim(value) == 2} for layer in (F2, F1, E)]
            grid = edp_update.reconstruct_density_from_parameters_1level(
                *layers, height.ravel()[block])
            density[row, start:start + BLOCK] = np.diagonal(grid[0])
    return density


class IRI:
    """The IRI electron density (PyIRI) at inertial positions, a co-rotating plasma.

    Parameters
    ----------
    epoch : Epoch, datetime, astropy Time, str or None
        The instant of ``t = 0``; None: the epoch of the system whose load the model
        serves (``System.add_orbit(orbit, epoch=...)``; ``epoch.bound_model``).
    f107 : float or callable
        The F10.7 solar radio flux (sfu, in [0, 500]) or a function of ``t`` (s).
    temperature : float
        Electron temperature (K, > 0), uniform (PyIRI has no temperature model).
    ion_mass : float
        Ion mass (kg, > 0); default O+.

    Notes
    -----
    A load evaluates the density once per step (its ``Term.prepare(t)``) and keeps it
    through the Newton iterations: one PyIRI call per step for all the points.

    Examples
    --------
    >>> import skfem_cable as sc
    >>> iri = sc.environment.IRI("2026-01-01T12:00:00", f107=150.0)
    >>> n_e = iri.density([[sc.R_EARTH + 400e3, 0.0, 0.0]])
    >>> bool(1e9 < n_e[0] < 1e13)
    True
    """

    def __init__(self, epoch=None, f107=None, temperature=1500.0, ion_mass=OXYGEN_ION_MASS):
        self.epoch = epoch_or_none(epoch)
        self.f107 = index("f107", f107, 0.0, 500.0)
        self.electron_temperature = check_positive("temperature", temperature)
        self.ion_mass = check_positive("ion_mass", ion_mass)

    def density(self, x, t=0.0):
        """Electron density (m^-3) at GCRS positions ``x`` (..., 3) (m): shape (...)."""
        x = np.asarray(x, dtype=float)
        lon, lat, height = model_epoch(self).geodetic(x.reshape(-1, 3), t)
        n_e = pyiri_density(model_epoch(self).datetime(t), np.atleast_1d(lon),
                            np.atleast_1d(lat), np.atleast_1d(height), float(self.f107(t)))
        return n_e.reshape(x.shape[:-1])

    def density_series(self, x, times):
        """``density`` at several times in few PyIRI calls (one per UTC day): positions
        ``x`` (k, n, 3) at the times ``times`` (k,) (s); F10.7 at the middle time:
        shape (k, n)."""
        x, times = np.asarray(x, dtype=float), np.asarray(times, dtype=float)
        epoch = model_epoch(self)
        whens = [epoch.datetime(t) for t in times]
        where = np.array(epoch.geodetic_series(x, times))
        out = np.empty(x.shape[:2])
        for day in sorted({when.date() for when in whens}):
            rows = np.array([when.date() == day for when in whens])
            out[rows] = pyiri_series([w for w, r in zip(whens, rows) if r],
                                     *where[:, rows],
                                     float(self.f107(np.median(times[rows]))))
        return out

    def temperature(self, x, t=0.0):
        """Electron temperature (K) at positions ``x`` (..., 3): the uniform argument."""
        return np.full(np.shape(x)[:-1], self.electron_temperature)

    def velocity(self, x, t=0.0):
        """The co-rotating plasma's velocity ``omega_E x r`` (m/s) at ``x`` (..., 3)."""
        return corotation_velocity(x, model_epoch(self).earth_rotation(t))

    def __repr__(self):
        return f"IRI({self.epoch!r})"

