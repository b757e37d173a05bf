"""The last accepted state of a run, kept for a load's per-step refresh
(``AcceptedState``): the step hook shared by the loads that evaluate something once per
time step from the state the step starts from (a density model, ``sampling``; the broad
phases of contact, ``surface_broad_phase`` and ``contact_lines``)."""

import numpy as np


class AcceptedState:
    """A step hook (``protocols.StepHook``, called by ``simulate``) keeping the last
    accepted state ``q``, ``v``, ``t`` of a run; ``done`` (the time the owner last
    refreshed for) is cleared whenever the state changes.  Nothing of its own goes into a
    checkpoint: a resumed run restores the checkpoint's state.  ``t`` is None until a
    state is accepted."""

    q = v = t = done = None

    def accept(self, q, v, t):
        """Keep ``(q, v, t)`` as the state the next step starts from."""
        self.q, self.v, self.t = np.array(q, dtype=float), np.array(v, dtype=float), float(t)
        self.done = None

    def start(self, integrator):
        """A fresh run: its initial state."""
        self.accept(integrator.q, integrator.v, integrator.t)

    def after_step(self, integrator):
        """A step was accepted: its state (after the rectification's rebase, which runs
        first)."""
        self.accept(integrator.q, integrator.v, integrator.t)

    def next_event(self, t):
        """No time a step must end on."""
        return np.inf

    def snapshot(self):
        """Nothing of its own: the checkpoint's state is the integrator's."""
        return {}

    def restore(self, snap):
        """A resumed run: the checkpoint's state."""
        self.accept(snap["q"], snap["v"], snap["t"])
