"""The ``ed-deorbit`` scene: a bare electrodynamic tape deorbiting in the near-Earth
environment (``demos/ed_tether_deorbit.py`` runs it for a day, re-centring its reference
every orbit; ``skfem-cable run ed-deorbit --epoch 2026-01-01`` runs one orbit).

A 5 km aluminium tape (2 cm x 50 um, 3.5e7 S/m) along the local vertical between two
500 kg end masses, 400 km circular orbit at 51.6 deg, collecting its OML current from IRI
in IGRF (both at 60 s knots, ``ElectrodynamicForce(sample_every=60)``) through a 10 V
hollow cathode and a 100 ohm load, with NRLMSIS's drag (F10.7 = 150, Ap = 4; at the same
knots, ``AtmosphericDrag(sample_every=60)``).  Its run refactors the iteration matrix at
every Newton iteration (``NEWTON``).
"""

import numpy as np

from .. import environment
from ..bodies.cable import Cable
from ..bodies.section import Section
from ..environment.oml import Cathode
from ..loads.atmosphere import AtmosphericDrag
from ..loads.electrodynamic import ElectrodynamicForce
from ..loads.orbit_gravity import system_mass_points
from ..model.system import System
from ..runner.drive import RunScene
from ..solvers.steady import at_rest_in_orbit
from ..space.constants import MU_EARTH, R_EARTH
from ..space.orbit import Orbit

#: The epoch of ``t = 0`` (UTC).
EPOCH = "2026-01-01T00:00:00"
#: The integrator's Newton iteration: the matrix refactored at every iteration (with
#: modified Newton's stale matrix a day of the demo refused 976 of 5071 attempted steps,
#: with full Newton 28 of 3175, the OML current then held fixed in the tangent; with its
#: coupling in the tangent, 43 of 3162: ``docs/environment.md``).
NEWTON = "full"
#: The tape, its circuit and its orbit (SI units); space weather F10.7 (sfu), Ap.
TETHER = {"length": 5e3, "width": 0.02, "thickness": 5e-5, "E": 7e10, "density": 2700.0,
          "conductivity": 3.5e7, "cathode": 10.0, "load": 100.0, "end_mass": 500.0,
          "altitude": 400e3, "inclination": 51.6, "f107": 150.0, "ap": 4.0, "cd": 2.2,
          "n_elements": 4, "steps_per_orbit": 200, "sample_every": 60.0}


def build(orbit, p=TETHER, lorentz=True, drag=True, epoch=EPOCH):
    """The tape between its end masses (``p["end_mass"]``: one mass for both ends, or
    the pair at the cathode's end and at the free end), in orbit on ``orbit`` at
    ``epoch``, collecting its OML current from IRI in IGRF (without it if not
    ``lorentz``), with MSIS's drag (if ``drag``): ``(system, load)``."""
    half = p["length"] / 2
    section = Section(E=p["E"], A=p["width"] * p["thickness"], I=1e-12,
                         rho=p["density"])
    cable = Cable.straight([-half, 0, 0], [half, 0, 0], p["n_elements"], section)
    cathode_end, free_end = np.broadcast_to(np.asarray(p["end_mass"], dtype=float), 2)
    load = ElectrodynamicForce(
        cable, "oml", environment.IGRF(), plasma=environment.IRI(f107=p["f107"]),
        cathode=Cathode(p["cathode"]), load=p["load"], conductivity=p["conductivity"],
        perimeter=2 * (p["width"] + p["thickness"]), sample_every=p["sample_every"])
    system = (System([cable]).add_point_mass(cable.node(0), cathode_end)
              .add_point_mass(cable.node(-1), free_end).add_orbit(orbit, epoch=epoch))
    if drag:
        system.add_load(AtmosphericDrag(cable, environment.MSIS(
            f107=p["f107"], f107a=p["f107"], ap=p["ap"]), cd=p["cd"], area=p["width"],
            sample_every=p["sample_every"]))
    return (system.add_load(load) if lorentz else system), load


def start(p=TETHER, epoch=EPOCH):
    """The circular orbit and the gravity-gradient steady state (found without the
    Lorentz force), at rest in the orbiting frame: ``(orbit, State)``."""
    orbit = Orbit(MU_EARTH, R_EARTH + p["altitude"],
                  inclination=np.radians(p["inclination"]))
    free = build(orbit, p, lorentz=False, drag=False, epoch=epoch)[0]  # none with drag
    return orbit, at_rest_in_orbit(free, build(orbit, p, epoch=epoch)[0], orbit)


def centre_of_mass(system, reference, q, v, t):
    """The absolute position and velocity (3,) each of the centre of mass of ``system``
    at offsets ``q``, ``v`` from the point of ``reference`` (an ``Orbit`` or a run's
    ``Reference``) at ``t``, and the total mass."""
    return (reference.position(t) + system.centre_of_mass(q),
            reference.velocity(t) + system.centre_of_mass(v),
            system_mass_points(system).mass.sum())


def semi_major_axis(position, velocity):
    """The osculating semi-major axis (m) of an absolute state about the Earth."""
    return Orbit.from_state(MU_EARTH, position, velocity).a


def gauss_rate(a, velocity, force, mass):
    """Gauss's equation for the semi-major axis (m/s): ``2 a^2 (V . F) / (mu m)``, the
    specific orbital energy ``-mu / (2 a)`` changing at the force's power per unit
    mass."""
    return 2 * a**2 * np.dot(velocity, force) / (MU_EARTH * mass)


def scene(epoch=EPOCH, orbits=1.0, p=TETHER):
    """The tape at ``epoch`` from its gravity-gradient steady state (``start``), run for
    ``orbits`` orbits at ``p["steps_per_orbit"]`` steps per orbit (``skfem-cable run
    ed-deorbit``; the reference is rebased by the run, not re-centred)."""
    orbit, initial = start(p, epoch)
    period = orbit.period
    return RunScene("ed-deorbit", initial.system, initial,
                    {"t_end": orbits * period, "dt": period / p["steps_per_orbit"],
                     "every": 10, "newton": NEWTON},
                    {"epoch": str(epoch), "length": p["length"], "width": p["width"],
                     "thickness": p["thickness"], "altitude": p["altitude"],
                     "inclination_deg": p["inclination"], "f107": p["f107"]})


def run(options):
    """``skfem-cable run ed-deorbit`` (``--epoch``, default ``EPOCH``)."""
    return scene(options.value("epoch", EPOCH)).run(options)
