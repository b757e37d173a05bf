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
from .epoch import corotation_velocity, epoch_or_none, model_epoch
from .msis import index
from .plasma import OXYGEN_ION_MASS

BLOCK = 64
"""Points per PyIRI profile build: the profile is built on a (heights x points) grid, of
which the diagonal is kept, so blocks bound the work to ``BLOCK`` times the points."""


def pyiri_density(when, lon, lat, height, f107):
    """PyIRI's electron density (m^-3) at the datetime ``when`` (UTC) at longitudes,
    latitudes (deg) and heights (km) ``(n,)`` each, for the F10.7 index ``f107``."""
    import PyIRI
    from PyIRI import edp_update
    hours = when.hour + when.minute / 60.0 + (when.second + when.microsecond * 1e-6) / 3600.0
    F2, F1, E, *_ = edp_update.IRI_density_1day(
        when.year, when.month, when.day, np.array([hours]), lon, lat, np.array([300.0]),
        f107, PyIRI.coeff_dir)
    density = np.empty(lon.size)
    for start in range(0, lon.size, BLOCK):
        block = slice(start, start + BLOCK)
        layers = [{key: value[:, block] for key, value in layer.items()
                   if np.ndim(value) == 2} for layer in (F2, F1, E)]
        grid = edp_update.reconstruct_density_from_parameters_1level(*layers, height[block])
        density[block] = np.diagonal(grid[0])
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

    def temperature(self, x, t=0.0):
        """Electron temperature (K) at positions ``x`` (..., 3): the uniform argument."""
        return np.full(np.shape(x)[:-1], self.electron_temperature)

    def velocity(self, x, t=0.0):
        """The co-rotating plasma's velocity ``omega_E x r`` (m/s) at ``x`` (..., 3)."""
        return corotation_velocity(x, model_epoch(self).earth_rotation(t))

    def __repr__(self):
        return f"IRI({self.epoch!r})"

