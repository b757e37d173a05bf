"""The tethered satellite system (``skfem-cable run tss``): two 100 kg end bodies on a
20 km tether along the local vertical of a circular 400 km Earth orbit, released at rest
in the orbiting frame with small pitch and roll offsets, so that it librates.

The rigid dumbbell's small librations (Beletsky & Levin) are the pitch (in the orbit
plane, about the orbit normal) at ``sqrt(3) n`` and the roll (out of the plane, about the
along-track axis) at ``2 n``, ``n`` the mean motion.  The tether is stiff and nearly
massless, so the cable model librates as the dumbbell does; the scene's outputs compare
its measured libration frequencies with these.

The scene has a ``model``: ``"ancf"`` (ANCF cable, ``ancf_scene``).  Another model is one
entry of ``MODELS``: a builder taking the keywords of ``scene`` but ``model`` and
returning a scene with ``run(options) -> summary`` (as ``runner.RunScene``).
"""

import numpy as np
from scipy.spatial.transform import Rotation

from ..cable import Cable
from ..orbit import MU_EARTH, R_EARTH, Orbit
from ..runner import RunScene
from ..section import Section
from ..solvers.steady import solve_steady
from ..state import State
from ..system import System

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
    n_dofs) holds the cable's coordinates at the times ``t``."""
    ends = np.array([cable.interpolate(qi, np.array([0.0, cable.length]))[0] for qi in q])
    y = orbit.to_lvlh(np.asarray(t, dtype=float), ends[:, 1] - ends[:, 0])
    pitch = np.arctan2(y[:, 1], y[:, 0])
    roll = np.arcsin(-y[:, 2] / np.linalg.norm(y, axis=1))
    return pitch, roll


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
    n = orbit.mean_motion
    return {"pitch_max": np.abs(pitch).max(), "roll_max": np.abs(roll).max(),
            "pitch_frequency_over_n": crossing_frequency(result.t, pitch) / n,
            "pitch_frequency_rigid": np.sqrt(3.0),
            "roll_frequency_over_n": crossing_frequency(result.t, roll) / n,
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


#: The models of the scene by name: ``builder(**keywords of scene but model)``.
MODELS = {"ancf": ancf_scene}
#: Why a model that is planned but not written yet cannot be built.
PLANNED = {"rodchain": "the rod-chain model of this scene is not written yet (it is to "
                       "join tss.MODELS from skfem_cable.rodchain)"}


def scene(model="ancf", elements=8, formulation=None, altitude=ALTITUDE, pitch=PITCH,
          roll=ROLL, periods=3.0, steps_per_period=200, every=4):
    """The scene (``skfem-cable sweep tss`` sweeps these keywords) in the ``model`` of
    ``MODELS``; see ``ancf_scene``."""
    if model not in MODELS:
        reason = f": {PLANNED[model]}" if model in PLANNED else ""
        raise ValueError(f"tss: model must be one of {', '.join(map(repr, MODELS))}, got "
                         f"{model!r}{reason}")
    return MODELS[model](elements=elements, formulation=formulation, altitude=altitude,
                         pitch=pitch, roll=roll, periods=periods,
                         steps_per_period=steps_per_period, every=every)


def run(options):
    """``skfem-cable run tss``: the ANCF model, ``--elements`` per tether (default 8)."""
    options.reject("tss", "alpha")
    return scene(elements=options.value("elements", 8),
                 formulation=options.formulation).run(options)
