"""The E-sail's configuration: the paper's baseline (Table 1) and the full-size sail."""

from dataclasses import dataclass, field

import numpy as np

from ...bodies.rigid import RigidBody
from ...bodies.section import Section, check_positive
from ...loads.coulomb import AU, SolarWind, SolarWindForce
from ...model.state import State
from ...model.system import System
from ...space.orbit import Orbit


@dataclass
class BaselineConfig:
    """Table 1 of the paper and Sect. 4.1 (SI units); every field is editable.

    ``voltage`` is one value for all tethers, a sequence with one per tether, or callables
    ``V(t)`` (voltage modulation); one callable may return all the voltages (an
    ``Input`` of one value per tether that a controller sets, ``control``).
    """

    n_tethers: int = 12
    tether_length: float = 10e3
    tether_area: float = 4.28e-9
    tether_inertia: float = 1.47e-18
    tether_density: float = 7653.0
    tether_E: float = 70e9
    gamma_axial: float = 1.0
    gamma_bending: float = 1.0
    voltage: object = 20e3
    remote_mass: float = 1.5
    hub_height: float = 2.0
    hub_radius: float = 1.0
    hub_density: float = 884.0
    spin_rate: float = 4e-3
    R0: tuple = (np.sqrt(0.5) * AU, np.sqrt(0.5) * AU, 0.0)
    wind: SolarWind = field(default_factory=SolarWind)

    def validate(self):
        """Raise ``ValueError`` naming the first invalid field."""
        if int(self.n_tethers) != self.n_tethers or self.n_tethers < 1:
            raise ValueError(f"n_tethers must be a positive integer, got {self.n_tethers!r}")
        for name in ("tether_length", "tether_area", "tether_inertia", "tether_density",
                     "tether_E", "remote_mass", "hub_height", "hub_radius", "hub_density",
                     "spin_rate"):
            check_positive(name, getattr(self, name))
        for name in ("gamma_axial", "gamma_bending"):
            check_positive(name, getattr(self, name), allow_zero=True)
        R0 = np.asarray(self.R0, dtype=float)
        if R0.shape != (3,) or not np.all(np.isfinite(R0)) or np.hypot(R0[0], R0[1]) == 0:
            raise ValueError(f"R0 must be a finite 3-vector off the ecliptic pole, got {self.R0!r}")
        return self

    @property
    def spin_period(self):
        """Nominal spin period ``T_s = 2 pi / omega_0`` (s)."""
        return 2 * np.pi / self.spin_rate

    @property
    def centrifugal_ratio(self):
        """The centrifugal tension at a tether's root, ``omega_0^2 L (m_u + m_t / 2)``
        (remote unit ``m_u``, tether ``m_t``), over the Coulomb force on the tether
        perpendicular to the wind at the voltage (20 kV when it is modulated), ``f L``:
        Janhunen and Toivanen's criterion for the spin rate asks for at least 5 (the
        E-sail paper's Ref. 18)."""
        tether = self.tether_density * self.tether_area * self.tether_length
        nominal = self.voltage if np.isscalar(self.voltage) else BaselineConfig.voltage
        return self.spin_rate**2 * (self.remote_mass + tether / 2) \
            / self.wind.force_per_length(nominal)

    @property
    def section(self):
        return Section(E=self.tether_E, A=self.tether_area, I=self.tether_inertia,
                       rho=self.tether_density, gamma_axial=self.gamma_axial,
                       gamma_bending=self.gamma_bending)


#: A full-size sail: 100 tethers of 20 km (the paper's section and remote units; about
#: 0.9 N at 1 AU), spinning at 1.2e-3 rad/s (period 87 min) so that the centrifugal
#: ratio (``BaselineConfig.centrifugal_ratio``) is 5.85, above the 5 of Janhunen and
#: Toivanen, "An intrinsic way to control E-sail spin" (2014, arXiv:1406.6847).
FULL_SIZE = BaselineConfig(n_tethers=100, tether_length=20e3, spin_rate=1.2e-3)

#: The relative tolerance of adaptive steps (``simulate(rtol=...)``, with ``atol`` 1e-3 m)
#: that keeps the thrust, the mean coning and the sail's spin rate (``outputs``'
#: ``spin_rate``) of ``FULL_SIZE`` within 1e-3 of a fixed 0.5 s run over an hour (largest
#: differences measured over the hour from the windless spin: spin rate 2.8e-5, coning
#: 2.5e-4, thrust 8.6e-6; at 3e-4 the coning is 2.1e-3 off; ``docs/benchmarks.md``).  The
#: steps hold their local error to 1.1e-5 (``GeneralizedAlpha``'s proportionality
#: transform).  Over a day the coning's slow swing accumulates phase.  The hub's own
#: rate carries a libration against the tethers (a period of about 130 s, up to 20 %)
#: whose phase only steps of about 0.5 s follow.  From the sail's state under the wind
#: (``settled``) the hour takes 146 steps instead of 1037, its outputs within 2.0e-3 (the
#: hub's rate; the others within 2.4e-4).
MISSION_RTOL = 5e-5


@dataclass
class ESailScene:
    """A built E-sail: the system, its bodies, the initial state and what ``outputs``
    needs (``zeta`` tether angles, ``anchors`` in the body frame, ``R0`` the heliocentric
    position of the origin of I at t = 0, ``orbit`` the heliocentric orbit of the system's
    reference point or None: I fixed; ``options`` the tethers' ``n_elements``, ``kind``,
    ``formulation`` and the wind's ``exponent`` it was built with, and the rig's
    ``remote_units``, ``auxiliary`` section and ``auxiliary_tension``; ``auxiliary`` the
    ring's auxiliary tethers, empty without one; ``facing`` a start for ``steady_facing``
    in its turned frame, or None)."""

    config: BaselineConfig
    alpha: float
    system: System
    hub: RigidBody
    tethers: list
    anchors: np.ndarray
    zeta: np.ndarray
    wind_force: SolarWindForce
    initial: State
    R0: np.ndarray
    orbit: Orbit | None = None
    options: dict = field(default_factory=dict)
    auxiliary: list = field(default_factory=list)
    facing: State | None = None

    def heliocentric(self, t, reference=None):
        """Heliocentric position (m) of the origin of the system's coordinates at times
        ``t`` (nt,): ``R0`` fixed, or the reference point ``R(t)`` of the run's
        ``reference`` (``Result.reference``: the orbit and its rebases; None: the orbit as
        given); (nt, 3)."""
        t = np.asarray(t, dtype=float)
        if self.orbit is None:
            return np.broadcast_to(self.R0, t.shape + (3,))
        return (self.orbit if reference is None else reference).position(t)
