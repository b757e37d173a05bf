"""Gravitational parameters, radii and rotation rates of the central bodies (SI)."""

from dataclasses import dataclass

MU_EARTH = 3.986004418e14
"""Earth's gravitational parameter (m^3/s^2, WGS 84 / IERS)."""
MU_SUN = 1.32712440018e20
"""The Sun's gravitational parameter (m^3/s^2, IAU 2009 / DE405)."""
R_EARTH = 6378.137e3
"""Earth's equatorial radius (m, WGS 84)."""
AU = 1.495978707e11
"""The astronomical unit (m, IAU 2012, exact)."""
OMEGA_EARTH = 7.2921150e-5
"""The Earth's rotation rate (rad/s, IERS)."""
J2_EARTH = 1.08262668e-3
"""The Earth's second zonal harmonic (EGM2008, unnormalised)."""
R_SUN = 6.957e8
"""The Sun's nominal radius (m, IAU 2015 Resolution B3)."""
OMEGA_SUN = 2.8653e-6
"""The Sun's sidereal (Carrington) rotation rate (rad/s: one turn in 25.38 days)."""


@dataclass(frozen=True)
class CentralBody:
    """A central body: gravitational parameter ``mu`` (m^3/s^2), equatorial ``radius``
    (m), second zonal harmonic ``j2`` and ``rotation_rate`` (rad/s, about the inertial
    ``z`` axis: the rate of the atmosphere a drag load co-rotates with); None: no value
    known."""

    mu: float
    radius: float | None
    j2: float | None
    rotation_rate: float | None = None


#: The central bodies known by name (scene files' ``central_body``) and by ``mu``
#: (``Orbit.central_body``); a new one is one more entry.
CENTRAL_BODIES = {"earth": CentralBody(MU_EARTH, R_EARTH, J2_EARTH, OMEGA_EARTH),
                  "sun": CentralBody(MU_SUN, R_SUN, None, OMEGA_SUN)}
