"""The ``[[deploy]]`` tables of a scene file: cables leaving (or entering) a reel
(``System.deploy``)."""

from ..cable import Cable
from ..deploy import constant_rate, smooth_profile
from .schema import number, positive, vector3


def read_length(t):
    """``length``: a number (m, held), ``{start, rate}`` (a constant rate, m/s) or
    ``{start, end, duration}`` (a smooth change, ``deploy.smooth_profile``)."""
    value = t.data.get("length")
    if not isinstance(value, dict):
        return t.get("length", positive), None, None
    p = t.inline("length")
    start = p.get("start", positive)
    if "rate" in p.data:
        profile = constant_rate(start, p.get("rate", number))
    else:
        profile = smooth_profile(start, p.get("end", positive), p.get("duration", positive))
    p.finish()
    return profile


def read_deploy(t, bodies, system):
    """One ``[[deploy]]`` table: ``cable``, ``length``, optional ``anchor`` (a ground
    point or ``{body, point}``; default the cable's node 0), ``direction`` (reels fixed in
    space) and ``capacity`` (m)."""
    cable = bodies.body(t, "cable", Cable)
    anchor = bodies.point(t, "anchor", ground=True) if "anchor" in t.data else None
    length, rate, acceleration = read_length(t)
    try:
        system.deploy(cable, anchor, length, rate, acceleration,
                      direction=t.get("direction", vector3, None),
                      capacity=t.get("capacity", positive, None))
    except ValueError as err:
        t.fail("length", f"is not a valid deployment: {err}")
    t.finish()
