"""The ``[[deploy]]`` tables of a scene file: cables leaving (or entering) a reel
(``System.deploy``), with a prescribed free length or from a reel with inertia and a torque
law (``reel``)."""

from ..bodies.cable import Cable
from ..bodies.reel import Brake, Motor, Reel, Servo
from ..constraints.deploy import constant_rate, smooth_profile
from .schema import input_or, number, positive, vector3


def read_profile(t, key):
    """``t[key]``: a number (m, held), ``{start, rate}`` (a constant rate, m/s) or
    ``{start, end, duration}`` (a smooth change, ``deploy.smooth_profile``); returns
    ``(length, rate, acceleration)`` (the last two None for a number)."""
    value = t.data.get(key)
    if not isinstance(value, dict):
        return t.get(key, positive), None, None
    p = t.inline(key)
    start = p.get("start", positive)
    if "rate" in p.data:
        profile = constant_rate(start, p.get("rate", number))
    else:
        profile = smooth_profile(start, p.get("end", positive), p.get("duration", positive))
    p.finish()
    return profile


def read_reel(t, bodies):
    """The ``Reel`` body of a ``[[deploy]]`` table's ``reel = {radius, inertia, brake |
    motor | servo}`` (registered in ``bodies`` as ``"<cable> reel"``; it must exist
    before the system is built), or None without ``reel``.  ``brake``: N m s/m; ``motor``:
    a torque (N m, or ``{input = "name", value = ...}`` that a controller sets);
    ``servo``: ``{length, stiffness, damping}`` with ``length`` as the prescribed
    length."""
    if not t.has("reel"):
        return None
    cable = bodies.body(t, "cable", Cable)
    r = t.inline("reel")
    laws = [key for key in ("brake", "motor", "servo") if key in r.data]
    if len(laws) > 1:
        r.fail(laws[1], f"and {laws[0]} are two torque laws: give at most one")
    law = None
    if "brake" in r.data:
        law = Brake(r.get("brake", number))
    elif "motor" in r.data:
        law = Motor(r.get("motor", input_or(number)))
    elif "servo" in r.data:
        s = r.inline("servo")
        length, rate, _ = read_profile(s, "length")
        law = Servo(length if callable(length) else (lambda t, x=length: x),
                    s.get("stiffness", positive), s.get("damping", number), rate=rate)
        s.finish()
    radius, inertia = r.get("radius", positive), r.get("inertia", number, 0.0)
    if inertia < 0:
        r.fail("inertia", "must be >= 0 (kg m^2)", inertia)
    r.finish()
    reel = Reel(cable.length, radius, inertia, law, name=f"{cable.name} reel")
    bodies.add(r, reel)
    return reel


def read_deploy(t, bodies, system, reel=None):
    """One ``[[deploy]]`` table: ``cable``, ``length`` (or a ``reel``, ``read_reel``),
    optional ``anchor`` (a ground point or ``{body, point}``; default the cable's node 0),
    ``direction`` (an exit guide: in space, or in the body frame of a body anchor) and
    ``capacity`` (m; required with a reel)."""
    cable = bodies.body(t, "cable", Cable)
    anchor = bodies.point(t, "anchor", ground=True) if "anchor" in t.data else None
    if reel is not None and "length" in t.data:
        t.fail("length", "and reel both set the free length: give one")
    length, rate, acceleration = (None, None, None) if reel is not None else \
        read_profile(t, "length")
    try:
        system.deploy(cable, anchor, length, rate, acceleration,
                      direction=t.get("direction", vector3, None),
                      capacity=t.get("capacity", positive, None), reel=reel)
    except ValueError as err:
        t.fail("reel" if reel is not None else "length",
               f"is not a valid deployment: {err}")
    t.finish()
