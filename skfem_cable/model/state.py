"""A configuration of a system (coordinates and multipliers) with field evaluation.

Examples
--------
>>> import skfem_cable as sc
>>> cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], 2, sc.Section.circular(1e-3, 2e11, 7850.0))
>>> system = sc.System([cable]).pin(cable.node(0))
>>> state = sc.State(system, system.q0)
>>> state.position(cable, 0.5).tolist(), state.multipliers
([0.5, 0.0, 0.0], {'pin Node(cable, 0)': array([0., 0., 0.])})
"""

import numpy as np


class State:
    """Coordinates ``q``, multipliers ``lam``, optional velocities ``v`` and solver
    statistics (an initial condition for ``simulate`` is a ``State`` with ``v``).

    ``position``, ``slope``, ``tension``, ``strain`` and ``curvature`` evaluate a cable's
    fields at reference arc lengths ``s`` (scalar or array; results ``s.shape + (3,)`` for
    vectors).

    Parameters
    ----------
    system : System
    q : array_like (n_dofs,)
        Coordinates.
    lam : array_like (n_constraints,), optional
        Lagrange multipliers (default zeros).
    stats : dict, optional
        Solver statistics (``solve_static``: ``iterations`` per load step, ...).
    v : array_like (n_dofs,), optional
        Velocities (an initial condition of ``simulate``).
    t : float
        Time (s): where a cable deploys (``System.deploy``), its fields depend on it.

    Attributes
    ----------
    system : System
    q, v, lam : ndarray
        Coordinates, velocities (or None) and multipliers.
    stats : dict
        Solver statistics.

    See Also
    --------
    Result : the saved steps of a run (``Result.state(i)`` is one as a ``State``).

    Examples
    --------
    The elastica of a cantilever with a tip load (``k = P L^2 / EI = 2``):

    >>> import skfem_cable as sc
    >>> sec = sc.Section(E=1e9, A=1e-4, I=1e-11, rho=7850.0)
    >>> cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], 8, sec)
    >>> system = sc.System([cable]).clamp(cable.node(0))
    >>> system = system.add_point_load(cable.node(-1), [0, -2 * sec.EI, 0])
    >>> state = sc.solve_static(system, load_steps=10)
    >>> tip = state.position(cable, 1.0)
    >>> print(tip.round(2))
    [ 0.84 -0.49  0.  ]
    >>> from skfem_cable.analysis.analytic import elastica_tip_load
    >>> u, w = elastica_tip_load(2.0)                 # exact: u = 0.161, w = 0.493
    >>> bool(abs(1 - tip[0] - u) < 2e-3 and abs(-tip[1] - w) < 3e-3)
    True
    """

    def __init__(self, system, q, lam=None, stats=None, v=None, t=0.0):
        self.system = system
        self.t = float(t)
        self.q = np.asarray(q, dtype=float)
        self.v = None if v is None else np.asarray(v, dtype=float)
        self.lam = np.zeros(system.n_constraints) if lam is None else np.asarray(lam, float)
        self.stats = dict(stats or {})

    def _q(self, cable):
        return self.q[self.system.dofs(cable)]

    def position(self, cable, s):
        """Position ``r`` (m) at arc lengths ``s``: ``s.shape + (3,)``."""
        return cable.interpolate(self._q(cable), s)[0]

    def slope(self, cable, s):
        """Slope ``r_x`` at arc lengths ``s``: ``s.shape + (3,)``."""
        return cable.interpolate(self._q(cable), s)[1]

    def strain(self, cable, s):
        """Green axial strain at arc lengths ``s`` (``Cable.strain``)."""
        return cable.strain(self._q(cable), s, self.system.stretch(cable, self.t, self.q))

    def tension(self, cable, s):
        """Axial force (N) at arc lengths ``s`` (``Cable.tension``)."""
        return cable.tension(self._q(cable), s, self.system.stretch(cable, self.t, self.q),
                             self.t)

    def curvature(self, cable, s):
        """Curvature (1/m) at arc lengths ``s`` (``Cable.curvature``)."""
        return cable.curvature(self._q(cable), s, self.system.stretch(cable, self.t, self.q))

    @property
    def multipliers(self):
        """Multipliers of each constraint by name (``C_q^T lambda`` is the force the
        constraint exerts *on the system*, with a minus sign: reactions are ``-lambda``)."""
        out, k = {}, 0
        for c in self.system.constraints:
            out[c.name] = self.lam[k: k + c.n_eq]
            k += c.n_eq
        return out
