"""Scenes described in TOML files: bodies, sections, constraints, loads, initial motion and
solver settings (the schema is documented in ``docs/scene_files.md``).

Every value is checked; an error names the file, the key (e.g. ``cables[1].elements``) and
the offending value, and an unknown key lists the keys allowed in its table::

    >>> loads_text('[solver]\\nt_end = -1', "demo.toml")      # doctest: +SKIP
    SceneFileError: demo.toml: solver.t_end must be a number > 0, got -1
"""

import difflib
import math
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .cable import Cable
from .loads import PointMoment
from .rigid import RigidBody
from .runner import run_dynamic, run_static
from .section import Section
from .solvers.static import solve_static
from .state import State
from .system import System

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib


class SceneFileError(ValueError):
    """A scene file that does not follow the schema."""


_REQUIRED = object()


# --- value checks: each returns the converted value or raises ValueError(expectation) ----------
def _number(v):
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
        raise ValueError("must be a finite number")
    return float(v)


def positive(v):
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not (math.isfinite(v) and v > 0):
        raise ValueError("must be a number > 0")
    return float(v)


def non_negative(v):
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not (math.isfinite(v) and v >= 0):
        raise ValueError("must be a number >= 0")
    return float(v)


def count(v):
    if isinstance(v, bool) or not isinstance(v, int) or v < 1:
        raise ValueError("must be an integer >= 1")
    return v


def integer(v):
    if isinstance(v, bool) or not isinstance(v, int):
        raise ValueError("must be an integer")
    return v


def vector3(v):
    if not isinstance(v, list) or len(v) != 3:
        raise ValueError("must be a list of 3 numbers")
    return np.array([_number(x) for x in v])


def matrix3(v):
    if not isinstance(v, list) or len(v) != 3:
        raise ValueError("must be a 3 x 3 list of lists of numbers")
    return np.array([vector3(row) for row in v])


def text(v):
    if not isinstance(v, str) or not v:
        raise ValueError("must be a non-empty string")
    return v


def choice(*options):
    def check(v):
        if v not in options:
            raise ValueError(f"must be one of {', '.join(map(repr, options))}")
        return v
    return check


def interval(lo, hi):
    def check(v):
        x = _number(v)
        if not lo <= x <= hi:
            raise ValueError(f"must lie in [{lo}, {hi}]")
        return x
    return check


class _Table:
    """A TOML table being read: remembers the keys asked for, so that ``finish`` can reject
    the others, and turns every problem into a ``SceneFileError`` naming the key."""

    def __init__(self, data, where, source):
        self.data, self.where, self.source = data, where, source
        self.asked = []

    def name(self, key):
        return f"{self.where}.{key}" if self.where else key

    def fail(self, key, problem, value=_REQUIRED):
        got = "" if value is _REQUIRED else f", got {value!r}"
        raise SceneFileError(f"{self.source}: {self.name(key)} {problem}{got}")

    def has(self, key):
        self.asked.append(key)
        return key in self.data

    def get(self, key, check, default=_REQUIRED):
        if not self.has(key):
            if default is _REQUIRED:
                unknown = [k for k in self.data if k not in self.asked]
                close = difflib.get_close_matches(key, unknown, n=1)
                self.fail(key, "is required" + (f" (found the unknown key {close[0]!r})"
                                                if close else ""))
            return default
        value = self.data[key]
        try:
            return check(value)
        except ValueError as err:
            self.fail(key, str(err), value)

    def table(self, key):
        """The sub-table ``key`` (empty if missing)."""
        value = self.data.get(key, {}) if self.has(key) else {}
        if not isinstance(value, dict):
            self.fail(key, "must be a table", value)
        return _Table(value, self.name(key), self.source)

    def tables(self, key):
        """The array of tables ``[[key]]`` (empty if missing)."""
        value = self.data.get(key, []) if self.has(key) else []
        if not isinstance(value, list) or not all(isinstance(v, dict) for v in value):
            self.fail(key, "must be an array of tables ([[...]])", value)
        return [_Table(v, f"{self.name(key)}[{i}]", self.source) for i, v in enumerate(value)]

    def finish(self):
        unknown = [k for k in self.data if k not in self.asked]
        if unknown:
            allowed = ", ".join(dict.fromkeys(self.asked)) or "none"
            self.fail(unknown[0], f"is not a known key (allowed here: {allowed})",
                      self.data[unknown[0]])


@dataclass
class SceneSpec:
    """A scene read from a file: ``analysis`` is ``"dynamic"`` (``solver`` holds the
    ``simulate`` keywords) or ``"static"`` (``solve_static`` keywords)."""

    title: str
    system: System
    initial: State
    analysis: str
    solver: dict
    points_per_element: int


class _Builder:
    """Builds a system from the tables of a scene file, in schema order."""

    def __init__(self, root, elements):
        self.root = root
        self.elements = elements
        self.sections, self.bodies = {}, {}

    def section(self, t):
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
        if radius is not None:
            return Section.circular(radius=radius, **common)
        return Section(A=A, I=I, **common)

    def add_body(self, t, body):
        if body.name in self.bodies:
            t.fail("name", "repeats the name of another body", body.name)
        self.bodies[body.name] = body

    def cable(self, t):
        name = t.get("name", text)
        section = t.get("section", text)
        if section not in self.sections:
            t.fail("section", f"names no section (defined: {', '.join(self.sections) or 'none'})",
                   section)
        start, end = t.get("start", vector3), t.get("end", vector3)
        # relative to the coordinates: a cable far from the origin is no special case
        if not np.linalg.norm(end - start) > 1e-12 * max(np.abs(start).max(),
                                                         np.abs(end).max(), 1.0):
            t.fail("end", "must differ from start", list(end))
        n = t.get("elements", count, self.elements)
        if n is None:
            t.fail("elements", "is required")
        kind = t.get("kind", choice("cable", "truss"), "cable")
        t.finish()
        cable = Cable.straight(start, end, self.elements or n, self.sections[section], kind=kind,
                               name=name)
        self.add_body(t, cable)

    def rigid_body(self, t):
        name = t.get("name", text)
        t.get("shape", choice("cylinder"), "cylinder")
        body = RigidBody.cylinder(t.get("radius", positive), t.get("height", positive),
                                  t.get("density", positive),
                                  position=t.get("position", vector3, np.zeros(3)),
                                  rotation=t.get("rotation", _rotation, None), name=name)
        t.finish()
        self.add_body(t, body)

    def body(self, t, key, kind):
        name = t.get(key, text)
        body = self.bodies.get(name)
        if not isinstance(body, kind):
            names = [n for n, b in self.bodies.items() if isinstance(b, kind)]
            t.fail(key, f"names no {'cable' if kind is Cable else 'rigid body'} "
                        f"(defined: {', '.join(names) or 'none'})", name)
        return body

    def point(self, parent, key, ground=False, body_points=True):
        """A point reference: ``{cable, index}`` (a cable node), ``{body, point}`` (a
        rigid-body point) or, with ``ground``, a list of 3 numbers."""
        value = parent.data.get(key)
        if ground and isinstance(value, list):
            return parent.get(key, vector3)
        if not isinstance(value, dict):
            forms = "{cable = NAME, index = I}" + (", {body = NAME, point = [x, y, z]}"
                                                   if body_points else "")
            forms += ", or [x, y, z]" if ground else ""
            parent.fail(key, f"must be {forms}", value)
        parent.asked.append(key)
        t = _Table(value, parent.name(key), parent.source)
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

    def constraint(self, t, system):
        kind = t.get("type", choice("pin", "clamp"))
        node = self.point(t, "node", body_points=False)
        if kind == "pin":
            target = self.point(t, "target", ground=True) if "target" in t.data else None
            system.pin(node, target)
        else:
            system.clamp(node, t.get("direction", vector3, None))
        t.finish()

    def loads(self, t, system, analysis):
        gravity = t.get("gravity", vector3, None)
        if gravity is not None:
            system.add_gravity(gravity)
        if t.has("centrifugal"):
            if analysis != "static":
                t.fail("centrifugal", "applies to static analyses only (the steady state in a "
                       "frame rotating at this rate)", t.data["centrifugal"])
            system.add_centrifugal(t.get("centrifugal", vector3))
        for p in t.tables("point"):
            system.add_point_load(self.point(p, "at", body_points=False), p.get("force", vector3))
            p.finish()
        for p in t.tables("line"):
            system.add_line_load(self.body(p, "cable", Cable), p.get("force_per_length", vector3))
            p.finish()
        for p in t.tables("moment"):
            system.add_load(PointMoment(self.point(p, "at", body_points=False),
                                        p.get("moment", vector3)))
            p.finish()
        t.finish()

    def solver(self, t, analysis):
        common = {"tol": t.get("tol", interval(1e-16, 0.1), None),
                  "max_iter": t.get("max_iter", count, None)}
        if analysis == "dynamic":
            s = {"t_end": t.get("t_end", positive), "dt": t.get("dt", positive),
                 "rho_inf": t.get("rho_inf", interval(0.0, 1.0), 0.8),
                 "every": t.get("every", count, 1),
                 "newton": t.get("newton", choice("full", "modified"), None)}
        else:
            s = {"load_steps": t.get("load_steps", count, 1)}
        t.finish()
        return {k: v for k, v in {**s, **common}.items() if v is not None}

    def build(self):
        root = self.root
        title = root.get("title", text, "")
        solver = root.table("solver")
        analysis = solver.get("analysis", choice("dynamic", "static"), "dynamic")
        settings = self.solver(solver, analysis)
        sections = root.table("sections")
        for name in list(sections.data):
            self.sections[name] = self.section(sections.table(name))
        sections.finish()
        for t in root.tables("cables"):
            self.cable(t)
        for t in root.tables("rigid_bodies"):
            self.rigid_body(t)
        if not self.bodies:
            root.fail("cables", "or rigid_bodies must define at least one body")
        system = System(list(self.bodies.values()))
        for t in root.tables("constraints"):
            self.constraint(t, system)
        for t in root.tables("point_masses"):
            system.add_point_mass(self.point(t, "at"), t.get("mass", positive))
            t.finish()
        self.loads(root.table("loads"), system, analysis)
        initial = self.initial(root.table("initial"), system, analysis)
        out = root.table("output")
        ppe = out.get("points_per_element", count, 8)
        out.finish()
        root.finish()
        return SceneSpec(title, system, initial, analysis, settings, ppe)

    def initial(self, t, system, analysis):
        q = system.q0
        if analysis == "static":
            t.finish()
            return State(system, q)
        v = system.rigid_motion_velocity(q, t.get("angular_velocity", vector3, np.zeros(3)),
                                         t.get("center", vector3, np.zeros(3)),
                                         t.get("velocity", vector3, np.zeros(3)))
        t.finish()
        return State(system, q, v=v)


def _rotation(v):
    R = matrix3(v)
    if not np.allclose(R.T @ R, np.eye(3), atol=1e-9) or np.linalg.det(R) < 0:
        raise ValueError("must be a proper rotation matrix (orthonormal rows, det = +1)")
    return R


def loads_text(content, source="<string>", elements=None):
    """Read a scene from TOML text; ``elements`` overrides every cable's element count.
    Returns a ``SceneSpec``; raises ``SceneFileError``."""
    try:
        data = tomllib.loads(content)
    except tomllib.TOMLDecodeError as err:
        raise SceneFileError(f"{source}: not valid TOML: {err}") from None
    return _Builder(_Table(data, "", source), elements).build()


def load(path, elements=None):
    """Read the scene file ``path`` (see ``loads_text``)."""
    path = Path(path)
    if not path.is_file():
        raise SceneFileError(f"{path}: no such scene file")
    return loads_text(path.read_text(), str(path), elements)


def run(path, options):
    """Run a scene file into the run directory ``options.out``; returns the summary."""
    options.reject(Path(path).name, "alpha")
    spec = load(path, options.elements)
    name = Path(path).stem
    parameters = {"file": str(path), "title": spec.title}
    if spec.analysis == "dynamic":
        return run_dynamic(name, spec.system, spec.initial, options, spec.solver, parameters,
                           points_per_element=spec.points_per_element)[0]
    options.reject(Path(path).name, "t_end", "dt", "every")
    state = solve_static(spec.system, **spec.solver)
    return run_static(name, spec.system, [(1.0, state)], options, {**parameters, **spec.solver},
                      title=spec.title or name, points_per_element=spec.points_per_element)
