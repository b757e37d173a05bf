"""A scene of cables and rigid bodies (``System``) from a scene file: the tables are read
in schema order by the readers of ``bodies``, ``constraints``, ``deploy``,
``environment``, ``orbit``, ``loads``, ``contacts``, ``controllers`` and ``solver``;
``run`` simulates (``runner.run_dynamic``) or solves it (``runner.run_static``)."""

from dataclasses import dataclass
from pathlib import Path

from ..model.state import State
from ..model.system import System
from ..runner.drive import run_dynamic, run_static
from ..solvers.static import solve_static
from ..solvers.steady import solve_steady
from .bodies import (
    Bodies,
    check_cables_memory,
    read_cable,
    read_rigid_body,
    read_rod,
    read_sections,
)
from .constraints import read_constraint
from .contacts import read_contact
from .controllers import read_controllers
from .deploy import read_deploy, read_reel
from .environment import EnvironmentSpec, check_orbit, read_environment
from .loads import read_loads, read_point_mass
from .orbit import place_in_orbit, read_orbit
from .schema import text
from .solver import default_every, read_analysis, read_initial, read_output, read_solver


@dataclass
class SceneSpec:
    """A scene read from a file: ``analysis`` is ``"dynamic"`` (``solver`` holds the
    ``simulate`` keywords), ``"static"`` (``solve_static`` keywords) or ``"steady"``
    (``solve_steady`` keywords); ``motion`` is the ``[initial]`` table as written (a
    parameter of the run: a continued run must start from the same)."""

    title: str
    system: System
    initial: State
    analysis: str
    solver: dict
    points_per_element: int
    motion: dict
    controllers: list
    environment: EnvironmentSpec | None = None


def build(root, elements=None, epoch=None):
    """The ``SceneSpec`` of the root table ``root``; ``elements`` overrides every cable's
    element count, ``epoch`` (text: the run's ``--epoch``) the ``[environment]``'s."""
    title = root.get("title", text, "")
    solver = root.table("solver")
    analysis = read_analysis(solver)
    settings = read_solver(solver, analysis)
    bodies = Bodies(elements)
    read_sections(root.table("sections"), bodies)
    cables = root.tables("cables")
    rods = root.tables("rods")
    check_cables_memory(root, cables + rods, bodies)
    for t in cables:
        read_cable(t, bodies)
    for t in rods:
        read_rod(t, bodies)
    for t in root.tables("rigid_bodies"):
        read_rigid_body(t, bodies)
    if not bodies.bodies:
        root.fail("cables", "or rods or rigid_bodies must define at least one body")
    deploys = root.tables("deploy")
    reels = [read_reel(t, bodies) for t in deploys]     # bodies too
    system = System(list(bodies.bodies.values()))
    for t in root.tables("constraints"):
        read_constraint(t, bodies, system)
    for t, reel in zip(deploys, reels):
        read_deploy(t, bodies, system, reel)
    for t in root.tables("point_masses"):
        read_point_mass(t, bodies, system)
    environment = read_environment(root.table("environment"), epoch)
    check_orbit(root, environment)
    if root.has("orbit"):
        place_in_orbit(root, read_orbit(root.table("orbit")), system, environment.epoch)
    read_loads(root.table("loads"), bodies, system, analysis, environment)
    for t in root.tables("contacts"):
        read_contact(t, bodies, system)
    controllers = read_controllers(root, system)
    motion = root.table("initial")
    initial = read_initial(motion, system, analysis)
    ppe = read_output(root.table("output"))
    root.finish()
    return SceneSpec(title, system, initial, analysis, settings, ppe, motion.data,
                     controllers, environment)


def run(path, spec, options):
    """Run the ``SceneSpec`` read from ``path`` into the run directory ``options.out``;
    returns the summary."""
    options.reject(Path(path).name, "formulation")
    name = Path(path).stem
    parameters = {"file": str(path), "title": spec.title, "initial": spec.motion}
    if spec.analysis == "dynamic":
        solver = dict(spec.solver)
        # the file's t_end, not --t-end: a continuation to a later end keeps the run's
        solver.setdefault("every", default_every(solver["t_end"],
                                                 options.value("dt", solver["dt"])))
        return run_dynamic(name, spec.system, spec.initial, options, solver, parameters,
                           points_per_element=spec.points_per_element,
                           controllers=spec.controllers)[0]
    options.reject(Path(path).name, "t_end", "dt", "every")
    settings = {k: v.tolist() if hasattr(v, "tolist") else v for k, v in spec.solver.items()}
    outputs = None
    if spec.analysis == "steady":
        state = solve_steady(spec.system, **spec.solver)
        outputs = {"frame_acceleration": state.stats["frame_acceleration"].tolist(),
                   "phase_torque": state.stats["phase_torque"]}
    else:
        state = solve_static(spec.system, **spec.solver)
    return run_static(name, spec.system, [(1.0, state)], options, {**parameters, **settings},
                      outputs=outputs, title=spec.title or name,
                      points_per_element=spec.points_per_element)
