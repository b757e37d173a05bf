"""The ``[[point_masses]]`` and the ``[loads]`` of a scene file (gravity, centrifugal,
``[[loads.point]]``, ``[[loads.line]]``, ``[[loads.moment]]``, ``[[loads.morison]]``,
``[[loads.buoyancy]]``, ``[[loads.free_molecular]]``).  ``LOADS`` maps each array
of load tables to its reader; a new kind of load is one more entry."""

from ..bodies.cable import Cable
from ..loads.drag import Buoyancy, CurrentProfile, FreeMolecularDrag, MorisonDrag
from ..loads.point import PointMoment
from .schema import input_or, non_negative, number, positive, vector3


def read_point_mass(t, bodies, system):
    """A ``[[point_masses]]`` table: ``mass`` at a cable node or body point."""
    system.add_point_mass(bodies.point(t, "at"), t.get("mass", positive))
    t.finish()


def point_load(p, bodies, system):
    """``[[loads.point]]``: a dead ``force`` at a cable node, or an input
    (``{input = "name", value = [...]}``) that a controller sets."""
    system.add_point_load(bodies.point(p, "at", body_points=False),
                          p.get("force", input_or(vector3)))


def line_load(p, bodies, system):
    """``[[loads.line]]``: a uniform ``force_per_length`` on a cable."""
    system.add_line_load(bodies.body(p, "cable", Cable), p.get("force_per_length", vector3))


def moment_load(p, bodies, system):
    """``[[loads.moment]]``: a ``moment`` fixed in space at a cable node."""
    system.add_load(PointMoment(bodies.point(p, "at", body_points=False),
                                p.get("moment", vector3)))


def profile(p, key):
    """An inline table ``{ elevations = [...], velocities = [[...], ...], vertical = [...] }``
    as a ``CurrentProfile``."""
    if not isinstance(p.data[key], dict):
        p.fail(key, "must be an inline table { elevations = ..., velocities = ... }",
               p.data[key])
    t = p.inline(key)

    def numbers(v):
        if not isinstance(v, list) or not v:
            raise ValueError("must be a non-empty list of numbers")
        return [number(x) for x in v]

    def vectors(v):
        if not isinstance(v, list) or not v:
            raise ValueError("must be a non-empty list of 3-vectors")
        return [vector3(x) for x in v]

    z, u = t.get("elevations", numbers), t.get("velocities", vectors)
    vertical = t.get("vertical", vector3, (0.0, 0.0, 1.0))
    t.finish()
    try:
        return CurrentProfile(z, u, vertical)
    except ValueError as err:
        p.fail(key, str(err))


def morison_load(p, bodies, system):
    """``[[loads.morison]]``: Morison drag of a steady ``current`` (vector) or
    ``current_profile`` on a cable."""
    cable = bodies.body(p, "cable", Cable)
    args = [p.get(k, positive) for k in ("rho", "diameter")]
    args += [p.get(k, non_negative) for k in ("cd_normal", "cd_tangential")]
    current = p.get("current", vector3, None)
    if p.has("current_profile"):
        if current is not None:
            p.fail("current_profile", "cannot be given with current")
        current = profile(p, "current_profile")
    system.add_load(MorisonDrag(cable, *args, current=current))


def buoyancy_load(p, bodies, system):
    """``[[loads.buoyancy]]``: the weight of the water a cable displaces."""
    system.add_load(Buoyancy(bodies.body(p, "cable", Cable), p.get("rho", positive),
                             p.get("diameter", positive), p.get("g", vector3)))


def free_molecular_load(p, bodies, system):
    """``[[loads.free_molecular]]``: free-molecular drag of a rarefied atmosphere."""
    system.add_load(FreeMolecularDrag(
        bodies.body(p, "cable", Cable), p.get("density", positive),
        p.get("diameter", positive), p.get("cd", non_negative, 2.2),
        p.get("velocity", vector3, (0.0, 0.0, 0.0)), p.get("omega", vector3, None)))


#: Readers of the arrays of load tables ``[[loads.KEY]]``: ``reader(p, bodies, system)``.
LOADS = {"point": point_load, "line": line_load, "moment": moment_load,
         "morison": morison_load, "buoyancy": buoyancy_load,
         "free_molecular": free_molecular_load}


def read_loads(t, bodies, system, analysis):
    """The ``[loads]`` table, added to ``system``."""
    gravity = t.get("gravity", vector3, None)
    if gravity is not None:
        system.add_gravity(gravity)
    if t.has("centrifugal"):
        if analysis != "static":
            t.fail("centrifugal", "applies to static analyses only (the steady state in a "
                   "frame rotating at this rate); analysis = \"steady\" adds it from "
                   "[solver] omega", t.data["centrifugal"])
        system.add_centrifugal(t.get("centrifugal", vector3))
    for key, reader in LOADS.items():
        for p in t.tables(key):
            reader(p, bodies, system)
            p.finish()
    t.finish()
