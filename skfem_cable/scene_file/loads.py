"""The ``[[point_masses]]`` and the ``[loads]`` of a scene file (gravity, centrifugal,
``[[loads.point]]``, ``[[loads.line]]``, ``[[loads.moment]]``).  ``LOADS`` maps each array
of load tables to its reader; a new kind of load is one more entry."""

from ..cable import Cable
from ..loads import PointMoment
from .schema import positive, vector3


def read_point_mass(t, bodies, system):
    """A ``[[point_masses]]`` table: ``mass`` at a cable node or body point."""
    system.add_point_mass(bodies.point(t, "at"), t.get("mass", positive))
    t.finish()


def point_load(p, bodies, system):
    """``[[loads.point]]``: a dead ``force`` at a cable node."""
    system.add_point_load(bodies.point(p, "at", body_points=False), p.get("force", vector3))


def line_load(p, bodies, system):
    """``[[loads.line]]``: a uniform ``force_per_length`` on a cable."""
    system.add_line_load(bodies.body(p, "cable", Cable), p.get("force_per_length", vector3))


def moment_load(p, bodies, system):
    """``[[loads.moment]]``: a ``moment`` fixed in space at a cable node."""
    system.add_load(PointMoment(bodies.point(p, "at", body_points=False),
                                p.get("moment", vector3)))


#: Readers of the arrays of load tables ``[[loads.KEY]]``: ``reader(p, bodies, system)``.
LOADS = {"point": point_load, "line": line_load, "moment": moment_load}


def read_loads(t, bodies, system, analysis):
    """The ``[loads]`` table, added to ``system``."""
    gravity = t.get("gravity", vector3, None)
    if gravity is not None:
        system.add_gravity(gravity)
    if t.has("centrifugal"):
        if analysis != "static":
            t.fail("centrifugal", "applies to static analyses only (the steady state in a "
                   "frame rotating at this rate)", t.data["centrifugal"])
        system.add_centrifugal(t.get("centrifugal", vector3))
    for key, reader in LOADS.items():
        for p in t.tables(key):
            reader(p, bodies, system)
            p.finish()
    t.finish()
