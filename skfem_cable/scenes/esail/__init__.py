"""The electric solar-wind sail of the paper (Sects. 2.1, 3, 4.1): a rigid cylindrical hub
in natural coordinates, ``p`` ANCF tethers pinned to its rim, remote units at their tips,
the solar-wind Coulomb force, and the auxiliary outputs of Sect. 3.

Frames (Sect. 2.1): H heliocentric ecliptic; I parallel to H with origin at ``R0`` (the hub
centre at t = 0), in which the system is formulated; O the orbit frame (``Z_O`` radial from
the Sun); B the hub body frame (``X_B`` the spin axis); E the frame of the remote units'
mean plane.

Departures from the paper, each a slip of the text (see ``docs/esail.md``): tether ``i``
sits at ``zeta_i = 2 pi (i - 1)/p`` in the hub mid-plane (Eqs. 57, 79; Eq. 54 writes
``2 pi i / p`` and measures from base point A); the initial stretch is the exact steady
rotating-cable solution anchored at the hub rim (Eq. 79 ignores the hub radius in the
strain, which would open the joints by ``R eps``); angles are measured from ``Z_O`` for both
the thrust and the reaction (Eqs. 74, 77 write an elevation); the precession angle is the
azimuth of the projection of ``X_E`` (``atan2``, not ``acos``); ``reaction_force`` is the force
the tethers apply to the hub (the paper's multipliers carry the opposite sign).
"""

from .config import FULL_SIZE, MISSION_RTOL, BaselineConfig, ESailScene
from .full_rig import FULL_RIG, Rig
from .pictures import TABLE2_HZ, coning_animation, distinct_frequencies, figures, psd, psd_figure
from .references import rigid_coning, spinning_modes, spinning_tether
from .report import outputs
from .rig import SETTLE_SPINS, SETTLE_STEP, build, build_orbit, rotating_cable_stretch, settled
from .ring import RemoteUnit, auxiliary_tension, tip_positions, tip_spacing
from .scene import run
from .spin_control import SpinController
from .thrusters import RemoteUnitThrust, tip_points

__all__ = [
    "BaselineConfig",
    "ESailScene",
    "FULL_RIG",
    "FULL_SIZE",
    "MISSION_RTOL",
    "RemoteUnit",
    "RemoteUnitThrust",
    "Rig",
    "SETTLE_SPINS",
    "SETTLE_STEP",
    "SpinController",
    "TABLE2_HZ",
    "auxiliary_tension",
    "build",
    "build_orbit",
    "coning_animation",
    "distinct_frequencies",
    "figures",
    "outputs",
    "psd",
    "psd_figure",
    "rigid_coning",
    "rotating_cable_stretch",
    "run",
    "settled",
    "spinning_modes",
    "spinning_tether",
    "tip_points",
    "tip_positions",
    "tip_spacing",
]
