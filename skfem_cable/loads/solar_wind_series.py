"""A solar wind that varies in time: series of density and speed (and magnetic field) at
1 AU, linear in time between samples, from arrays (``SolarWind.series``), a CSV file or an
xarray Dataset (``read_series``); and a seeded synthetic series of stated statistics
(``synthetic_series``) for studies without data.

``SolarWindForce`` samples the wind once per time step (``wind.at(t)``, as a voltage
callable); the series' arrays are part of a run's fingerprint (``model.fingerprint``
describes them by their bytes), so a run resumed with other data is refused, naming the
wind (``io.resume``).  ``digest`` is their SHA-256.

Examples
--------
>>> import skfem_cable as sc
>>> wind = sc.SolarWind.series([0.0, 100.0], [7.3e6, 21.9e6], [4e5, 4e5])
>>> wind.at(50.0).density / 1e6
14.6
"""

import hashlib
import os
from dataclasses import dataclass, replace
from typing import ClassVar

import numpy as np

#: Columns of a CSV series (SI units: s, 1/m^3, m/s; optional field ``Bx, By, Bz`` in T).
COLUMNS = ("time", "density", "speed")


def _column(name, values, n=None):
    a = np.ascontiguousarray(values, dtype=float)
    if a.ndim != 1 or a.size < 2 or (n is not None and a.size != n):
        size = "at least 2" if n is None else str(n)
        raise ValueError(f"{name} must be a 1-d array of {size} samples, got shape {a.shape}")
    if not np.all(np.isfinite(a)):
        raise ValueError(f"{name} must be finite")
    return a


@dataclass(frozen=True, eq=False)
class SolarWindSeries:
    """Solar-wind data at 1 AU as functions of time (``SolarWind.series``).

    Parameters
    ----------
    times : array (nt,)
        Strictly increasing sample times (s) of the run's clock.
    density, speed : array (nt,)
        Proton density (1/m^3) and bulk speed (m/s), > 0.
    B : array (nt, 3) or None
        Magnetic field (T), carried for observers and controllers (``field``); the
        Coulomb force does not read it.
    constants : SolarWind
        ``V1``, ``proton_mass`` and ``eps0`` of the samples (its speed and density are
        not read).
    """

    times: np.ndarray
    density: np.ndarray
    speed: np.ndarray
    B: np.ndarray | None
    constants: object

    #: The wind varies in time: ``SolarWindForce`` samples it once per step.
    varies: ClassVar[bool] = True

    def __post_init__(self):
        t = _column("times", self.times)
        if np.any(np.diff(t) <= 0):
            raise ValueError("times must be strictly increasing")
        object.__setattr__(self, "times", t)
        for name in ("density", "speed"):
            a = _column(name, getattr(self, name), t.size)
            if np.any(a <= 0):
                raise ValueError(f"{name} must be > 0 at every sample")
            object.__setattr__(self, name, a)
        if self.B is not None:
            B = np.ascontiguousarray(self.B, dtype=float)
            if B.shape != (t.size, 3) or not np.all(np.isfinite(B)):
                raise ValueError(f"B must be a finite array of shape ({t.size}, 3), got "
                                 f"shape {B.shape}")
            object.__setattr__(self, "B", B)

    def _check(self, t):
        if not self.times[0] <= t <= self.times[-1]:
            raise ValueError(f"t = {t!r} s is outside the solar-wind series, "
                             f"[{self.times[0]!r}, {self.times[-1]!r}] s")

    def at(self, t):
        """The wind (a ``SolarWind``) at time ``t`` (s), linear between samples; a time
        outside the series is an error naming it."""
        self._check(t)
        return replace(self.constants, density=float(np.interp(t, self.times, self.density)),
                       speed=float(np.interp(t, self.times, self.speed)))

    def field(self, t):
        """The magnetic field (3,) (T) at ``t``, linear between samples."""
        if self.B is None:
            raise ValueError("this series has no magnetic field (B=None)")
        self._check(t)
        return np.array([np.interp(t, self.times, b) for b in self.B.T])

    def force_per_length(self, voltage):
        """The paper's force per unit length (Eq. 29) of the wind at the first sample."""
        return self.at(self.times[0]).force_per_length(voltage)

    @property
    def V1(self):
        """``V1`` (V) of the samples (``SolarWind.V1``)."""
        return self.constants.V1

    @property
    def digest(self):
        """SHA-256 (hex) of the samples."""
        h = hashlib.sha256()
        for a in (self.times, self.density, self.speed, self.B):
            h.update(b"-" if a is None else a.tobytes())
        return h.hexdigest()


def read_series(source, constants):
    """The ``SolarWindSeries`` of a CSV file (a path: columns ``COLUMNS``, optional
    ``Bx, By, Bz``, SI units) or of an xarray Dataset (variables ``density``, ``speed``,
    optional ``B`` of dims ``(time, 3)``, along the coordinate ``time``: seconds, or
    datetimes counted from the first), with the ``constants`` of a ``SolarWind``."""
    if isinstance(source, (str, os.PathLike)):
        import pandas

        table = pandas.read_csv(source)
        missing = [c for c in COLUMNS if c not in table.columns]
        if missing:
            raise ValueError(f"{source}: missing columns {missing} (needs {COLUMNS})")
        B = table[["Bx", "By", "Bz"]].to_numpy() if "Bx" in table.columns else None
        return SolarWindSeries(*(table[c].to_numpy() for c in COLUMNS), B, constants)
    time = np.asarray(source["time"].values)
    if np.issubdtype(time.dtype, np.datetime64):
        time = (time - time[0]) / np.timedelta64(1, "s")
    B = source["B"].values if "B" in source else None
    return SolarWindSeries(time, source["density"].values, source["speed"].values, B,
                           constants)


@dataclass(frozen=True)
class WindStatistics:
    """Statistics of the solar wind at 1 AU for ``synthetic_series``.

    The wind alternates between slow and fast streams (Schwenn, Living Rev. Sol. Phys. 3,
    2, 2006, Table 1, after Schwenn 1990: slow wind ``n ~ 10.7 cm^-3``, ``u`` 250-400
    km/s; fast wind ``n ~ 3.0 cm^-3``, ``u`` 400-800 km/s), separated by stream
    interfaces at which density and speed change within ``interface`` seconds; within a
    stream, ``ln n`` and ``ln u`` fluctuate about the stream's medians as AR(1)
    processes of standard deviations ``sigma_ln_density``, ``sigma_ln_speed`` and
    correlation time ``correlation`` (hour averages of density and speed at 1 AU are
    log-normal: Burlaga & Szabo, Space Sci. Rev. 87, 137, 1999; Burlaga & Lazarus,
    J. Geophys. Res. 105, 2357, 2000; the widths here are of their order, not fitted).
    Stream durations are exponential of mean ``stream_mean`` (a 27-day rotation
    carries a few streams)."""

    slow_density: float = 10.7e6
    slow_speed: float = 3.7e5
    fast_density: float = 3.0e6
    fast_speed: float = 7.0e5
    sigma_ln_density: float = 0.4
    sigma_ln_speed: float = 0.08
    correlation: float = 6 * 3600.0
    stream_mean: float = 4 * 86400.0
    interface: float = 3600.0


def _ar1(rng, n, step, correlation, sigma):
    """An AR(1) series of ``n`` samples ``step`` apart, stationary standard deviation
    ``sigma`` and correlation time ``correlation``."""
    from scipy.signal import lfilter  # here, not at import: scipy.signal costs 0.6 s

    phi = np.exp(-step / correlation)
    noise = rng.normal(0.0, sigma * np.sqrt(1 - phi * phi), n)
    noise[0] = rng.normal(0.0, sigma)
    return lfilter([1.0], [1.0, -phi], noise)


def synthetic_series(duration, constants, step=600.0, seed=0, stats=None):
    """A seeded synthetic ``SolarWindSeries`` of ``duration`` seconds sampled every ``step``
    seconds, of the statistics ``stats`` (``WindStatistics``; None: its defaults),
    starting in slow wind."""
    stats = stats or WindStatistics()
    if not (duration > 0 and step > 0 and duration >= step):
        raise ValueError(f"duration ({duration!r} s) and step ({step!r} s) must be > 0, "
                         "duration >= step")
    rng = np.random.default_rng(seed)
    t = np.arange(0.0, duration + step, step)
    edges = np.cumsum(rng.exponential(stats.stream_mean, int(duration // 3600) + 2))
    fast = np.searchsorted(edges, t) % 2 == 1
    # the stream's share of fast wind, ramped over the interface
    blend = np.convolve(fast.astype(float), np.ones(max(1, round(stats.interface / step)))
                        / max(1, round(stats.interface / step)), mode="same")
    ln_n = (1 - blend) * np.log(stats.slow_density) + blend * np.log(stats.fast_density)
    ln_u = (1 - blend) * np.log(stats.slow_speed) + blend * np.log(stats.fast_speed)
    ln_n += _ar1(rng, t.size, step, stats.correlation, stats.sigma_ln_density)
    ln_u += _ar1(rng, t.size, step, stats.correlation, stats.sigma_ln_speed)
    return SolarWindSeries(t, np.exp(ln_n), np.exp(ln_u), None, constants)
