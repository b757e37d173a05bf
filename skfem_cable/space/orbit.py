"""Keplerian reference orbits (``Orbit``): the moving origin of a system in orbit."""

import numpy as np

from .constants import CENTRAL_BODIES
from .kepler import _finite, _rotation, eccentric_anomaly, kepler_state


class _FunctionsOfTime:
    """The functions of time of a reference, evaluated on the Keplerian arc in force at
    each time: a subclass gives ``arc(t)`` (the arc at one time) and ``_each_arc(t,
    function)`` (``function(arc, times)`` over the times of each arc)."""

    def position(self, t):
        """Absolute position of the reference point (m): shape (3,) or ``t.shape + (3,)``."""
        if isinstance(t, float):
            return self.arc(t)._one(t)[:3].copy()
        return self._each_arc(t, lambda arc, s: arc._perifocal_at(s)[0] @ arc.axes[:, :2].T)

    def velocity(self, t):
        """Absolute velocity of the reference point (m/s)."""
        if isinstance(t, float):
            return self.arc(t)._one(t)[3:].copy()
        return self._each_arc(t, lambda arc, s: arc._perifocal_at(s)[1] @ arc.axes[:, :2].T)

    def true_anomaly(self, t):
        """True anomaly (rad) at ``t``, continuous in time on each arc (not wrapped)."""
        return self._each_arc(t, Orbit._true_anomaly)

    def lvlh(self, t):
        """The orbiting frame at ``t``: rows radial, along-track, orbit normal, in the
        system's axes; shape (3, 3) or ``t.shape + (3, 3)``."""
        return self._each_arc(t, Orbit._lvlh)

    def angular_velocity(self, t):
        """Angular velocity of the orbiting frame (rad/s, a vector along the orbit normal
        in the system's axes): ``h / |R|^2``."""
        return self._each_arc(t, Orbit._angular_velocity)

    def to_lvlh(self, t, x):
        """Offsets ``x`` (..., 3) in the system's axes, expressed in the orbiting frame at
        ``t`` (a scalar, or one time per leading entry of ``x``)."""
        frame = self.lvlh(t)
        x = np.asarray(x, dtype=float)
        if frame.ndim == 2:
            return x @ frame.T
        return np.einsum("tij,t...j->t...i", frame, x)

    def libration(self, t, axis):
        """In-plane and out-of-plane libration angles (rad) of the vectors ``axis``
        (n, 3; a tether's end-to-end line) at the times ``t`` (n,) in the orbiting frame:
        the in-plane angle (pitch) ``atan2(along-track, radial)``, a turn about the orbit
        normal, and the out-of-plane angle (roll), positive away from the orbit normal, a
        turn about the along-track axis.  Returns ``(in_plane, out_of_plane)``, (n,)
        each."""
        y = self.to_lvlh(np.asarray(t, dtype=float), axis)
        in_plane = np.arctan2(y[:, 1], y[:, 0])
        out_of_plane = np.arcsin(-y[:, 2] / np.linalg.norm(y, axis=1))
        return in_plane, out_of_plane

    def from_lvlh(self, t, y):
        """Inverse of :meth:`to_lvlh`."""
        frame = self.lvlh(t)
        y = np.asarray(y, dtype=float)
        if frame.ndim == 2:
            return y @ frame
        return np.einsum("tji,t...j->t...i", frame, y)


class Orbit(_FunctionsOfTime):
    """A Keplerian reference orbit (``0 <= e < 1``).

    Parameters
    ----------
    mu : float
        Gravitational parameter of the central body (m^3/s^2), e.g. :data:`MU_EARTH`.
    a : float
        Semi-major axis (m), positive.
    e : float
        Eccentricity in ``[0, 1)``.
    inclination, raan, argp : float
        Inclination, right ascension of the ascending node and argument of periapsis
        (rad), the 3-1-3 rotation from the perifocal to the inertial axes.
    anomaly : float
        True anomaly at ``t0`` (rad).
    t0 : float
        Epoch (s) of ``anomaly``.

    Notes
    -----
    With the default angles the orbit lies in the ``x, y`` plane, periapsis on ``+x``: at
    ``t = t0`` the local vertical (radial) is ``+x``, along-track ``+y`` and the orbit
    normal ``+z``.

    An ``Orbit`` is what the user gave, and what a run's fingerprint records; a run
    never changes it.  Encke's rectification rebases the run's ``Reference`` (made from
    the orbit per run), not the orbit.

    Examples
    --------
    >>> import skfem_cable as sc
    >>> orbit = sc.Orbit(sc.MU_EARTH, sc.R_EARTH + 400e3)
    >>> round(orbit.period / 60, 2)
    92.56
    """

    #: The memo of ``_one``, left out of a system's fingerprint (``io.fingerprint``).
    caches = ("_last", "_state")

    def __init__(self, mu, a, e=0.0, inclination=0.0, raan=0.0, argp=0.0, anomaly=0.0,
                 t0=0.0):
        self.mu = _finite("mu", mu)
        self.a = _finite("a", a)
        self.e = _finite("e", e)
        if self.mu <= 0:
            raise ValueError(f"Orbit: mu must be > 0 (m^3/s^2), got {self.mu}")
        if self.a <= 0:
            raise ValueError(f"Orbit: a must be > 0 (m; only elliptic orbits), got {self.a}")
        if not 0.0 <= self.e < 1.0:
            raise ValueError(f"Orbit: e must be in [0, 1) (elliptic orbits), got {self.e}")
        self.inclination = _finite("inclination", inclination)
        self.raan = _finite("raan", raan)
        self.argp = _finite("argp", argp)
        self.anomaly = _finite("anomaly", anomaly)
        self.t0 = _finite("t0", t0)
        self.axes = _rotation(self.raan, self.inclination, self.argp)
        half = 0.5 * self.anomaly
        ecc0 = 2.0 * np.arctan2(np.sqrt(1.0 - self.e) * np.sin(half),
                                np.sqrt(1.0 + self.e) * np.cos(half))
        self.mean_anomaly0 = ecc0 - self.e * np.sin(ecc0)
        self._last, self._state = None, np.empty(6)  # memo of _one

    @classmethod
    def from_state(cls, mu, r, v, t0=0.0):
        """The orbit through position ``r`` (m) and velocity ``v`` (m/s) at time ``t0``.

        A circular orbit takes its periapsis on the ascending node (``argp = 0``), an
        equatorial one its node on ``+x`` (``raan = 0``); position and velocity are
        reproduced to round-off either way.  Parabolic and hyperbolic states are refused.
        """
        r = np.asarray(r, dtype=float).reshape(3)
        v = np.asarray(v, dtype=float).reshape(3)
        if not (np.all(np.isfinite(r)) and np.all(np.isfinite(v))):
            raise ValueError("Orbit.from_state: r and v must be finite")
        mu = _finite("mu", mu)
        h = np.cross(r, v)
        rn, hn = np.linalg.norm(r), np.linalg.norm(h)
        if rn == 0 or hn == 0:
            raise ValueError("Orbit.from_state: r and v must span a plane (a rectilinear "
                             "orbit has no elements)")
        energy = 0.5 * (v @ v) - mu / rn
        if energy >= 0:
            raise ValueError(f"Orbit.from_state: the state is not bound (specific energy "
                             f"{energy:.6g} J/kg >= 0): only elliptic orbits")
        w = h / hn
        ecc = ((v @ v - mu / rn) * r - (r @ v) * v) / mu
        e = np.linalg.norm(ecc)
        node = np.array([-h[1], h[0], 0.0])
        node_norm = np.linalg.norm(node)
        node = node / node_norm if node_norm > 1e-15 * hn else np.array([1.0, 0.0, 0.0])
        p = ecc / e if e > 0 else node
        q = np.cross(w, p)
        inclination = np.arccos(np.clip(w[2], -1.0, 1.0))
        raan = np.arctan2(node[1], node[0])
        argp = np.arctan2(p @ np.cross(w, node), p @ node)
        anomaly = np.arctan2(r @ q, r @ p)
        return cls(mu, -mu / (2 * energy), e, inclination, raan, argp, anomaly, t0)

    @property
    def mean_motion(self):
        """Mean motion ``n = sqrt(mu / a^3)`` (rad/s)."""
        return np.sqrt(self.mu / self.a**3)

    @property
    def period(self):
        """Orbital period ``2 pi / n`` (s)."""
        return 2 * np.pi / self.mean_motion

    def keplerian(self):
        """A copy of the orbit as given (an ``Orbit`` is never rebased: a run's rebases
        are its ``Reference``'s)."""
        return Orbit(self.mu, self.a, self.e, self.inclination, self.raan, self.argp,
                     self.anomaly, self.t0)

    # --- one arc: the orbit as given ------------------------------------------------------
    def arc(self, t):
        """The Keplerian orbit in force at the time ``t``: this one (an ``Orbit`` is one
        arc; a run's ``Reference`` chains the arcs of its rebases)."""
        return self

    def _each_arc(self, t, function):
        """``function(self, t)``, ``t`` as an array."""
        return function(self, np.asarray(t, dtype=float))

    def _one(self, t):
        """Position and velocity (6,) of this arc at one time ``t`` (a float), compiled
        (``kepler_state``) and remembered: the loads of a time step ask for the same
        time (a step's Python cost in orbit: a few microseconds)."""
        if self._last != t:
            kepler_state(self.mu, self.a, self.e, self.mean_anomaly0, self.mean_motion,
                         self.t0, self.axes, t, self._state)
            self._last = t
        return self._state

    def _perifocal_at(self, t):
        """Position and velocity of this arc in its perifocal axes (P, Q) at the times
        ``t`` (array), shape ``t.shape + (2,)``."""
        ecc = eccentric_anomaly(self.mean_anomaly0 + self.mean_motion * (t - self.t0),
                                self.e)
        c, s = np.cos(ecc), np.sin(ecc)
        root = np.sqrt(1.0 - self.e**2)
        r = self.a * (1.0 - self.e * c)
        pos = np.stack([self.a * (c - self.e), self.a * root * s], axis=-1)
        speed = np.sqrt(self.mu * self.a) / r
        vel = np.stack([-speed * s, speed * root * c], axis=-1)
        return pos, vel

    def _true_anomaly(self, t):
        pos = self._perifocal_at(t)[0]
        angle = np.arctan2(pos[..., 1], pos[..., 0])
        mean = self.mean_anomaly0 + self.mean_motion * (t - self.t0)
        return angle + 2 * np.pi * np.round((mean - angle) / (2 * np.pi))

    def _lvlh(self, t):
        pos = self._perifocal_at(t)[0]
        radial = pos / np.linalg.norm(pos, axis=-1, keepdims=True)
        along = np.stack([-radial[..., 1], radial[..., 0]], axis=-1)
        plane = self.axes[:, :2].T
        normal = np.broadcast_to(self.axes[:, 2], radial.shape[:-1] + (3,))
        return np.stack([radial @ plane, along @ plane, normal], axis=-2)

    def _angular_velocity(self, t):
        pos = self._perifocal_at(t)[0]
        h = np.sqrt(self.mu * self.a * (1.0 - self.e**2))
        rate = h / np.sum(pos**2, axis=-1)
        return rate[..., None] * self.axes[:, 2]

    @property
    def central_body(self):
        """The entry of ``CENTRAL_BODIES`` of this orbit's ``mu`` (the Earth for
        ``MU_EARTH``, the Sun for ``MU_SUN``), or None for another ``mu``."""
        return next((body for body in CENTRAL_BODIES.values() if body.mu == self.mu), None)

    def body_rotation(self):
        """The central body's angular velocity (3,) (rad/s) about the inertial ``z`` axis
        (``central_body.rotation_rate``): what an atmosphere or a plasma co-rotating with
        the body turns at; zero for a ``mu`` of no known body."""
        body = self.central_body
        rate = None if body is None else body.rotation_rate
        return np.array([0.0, 0.0, rate or 0.0])

    @property
    def periapsis(self):
        """Periapsis distance ``a (1 - e)`` (m) from the central body's centre."""
        return self.a * (1.0 - self.e)

    def check_above(self, radius, body="the central body"):
        """Refuse (``ValueError``) an orbit whose periapsis ``a (1 - e)`` lies inside a
        central body of ``radius`` (m; None: not known, nothing to check): ``a`` is
        measured from the body's centre (``R_EARTH + altitude``), and an elliptic orbit
        that dips below the surface would fly through the body."""
        if radius is None or self.periapsis > radius:
            return
        where = (f"a = {self.a:.10g} m" if self.e == 0.0 else f"the periapsis a (1 - e) "
                 f"= {self.a:.10g} m * (1 - {self.e:.6g}) = {self.periapsis:.10g} m")
        raise ValueError(
            f"Orbit: {where} lies inside {body} of radius "
            f"{radius:.10g} m: a is the semi-major axis from the body's centre (the "
            f"radius plus the altitude: for 400 km above the surface a = "
            f"{radius + 400e3:.10g} m); a (1 - e) must exceed {radius:.10g} m")

    def __repr__(self):
        return (f"Orbit(mu={self.mu:.10g}, a={self.a:.10g}, e={self.e:.6g}, "
                f"inclination={self.inclination:.6g}, raan={self.raan:.6g}, "
                f"argp={self.argp:.6g}, anomaly={self.anomaly:.6g}, t0={self.t0:.6g})")


def co_rotation(omega, orbit):
    """The rotation rate (3,) (rad/s) of a medium a load's ``omega`` gives (an atmosphere,
    a plasma): ``omega`` itself, or when it is None the central body's rotation of the
    system's ``orbit`` (``Orbit.body_rotation``), zero without an orbit (None)."""
    if omega is not None:
        return np.array(omega, dtype=float)
    return np.zeros(3) if orbit is None else orbit.body_rotation()
