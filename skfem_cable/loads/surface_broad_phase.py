"""The broad phase of line-to-surface contact (``loads.contact``): once per time step, the
elements of the line that the step may bring into touch with the surface; the line loop
skips the others (their factor ``scale[e] = 0``, ``kernels.line``), so a contact with
nothing near costs the test of each point's distance, not the point loop's gather,
interpolation and tangent.

It is a step hook of the run (``protocols.StepHook``: it keeps the last accepted state,
as ``loads.sampling.DensitySampler`` does) and the term's ``prepare(t)``: the mask for
the step to ``t`` from that state (``kernels.contact.near``).  Outside a run (a static
solve, an evaluation at or before the last accepted time) every element is evaluated.

The same pass finds the deepest penetration ``p``.  Where a run at ``rho_inf > 0`` has
its whole contact within ``SHALLOW`` of the onset ``p_0`` for ``PERSISTENT`` steps in a
row, it warns once
(``ContactDampingWarning``): there the default damping is below 0.8 of critical on the
penalty's stiffness ``k p / p_0`` (``kernels.contact``), and the generalized-alpha does
not hold the penalty's oscillation down.  Measured (``docs/contact.md``): the Atwood
machine with a rope of EA = 1e6 N works at ``p = 0.12 p_0`` and at ``rho_inf = 0.8``,
dt = 5e-3 s, its rope bounced off the drum and m1 fell 15 % short in 1 s; at
``rho_inf = 0`` it is right.
"""

import warnings

import numpy as np

from ..kernels import contact as kernel
from ..kernels import line
from .accepted import AcceptedState

#: The deepest penetration, in units of the onset ``p_0``, below which a contact is
#: under-damped (damping ratio ``2 sqrt(u) - u^1.5`` below 0.8).
SHALLOW = 0.2
#: Steps in a row that a contact must stay that shallow before the warning.
PERSISTENT = 50


class ContactDampingWarning(UserWarning):
    """A contact's normal damping is below critical on its penalty: the penalty's
    oscillation, faster than a time step resolves, can gain energy (``docs/contact.md``)."""


class BroadPhase(AcceptedState):
    """The per-step mask ``scale`` (ne,) of the contact of the points ``points``
    (``lines.LinePoints``) of a line of cross-section radius ``radius`` with the surface
    array ``surface``: elements whose points are all farther than ``margin + 3 h v_max``
    from touching are off (``kernels.contact.near``).

    Attributes
    ----------
    scale : ndarray (ne,)
        The factor of each element's force, read by the contact's kernels (refreshed in
        place).
    skipped : int
        Element evaluations left out so far (one count per element and step).

    ``seen(q, v, X, V)``, if given, returns the surface array and the points'
    velocities relative to it at the accepted state (a surface carried by a body,
    ``loads.contact_body``); the distance changes by at most the relative motion.
    """

    def __init__(self, points, surface, radius, margin, onset, name, seen=None):
        self.points, self.surface, self.name = points, surface, name
        self.seen = seen
        self.radius, self.margin, self.onset = float(radius), float(margin), float(onset)
        self.rho_inf, self.warned, self.shallow = 0.0, False, 0
        self.scale = np.ones(points.shape[0])
        self.X, self.A, self.V = (np.empty(points.shape + (3,)) for _ in range(3))
        self.skipped = 0

    def prepare(self, t):
        """The mask for the step that ends at ``t`` (from the last accepted state; every
        element outside a run or at a time not after it)."""
        t = float(t)
        if t == self.done:
            return
        self.done = t
        if self.t is None or not t > self.t:
            self.scale[:] = 1.0
            return
        q, v, t0 = self.q, self.v, self.t
        p = self.points
        line.points(p.edofs, p.S, p.Sx, q, v, self.X, self.A, self.V)
        surface, V = self.surface, self.V
        if self.seen is not None:
            shape = self.V.shape
            surface, V = self.seen(q, v, self.X.reshape(-1, 3), self.V.reshape(-1, 3))
            V = V.reshape(shape)
        depth = -kernel.near(surface, self.X, V, self.radius, t - t0, self.margin,
                             self.scale)
        self.skipped += int(self.scale.size - np.count_nonzero(self.scale))
        self.check(depth)

    def check(self, depth):
        """Warn once where a run at ``rho_inf > 0`` touches no deeper than ``SHALLOW p_0``
        for ``PERSISTENT`` steps in a row (module notes: not while a load sets in)."""
        shallow = 0.0 < depth < SHALLOW * self.onset
        self.shallow = self.shallow + 1 if shallow else 0
        if self.warned or self.rho_inf == 0.0 or self.shallow < PERSISTENT:
            return
        self.warned = True
        warnings.warn(f"contact {self.name}: the deepest penetration {depth:.3g} m is "
                      f"{depth / self.onset:.2f} of the onset {self.onset:.3g} m, where the "
                      "normal damping is below 0.8 of critical: at rho_inf = "
                      f"{self.rho_inf:g} the penalty's oscillation can gain energy (a stiff "
                      "rope bounced off its drum); run at rho_inf = 0, or give a softer "
                      "stiffness= (docs/contact.md)", ContactDampingWarning, stacklevel=2)

    def start(self, integrator):
        """A fresh run: its initial state (``AcceptedState``) and ``rho_inf``."""
        super().start(integrator)
        self.rho_inf = float(getattr(integrator, "rho_inf", 0.0))
        self.warned, self.shallow = False, 0
