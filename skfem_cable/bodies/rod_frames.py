"""The reference frames of a rod's nodes: what its twist is measured from, transported in
time (``docs/rods.md``).

Each node holds a reference tangent ``t0`` and a unit director ``d0`` normal to it, fixed
during a time step; after every step they are re-based on the current tangents by the
smallest rotation (the time-parallel transport of Bergou et al. 2010, Sect. 5).  They are
a run's state: a ``protocols.StepHook`` whose ``snapshot`` joins every checkpoint, so a
continued run is bit for bit the uninterrupted one.
"""

import numpy as np

from ..kernels.rod import rebase


class ReferenceFrames:
    """The nodal reference frames of a rod in one system (``Rod.bind``), a ``StepHook``.

    Parameters
    ----------
    rod : Rod
        The rod; its ``reference_frames(q0)`` are where a run starts from.
    slopes : int ndarray (n_nodes, 3)
        The global coordinates of the nodes' slopes.

    Attributes
    ----------
    t0, d0 : ndarray (n_nodes, 3)
        The reference tangents and directors, changed in place (the rod term's kernel
        reads these arrays).
    """

    def __init__(self, rod, slopes):
        self.rod = rod
        self.slopes = np.ascontiguousarray(slopes, dtype=np.int64)
        self.t0, self.d0 = (np.ascontiguousarray(a) for a in rod.initial_frames())
        self.key = f"rod_frames_{rod.name}_{self.slopes[0, 0]}"  # unique in a system

    def reset(self):
        """Back to the rod's initial frames."""
        t0, d0 = self.rod.initial_frames()
        self.t0[:] = t0
        self.d0[:] = d0

    def rebase(self, q):
        """Re-base on the slopes of the global coordinates ``q``."""
        rebase(np.ascontiguousarray(q, dtype=float), self.slopes, self.t0, self.d0)

    # --- StepHook -------------------------------------------------------------------------
    def start(self, integrator):
        """A fresh run: the rod's initial frames carried to the initial state."""
        self.reset()
        self.rebase(integrator.q)

    def after_step(self, integrator):
        """Re-base on the accepted step's tangents."""
        self.rebase(integrator.q)

    def next_event(self, t):
        """No event: ``inf``."""
        return np.inf

    def snapshot(self):
        """The frames (``rod_frames_<name>_<first slope coordinate>_t``, ``_d``) for a
        checkpoint."""
        return {self.key + "_t": self.t0.copy(), self.key + "_d": self.d0.copy()}

    def restore(self, snap):
        """The frames of a checkpoint back, in place."""
        self.t0[:] = snap[self.key + "_t"]
        self.d0[:] = snap[self.key + "_d"]
