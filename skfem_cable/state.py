"""A configuration of a system (coordinates and multipliers) with field evaluation."""

import numpy as np


class State:
    """Coordinates ``q``, multipliers ``lam``, optional velocities ``v`` and solver
    statistics (an initial condition for ``simulate`` is a ``State`` with ``v``).

    ``position``, ``slope``, ``tension``, ``strain`` and ``curvature`` evaluate a cable's
    fields at reference arc lengths ``s`` (scalar or array; results ``s.shape + (3,)`` for
    vectors).
    """

    def __init__(self, system, q, lam=None, stats=None, v=None):
        self.system = system
        self.q = np.asarray(q, dtype=float)
        self.v = None if v is None else np.asarray(v, dtype=float)
        self.lam = np.zeros(system.n_constraints) if lam is None else np.asarray(lam, float)
        self.stats = dict(stats or {})

    def _q(self, cable):
        return self.q[self.system.dofs(cable)]

    def position(self, cable, s):
        return cable.interpolate(self._q(cable), s)[0]

    def slope(self, cable, s):
        return cable.interpolate(self._q(cable), s)[1]

    def strain(self, cable, s):
        return cable.strain(self._q(cable), s)

    def tension(self, cable, s):
        return cable.tension(self._q(cable), s)

    def curvature(self, cable, s):
        return cable.curvature(self._q(cable), s)

    @property
    def multipliers(self):
        """Multipliers of each constraint by name (``C_q^T lambda`` is the force the
        constraint exerts *on the system*, with a minus sign: reactions are ``-lambda``)."""
        out, k = {}, 0
        for c in self.system.constraints:
            out[c.name] = self.lam[k: k + c.n_eq]
            k += c.n_eq
        return out
