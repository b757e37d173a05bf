"""The full rig as one value: a sail with its remote units and its ring (``Rig``), and
the preset ``FULL_RIG`` of the E-sail's baseline design."""

from dataclasses import dataclass

from ...bodies.section import Section
from .config import FULL_SIZE
from .rig import AUXILIARY_SHARE, build
from .ring import RemoteUnit


@dataclass(frozen=True)
class Rig:
    """A full E-sail rig: the sail ``config`` with ``remote_units`` at the tips and a ring
    of ``auxiliary`` tethers at the design ``auxiliary_tension`` (N);
    ``rig.build(alpha_deg, n_elements, ...)`` is ``esail.build`` with them."""

    config: object
    remote_units: RemoteUnit
    auxiliary: Section
    auxiliary_tension: float

    def build(self, alpha_deg, n_elements, **options):
        """``esail.build(self.config, alpha_deg, n_elements, remote_units=...,
        auxiliary=..., auxiliary_tension=..., **options)``."""
        return build(self.config, alpha_deg, n_elements, remote_units=self.remote_units,
                     auxiliary=self.auxiliary, auxiliary_tension=self.auxiliary_tension,
                     **options)


#: The full rig of the E-sail's baseline design (Janhunen et al. 2010, Rev. Sci. Instrum.
#: 81, 111301: about 1 N from 100 main tethers of 20 km with a remote unit at each tip and
#: auxiliary tethers joining neighbouring units): ``FULL_SIZE``'s sail (spin 1.2e-3 rad/s)
#: with remote units of the paper's 1.5 kg.  Not found in the papers followed, and chosen
#: here: the unit's inertia, 0.01 kg m^2 (a 1.5 kg box of 10 x 10 x 25 cm); its thrust,
#: 100 uN (the sail's spin-up from rest in 4.7 days); the auxiliary tether, a polyimide
#: tape 3 mm x 12.7 um (E = 2.5 GPa, rho = 1420 kg/m^3: EA = 95 N, 68 g per 1.26 km
#: tether); and its design tension, the default ``rig.AUXILIARY_SHARE`` (half) of a unit's
#: centrifugal force, 21.6 mN, which keeps the ring taut while the sail sails (the ring
#: then pulls each unit inwards by 3.1 % of that force).
FULL_RIG = Rig(FULL_SIZE, RemoteUnit(mass=1.5, inertia=0.01, thrust_max=1e-4),
               Section(E=2.5e9, A=3e-3 * 12.7e-6, I=1e-20, rho=1420.0, gamma_axial=1.0,
                       gamma_bending=0.0),
               AUXILIARY_SHARE * 1.5 * FULL_SIZE.spin_rate**2 * FULL_SIZE.tether_length)
