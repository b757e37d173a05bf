"""The instability guard: a time step that creates energy is not accepted.

The integrator books the energy balance ``B = kinetic + elastic + potential + dissipated -
external work`` (``GeneralizedAlpha.energies``); exactly, ``B`` is constant.  The
generalized-alpha method with ``rho_inf < 1`` dissipates (``B`` decreases: numerical
dissipation is not growth), and with ``rho_inf = 1`` it oscillates by ``O(h^2)``.  A step
that raises ``B`` above its lowest value so far by more than ``tol`` times the energy
content of the run (the largest ``kinetic + elastic + |potential - potential_0| +
dissipated + |external work|`` seen, the candidate state included) is a numerical
instability, or a Newton iteration that "converged" to a runaway state: it is rejected,
and the step is retried smaller.  So is a step that a term's own ``check`` refuses
(``refusal``: two lines carried through each other, ``loads.contact_crossing``).

The content is floored at ``FLOOR`` times the kinetic energy of the whole mass moving by
the system's size per (first) step, ``m (L / h)^2``: round-off in a system at rest is not
growth.
"""

import math
from collections import deque

import numpy as np

from ..core.records import ENERGIES

#: Energy content below which nothing is judged, relative to ``m (L / h)^2``.
FLOOR = 1e-12


def measure(energies, potential0):
    """The balance ``kinetic + elastic + potential + dissipated - external work`` and the
    energy content, the magnitudes of all its terms, of a state's ``energies`` (floats in
    the order of ``records.ENERGIES``; J)."""
    kinetic, axial, bending, potential, dissipated, external_work = energies
    stored = kinetic + axial + bending
    return (stored + potential + dissipated - external_work,
            stored + abs(potential - potential0) + abs(dissipated) + abs(external_work))


def refusal(checks, q0, q1):
    """The first reason one of the terms' ``checks`` (``contract.Term.check``) gives to
    refuse the step from ``q0`` to the converged candidate ``q1``, or None."""
    for check in checks:
        reason = check(q0, q1)
        if reason is not None:
            return reason
    return None


class EnergyGuard:
    """Rejects steps whose energy balance grows (see the module docstring).

    Parameters
    ----------
    tol : float or None
        Allowed growth relative to the energy content; None switches the guard off.
    keep : int
        Accepted steps kept for the diagnostic's energy history.
    """

    STATE = ("lowest", "largest", "potential0", "floor")

    def __init__(self, tol=0.05, keep=8):
        if tol is not None and not (np.isfinite(tol) and tol > 0):
            raise ValueError(f"energy_tol must be a number > 0 or None, got {tol!r}")
        self.tol = tol
        self.history = deque(maxlen=keep)

    def reset(self, t, energies):
        """Start from an accepted initial state (``energies``: a dict of ``ENERGIES``)."""
        energies = tuple(float(energies[name]) for name in ENERGIES)
        self.potential0 = energies[3]
        self.lowest, self.largest = measure(energies, self.potential0)
        self.floor = 0.0
        self.history.clear()
        self.history.append((t, self.lowest))

    def set_scale(self, mass, length, h):
        """Fix the floor of the energy content from the total ``mass``, the system size
        ``length`` and the first step ``h`` (once per run)."""
        if not self.floor:
            self.floor = FLOOR * mass * (length / h) ** 2

    def admit(self, t, energies):
        """Judge the candidate state at ``t`` of ``energies`` (floats in the order of
        ``ENERGIES``): None if it is acceptable, and it becomes the guard's reference
        (lowest balance, largest content, history); else a short reason: the rise of its
        balance above the lowest so far against the energy content (the largest seen, the
        candidate's included).  (The last check of a step: judging and taking it in one
        call.)"""
        balance, content = measure(energies, self.potential0)
        if self.tol is not None:
            grown = balance - self.lowest
            scale = max(self.largest, content, self.floor, 1e-300)
            if not math.isfinite(grown) or grown > self.tol * scale:
                return (f"energy balance grew by {grown:.4g} J ({grown / scale:.3g} of the "
                        f"energy content {scale:.4g} J; energy_tol = {self.tol:g})")
        if balance < self.lowest:  # min() and max() as comparisons: 0.15 us less a step
            self.lowest = balance
        if content > self.largest:
            self.largest = content
        self.history.append((t, balance))
        return None

    def describe_history(self):
        return ", ".join(f"t={t:.6g}: {b:.6g} J" for t, b in self.history)

    # --- checkpoints (``protocols.Checkpointed``) -----------------------------------------
    def snapshot(self):
        """The references of the balance (``guard_*``), for the integrator's checkpoint."""
        return {"guard_" + k: np.float64(getattr(self, k)) for k in self.STATE}

    def restore(self, snap):
        """The references of a checkpoint back (none in one written before the guard)."""
        if "guard_lowest" in snap:
            for k in self.STATE:
                setattr(self, k, float(snap["guard_" + k]))
            self.history.clear()
