"""The ``[[point_masses]]`` and the ``[loads]`` of a scene file (gravity, centrifugal,
``[[loads.point]]``, ``[[loads.line]]``, ``[[loads.moment]]``, ``[[loads.morison]]``,
``[[loads.buoyancy]]``, ``[[loads.free_molecular]]``, ``[[loads.atmospheric_drag]]``,
``[[loads.electrodynamic]]``).
``LOADS`` maps each array of load tables to its reader; a new kind of load is one more
entry."""

from ..bodies.cable import Cable
from ..bodies.rigid import RigidBody
from ..environment.oml import Cathode
from ..loads.atmosphere import AtmosphericDrag
from ..loads.drag import Buoyancy, CurrentProfile, FreeMolecularDrag, MorisonDrag
from ..loads.electrodynamic import ElectrodynamicForce
from ..loads.point import PointMoment
from .schema import choice, input_or, non_negative, number, one_of, positive, vector3


def read_point_mass(t, bodies, system):
    """A ``[[point_masses]]`` table: ``mass`` at a cable node or body point."""
    system.add_point_mass(bodies.point(t, "at"), t.get("mass", positive))
    t.finish()


def point_load(p, bodies, system, environment):
    """``[[loads.point]]``: a dead ``force`` at a cable node, or an input
    (``{input = "name", value = [...]}``) that a controller sets."""
    system.add_point_load(bodies.point(p, "at", body_points=False),
                          p.get("force", input_or(vector3)))


def line_load(p, bodies, system, environment):
    """``[[loads.line]]``: a uniform ``force_per_length`` on a cable."""
    system.add_line_load(bodies.body(p, "cable", Cable), p.get("force_per_length", vector3))


def moment_load(p, bodies, system, environment):
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


def morison_load(p, bodies, system, environment):
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


def buoyancy_load(p, bodies, system, environment):
    """``[[loads.buoyancy]]``: the weight of the water a cable displaces."""
    system.add_load(Buoyancy(bodies.body(p, "cable", Cable), p.get("rho", positive),
                             p.get("diameter", positive), p.get("g", vector3)))


def density(p, environment):
    """``density`` (kg/m^3), or when absent the ``[environment]``'s atmosphere (a model
    sampled once per step); one of the two is required."""
    if p.has("density") or environment.atmosphere is None:
        return p.get("density", positive)
    return environment.atmosphere


def free_molecular_load(p, bodies, system, environment):
    """``[[loads.free_molecular]]``: free-molecular drag of a rarefied atmosphere."""
    system.add_load(FreeMolecularDrag(
        bodies.body(p, "cable", Cable), density(p, environment),
        p.get("diameter", positive), p.get("cd", non_negative, 2.2),
        p.get("velocity", vector3, (0.0, 0.0, 0.0)), p.get("omega", vector3, None),
        sample_every=p.get("sample_every", positive, None)))


def atmospheric_drag_load(p, bodies, system, environment):
    """``[[loads.atmospheric_drag]]``: the co-rotating atmosphere's drag on a ``cable``
    (``area``: its projected width, m), a rigid ``body`` (at its centre of mass) or a
    point ``at`` (``area``: m^2), with the ``[environment]``'s atmosphere unless a
    ``density`` is given; ``sample_every`` (s): the model at knots (``loads.knots``)."""
    key, _ = one_of(p, ("cable", "body", "at"), lambda v: v)
    if key is None:
        p.missing("cable", "is required (a cable's name), or body (a rigid body's) or at "
                  "(a point reference)", ("cable", "body", "at"))
    target = bodies.point(p, "at") if key == "at" else \
        bodies.body(p, key, Cable if key == "cable" else RigidBody)
    system.add_load(AtmosphericDrag(target, density(p, environment),
                                    p.get("cd", non_negative, 2.2), p.get("area", positive),
                                    sample_every=p.get("sample_every", positive, None)))


def electrodynamic_load(p, bodies, system, environment):
    """``[[loads.electrodynamic]]``: the OML current of a bare ``cable`` (``current =
    "oml"``) in the ``[environment]``'s ``field`` and ``plasma``, with its hollow
    cathode's ``cathode_drop`` (V), ``load`` (ohm), ``conductivity`` (S/m), ``perimeter``
    (m; default a round wire's) and ``sample_every`` (s; the models at knots,
    ``loads.knots``)."""
    cable = bodies.body(p, "cable", Cable)
    current = p.get("current", choice("oml"))
    for key in ("field", "plasma"):
        if getattr(environment, key) is None:
            p.fail("current", f"= \"oml\" needs [environment] {key}", current)
    system.add_load(ElectrodynamicForce(
        cable, current, environment.field, plasma=environment.plasma,
        cathode=Cathode(p.get("cathode_drop", non_negative, 0.0)),
        load=p.get("load", non_negative, 0.0), conductivity=p.get("conductivity", positive),
        perimeter=p.get("perimeter", positive, None),
        sample_every=p.get("sample_every", positive, None)))


#: Readers of the arrays of load tables ``[[loads.KEY]]``: ``reader(p, bodies, system,
#: environment)``.
LOADS = {"point": point_load, "line": line_load, "moment": moment_load,
         "morison": morison_load, "buoyancy": buoyancy_load,
         "free_molecular": free_molecular_load, "atmospheric_drag": atmospheric_drag_load,
         "electrodynamic": electrodynamic_load}


def read_loads(t, bodies, system, analysis, environment):
    """The ``[loads]`` table, added to ``system``; ``environment`` (``EnvironmentSpec``)
    gives the models of the loads that read them."""
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
            reader(p, bodies, system, environment)
            p.finish()
    t.finish()
