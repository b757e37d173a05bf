"""The bodies of a scene file: ``[sections.NAME]``, ``[[cables]]``, ``[[rods]]``,
``[[rigid_bodies]]``, and the references to their points (cable and rod nodes,
rigid-body points) that constraints, point masses and loads use.  ``Bodies`` holds what
was defined so far, by name."""

import numpy as np

from ..bodies.cable import Cable
from ..bodies.formulation import FORMULATIONS
from ..bodies.memory import check_total_memory
from ..bodies.rigid import RigidBody
from ..bodies.rod import Rod
from ..bodies.section import Section
from ..elements import DEFAULT_ELEMENT, ELEMENTS
from ..laws import BUILTIN
from .schema import (
    choice,
    count,
    direction3,
    integer,
    interval,
    non_negative,
    positive,
    rotation,
    text,
    vector3,
)

#: What ``Bodies.body`` calls a body of each kind in its errors.
KIND_NAMES = {Cable: "cable", Rod: "rod", RigidBody: "rigid body"}


class Bodies:
    """Sections and bodies by name, in the order of the file; ``elements`` overrides the
    element count of every cable (``--elements``)."""

    def __init__(self, elements=None):
        self.elements = elements
        self.sections, self.bodies = {}, {}

    def add(self, t, body):
        """Register ``body`` read from the table ``t`` (its name must be new)."""
        if body.name in self.bodies:
            t.fail("name", "repeats the name of another body", body.name)
        self.bodies[body.name] = body

    def body(self, t, key, kind):
        """The body of type ``kind`` named by ``t[key]``."""
        name = t.get(key, text)
        body = self.bodies.get(name)
        if not isinstance(body, kind):
            names = [n for n, b in self.bodies.items() if isinstance(b, kind)]
            t.fail(key, f"names no {KIND_NAMES[kind]} (defined: {', '.join(names) or 'none'})",
                   name)
        return body

    def point(self, parent, key, ground=False, body_points=True):
        """A point reference ``parent[key]``: ``{cable, index}`` (a cable node), ``{rod,
        index}`` (a rod node), ``{body, point}`` (a rigid-body point) or, with ``ground``,
        a list of 3 numbers."""
        value = parent.data.get(key)
        if ground and isinstance(value, list):
            return parent.get(key, vector3)
        if not isinstance(value, dict):
            forms = "{cable = NAME, index = I}" + (", {body = NAME, point = [x, y, z]}"
                                                   if body_points else "")
            forms += ", or [x, y, z]" if ground else ""
            parent.fail(key, f"must be {forms}", value)
        t = parent.inline(key)
        if "rod" in value or "cable" in value or not body_points:
            line = "rod" if "rod" in value else "cable"
            cable = self.body(t, line, Cable if line == "cable" else Rod)
            index = t.get("index", integer)
            if not -cable.n_nodes <= index < cable.n_nodes:
                t.fail("index", f"is out of range for {cable.n_nodes} nodes", index)
            t.finish()
            return cable.node(index)
        body = self.body(t, "body", RigidBody)
        x = t.get("point", vector3)
        t.finish()
        return body.point(x)


def read_section(t):
    """A ``[sections.NAME]`` table: ``E``, ``rho``, ``radius``, or ``A`` and ``I`` (with a
    rod's ``G``, ``J``, ``I_edge``), or a tape's ``width`` and ``thickness``; ``G`` or
    ``nu`` for the round wire and the tape; damping."""
    common = {"E": t.get("E", positive), "rho": t.get("rho", positive),
              "gamma_axial": t.get("gamma_axial", non_negative, 0.0),
              "gamma_bending": t.get("gamma_bending", non_negative, 0.0),
              "G": t.get("G", positive, None)}
    if "A" in t.data or "I" in t.data:
        section = Section(A=t.get("A", positive), I=t.get("I", positive),
                          J=t.get("J", positive, None), I_edge=t.get("I_edge", positive, None),
                          **common)
        t.finish()
        return section
    nu = t.get("nu", interval(-1.0, 0.5), 0.3)
    tape = "width" in t.data or "thickness" in t.data
    key = "width" if tape else "radius"
    sizes = [t.get(k, positive) for k in (("width", "thickness") if tape else ("radius",))]
    try:
        section = (Section.tape if tape else Section.circular)(*sizes, nu=nu, **common)
    except ValueError as err:  # a tape thicker than wide; pi r^2 or pi r^4 / 4 out of range
        t.fail(key, f"is out of range ({err})", sizes[0])
    t.finish()
    return section


def read_sections(t, bodies):
    """All ``[sections.NAME]`` of the table ``t`` (``[sections]``) into ``bodies``."""
    for name in list(t.data):
        bodies.sections[name] = read_section(t.table(name))
    t.finish()


def read_quadrature(t):
    """``quadrature = {axial = 5, bending = 3}``: Gauss points per part of the law."""
    q = t.inline("quadrature")
    rules = {part: q.get(part, count, None) for part in ("axial", "bending")}
    q.finish()
    return {part: n for part, n in rules.items() if n is not None}


def check_cables_memory(root, tables, bodies):
    """Refuse, before any is built, ``[[cables]]`` tables whose elements together do not
    fit in this machine's memory (``cable.check_total_memory``); the element counts that
    are not integers >= 1 are left to ``read_cable`` to refuse."""
    counts = [bodies.elements or t.data.get("elements") for t in tables]
    try:
        check_total_memory([n for n in counts if isinstance(n, int) and n >= 1])
    except ValueError as err:
        root.fail("cables", f"are too large: {err}")


def read_line(t, bodies):
    """The keys a cable and a rod share: ``name``, ``section``, ``start``, ``end``,
    ``elements``, ``length`` and ``sag``; returns them as a dict."""
    name = t.get("name", text)
    section = t.get("section", text)
    if section not in bodies.sections:
        t.fail("section", f"names no section (defined: {', '.join(bodies.sections) or 'none'})",
               section)
    start, end = t.get("start", vector3), t.get("end", vector3)
    # relative to the coordinates: a cable far from the origin is no special case
    if not np.linalg.norm(end - start) > 1e-12 * max(np.abs(start).max(),
                                                     np.abs(end).max(), 1.0):
        t.fail("end", "must differ from start", list(end))
    n = t.get("elements", count, bodies.elements)
    if n is None:
        t.fail("elements", "is required")
    length = t.get("length", positive, None)
    sag = t.get("sag", vector3, None)
    if sag is not None and length is None:
        t.fail("sag", "needs length (the unstretched length of a cable that may sag)")
    return {"name": name, "section": bodies.sections[section], "start": start, "end": end,
            "n": bodies.elements or n, "length": length, "sag": sag}


def build_line(t, kind, line, **options):
    """``kind.straight`` or, with a ``length``, ``kind.between`` (``Cable``, ``Rod``) of
    the keys ``line`` (``read_line``) and ``options``; a ``ValueError`` of the body names
    the key its message starts with (``quadrature``, ``sag``, ``normal``), else
    ``element``."""
    args = (line["start"], line["end"], line["n"], line["section"])
    try:
        if line["length"] is None:
            return kind.straight(*args, name=line["name"], **options)
        return kind.between(*args[:2], line["length"], *args[2:], line["sag"],
                            name=line["name"], **options)
    except ValueError as err:  # a rule or sag refused, a law or formulation the element
        # does not have: the key the message starts with, else the element
        key = next((k for k in ("quadrature", "sag", "normal") if str(err).startswith(k)),
                   "element")
        t.fail(key, f"does not take this {kind.__name__.lower()}: {err}")


def read_cable(t, bodies):
    """A ``[[cables]]`` table: a straight, stress-free cable, or, with ``length``, a cable of
    that unstretched length between ``start`` and ``end`` (``Cable.between``); ``element =
    "rod"`` makes it a rod (``rods.read_rod``)."""
    if t.data.get("element") == ROD_ELEMENT:
        return read_rod(t, bodies)
    line = read_line(t, bodies)
    element = t.get("element", choice(*ELEMENTS, ROD_ELEMENT), DEFAULT_ELEMENT)
    kind = t.get("kind", choice(*BUILTIN), None)
    formulation = t.get("formulation", choice(*FORMULATIONS), None)
    quadrature = read_quadrature(t) if "quadrature" in t.data else None
    t.finish()
    bodies.add(t, build_line(t, Cable, line, law=kind, formulation=formulation,
                             element=element, quadrature=quadrature))


#: ``element = "rod"`` in a ``[[cables]]`` table: the table is read as a ``[[rods]]`` one.
ROD_ELEMENT = "rod"


def read_rod(t, bodies):
    """A ``[[rods]]`` table (or a ``[[cables]]`` one with ``element = "rod"``): the keys
    of a cable (``read_line``) and ``normal``, the direction of the section's normal axis
    (a tape's thickness direction; default one normal to the rod), ``sc.Rod``."""
    line = read_line(t, bodies)
    t.get("element", choice(ROD_ELEMENT), ROD_ELEMENT)
    normal = t.get("normal", direction3, None)
    formulation = t.get("formulation", choice(*FORMULATIONS), None)
    t.finish()
    bodies.add(t, build_line(t, Rod, line, normal=normal, formulation=formulation))


def read_rigid_body(t, bodies):
    """A ``[[rigid_bodies]]`` table: a cylinder in natural coordinates."""
    name = t.get("name", text)
    t.get("shape", choice("cylinder"), "cylinder")
    body = RigidBody.cylinder(t.get("radius", positive), t.get("height", positive),
                              t.get("density", positive),
                              position=t.get("position", vector3, np.zeros(3)),
                              rotation=t.get("rotation", rotation, None), name=name)
    t.finish()
    bodies.add(t, body)
