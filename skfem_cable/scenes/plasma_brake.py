"""The ``plasma-brake`` scene: a 5 km plasma-brake tether deorbiting a 260 kg object from
a circular 800 km orbit (Janhunen, Ann. Geophys. 32, 1207, 2014: 0.43 mN, about 100 km of
altitude a year; ``demos/plasma_brake.py`` runs it for days, re-centring its reference
every orbit; ``skfem-cable run plasma-brake --epoch 2026-01-01`` runs one orbit).

The object (a point mass) sits at the tether's lower end, a 0.5 kg tip mass at its upper
end (our choice: it keeps the tether along the local vertical by the gravity gradient,
its root tension of about 8 mN far above the brake's 0.4 mN), in a sun-synchronous 800 km
orbit (98.6 deg).  The tether is the paper's: 5 km of 0.055 kg (an aluminium section of
that mass per length), at -1 kV, of electric radius 1 mm; the plasma is IRI's (F10.7 =
150, O+), sampled at knots every 60 s (``PlasmaBrake(sample_every=60)``).
"""

import numpy as np

from .. import environment
from ..bodies.cable import Cable
from ..bodies.section import Section
from ..loads.plasma_brake import PlasmaBrake
from ..model.system import System
from ..runner.drive import RunScene
from ..solvers.steady import at_rest_in_orbit
from ..space.constants import MU_EARTH, R_EARTH
from ..space.orbit import Orbit

#: The epoch of ``t = 0`` (UTC).
EPOCH = "2026-01-01T00:00:00"
#: The tether, its bias and its orbit (SI units); F10.7 (sfu).
BRAKE = {"length": 5e3, "tether_mass": 0.055, "E": 7e10, "density": 2700.0,
         "voltage": -1e3, "mass": 260.0, "tip_mass": 0.5, "altitude": 800e3,
         "inclination": 98.6, "f107": 150.0, "n_elements": 4, "steps_per_orbit": 200,
         "sample_every": 60.0}


def plasma_of(p=BRAKE):
    """The scene's plasma: IRI at the F10.7 of ``p`` (without an epoch: the system's)."""
    return environment.IRI(f107=p["f107"])


def build(orbit, p=BRAKE, brake=True, epoch=EPOCH, plasma=None):
    """The object, the tether and its tip mass in orbit on ``orbit`` at ``epoch``, with
    the plasma brake in ``plasma`` (default ``plasma_of(p)``, at knots every
    ``p["sample_every"]`` s; a ``UniformPlasma`` is evaluated at every step) unless not
    ``brake``: ``(system, load)``."""
    area = p["tether_mass"] / (p["length"] * p["density"])
    section = Section(E=p["E"], A=area, I=area**2 / (4 * np.pi), rho=p["density"])
    cable = Cable.straight([0, 0, 0], [p["length"], 0, 0], p["n_elements"], section,
                           name="tether")
    every = p["sample_every"] if plasma is None else None
    load = PlasmaBrake(cable, p["voltage"], plasma_of(p) if plasma is None else plasma,
                       sample_every=every)
    system = (System([cable]).add_point_mass(cable.node(0), p["mass"])
              .add_point_mass(cable.node(-1), p["tip_mass"]).add_orbit(orbit, epoch=epoch))
    return (system.add_load(load) if brake else system), load


def start(p=BRAKE, epoch=EPOCH, plasma=None):
    """The circular orbit and the gravity-gradient steady state (found without the
    brake), at rest in the orbiting frame: ``(orbit, State)``, the state's system with
    the brake in ``plasma`` (``build``)."""
    orbit = Orbit(MU_EARTH, R_EARTH + p["altitude"], inclination=np.radians(p["inclination"]))
    free = build(orbit, p, brake=False, epoch=epoch)[0]
    return orbit, at_rest_in_orbit(free, build(orbit, p, epoch=epoch, plasma=plasma)[0], orbit)


def scene(epoch=EPOCH, orbits=1.0, p=BRAKE, plasma=None):
    """The tether at ``epoch`` from its gravity-gradient steady state (``start``), run for
    ``orbits`` orbits at ``p["steps_per_orbit"]`` steps per orbit (``skfem-cable run
    plasma-brake``; the summary's loads: the brake's along-track force and power,
    ``PlasmaBrake.outputs``)."""
    orbit, initial = start(p, epoch, plasma)
    return RunScene("plasma-brake", initial.system, initial,
                    {"t_end": orbits * orbit.period, "dt": orbit.period / p["steps_per_orbit"],
                     "every": 10},
                    {"epoch": str(epoch), "length": p["length"], "voltage": p["voltage"],
                     "mass": p["mass"], "altitude": p["altitude"],
                     "inclination_deg": p["inclination"], "f107": p["f107"]})


def run(options):
    """``skfem-cable run plasma-brake`` (``--epoch``, default ``EPOCH``)."""
    return scene(options.value("epoch", EPOCH)).run(options)
