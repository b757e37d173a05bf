"""Deploying a tethered subsatellite from 10 m to 10 km under tension control (``control``).

A 100 kg subsatellite leaves a 1000 kg mother in a circular 400 km orbit (the ``tss``
scene's orbit) on a SEDS-like tether (0.75 mm Spectra, 0.43 kg/km) paid out by a reel
on the mother.  In the orbiting frame the gravity gradient pulls the subsatellite
outwards (``3 n^2 l`` per unit mass along the local vertical) and the Coriolis force of
the paying out swings it backwards, so the tether's in-plane libration ``theta``
follows (massless tether, reduced mass ``m``, mean motion ``n``)

    l'' = l ((theta' + n)^2 - n^2 + 3 n^2 cos^2 theta) - T / m,
    theta'' = -2 (l' / l) (theta' + n) - 3 n^2 sin theta cos theta.

A constant brake (``Brake``) lets the deployment run away: the length grows
exponentially and never stops.  The reel's motor is instead commanded with Rupp's
length-rate tension law (C. C. Rupp, "A tether tension control law for tethered
subsatellites deployed along local vertical", NASA TM X-64963, 1975; in the form of
the review of K. D. Kumar, J. Spacecraft Rockets 43 (2006) 705-720), a tension linear in
the length and rate errors about a commanded length ``l_c(t)``,

    T = m n^2 (3 l_c + a (l - l_c) + b (l' - l_c') / n) + 3 mu n^2 l_c^2 (1/2 - m_s / M),

whose first term is the subsatellite's equilibrium tension ``3 m n^2 l`` and whose last
is the tether's own, fed forward: its mass ``mu l`` at the mean arm ``l / 2`` from the
mother, less the centre of mass's distance ``l m_s / M`` (subsatellite ``m_s``, all
``M``).  About
the local vertical at a fixed ``l_c`` the linearized equations in ``x = (l - l_c) /
l_c`` and ``theta`` over ``tau = n t`` are ``x'' + b x' + (a - 3) x - 2 theta' = 0``,
``theta'' + 2 x' + 3 theta = 0``, with the characteristic polynomial ``s^4 + b s^3 + (a
+ 4) s^2 + 3 b s + 3 (a - 3)``; Routh-Hurwitz gives stability exactly for ``a > 3``, ``b
> 0`` (its last determinant is ``12 b^2``): the libration is damped through the length.
The command is an exponential deployment ``l0 e^(k n t)`` (``k = 0.3``: the Coriolis
swing settles near ``sin 2 theta = -4 k / 3``, -11.8 deg) rounded off at the target,
``l_c = (x^-2 + L^-2)^(-1/2)``; ``a = 5``, ``b = 3``.

``RuppTension`` is the controller (sampled every ``sample_time`` seconds, its tension held
in between); ``deploy_subsatellite`` runs the scene with it or with the brake.
"""

import numpy as np

from ..bodies.cable import Cable
from ..bodies.reel import Brake, Motor, Reel
from ..bodies.rigid import RigidBody
from ..bodies.section import Section
from ..control import sensors
from ..control.controller import Controller
from ..core.inputs import Input
from ..model.state import State
from ..model.system import System
from ..solvers.simulate import simulate
from ..space.constants import MU_EARTH, R_EARTH
from ..space.orbit import Orbit
from .tss import ALTITUDE

#: Mother and subsatellite masses (kg), the initial and the target free length (m).
MOTHER, SUBSATELLITE, START, TARGET = 1000.0, 100.0, 10.0, 10e3
#: The tether: 0.75 mm Spectra (E = 100 GPa, 970 kg/m^3: 0.43 kg/km).
SECTION = Section.circular(0.375e-3, 1e11, 970.0)
#: The reel: drum radius (m), inertia (kg m^2) and the tether it carries (m).
RADIUS, INERTIA, CAPACITY = 0.1, 1e-3, 20e3
#: The deployment's exponent ``k`` (per radian of orbit) and Rupp's gains ``a``, ``b``.
RATE, GAIN_LENGTH, GAIN_RATE = 0.3, 5.0, 3.0


def commanded_length(t, mean_motion, start=START, target=TARGET, rate=RATE):
    """``(l_c, l_c')``: the exponential deployment ``x = start e^(rate n t)`` rounded off
    at ``target``, ``l_c = (x^-2 + target^-2)^(-1/2)`` (m, m/s)."""
    x = start * np.exp(rate * mean_motion * np.asarray(t, dtype=float))
    length = (x**-2.0 + target**-2.0) ** -0.5
    return length, length**3 * x**-2.0 * rate * mean_motion


def reduced_mass(mother=MOTHER, subsatellite=SUBSATELLITE):
    """``m M / (m + M)`` (kg): the mass the tether's length equation sees."""
    return mother * subsatellite / (mother + subsatellite)


class RuppTension(Controller):
    """Rupp's length-rate tension law (module docstring) commanding the torque of a
    reel's motor, ``-R T`` (its input ``reel_torque``; ``T`` clipped at zero, a tether
    cannot push).

    Parameters
    ----------
    reel : Reel
        The reel, read by ``sensors.reel_length``.
    orbit : Orbit
        Gives the mean motion ``n``.
    mass : float
        The reduced mass ``m`` (kg) of the subsatellite and the mother.
    mass_per_length : float
        The tether's ``mu`` (kg/m), for the fed-forward tension of its own mass.
    centre : float
        ``m_s / M``: the centre of mass's distance from the mother over the length.
    gains : (float, float)
        ``(a, b)``: stable for ``a > 3``, ``b > 0``.
    command : callable
        ``command(t) -> (l_c, l_c')`` (m, m/s).
    sample_time : float
        Seconds between samples.
    """

    def __init__(self, reel, orbit, mass, mass_per_length, centre, gains, command,
                 sample_time):
        super().__init__(sample_time)
        a, b = gains
        if not (a > 3 and b > 0):
            raise ValueError(f"gains (a, b) must have a > 3 and b > 0 (Routh-Hurwitz), "
                             f"got {gains!r}")
        self.reel, self.gains, self.command = reel, (float(a), float(b)), command
        self.n, self.mass = orbit.mean_motion, float(mass)
        self.tether = 3.0 * float(mass_per_length) * (0.5 - float(centre))

    def tension(self, t, length, rate):
        """The commanded tension (N) at the measured ``length`` and ``rate``."""
        a, b = self.gains
        n = self.n
        target, target_rate = self.command(t)
        tension = self.mass * n**2 * (3 * target + a * (length - target)
                                      + b * (rate - target_rate) / n) \
            + self.tether * n**2 * target**2
        return max(float(tension), 0.0)

    def update(self, t, state):
        return {"reel_torque": -self.reel.radius * self.tension(
            t, *sensors.reel_length(state, self.reel))}


def build(elements=20, drive=None, orbit=None):
    """The mother (a cylinder, its centre on the local vertical), the reel at its centre
    and the tether of ``START`` m with the subsatellite at its tip along the local
    vertical, the system's centre of mass on the orbit's reference point.  ``drive``:
    the reel's (default: a ``Motor`` of the input ``reel_torque``).  Returns ``(system,
    parts)``, ``parts`` a dict of ``mother``, ``tether``, ``reel`` and ``orbit``."""
    orbit = orbit or Orbit(MU_EARTH, R_EARTH + ALTITUDE)
    x0 = -START * SUBSATELLITE / (MOTHER + SUBSATELLITE)
    radius, height = 0.6, 1.0
    mother = RigidBody.cylinder(radius, height, MOTHER / (np.pi * radius**2 * height),
                                position=(x0, 0, 0), name="mother")
    tether = Cable.straight([x0, 0, 0], [x0 + START, 0, 0], elements, SECTION, name="tether")
    reel = Reel(START, RADIUS, INERTIA, drive or Motor(Input("reel_torque", 0.0)))
    system = System([mother, tether, reel]).deploy(tether, mother.point([0, 0, 0]),
                                                   capacity=CAPACITY, reel=reel)
    system.add_point_mass(tether.node(-1), SUBSATELLITE).add_orbit(orbit)
    return system, {"mother": mother, "tether": tether, "reel": reel, "orbit": orbit}


def initial_state(system, parts, rate, tension):
    """At rest in the orbiting frame (turning at the orbit's rate), paying out at
    ``rate`` (m/s), with the reel's length shortened by the stretch of ``tension`` (N)
    so that the tether starts at that tension."""
    orbit, tether, reel = parts["orbit"], parts["tether"], parts["reel"]
    q = system.q0.copy()
    q[system.dofs(reel)] = START / (1 + tension / SECTION.EA)
    v = system.rigid_motion_velocity(q, orbit.angular_velocity(0.0))
    v += system.deployment(tether).paying_out(system, q, rate)
    return State(system, q, None, v=v)


def deploy_subsatellite(controlled=True, orbits=5.0, dt=10.0, elements=20, brake=0.14,
                        sample_time=None, every=6, **options):
    """Deploy for ``orbits`` orbital periods with steps of ``dt`` s: under Rupp's law
    sampled every ``sample_time`` s (default ``dt``), or with a constant brake of
    ``brake`` N m s/m.  Returns the run (``sc.Result``) and the parts (``build``; with
    the controller as ``controller``); ``options`` go to ``simulate``."""
    brake_drive = None if controlled else Brake(brake)
    system, parts = build(elements, brake_drive)
    orbit = parts["orbit"]
    command = lambda t: commanded_length(t, orbit.mean_motion)  # noqa: E731
    controller = RuppTension(parts["reel"], orbit, reduced_mass(), SECTION.mass_per_length,
                             SUBSATELLITE / (MOTHER + SUBSATELLITE), (GAIN_LENGTH, GAIN_RATE),
                             command, sample_time or dt)
    rate = command(0.0)[1]
    initial = initial_state(system, parts, rate, controller.tension(0.0, START, rate))
    result = simulate(system, t_end=orbits * orbit.period, dt=dt, rho_inf=0.8,
                      initial=initial, every=every,
                      controllers=[controller] if controlled else (), **options)
    return result, {**parts, "controller": controller}


def histories(result, parts):
    """Time histories of a run: ``t`` (s), the free ``length`` (m) and its ``rate``
    (m/s), and the ``pitch`` and ``roll`` (rad) of the line from the mother to the
    subsatellite in the orbiting frame (``sensors.libration``)."""
    reel, tether, orbit = parts["reel"], parts["tether"], parts["orbit"]
    states = [result.state(i) for i in range(len(result.t))]
    length, rate = np.array([sensors.reel_length(s, reel) for s in states]).T
    pitch, roll = np.array([sensors.libration(s, tether, orbit) for s in states]).T
    return {"t": result.t, "length": length, "rate": rate, "pitch": pitch, "roll": roll}
