"""The bodies of a scene file: ``[sections.NAME]``, ``[[cables]]``, ``[[rigid_bodies]]``,
and the references to their points (cable nodes, rigid-body points) that constraints,
point masses and loads use.  ``Bodies`` holds what was defined so far, by name."""

import numpy as np

from ..bodies.cable import Cable
from ..bodies.formulation import FORMULATIONS
from ..bodies.memory import check_total_memory
from ..bodies.rigid import RigidBody
from ..bodies.section import Section
from ..elements import DEFAULT_ELEMENT, ELEMENTS
from ..laws import BUILTIN
from .schema import choice, count, integer, non_negative, positive, rotation, text, vector3


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
            t.fail(key, f"names no {'cable' if kind is Cable else 'rigid body'} "
                        f"(defined: {', '.join(names) or 'none'})", name)
        return body

    def point(self, parent, key, ground=False, body_points=True):
        """A point reference ``parent[key]``: ``{cable, index}`` (a cable node), ``{body,
        point}`` (a rigid-body point) or, with ``ground``, a list of 3 numbers."""
        value = parent.data.get(key)
        if ground and isinstance(value, list):
            return parent.get(key, vector3)
        if not isinstance(value, dict):
            forms = "{cable = NAME, index = I}" + (", {body = NAME, point = [x, y, z]}"
                                                   if body_points else "")
            forms += ", or [x, y, z]" if ground else ""
            parent.fail(key, f"must be {forms}", value)
        t = parent.inline(key)
        if "cable" in value or not body_points:
            cable = self.body(t, "cable", Cable)
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
    """A ``[sections.NAME]`` table: ``E``, ``rho``, ``radius`` or ``A`` and ``I``, damping."""
    if "A" in t.data or "I" in t.data:
        radius = None
        A, I = t.get("A", positive), t.get("I", positive)
    else:
        A = I = None
        radius = t.get("radius", positive)
    common = {"E": t.get("E", positive), "rho": t.get("rho", positive),
              "gamma_axial": t.get("gamma_axial", non_negative, 0.0),
              "gamma_bending": t.get("gamma_bending", non_negative, 0.0)}
    t.finish()
    if radius is None:
        return Section(A=A, I=I, **common)
    try:
        return Section.circular(radius=radius, **common)
    except ValueError as err:  # pi r^2 or pi r^4 / 4 out of floating-point range
        t.fail("radius", f"is out of range ({err}: A = pi r^2, I = pi r^4 / 4 in floating "
               "point)", radius)


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


def read_cable(t, bodies):
    """A ``[[cables]]`` table: a straight, stress-free cable, or, with ``length``, a cable of
    that unstretched length between ``start`` and ``end`` (``Cable.between``)."""
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
    element = t.get("element", choice(*ELEMENTS), DEFAULT_ELEMENT)
    kind = t.get("kind", choice(*BUILTIN), None)
    formulation = t.get("formulation", choice(*FORMULATIONS), None)
    length = t.get("length", positive, None)
    sag = t.get("sag", vector3, None)
    if sag is not None and length is None:
        t.fail("sag", "needs length (the unstretched length of a cable that may sag)")
    quadrature = read_quadrature(t) if "quadrature" in t.data else None
    t.finish()
    options = dict(law=kind, name=name, formulation=formulation, element=element,
                   quadrature=quadrature)
    n = bodies.elements or n
    try:
        cable = Cable.straight(start, end, n, bodies.sections[section], **options) \
            if length is None else \
            Cable.between(start, end, length, n, bodies.sections[section], sag, **options)
    except ValueError as err:  # a rule or sag refused, a law or formulation the element
        # does not have: the key the message starts with, else the element
        key = next((k for k in ("quadrature", "sag") if str(err).startswith(k)), "element")
        t.fail(key, f"does not take this cable: {err}")
    bodies.add(t, cable)


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
