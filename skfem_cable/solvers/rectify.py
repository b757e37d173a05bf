"""Encke's rectification of a system in orbit: when the centre of mass has moved away from
the reference point (thrust), the reference is re-based on the osculating orbit of the
centre of mass, so that the coordinates stay small offsets.

A system in orbit (``System.add_orbit``) integrates offsets ``delta`` from a reference
point on a Keplerian orbit ``R(t)``.  Without thrust the centre of mass stays near it; an
E-sail's thrust carries it away by ``a t^2 / 2`` (some 1e8 m in a week at 1 mm/s^2), and
large offsets cost the precision that the translated frame was there to keep (the E-sail
paper, Sect. 2).  After every step, when the offset ``x`` of the centre of mass exceeds
``tolerance |R|`` or its velocity ``u`` exceeds ``tolerance |V|`` (``|R|`` and ``|V|``
taken at their smallest on the arc in force: periapsis distance, apoapsis speed), the
reference becomes
the orbit through ``R + x, V + u`` from that time on (``orbit.Reference.rebase`` of the
run's reference, never the user's ``Orbit``: Battin,
*An Introduction to the Mathematics and Methods of Astrodynamics*, AIAA 1999, on
Encke's method), and every position coordinate moves by ``-(R_new(t) - R(t))``, every
velocity of a position by ``-(V_new(t) - V(t))`` and every acceleration of a position by
``-(g(R_new) - g(R))``, the change of the reference point's fall
(``DifferentialGravity.frame_change``); slopes and scalar coordinates do not change.  The
difference of the two reference points is formed once, from the two arcs themselves, so
the absolute positions ``R + delta`` stay what they were to the rounding of ``delta``.
The integrator goes on from the shifted state with its memory and its books
(``GeneralizedAlpha.shift``).

A constraint that ties the system to the reference point (a pin to a fixed point of the
orbiting frame, in all directions or in one: a node sliding on a plane) would move with
it: the rectification is then off, and the reason is in the run's
``stats["rectification"]``.  Every constraint is tried with a translation along each of
the three axes (``_tied``).  The arcs are part of the checkpoint, so a
rectified run continues bit for bit.
"""

import numpy as np

from ..bodies.section import real_number
from ..core.protocols import IntegrableSystem


def check_rectify(tolerance):
    """``simulate``'s ``rectify``: None or a finite number > 0 (not a bool, not a string:
    ``True`` or ``"1e-4"`` taken as a number would be a tolerance nobody asked for);
    ``ValueError`` naming it otherwise."""
    if tolerance is not None:
        real_number("rectify", tolerance, hint=" (a relative offset of the centre of mass, "
                    "e.g. 1e-4) or None")


class Rectification:
    """Encke's rectification of the run of ``system`` (in orbit) with ``tolerance``
    (module docstring); ``reason`` is None when it is on, else why it is off.

    Parameters
    ----------
    system : System
        In orbit (``system.orbit``).
    tolerance : float
        Relative offset of the centre of mass (position to ``|R|``, velocity to ``|V|``)
        beyond which the reference is re-based, > 0.
    t : float
        The run's start time (s): where the constraints are checked.
    reference : orbit.Reference
        The run's reference (``Layout.reference``), which the rebases extend.
    """

    def __init__(self, system: IntegrableSystem, tolerance, t, reference):
        self.reference, self.tolerance = reference, float(tolerance)
        self.gravity = system.orbit_gravity
        n = system.n_dofs
        self.positions = system.vectors[system.vector_is_position]  # (k, 3) coordinates
        M = system.mass_matrix()
        unit = np.zeros((3, n))
        for i in range(3):
            unit[i, self.positions[:, i]] = 1.0
        mass = unit[0] @ (M @ unit[0])
        self.weights = np.asarray(M @ unit.T).T / mass  # centre of mass: weights @ q
        self.reason = _tied(system, self.positions, t, reference)
        self._bounds(t)

    def _bounds(self, t):
        """The squared limits of the offset and the velocity of the centre of mass on
        the arc in force at ``t``: ``tolerance`` times its smallest distance ``a (1 -
        e)`` and smallest speed (at apoapsis), so that no step asks the orbit."""
        arc = self.reference.arc(float(t))
        slowest = arc.mu / arc.a * (1.0 - arc.e) / (1.0 + arc.e)
        self.limits = (self.tolerance**2 * (arc.a * (1.0 - arc.e)) ** 2,
                       self.tolerance**2 * slowest)

    def shift(self, delta):
        """The coordinate change ``(n,)`` that moves every position by ``delta`` (3,)."""
        out = np.zeros(self.weights.shape[1])
        out[self.positions] = delta
        return out

    # --- the step hook (``protocols.StepHook``, called by ``simulate``) ------------------
    def start(self, integrator):
        """A fresh run: nothing to do (``simulate`` starts it on the orbit as given)."""

    def next_event(self, t):
        """No time a step must end on."""
        return np.inf

    def snapshot(self):
        """The rebases so far, for a checkpoint (``Reference.rebases``)."""
        return {"orbit_rebases": self.reference.rebases}

    def restore(self, snap):
        """The rebases of a checkpoint back on the run's reference."""
        self.reference.restore(snap.get("orbit_rebases"))
        self._bounds(float(snap["t"]))

    def after_step(self, integrator):
        """After a step: re-base the reference when the centre of mass of the
        integrator's state is past the tolerance; returns whether it did."""
        x, u = self.weights @ integrator.q, self.weights @ integrator.v
        if x @ x <= self.limits[0] and u @ u <= self.limits[1]:
            return False
        t, reference = integrator.t, self.reference
        R, V = reference.position(t), reference.velocity(t)
        reference.rebase(R + x, V + u, t)
        self._bounds(t)
        new = reference.position(t)
        integrator.shift(self.shift(R - new), self.shift(V - reference.velocity(t)),
                         self.shift(-self.gravity.frame_change(R, new)))
        integrator.stats["rectifications"] = integrator.stats.get("rectifications", 0) + 1
        return True


def _tied(system, positions, t, reference):
    """Why the rectification must stay off for ``system`` (a constraint that a
    translation of all positions violates, named), or None.

    A rebase moves every position by a vector ``d`` and every velocity of a position by a
    vector ``w``, both in any direction: a constraint is left alone only if its value is
    the same for every ``d`` (then its velocity-level equation, its derivative along the
    translation, is unchanged by every ``w`` too).  The constraints are tried with a
    translation along each of the three axes (a sliding pin holds one direction only),
    of ``1e-3 |R|``."""
    if not system.n_constraints:
        return None
    q = system.q0
    size = 1e-3 * np.linalg.norm(reference.position(float(t)))
    rest = system.constraint_values(q, t)
    for axis in np.eye(3):
        step = np.zeros(system.n_dofs)
        step[positions] = size * axis
        moved = system.constraint_values(q + step, t) - rest
        if np.max(np.abs(moved)) > 1e-9 * size:
            k = int(np.argmax(np.abs(moved)))
            return (f"off: {system.describe_dof(system.n_dofs + k)} ties the system to "
                    "the reference point, which a rectification would move")
    return None
