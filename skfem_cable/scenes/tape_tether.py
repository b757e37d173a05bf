"""A tape tether in orbit (``skfem-cable run tape-tether``): a 5 km x 2 cm x 50 um
aluminium tape (``sc.Rod`` of ``Section.tape``, ``docs/rods.md``) between two 20 kg end
masses along the local vertical of a circular 400 km Earth orbit, held taut by the
gravity gradient (the central body's differential gravity, ``docs/orbits.md``), released
at rest in the orbiting frame with the librating offsets of ``tss`` and ``TURNS`` turns of
twist spread uniformly along it.

The ends are free to turn (point masses carry no rotary inertia), so the twist is a
torsional wave of the free-free tape: the twist of one end relative to the other swings
as a triangle wave of period ``2 L / c``, ``c = sqrt(GJ / rho I_p)`` (15.8 m/s for this
tape: 640 s, about a ninth of the orbit).  The round tether of equal mass (``ROUND``)
twists two hundred times faster (its ``c`` is 3.2 km/s).  Its libration is the round
tether's: under the gravity-gradient tension (0.2 N) the bending stiffness of either,
edgewise or flatwise, is 1e-6 or less of ``T L^2`` (``demos/tape_tether.py`` compares
them).  The scene's outputs: that period against ``2 L / c``, and the pitch libration.
"""

import numpy as np

from ..bodies.cable import Cable
from ..bodies.rod import Rod
from ..bodies.section import Section
from ..model.state import State
from ..model.system import System
from ..runner.drive import RunScene
from ..space.constants import MU_EARTH, R_EARTH
from ..space.orbit import Orbit
from . import tss

#: The tape: 2 cm x 50 um aluminium (E = 70 GPa, G = E / 2.6).
TAPE = Section.tape(0.02, 50e-6, E=7e10, rho=2700.0)
#: The round aluminium tether of the tape's mass per length (radius 0.564 mm).
ROUND = Section.circular(np.sqrt(TAPE.A / np.pi), E=7e10, rho=2700.0)
#: Altitude (m), tether length (m), end masses (kg), turns of initial twist.
ALTITUDE, LENGTH, MASS, TURNS = 400e3, 5e3, 20.0, 1.0


def torsion_speed(section):
    """The speed ``sqrt(GJ / rho I_p)`` (m/s) of torsional waves along ``section``."""
    return float(np.sqrt(section.GJ / section.polar_mass_moment))


def tether(n_elements=16, section=TAPE, rod=True, length=LENGTH, mass=MASS):
    """The tether along the local vertical (``+x`` at ``t = 0``) of the orbit at
    ``ALTITUDE``, centred on the reference point, with point masses ``mass`` at both ends:
    a ``Rod`` (``rod``; its section's normal axis along the orbit normal ``z``) or a
    ``Cable`` of ``section``; returns ``(system, line, orbit)``."""
    ends = ([-length / 2, 0, 0], [length / 2, 0, 0])
    line = Rod.straight(*ends, n_elements, section, normal=[0, 0, 1], name="tether") if rod \
        else Cable.straight(*ends, n_elements, section, name="tether")
    orbit = Orbit(MU_EARTH, a=R_EARTH + ALTITUDE)
    system = System([line]).add_point_mass(line.node(0), mass)
    return system.add_point_mass(line.node(-1), mass).add_orbit(orbit), line, orbit


def twisted(system, rod, state, turns=TURNS):
    """``state`` with ``turns`` turns of twist spread uniformly along ``rod`` (twist
    ``2 pi turns s / L`` at the nodes and its rate as their ``phi_x``), at rest in
    twist."""
    q = state.q.copy()
    dofs = system.dofs(rod)[rod.n_centreline:]
    rate = 2 * np.pi * turns / rod.length
    q[dofs] = np.column_stack([rate * rod.mesh.p[0], np.full(rod.n_nodes, rate)]).ravel()
    return State(system, q, state.lam, v=state.v)


def relative_twist(system, rod, q):
    """The twist of the last end against the first (rad) for each row of ``q``
    (n_steps, n_dofs): ``rod.twist`` at ``L`` minus at 0."""
    dofs = system.dofs(rod)
    return np.array([np.subtract(*rod.twist(qi[dofs], [rod.length, 0.0])) for qi in q])


def numbers(system, rod, orbit, result):
    """The scene's outputs: the period of the relative twist (``relative_twist``) against
    ``2 L / c`` (NaN with fewer than two zero crossings: ``tss.crossing_frequency``)
    and the largest pitch and roll (rad) of the end-to-end line."""
    twist = relative_twist(system, rod, result.q)
    pitch, roll = tss.attitude(orbit, rod, result.t, result.q[:, system.dofs(rod)])
    return {"torsion_period": 2 * np.pi / tss.crossing_frequency(result.t, twist),
            "torsion_period_exact": 2 * rod.length / torsion_speed(rod.section),
            "twist_max": float(np.abs(twist).max()),
            "pitch_max": float(np.abs(pitch).max()), "roll_max": float(np.abs(roll).max())}


def scene(elements=16, t_end=None, dt=10.0, every=5, turns=TURNS):
    """The ``tape-tether`` scene (module docstring) with ``elements`` rod elements, run to
    ``t_end`` (default one orbit) with step ``dt``, every ``every``-th step saved."""
    system, rod, orbit = tether(elements)
    initial = twisted(system, rod, tss.librated(system, orbit), turns)
    settings = {"t_end": orbit.period if t_end is None else t_end, "dt": dt,
                "every": every, "rho_inf": 0.8}
    parameters = {"elements": elements, "length": LENGTH, "width": 0.02,
                  "thickness": 50e-6, "end_mass": MASS, "altitude": ALTITUDE,
                  "turns": turns}
    return RunScene("tape-tether", system, initial, settings, parameters,
                    lambda result: numbers(system, rod, orbit, result))


def run(options):
    """``scene`` run by ``skfem-cable run tape-tether`` (``--elements``, ``--t-end``)."""
    return scene(options.value("elements", 16)).run(options)
