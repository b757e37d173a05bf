"""The ``[orbit]`` table of a scene file: the system in orbit (``System.add_orbit``) about a
named central body (``CENTRAL_BODIES``) or one of given ``mu``.  Lengths in m, angles in
rad (as every angle of a scene file), times in s."""

from dataclasses import dataclass

from ..space.constants import CENTRAL_BODIES, CentralBody
from ..space.orbit import Orbit
from .schema import choice, non_negative, number, one_of, positive


@dataclass
class OrbitSpec:
    """What ``[orbit]`` says: the ``Orbit`` and the ``System.add_orbit`` keywords ``j2``
    and ``body_radius`` (both None: a point-mass central body)."""

    orbit: Orbit
    j2: float | None = None
    body_radius: float | None = None

    def place(self, system, epoch=None):
        """Put ``system`` in this orbit (``System.add_orbit``) at ``epoch`` (an ``Epoch``
        or None: the ``[environment]``'s)."""
        system.add_orbit(self.orbit, j2=self.j2, body_radius=self.body_radius, epoch=epoch)


def _as_given(v):
    return v


def eccentricity(v):
    x = number(v)
    if not 0.0 <= x < 1.0:
        raise ValueError("must be a number in [0, 1) (elliptic orbits)")
    return x


def j2_value(v):
    if isinstance(v, bool):
        return v
    try:
        return number(v)
    except ValueError:
        raise ValueError("must be true (the central body's J2), false or a number") from None


def read_central_body(t):
    """``central_body`` (a name of ``CENTRAL_BODIES``) or ``mu`` (m^3/s^2), exactly one;
    ``body_radius`` (m) overrides the named body's radius.  Returns ``(mu, radius, j2)``,
    ``radius`` and ``j2`` None when unknown."""
    checks = {"central_body": choice(*CENTRAL_BODIES), "mu": positive}
    key, _ = one_of(t, tuple(checks), _as_given)
    if key is None:
        t.missing("central_body", f"is required ({' or '.join(map(repr, CENTRAL_BODIES))}), "
                  "or mu (m^3/s^2)", tuple(checks))
    value = t.get(key, checks[key])
    body = CENTRAL_BODIES[value] if key == "central_body" else CentralBody(value, None, None)
    return body.mu, t.get("body_radius", positive, body.radius), body.j2


def read_semi_major_axis(t, radius):
    """``a`` (m) or ``altitude`` (m above the central body's radius), exactly one."""
    key, _ = one_of(t, ("a", "altitude"), _as_given)
    if key is None:
        t.missing("a", "is required (the semi-major axis, m), or altitude (m above the "
                  "central body's radius)", ("a", "altitude"))
    if key == "a":
        return t.get("a", positive)
    value = t.get("altitude", non_negative)
    if radius is None:
        t.fail("altitude", "needs the central body's radius: name central_body, or give "
               "body_radius (m) with mu", value)
    return radius + value


def read_j2(t, radius, known):
    """``j2``: false (default), true (the central body's known value) or a number; the
    J2 term needs the body's radius."""
    value = t.get("j2", j2_value, False)
    if value is False:
        return None
    if value is True and known is None:
        t.fail("j2", "= true needs a central body whose J2 is known (central_body = "
               "\"earth\"): give j2 as a number instead", value)
    if radius is None:
        t.fail("j2", "needs the central body's radius: name central_body, or give "
               "body_radius (m) with mu", value)
    return known if value is True else value


def read_orbit(t):
    """The ``[orbit]`` table: the central body (``read_central_body``), the size (``a`` or
    ``altitude``), ``e`` (default 0), ``inclination``, ``raan``, ``argp`` (rad, default 0),
    ``anomaly`` (the true anomaly at ``t0``, rad, default 0), ``t0`` (s, default 0) and
    ``j2`` (``read_j2``).  Returns an ``OrbitSpec``."""
    mu, radius, known_j2 = read_central_body(t)
    a = read_semi_major_axis(t, radius)
    elements = {"e": t.get("e", eccentricity, 0.0)}
    for key in ("inclination", "raan", "argp", "anomaly", "t0"):
        elements[key] = t.get(key, number, 0.0)
    j2 = read_j2(t, radius, known_j2)
    t.finish()
    try:
        orbit = Orbit(mu, a, **elements)
    except ValueError as err:  # a radius and an altitude that overflow together
        t.fail("a" if "a" in t.data else "altitude", f"is refused: {err}")
    return OrbitSpec(orbit, j2, None if j2 is None else radius)


def place_in_orbit(root, spec, system, epoch=None):
    """Put ``system`` in the orbit ``spec`` read from ``root.orbit`` at ``epoch`` (the
    ``[environment]``'s, an ``Epoch`` or None); a scene with uniform
    gravity (``loads.gravity``) or that the orbit refuses otherwise fails naming the
    tables."""
    loads = root.data.get("loads")
    if isinstance(loads, dict) and "gravity" in loads:
        root.fail("orbit", "excludes loads.gravity: in orbit the central body's "
                  "differential gravity replaces uniform gravity (remove one of the two)")
    try:
        spec.place(system, epoch)
    except ValueError as err:  # e.g. a deploying cable
        root.fail("orbit", f"is refused: {err}")
