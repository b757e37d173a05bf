"""``System.contact``: the contact load between two things a system's lines touch,
chosen by what they declare (``protocols.Surface``: ``surface_array``; a line body:
``line_points``), not by their classes."""

import itertools

from ..loads.contact import LineSurfaceContact
from ..loads.contact_body import LineBodyContact
from ..loads.contact_lines import LineLineContact


def role(item, name):
    """``"surface"`` or ``"line"``: what ``item`` (the parameter ``name``) declares, or
    ``TypeError`` naming the parameter."""
    if callable(getattr(item, "surface_array", None)):
        return "surface"
    if callable(getattr(item, "line_points", None)):
        return "line"
    raise TypeError(f"{name} must be a line body (with line_points, e.g. a Cable) or a "
                    f"surface (with surface_array, e.g. sc.Cylinder), got {item!r}")


def _lines(first):
    """The line bodies of the sequence ``first`` (``TypeError`` naming ``first`` or
    ``second`` when it is not one)."""
    if role_or_none(first) is not None:
        raise TypeError(f"second must be given with a single body or surface as first "
                        f"(or give first a sequence of line bodies), got {first!r}")
    try:
        lines = list(first)
    except TypeError:
        raise TypeError(f"first must be a sequence of line bodies when second is not "
                        f"given, got {first!r}") from None
    for k, line in enumerate(lines):
        if role(line, f"first[{k}]") != "line":
            raise TypeError(f"first[{k}] must be a line body, got the surface {line!r}")
    return lines


def role_or_none(item):
    """``role`` of ``item``, or None where it declares neither."""
    try:
        return role(item, "item")
    except TypeError:
        return None


def distinct(name, taken):
    """``name``, else the first of ``name_2``, ``name_3``, ... not in ``taken``."""
    candidates = itertools.chain([name], (f"{name}_{k}" for k in itertools.count(2)))
    return next(n for n in candidates if n not in taken)


def contact(first, second=None, friction=0.0, taken=(), **options):
    """The contact load of ``first`` and ``second`` (a line body and a surface, in either
    order; a surface carried by a rigid body, with its ``body``, gives a
    ``LineBodyContact``) with Coulomb's ``friction``; ``options`` of
    ``LineSurfaceContact`` (``radius``, ``stiffness``, ``tolerance``, ``damping``,
    ``slip_velocity``, ``name``).  Two line bodies (or one twice: self-contact), or a
    sequence of line bodies as ``first`` and no ``second`` (contact among them all), give
    a ``LineLineContact`` (its ``options``); two surfaces raise ``ValueError``.  Without a
    ``name``, the default one numbered past the names in ``taken`` (``distinct``: a
    line's second contact, ``contact_<line>_2``), so that two contacts' per-step outputs
    do not clash."""
    load = _contact(first, second, friction, **options)
    if "name" not in options:
        load.name = distinct(load.name, set(taken))
    return load


def _contact(first, second, friction, **options):
    """``contact`` by the roles of ``first`` and ``second``."""
    if second is None:
        lines = _lines(first)
        return LineLineContact(*lines, friction=friction, **options)
    roles = (role(first, "first"), role(second, "second"))
    if roles in (("line", "surface"), ("surface", "line")):
        line, surface = (first, second) if roles[0] == "line" else (second, first)
        carried = getattr(surface, "body", None) is not None
        return (LineBodyContact if carried else LineSurfaceContact)(line, surface, friction,
                                                                    **options)
    if roles == ("line", "line"):
        return LineLineContact(first, second, friction=friction, **options)
    raise ValueError(f"contact between two surfaces ({first!r}, {second!r}): fixed surfaces "
                     "do not move; give a line body as first or second")
