"""The E-sail's full rig: a remote unit at each tether tip and the ring of auxiliary
tethers that joins neighbouring units (Janhunen et al., "Electric solar wind sail: toward
test missions", Rev. Sci. Instrum. 81, 111301, 2010, Sects. II and III.C; Janhunen,
"Photonic spin control for solar wind electric sail", Acta Astronaut. 83, 85, 2013, its
design "with auxiliary tethers").

A remote unit is a rigid body whose tether and whose two auxiliary tethers are all joined
at its centre of mass by spherical joints: no joint force has a moment about that centre,
so the unit's rotation decouples from the rig and its translation is that of a point
mass at the tether's tip node, which is what the rig carries (``RemoteUnit.inertia`` is
the unit's data for its own attitude; a thruster's force acts at the tip node).
"""

from dataclasses import dataclass

import numpy as np
from skfem import MeshLine

from ...bodies.cable import Cable
from ...bodies.section import Section, check_positive


@dataclass(frozen=True)
class RemoteUnit:
    """A remote unit at a tether tip: ``mass`` (kg), ``inertia`` (kg m^2, its principal
    moment about its centre: a scalar, or the 3 x 3 tensor) and ``thrust_max`` (N, the
    largest force its thrusters or photonic blades give, for ``RemoteUnitThrust``)."""

    mass: float
    inertia: object
    thrust_max: float

    def __post_init__(self):
        check_positive("mass", self.mass)
        check_positive("thrust_max", self.thrust_max, allow_zero=True)
        inertia = np.asarray(self.inertia, dtype=float)
        if inertia.shape not in ((), (3, 3)) or not np.allclose(inertia, inertia.T) \
                or np.any(np.linalg.eigvalsh(np.atleast_2d(inertia)) <= 0):
            raise ValueError(f"inertia must be a positive number or a symmetric positive "
                             f"definite 3 x 3 tensor (kg m^2), got {self.inertia!r}")


def check_ring(auxiliary, tension, n_tethers):
    """Validate the ring's ``auxiliary`` section (a ``Section`` or None) and design
    ``tension`` (N, > 0) for ``n_tethers`` tethers (at least 3)."""
    if auxiliary is None:
        return
    if not isinstance(auxiliary, Section):
        raise TypeError(f"auxiliary must be a skfem_cable.Section or None, "
                        f"got {type(auxiliary).__name__}")
    check_positive("auxiliary_tension", tension)
    if n_tethers < 3:
        raise ValueError(f"a ring of auxiliary tethers needs n_tethers >= 3, got {n_tethers}")


def ring_stretch(Green_EA, tension):
    """Stretch ``lambda`` of an auxiliary tether at ``tension`` (N): the Green-strain law
    ``T = EA (lambda^2 - 1) lambda / 2`` solved by Newton's method."""
    lam = 1.0 + tension / Green_EA
    for _ in range(30):
        lam -= (lam**3 - lam - 2 * tension / Green_EA) / (3 * lam**2 - 1)
    return lam


def ring_length(auxiliary, tension, n_tethers, tip_radius):
    """Reference length (m) of an auxiliary tether at ``tension`` (N) between neighbouring
    tips of a ring of ``n_tethers`` at ``tip_radius``: the chord ``2 r sin(pi / p)`` over
    the stretch ``ring_stretch``."""
    return 2 * tip_radius * np.sin(np.pi / n_tethers) / ring_stretch(auxiliary.EA, tension)


def ring_tension(auxiliary, length, n_tethers, tip_radius):
    """Tension (N) of the Green-strain auxiliary tethers of reference ``length`` between
    neighbouring tips of a ring of ``n_tethers`` at ``tip_radius``: at the chord
    ``2 r sin(pi / p)``, zero when slack."""
    lam = 2 * tip_radius * np.sin(np.pi / n_tethers) / length
    return max(auxiliary.EA * (lam**2 - 1) * lam / 2, 0.0)


def ring_tip_mass(unit_mass, auxiliary, length, tension, n_tethers, tip_radius, omega):
    """The tip mass ``m_eff`` with which a ringed tether spins as a free one: the unit's
    radial balance in the spinning frame, in the plane of the tips, is ``T_tip = m_eff
    omega^2 r`` with ``m_eff = m_u + rho_a A_a L_a (2 + cos 2 zeta) / 3 - 2 T_a sin(zeta)
    / (omega^2 r)``, ``zeta = pi / p``, ``r`` the tip's distance from the spin axis: the
    centrifugal load of the unit's shares of its two auxiliary tethers of reference length
    ``L_a`` (one linear element each, consistent mass: ``rho_a A_a L_a (2 x_i + x_j) / 6``
    at node ``i``) less the radial pull of their ``tension`` ``T_a``."""
    zeta = np.pi / n_tethers
    mass = unit_mass + auxiliary.mass_per_length * length * (2 + np.cos(2 * zeta)) / 3
    return mass - 2 * tension * np.sin(zeta) / (omega**2 * tip_radius)


def ring_cables(tips, lengths, auxiliary):
    """The auxiliary tethers: cable ``i`` (one linear element, law ``"tension-only"``)
    from tip ``tips[i]`` to ``tips[i + 1]`` (the last to the first), of reference length
    ``lengths``, stretched straight between them."""
    p = len(tips)
    mesh = MeshLine(np.array([0.0, lengths]))
    return [Cable(mesh, auxiliary, np.array([tips[i], tips[(i + 1) % p]]), element="linear",
                  law="tension-only", name=f"auxiliary{i + 1}") for i in range(p)]


def tip_positions(scene, q):
    """The remote units' positions (m) at coordinates ``q`` (..., n_dofs): (..., p, 3)."""
    q = np.asarray(q)
    dofs = np.array([scene.system.dofs(t.node(-1))[:3] for t in scene.tethers])
    return q[..., dofs]


def tip_spacing(scene, q):
    """Distances (m) between neighbouring remote units (unit ``i`` and ``i + 1``, the last
    and the first) at coordinates ``q`` (..., n_dofs): (..., p)."""
    x = tip_positions(scene, q)
    return np.linalg.norm(np.roll(x, -1, axis=-2) - x, axis=-1)


def auxiliary_tension(scene, q):
    """Tension (N) of each auxiliary tether at coordinates ``q`` (n_dofs,): (p,); zero
    when slack."""
    return np.array([max(float(c.tension(q[scene.system.dofs(c)], np.array([0.5 * c.length]))
                                [0]), 0.0) for c in scene.auxiliary])
