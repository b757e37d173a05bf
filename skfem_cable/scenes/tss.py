"""The tethered satellite system (``skfem-cable run tss``): two 100 kg end bodies on a
20 km tether along the local vertical of a circular 400 km Earth orbit, released at rest
in the orbiting frame with small pitch and roll offsets, so that it librates.

The rigid dumbbell's small librations (Beletsky & Levin) are the pitch (in the orbit
plane, about the orbit normal) at ``sqrt(3) n`` and the roll (out of the plane, about the
along-track axis) at ``2 n``, ``n`` the mean motion.  The tether is stiff and nearly
massless, so the cable model librates as the dumbbell does; the scene's outputs compare
its measured libration frequencies with these.

The scene has a ``model`` (``skfem-cable run tss --model NAME``): ``"ancf"`` (ANCF
cable, ``ancf_scene``, the default) or ``"rodchain"`` (the tethered-satellite paper's own
model, ``rodchain_scene``: the rod chain in orbit with its compiled RK4).  A model is one
entry of ``MODELS``: a builder taking the keywords of ``scene`` but ``model`` and
returning a scene with ``run(options) -> summary`` (as ``runner.RunScene``); both report
the same libration numbers (``libration_numbers``).
"""

import time

import numpy as np
from scipy.spatial.transform import Rotation

from ..bodies.cable import Cable
from ..bodies.section import Section
from ..model.state import State
from ..model.system import System
from ..rodchain.export import ChainSeriesWriter
from ..rodchain.integrate import rk4_step
from ..rodchain.tss import tss_chain
from ..runner.directory import run_directory
from ..runner.drive import RunScene
from ..runner.summary import write_summary
from ..solvers.steady import solve_steady
from ..space.constants import MU_EARTH, R_EARTH
from ..space.orbit import Orbit

#: Altitude (m), tether length (m), end masses (kg) and offsets (rad) of the scene.
ALTITUDE, LENGTH, MASS, PITCH, ROLL = 400e3, 20e3, 100.0, 0.05, 0.03
#: The tether: 1 mm radius, E = 100 GPa, a density of 1 kg/m^3 (nearly massless: 63 g).
SECTION = Section.circular(1e-3, 1e11, 1.0)


def pitch_period(orbit):
    """Period (s) of the small pitch libration, ``2 pi / (sqrt(3) n)``."""
    return 2 * np.pi / (np.sqrt(3) * orbit.mean_motion)


def dumbbell(orbit, n_elements=8, length=LENGTH, mass=MASS, formulation=None):
    """The tether along the local vertical (``+x`` at ``t = 0`` in an orbit with the
    default angles), centred on the reference point, with point masses ``mass`` at both
    ends; returns ``(system, cable)``."""
    cable = Cable.straight([-length / 2, 0, 0], [length / 2, 0, 0], n_elements, SECTION,
                           name="tether", formulation=formulation)
    system = System([cable]).add_point_mass(cable.node(0), mass)
    return system.add_point_mass(cable.node(-1), mass).add_orbit(orbit), cable


def librated(system, orbit, pitch=PITCH, roll=ROLL):
    """The steady state of ``system`` at rest in the orbiting frame (``solve_steady`` at
    the orbit's rate), turned by ``pitch`` about the orbit normal and then by ``roll``
    about the along-track axis, still at rest in the orbiting frame: every vector of
    coordinates moves with ``omega x``."""
    omega = orbit.angular_velocity(0.0)
    steady = solve_steady(system, omega=omega)
    axes = orbit.lvlh(0.0)
    turn = Rotation.from_rotvec(roll * axes[1]) * Rotation.from_rotvec(pitch * axes[2])
    q = system.rotate(steady.q, turn.as_matrix())
    return State(system, q, steady.lam, v=system.rigid_motion_velocity(q, omega))


def attitude(orbit, cable, t, q):
    """Pitch and roll (rad) of the line from the tether's first to its last end, in the
    orbiting frame, as ``librated`` turns it: pitch ``atan2(along-track, radial)`` in the
    orbit plane (a turn about the orbit normal), roll its angle out of the plane, positive
    away from the orbit normal (a turn about the along-track axis); ``q`` (n_steps,
    n_dofs) holds the cable's coordinates at the times ``t`` (``Orbit.libration``)."""
    ends = np.array([cable.interpolate(qi, np.array([0.0, cable.length]))[0] for qi in q])
    return orbit.libration(t, ends[:, 1] - ends[:, 0])


def crossing_frequency(t, x):
    """Angular frequency (rad/s) of the oscillation ``x(t)`` about zero from its zero
    crossings (linear interpolation between samples): ``pi`` over their mean spacing.
    NaN with fewer than two crossings."""
    k = np.nonzero(np.sign(x[:-1]) * np.sign(x[1:]) < 0)[0]
    crossings = t[k] - x[k] * (t[k + 1] - t[k]) / (x[k + 1] - x[k])
    if len(crossings) < 2:
        return np.nan
    return np.pi / np.mean(np.diff(crossings))


def libration_outputs(orbit, cable, result):
    """Key numbers of a libration run: pitch and roll amplitudes (rad) and their
    frequencies over the mean motion against ``sqrt(3)`` and ``2``."""
    pitch, roll = attitude(orbit, cable, result.t, result.q[:, result.system.dofs(cable)])
    return libration_numbers(orbit, result.t, pitch, roll)


def libration_numbers(orbit, t, pitch, roll):
    """The libration numbers of both models: the amplitudes (rad) and the frequencies of
    the pitch and roll histories over the mean motion, against ``sqrt(3)`` and ``2``."""
    n = orbit.mean_motion
    return {"pitch_max": np.abs(pitch).max(), "roll_max": np.abs(roll).max(),
            "pitch_frequency_over_n": crossing_frequency(t, pitch) / n,
            "pitch_frequency_rigid": np.sqrt(3.0),
            "roll_frequency_over_n": crossing_frequency(t, roll) / n,
            "roll_frequency_rigid": 2.0}


def ancf_scene(elements=8, formulation=None, altitude=ALTITUDE, pitch=PITCH, roll=ROLL,
               periods=3.0, steps_per_period=200, every=4):
    """The ANCF model of the scene: ``dumbbell`` of ``elements`` cable elements,
    ``librated`` by ``pitch`` and ``roll``, run for ``periods`` pitch periods at
    ``steps_per_period`` steps per period (rho_inf = 0.8), every ``every``-th step saved
    and every fifth saved step written to the ParaView series."""
    orbit = Orbit(MU_EARTH, R_EARTH + altitude)
    system, cable = dumbbell(orbit, elements, formulation=formulation)
    period = pitch_period(orbit)
    settings = {"t_end": periods * period, "dt": period / steps_per_period, "every": every,
                "rho_inf": 0.8, "series_every": 5}
    parameters = {"model": "ancf", "elements": elements, "formulation": cable.formulation,
                  "altitude": altitude, "length": LENGTH, "mass": MASS, "pitch": pitch,
                  "roll": roll, "mean_motion": orbit.mean_motion}
    return RunScene("tss", system, librated(system, orbit, pitch, roll), settings, parameters,
                    lambda result: libration_outputs(orbit, cable, result))


class ChainLibration:
    """The rod-chain model of the scene as a run (``run(options) -> summary``): the
    orbiting chain from ``x0, v0`` over ``t_end`` seconds by its compiled RK4, saved every
    ``output_dt``; the run directory gets ``summary.json`` and the ParaView series of the
    saved steps (every ``series_every``-th).  No checkpoint: ``--resume`` is refused."""

    def __init__(self, model, x0, v0, orbit, t_end, output_dt, parameters, series_every=5):
        self.model, self.x0, self.v0, self.orbit = model, x0, v0, orbit
        self.t_end, self.output_dt = t_end, output_dt
        self.parameters, self.series_every = parameters, series_every

    def run(self, options):
        options.reject("tss --model rodchain", "every", "frame")
        if options.resume:
            raise ValueError("tss --model rodchain has no checkpoint and cannot be resumed: "
                             "run it again into another --out, or with --overwrite")
        t_end = options.value("t_end", self.t_end)
        output_dt = options.value("dt", self.output_dt)
        step = rk4_step(self.model, output_dt)
        every = int(round(output_dt / step))
        t_end = np.ceil(t_end / output_dt - 1e-9) * output_dt
        with run_directory(options, can_resume=False) as out:
            start = time.perf_counter()
            result = self.model.simulate(self.x0, self.v0, t_end, step, every=every)
            wall = time.perf_counter() - start
            joints = result.joints
            pitch, roll = self.orbit.libration(result.t, joints[:, -1] - joints[:, 0])
            tension = result.tension
            summary = {"scene": "tss",
                       "parameters": {**self.parameters, "t_end": t_end, "dt": output_dt},
                       "wall_time": wall, "saved_steps": len(result),
                       "integration": {"method": "rk4", "step": step,
                                       "steps": result.stats["steps"],
                                       "stable_dt": self.model.stable_dt()},
                       "outputs": {"chain": {"rods": self.model.n,
                                             "mass": self.model.total_mass,
                                             "central_tension_mean":
                                                 tension[:, self.model.n // 2].mean(),
                                             "max_tension_run": tension.max(),
                                             "min_tension_run": tension.min()},
                                   **libration_numbers(self.orbit, result.t, pitch, roll)},
                       "warnings": []}
            if out is not None:
                writer = ChainSeriesWriter(out, self.model.chain)
                for k in sorted({*range(0, len(result), self.series_every), len(result) - 1}):
                    writer.write(result.t[k], result.x[k, 1:], result.v[k, 1:],
                                 result.x[k, 0], result.v[k, 0])
                summary["files"] = {"series": "series.pvd"}
                write_summary(out, summary)
        return summary


def rodchain_scene(elements=None, formulation=None, altitude=ALTITUDE, pitch=PITCH,
                   roll=ROLL, periods=3.0, steps_per_period=200, every=4):
    """The rod-chain model of the scene: ``tss_chain`` of ``elements`` rods (default 3)
    with the ANCF model's tether, end masses, orbit and offsets, run by its compiled RK4
    at its stable step over ``periods`` pitch periods, saved ``steps_per_period / every``
    times per period.  A rod chain has no ``formulation``."""
    if formulation is not None:
        raise ValueError("tss: the rod-chain model has no formulation (a rod is a "
                         f"spring); got formulation={formulation!r}")
    orbit = Orbit(MU_EARTH, R_EARTH + altitude)
    rods = 3 if elements is None else elements
    model, x0, v0 = tss_chain(rods, orbit=orbit, end_masses=(MASS, MASS), length=LENGTH,
                              radius=float(np.sqrt(SECTION.A / np.pi)), E=SECTION.E,
                              density=SECTION.rho, pitch=pitch, roll=roll)
    period = pitch_period(orbit)
    parameters = {"model": "rodchain", "rods": rods, "altitude": altitude,
                  "length": LENGTH, "mass": MASS, "pitch": pitch, "roll": roll,
                  "mean_motion": orbit.mean_motion}
    return ChainLibration(model, x0, v0, orbit, periods * period,
                          period * every / steps_per_period, parameters)


#: The models of the scene by name: ``builder(**keywords of scene but model)``.
MODELS = {"ancf": ancf_scene, "rodchain": rodchain_scene}


def scene(model="ancf", elements=None, formulation=None, altitude=ALTITUDE, pitch=PITCH,
          roll=ROLL, periods=3.0, steps_per_period=200, every=4):
    """The scene (``skfem-cable sweep tss`` sweeps these keywords) in the ``model`` of
    ``MODELS``; see ``ancf_scene`` and ``rodchain_scene`` (``elements``: the model's
    default when None)."""
    if model not in MODELS:
        raise ValueError(f"tss: model must be one of {', '.join(map(repr, MODELS))}, got "
                         f"{model!r}")
    counts = {} if elements is None else {"elements": elements}
    return MODELS[model](**counts, formulation=formulation, altitude=altitude, pitch=pitch,
                         roll=roll, periods=periods, steps_per_period=steps_per_period,
                         every=every)


def run(options):
    """``skfem-cable run tss``: the ``--model`` (default ANCF), ``--elements`` per tether
    (default 8 ANCF elements, 3 rods)."""
    return scene(model=options.value("model", "ancf"), elements=options.elements,
                 formulation=options.formulation).run(options)
