"""The ``[[contacts]]`` of a scene file: a cable touching a fixed surface, or one carried
by a named rigid body (``body = "NAME"``: the surface's vectors in the body's frame,
``body.plane``, ...; ``System.contact``, ``docs/contact.md``).  ``SURFACES`` maps each
surface key to its class and the keys of its inline table; a new kind of surface is one
more entry."""

from ..bodies.cable import Cable
from ..bodies.rigid import RigidBody
from ..loads.surfaces import Cylinder, Edge, Plane, Sphere
from .schema import non_negative, positive, vector3

#: The surfaces of a contact table: ``key = { ... }`` with the parameters of the class, in
#: the order of its constructor, and their checks.
SURFACES = {"plane": (Plane, (("point", vector3), ("normal", vector3))),
            "sphere": (Sphere, (("centre", vector3), ("radius", positive))),
            "cylinder": (Cylinder, (("axis_point", vector3), ("axis", vector3),
                                    ("radius", positive))),
            "edge": (Edge, (("point", vector3), ("normal", vector3), ("outward", vector3),
                            ("radius", positive)))}

#: The surfaces a rigid body carries (``body = "NAME"``): its methods of these names.
CARRIED = ("plane", "sphere", "cylinder")

#: The optional numbers of a contact table (``LineSurfaceContact``'s keywords).
OPTIONS = (("radius", positive), ("stiffness", positive), ("tolerance", positive),
           ("damping", non_negative), ("slip_velocity", positive))


def read_surface(t, bodies):
    """The one surface of the contact table ``t``: fixed, or carried by the rigid body
    ``t["body"]`` (one of ``bodies``)."""
    given = [key for key in SURFACES if t.has(key)]
    if len(given) != 1:
        t.fail("plane", f"or sphere or cylinder or edge: exactly one surface must be given, got "
               f"{given or 'none'}")
    key = given[0]
    cls, keys = SURFACES[key]
    carrier = bodies.body(t, "body", RigidBody) if t.has("body") else None
    if carrier is not None and key not in CARRIED:
        t.fail("body", f"carries a {', '.join(CARRIED)}, not a {key}", key)
    s = t.inline(key)
    args = [s.get(name, check) for name, check in keys]
    s.finish()
    try:
        return cls(*args) if carrier is None else getattr(carrier, key)(*args)
    except ValueError as err:
        t.fail(key, str(err))


def read_contact(t, bodies, system):
    """A ``[[contacts]]`` table: ``cable`` (name) on one surface (``plane``, ``sphere``,
    ``cylinder`` or ``edge``; with ``body``, a named rigid body's plane, sphere or
    cylinder) with ``friction`` (default 0) and the optional numbers ``OPTIONS``."""
    cable = bodies.body(t, "cable", Cable)
    surface = read_surface(t, bodies)
    friction = t.get("friction", non_negative, 0.0)
    options = {name: t.get(name, check, None) for name, check in OPTIONS}
    t.finish()
    system.contact(cable, surface, friction,
                   **{name: value for name, value in options.items() if value is not None})
