"""Keplerian reference orbits and the central body's differential gravity.

A system in orbit keeps small coordinates: positions are offsets ``delta`` from a
reference point moving on a Keplerian orbit, in axes parallel to the inertial ones (the
E-sail paper's translated frame, Sect. 2, which it needs because heliocentric positions of
1.5e11 m leave about 3e-5 m of double precision).  The reference point accelerates with
the central body's gravity ``g(R)``, so a body at ``R + delta`` feels, in the reference
point's frame, the *differential* gravity ``g(R + delta) - g(R)``: two nearly equal
vectors whose difference must not be formed by subtraction.  :func:`differential_gravity`
uses Battin's cancellation-free form (Battin, *An Introduction to the Mathematics and
Methods of Astrodynamics*, AIAA 1999: the function ``f(q)`` of Encke's method).

A long run with thrust carries its system away from the reference point; Encke's
*rectification* (``solvers.rectify``) then re-bases the reference on the osculating orbit
of the centre of mass.  The run's reference becomes a chain of Keplerian arcs, each in
force from its rebase time on: a ``Reference``, the run's state (made per run from the
system's ``Orbit``, held by the terms that read ``R(t)``, saved in checkpoints, carried by
the run's ``Result``), whose ``position``, ``velocity``, ``lvlh`` and the other functions
of time evaluate the arc in force at each time: the offsets a run saved at any time read
against the reference they were computed in.  An ``Orbit`` is one arc, as given: a run
never changes it.

Angles are in radians, lengths in metres, times in seconds, ``mu`` in m^3/s^2.
"""

from .constants import (
    AU,
    CENTRAL_BODIES,
    J2_EARTH,
    MU_EARTH,
    MU_SUN,
    OMEGA_EARTH,
    OMEGA_SUN,
    R_EARTH,
    R_SUN,
    CentralBody,
)
from .kepler import EPS, KEPLER_ITERATIONS, eccentric_anomaly, kepler_state, solve_kepler
from .orbit import Orbit, co_rotation
from .reference import Reference
from .tidal import battin_f, differential_gravity, gravity_gradient

__all__ = [
    "AU",
    "CENTRAL_BODIES",
    "CentralBody",
    "EPS",
    "J2_EARTH",
    "KEPLER_ITERATIONS",
    "MU_EARTH",
    "MU_SUN",
    "OMEGA_EARTH",
    "OMEGA_SUN",
    "Orbit",
    "R_EARTH",
    "R_SUN",
    "Reference",
    "battin_f",
    "co_rotation",
    "differential_gravity",
    "eccentric_anomaly",
    "gravity_gradient",
    "kepler_state",
    "solve_kepler",
]
