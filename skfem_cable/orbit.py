"""Keplerian reference orbits and the central body's differential gravity.

A system in orbit keeps small coordinates: positions are offsets ``delta`` from a
reference point moving on a Keplerian orbit, in axes parallel to the inertial ones (the
E-sail paper's translated frame, Sect. 2, which it needs because heliocentric positions of
1.5e11 m leave about 3e-5 m of double precision).  The reference point accelerates with
the central body's gravity ``g(R)``, so a body at ``R + delta`` feels, in the reference
point's frame, the *differential* gravity ``g(R + delta) - g(R)``: two nearly equal
vectors whose difference must not be formed by subtraction.  :func:`differential_gravity`
uses Battin's cancellation-free form (Battin, *An Introduction to the Mathematics and
Methods of Astrodynamics*, AIAA 1999: the function ``f(q)`` of Encke's method).

A long run with thrust carries its system away from the reference point; Encke's
*rectification* (``solvers.rectify``) then re-bases the reference on the osculating orbit
of the centre of mass.  The run's reference becomes a chain of Keplerian arcs, each in
force from its rebase time on: a ``Reference``, the run's state (made per run from the
system's ``Orbit``, held by the terms that read ``R(t)``, saved in checkpoints, carried by
the run's ``Result``), whose ``position``, ``velocity``, ``lvlh`` and the other functions
of time evaluate the arc in force at each time: the offsets a run saved at any time read
against the reference they were computed in.  An ``Orbit`` is one arc, as given: a run
never changes it.

Angles are in radians, lengths in metres, times in seconds, ``mu`` in m^3/s^2.
"""

import bisect
import math
from dataclasses import dataclass

import numpy as np
from numba import njit, vectorize

MU_EARTH = 3.986004418e14
"""Earth's gravitational parameter (m^3/s^2, WGS 84 / IERS)."""
MU_SUN = 1.32712440018e20
"""The Sun's gravitational parameter (m^3/s^2, IAU 2009 / DE405)."""
R_EARTH = 6378.137e3
"""Earth's equatorial radius (m, WGS 84)."""
AU = 1.495978707e11
"""The astronomical unit (m, IAU 2012, exact)."""
OMEGA_EARTH = 7.2921150e-5
"""The Earth's rotation rate (rad/s, IERS)."""
J2_EARTH = 1.08262668e-3
"""The Earth's second zonal harmonic (EGM2008, unnormalised)."""
R_SUN = 6.957e8
"""The Sun's nominal radius (m, IAU 2015 Resolution B3)."""
OMEGA_SUN = 2.8653e-6
"""The Sun's sidereal (Carrington) rotation rate (rad/s: one turn in 25.38 days)."""


@dataclass(frozen=True)
class CentralBody:
    """A central body: gravitational parameter ``mu`` (m^3/s^2), equatorial ``radius``
    (m), second zonal harmonic ``j2`` and ``rotation_rate`` (rad/s, about the inertial
    ``z`` axis: the rate of the atmosphere a drag load co-rotates with); None: no value
    known."""

    mu: float
    radius: float | None
    j2: float | None
    rotation_rate: float | None = None


#: The central bodies known by name (scene files' ``central_body``) and by ``mu``
#: (``Orbit.central_body``); a new one is one more entry.
CENTRAL_BODIES = {"earth": CentralBody(MU_EARTH, R_EARTH, J2_EARTH, OMEGA_EARTH),
                  "sun": CentralBody(MU_SUN, R_SUN, None, OMEGA_SUN)}

KEPLER_ITERATIONS = 50
EPS = float(np.finfo(float).eps)


def _finite(name, value):
    value = float(value)
    if not np.isfinite(value):
        raise ValueError(f"Orbit: {name} must be finite, got {value}")
    return value


def _rotation(raan, inclination, argp):
    """Columns: periapsis direction P, its in-plane normal Q and the orbit normal W, in
    the inertial axes (the 3-1-3 rotation ``Rz(raan) Rx(inclination) Rz(argp)``)."""
    co, so = np.cos(raan), np.sin(raan)
    ci, si = np.cos(inclination), np.sin(inclination)
    cw, sw = np.cos(argp), np.sin(argp)
    return np.array([
        [co * cw - so * sw * ci, -co * sw - so * cw * ci, so * si],
        [so * cw + co * sw * ci, -so * sw + co * cw * ci, -co * si],
        [sw * si, cw * si, ci],
    ])


@njit(cache=True)
def solve_kepler(mean_anomaly, e):
    """Solve Kepler's equation ``E - e sin E = M`` to round-off (``0 <= e < 1``) for one
    mean anomaly (compiled: a call from Python costs under a microsecond).

    Newton's iteration on ``M`` reduced to ``[-pi, pi]``, started from Danby's
    ``E = M + 0.85 e sign(sin M)`` (convergent for every ``e < 1``).
    """
    m = mean_anomaly - 2.0 * math.pi * round(mean_anomaly / (2.0 * math.pi))
    ecc = m + 0.85 * e * math.copysign(1.0, math.sin(m)) if m != 0.0 else 0.0
    for _ in range(KEPLER_ITERATIONS):
        step = (ecc - e * math.sin(ecc) - m) / (1.0 - e * math.cos(ecc))
        ecc -= step
        if abs(step) <= 4.0 * EPS * max(1.0, abs(ecc)):
            break
    return ecc + (mean_anomaly - m)


@njit(cache=True)
def kepler_state(mu, a, e, mean_anomaly0, mean_motion, t0, axes, t, out):
    """Position and velocity at time ``t`` of the orbit of these elements (``axes``: the
    perifocal axes P, Q, W as columns) into ``out`` (6,), in scalar arithmetic."""
    ecc = solve_kepler(mean_anomaly0 + mean_motion * (t - t0), e)
    c, s = math.cos(ecc), math.sin(ecc)
    root = math.sqrt(1.0 - e * e)
    speed = math.sqrt(mu * a) / (a * (1.0 - e * c))
    x, y = a * (c - e), a * root * s
    u, w = -speed * s, speed * root * c
    for i in range(3):
        out[i] = x * axes[i, 0] + y * axes[i, 1]
        out[3 + i] = u * axes[i, 0] + w * axes[i, 1]


@vectorize(["float64(float64, float64)"], cache=True)
def eccentric_anomaly(mean_anomaly, e):
    """``solve_kepler`` as a numba ufunc, for arrays of mean anomalies."""
    return solve_kepler(mean_anomaly, e)


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


class Reference(_FunctionsOfTime):
    """The reference of a run of a system in orbit: the system's ``orbit`` and the arcs
    of the rebases of Encke's rectification (``solvers.rectify``), each in force from its
    rebase time on.  A run's state, not the model's: ``simulate`` makes one per run from
    ``System.orbit`` (the terms reading ``R(t)``, ``V(t)`` hold it through the system's
    binding, ``Layout.reference``), checkpoints save its ``rebases`` and the run's
    ``Result`` carries it (``Result.reference``).

    Parameters
    ----------
    orbit : Orbit
        The orbit as given: the arc in force before the first rebase.
    rebases : array_like (k, 7), optional
        Rebases to make at once (``restore``).

    Examples
    --------
    >>> import skfem_cable as sc
    >>> orbit = sc.Orbit(sc.MU_EARTH, 7e6)
    >>> reference = sc.Reference(orbit)
    >>> reference.rebase(orbit.position(10.0) + 1.0, orbit.velocity(10.0), 10.0)
    >>> reference.rebases.shape, len(sc.Reference(orbit).rebases)
    ((1, 7), 0)
    """

    def __init__(self, orbit, rebases=None):
        self.orbit = orbit
        self.restore(rebases)

    @property
    def mu(self):
        """The orbit's gravitational parameter (m^3/s^2)."""
        return self.orbit.mu

    @property
    def t0(self):
        """The orbit's epoch (s)."""
        return self.orbit.t0

    @property
    def central_body(self):
        """The orbit's ``central_body``."""
        return self.orbit.central_body

    def body_rotation(self):
        """The orbit's ``body_rotation()``."""
        return self.orbit.body_rotation()

    def copy(self):
        """A reference with the same arcs, to the last bit, that later rebases of this one
        leave alone."""
        return Reference(self.orbit, self.rebases)

    # --- the arcs of the rebases ---------------------------------------------------------
    def rebase(self, r, v, t):
        """Encke's rectification: from time ``t`` on, the reference is the orbit through
        the absolute position ``r`` (m) and velocity ``v`` (m/s), ``from_state(mu, r, v,
        t)``; before ``t`` the arcs in force stay.  Times of rebases must increase."""
        t = float(t)
        if self._starts and not t > self._starts[-1]:
            raise ValueError(f"Reference.rebase: t = {t!r} s is not after the last "
                             f"rebase at {self._starts[-1]!r} s")
        row = np.concatenate([[t], np.asarray(r, dtype=float), np.asarray(v, dtype=float)])
        self._arcs.append((row, Orbit.from_state(self.mu, row[1:4], row[4:], t)))
        self._starts.append(t)

    @property
    def rebases(self):
        """The rebases so far, one row ``(t, r, v)`` (7,) each: shape (k, 7)."""
        return np.array([row for row, _ in self._arcs]).reshape(-1, 7)

    def restore(self, rebases=None):
        """Drop the rebases, then make those of ``rebases`` (rows of ``rebases``) again:
        the same arcs, to the last bit."""
        self._arcs, self._starts = [], []
        rows = np.asarray([] if rebases is None else rebases, dtype=float).reshape(-1, 7)
        for row in rows:
            self.rebase(row[1:4], row[4:7], row[0])

    def arc(self, t):
        """The Keplerian orbit in force at the time ``t`` (a float): the orbit as given
        before the first rebase, else that of the latest rebase at or before ``t``."""
        if not self._starts or t < self._starts[0]:
            return self.orbit
        return self._arcs[bisect.bisect_right(self._starts, t) - 1][1]

    def _each_arc(self, t, function):
        """``function(arc, times)`` over the times ``t`` (array_like) in force on each
        arc, gathered in the shape of ``t`` (leading axes)."""
        t = np.asarray(t, dtype=float)
        if not self._starts:
            return function(self.orbit, t)
        flat = t.reshape(-1)
        index = np.searchsorted(self._starts, flat, side="right")
        out = None
        for k in np.unique(index):
            where = index == k
            part = function(self.orbit if k == 0 else self._arcs[k - 1][1], flat[where])
            if out is None:
                out = np.empty((flat.size, *part.shape[1:]))
            out[where] = part
        return out.reshape(t.shape + out.shape[1:])


def co_rotation(omega, orbit):
    """The rotation rate (3,) (rad/s) of a medium a load's ``omega`` gives (an atmosphere,
    a plasma): ``omega`` itself, or when it is None the central body's rotation of the
    system's ``orbit`` (``Orbit.body_rotation``), zero without an orbit (None)."""
    if omega is not None:
        return np.array(omega, dtype=float)
    return np.zeros(3) if orbit is None else orbit.body_rotation()


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
