"""The Coulomb drag of a flowing plasma on a charged tether without trapped electrons:
Janhunen's analytical thrust formula (Ann. Geophys. 27, 3089, 2009), the one
implementation behind the E-sail law ``"janhunen2009"`` (``thrust_laws``) and the plasma
brake (``plasma_brake``, whose particle simulations the formula "reproduces ... well",
Janhunen, Ann. Geophys. 32, 1207, 2014).

Across a flow of speed ``u``, per unit length of tether,

    dF/dz = K 3.864 P_dyn sqrt(eps0 V~ / (e n)) exp(-V_i / V~),

    P_dyn = m_i n u^2,   V~ = |V0| / ln(lambda_eff / r_w*),
    lambda_eff = sqrt(eps0 |V0| / (e n)),   V_i = m_i u^2 / (2 e),

with ``n`` the plasma density, ``m_i`` the ion mass (protons of the solar wind, O+ of the
F region), ``V0`` the tether's voltage (positive for the E-sail, negative for the plasma
brake: the ions see the same barrier, the electrons, repelled or absent, do not shield
it), ``r_w*`` the tether's effective electric radius (about ``sqrt(b r_w)`` for a
multi-wire tether of width ``b`` and wire radius ``r_w``; default 1 mm, the order of a
2 cm wide tether of 25 um wires; the force grows with it only through the logarithm)
and ``K`` the simulations' fitting factor (1: the formula as
published; "reduced by a modest factor" when the magnetic field lies along the tether,
the 2014 abstract).  ``sqrt(eps0 V~ / (e n))`` is the width of the ion-deflecting
potential, ``exp(-V_i / V~)`` the ions that cross it.  The papers' full texts were not
reachable here (their abstracts were): the form and the factor 3.864 are checked against
the 2009 abstract's number, "1 N ... for 2000 km total tether length" (0.5 uN/m) at
20 kV in the average 1 AU wind, which the formula gives within 5 % (0.478 uN/m with
``r_w*`` = 1 mm), and the 2014 abstract's (``docs/esail.md``).

Examples
--------
The E-sail's 20 kV tether in the average 1 AU wind (7.3 cm^-3, 400 km/s):

>>> from scipy.constants import m_p
>>> from skfem_cable.loads.coulomb_drag import CoulombDrag
>>> f"{CoulombDrag().force_per_length(20e3, 7.3e6, 4e5, m_p) * 1e6:.3f} uN/m"
'0.478 uN/m'
"""

from dataclasses import dataclass

import numpy as np
from scipy.constants import e as ELEMENTARY_CHARGE
from scipy.constants import epsilon_0

from ..bodies.section import check_positive

THRUST_FACTOR = 3.864
"""The numerical factor of the thrust formula (Janhunen 2009, quoted in Janhunen 2014)."""


@dataclass(frozen=True)
class CoulombDrag:
    """Janhunen's thrust formula (module notes) for a tether of the given electric radius.

    Parameters
    ----------
    electric_radius : float
        The tether's effective electric radius ``r_w*`` (m, > 0), default 1 mm.
    fit : float
        The simulations' fitting factor ``K`` (> 0), default 1 (the formula as published).

    Examples
    --------
    O+ at 1e11 m^-3 meeting a -1 kV tether at 7.5 km/s (the plasma brake):

    >>> from skfem_cable.environment.plasma import OXYGEN_ION_MASS
    >>> f"{CoulombDrag().force_per_length(-1e3, 1e11, 7.5e3, OXYGEN_ION_MASS):.3e} N/m"
    '1.619e-07 N/m'
    """

    electric_radius: float = 1e-3
    fit: float = 1.0

    def __post_init__(self):
        check_positive("electric_radius", self.electric_radius)
        check_positive("fit", self.fit)

    def reduced_voltage(self, voltage, density, eps0=epsilon_0):
        """``V~ = |V0| / ln(lambda_eff / r_w*)`` (V) for the voltage ``voltage`` (V, != 0)
        in the density ``density`` (m^-3, array); ``ValueError`` when the screening length
        is not longer than the tether's radius (the formula's range)."""
        screening = np.sqrt(eps0 * abs(voltage) / (ELEMENTARY_CHARGE *
                                                   np.asarray(density, dtype=float)))
        ratio = screening / self.electric_radius
        if np.any(ratio <= 1.0):
            raise ValueError(f"CoulombDrag: the screening length sqrt(eps0 |V0| / (e n)) "
                             f"({np.min(screening):.3g} m) must exceed electric_radius "
                             f"({self.electric_radius:g} m): a larger voltage or a "
                             f"thinner tether")
        return abs(voltage) / np.log(ratio)

    def coefficient(self, voltage, density, speed, ion_mass, eps0=epsilon_0):
        """``k = (dF/dz) / u^2`` (kg/m^2) at the voltage ``voltage`` (V), the density
        ``density`` (m^-3, array), the flow speed ``speed`` (m/s, the one of ``V_i``), the
        ion mass ``ion_mass`` (kg) and the permittivity ``eps0`` (F/m)."""
        reduced = self.reduced_voltage(voltage, density, eps0)
        ion_voltage = ion_mass * speed**2 / (2.0 * ELEMENTARY_CHARGE)
        return (self.fit * THRUST_FACTOR * ion_mass
                * np.sqrt(eps0 * reduced * np.asarray(density, dtype=float)
                          / ELEMENTARY_CHARGE) * np.exp(-ion_voltage / reduced))

    def force_per_length(self, voltage, density, speed, ion_mass, eps0=epsilon_0):
        """``dF/dz`` (N/m) on a tether across a flow of speed ``speed`` (m/s)."""
        return self.coefficient(voltage, density, speed, ion_mass, eps0) * speed**2
