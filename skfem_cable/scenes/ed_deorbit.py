"""The ``ed-deorbit`` scene: a bare electrodynamic tape deorbiting in the near-Earth
environment (``demos/ed_tether_deorbit.py`` runs it for a day, re-centring its reference
every orbit; ``skfem-cable run ed-deorbit --epoch 2026-01-01`` runs one orbit).

A 5 km aluminium tape (2 cm x 50 um, 3.5e7 S/m) along the local vertical between two
500 kg end masses, 400 km circular orbit at 51.6 deg, collecting its OML current from IRI
in IGRF (both at 60 s knots, ``ElectrodynamicForce(sample_every=60)``) through a 10 V
hollow cathode and a 100 ohm load, with NRLMSIS's drag (F10.7 = 150, Ap = 4).
"""

import numpy as np

from .. import environment
from ..bodies.cable import Cable
from ..bodies.section import Section
from ..environment.oml import Cathode
from ..loads.atmosphere import AtmosphericDrag
from ..loads.electrodynamic import ElectrodynamicForce
from ..model.system import System
from ..runner.drive import RunScene
from ..solvers.steady import at_rest_in_orbit
from ..space.constants import MU_EARTH, R_EARTH
from ..space.orbit import Orbit

#: The epoch of ``t = 0`` (UTC).
EPOCH = "2026-01-01T00:00:00"
#: The tape, its circuit and its orbit (SI units); space weather F10.7 (sfu), Ap.
TETHER = {"length": 5e3, "width": 0.02, "thickness": 5e-5, "E": 7e10, "density": 2700.0,
          "conductivity": 3.5e7, "cathode": 10.0, "load": 100.0, "end_mass": 500.0,
          "altitude": 400e3, "inclination": 51.6, "f107": 150.0, "ap": 4.0, "cd": 2.2,
          "n_elements": 4, "steps_per_orbit": 200, "sample_every": 60.0}


def build(orbit, p=TETHER, lorentz=True, drag=True, epoch=EPOCH):
    """The tape between its end masses, in orbit on ``orbit`` at ``epoch``, collecting
    its OML current from IRI in IGRF (without it if not ``lorentz``), with MSIS's drag
    (if ``drag``): ``(system, load)``."""
    half = p["length"] / 2
    section = Section(E=p["E"], A=p["width"] * p["thickness"], I=1e-12,
                         rho=p["density"])
    cable = Cable.straight([-half, 0, 0], [half, 0, 0], p["n_elements"], section)
    load = ElectrodynamicForce(
        cable, "oml", environment.IGRF(), plasma=environment.IRI(f107=p["f107"]),
        cathode=Cathode(p["cathode"]), load=p["load"], conductivity=p["conductivity"],
        perimeter=2 * (p["width"] + p["thickness"]), sample_every=p["sample_every"])
    system = (System([cable]).add_point_mass(cable.node(0), p["end_mass"])
              .add_point_mass(cable.node(-1), p["end_mass"]).add_orbit(orbit, epoch=epoch))
    if drag:
        system.add_load(AtmosphericDrag(cable, environment.MSIS(
            f107=p["f107"], f107a=p["f107"], ap=p["ap"]), cd=p["cd"], area=p["width"]))
    return (system.add_load(load) if lorentz else system), load


def start(p=TETHER, epoch=EPOCH):
    """The circular orbit and the gravity-gradient steady state (found without the
    Lorentz force), at rest in the orbiting frame: ``(orbit, State)``."""
    orbit = Orbit(MU_EARTH, R_EARTH + p["altitude"],
                  inclination=np.radians(p["inclination"]))
    free = build(orbit, p, lorentz=False, drag=False, epoch=epoch)[0]  # none with drag
    return orbit, at_rest_in_orbit(free, build(orbit, p, epoch=epoch)[0], orbit)


def scene(epoch=EPOCH, orbits=1.0, p=TETHER):
    """The tape at ``epoch`` from its gravity-gradient steady state (``start``), run for
    ``orbits`` orbits at ``p["steps_per_orbit"]`` steps per orbit (``skfem-cable run
    ed-deorbit``; the reference is rebased by the run, not re-centred)."""
    orbit, initial = start(p, epoch)
    period = orbit.period
    return RunScene("ed-deorbit", initial.system, initial,
                    {"t_end": orbits * period, "dt": period / p["steps_per_orbit"],
                     "every": 10},
                    {"epoch": str(epoch), "length": p["length"], "width": p["width"],
                     "thickness": p["thickness"], "altitude": p["altitude"],
                     "inclination_deg": p["inclination"], "f107": p["f107"]})


def run(options):
    """``skfem-cable run ed-deorbit`` (``--epoch``, default ``EPOCH``)."""
    return scene(options.value("epoch", EPOCH)).run(options)
