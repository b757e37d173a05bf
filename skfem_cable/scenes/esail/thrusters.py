"""The remote units' spin thrusters: a thrust at each tether tip along the spin direction
(``RemoteUnitThrust``), the load ``SpinController`` sets (``spin_control``)."""

import numpy as np

from ...core.contract import Term
from ...core.inputs import declared, reader
from ...kernels.spin_thrust import spin_thrust


def tip_points(scene):
    """The points where the remote units are joined, one per tether: the tethers' last
    nodes (where ``build`` puts the point masses of the remote units).  With rigid remote
    units, their joint points."""
    return [cable.node(-1) for cable in scene.tethers]


class RemoteUnitThrust:
    """The remote units' spin thrusters: at each point ``x_j`` (a tether tip), a force of
    ``T_j`` (N) along the spin direction ``d_j = (a x c_j) / |a x c_j|``, ``a`` the hub's
    spin axis ``x_B`` and ``c_j = x_j - x_c`` the arm from the hub's centre of mass:
    perpendicular to the arm in the spin plane, the way the tip moves when the sail spins
    about ``+x_B``.  ``T_j > 0`` spins the sail up, ``T_j < 0`` down; each thrust is
    bounded by ``thrust_max`` (the values held are clipped to ``[-thrust_max,
    thrust_max]``).

    The force depends on the tip's and the hub's coordinates; its tangent in both is exact
    (``kernels.spin_thrust``), and its work is booked as external work (the run's
    ``energy["external_work"]``; its power is ``sum_j T_j d_j . v_j``, ``power``).

    Parameters
    ----------
    points : sequence of Node or body point
        Where the thrust acts: ``tip_points(scene)`` (the tethers' last nodes), or the
        remote units' body points.
    hub : rigid body
        The body whose first axis ``x_B`` is the spin axis and whose centre of mass is
        the spin centre (``RigidBody.point``).
    thrust : sc.Input, array_like (k,) or callable
        One thrust per point (N): an ``sc.Input`` of ``k`` values (a controller sets it,
        ``SpinController``), constant values, or ``thrust(t)``.
    thrust_max : float
        The largest thrust of one unit (N), > 0.
    name : str
        The load's name (its term's, in messages and tangent checks).

    Examples
    --------
    >>> import numpy as np, skfem_cable as sc
    >>> from skfem_cable.scenes import esail
    >>> scene = esail.build(esail.BaselineConfig(n_tethers=4), 0.0, 1)
    >>> thrust = sc.Input("thrust", np.zeros(4))
    >>> load = esail.RemoteUnitThrust(esail.tip_points(scene), scene.hub, thrust, 1e-3)
    >>> load.inputs() == (thrust,)
    True
    """

    def __init__(self, points, hub, thrust, thrust_max, name="remote-unit thrust"):
        self.points = list(points)
        if not self.points:
            raise ValueError("points must name at least one point (a tether tip)")
        self.hub = hub
        if not (np.isfinite(thrust_max) and thrust_max > 0):
            raise ValueError(f"thrust_max must be a finite number > 0 (N), got "
                             f"{thrust_max!r}")
        self.thrust_max = float(thrust_max)
        self.fn = thrust if callable(thrust) else None
        self.value = None if callable(thrust) else self._checked(thrust, "thrust")
        self.name = name
        self.thrust(0.0)  # fail now, not in the middle of a run

    def _checked(self, value, what):
        """``value`` as ``k`` thrusts clipped to ``thrust_max`` (N), or ``ValueError``."""
        value = np.asarray(value, dtype=float)
        if value.shape != (len(self.points),) or not np.all(np.isfinite(value)):
            raise ValueError(f"{what} must be {len(self.points)} finite thrusts (N), one "
                             f"per point, got {value!r}")
        return np.clip(value, -self.thrust_max, self.thrust_max)

    def thrust(self, t):
        """The thrusts (N) at time ``t``, clipped to ``thrust_max`` (an ``Input`` at its
        initial value: a run reads its own, ``bind``)."""
        if self.fn is None:
            return self.value
        return self._checked(self.fn(t), f"thrust({t!r})")

    def inputs(self):
        """The inputs the thrust reads (``inputs.declared``)."""
        return declared(self.fn)

    def _normals(self, system, q):
        """``a x c_j`` (k, 3) at the coordinates ``q``: the spin direction times the
        lever of each point about the spin axis."""
        hub, A, C = self._hub_maps(system)
        a, centre = A @ q[hub], C @ q[hub]
        arms = np.array([G @ q[dofs] for dofs, G in map(system.position_map, self.points)])
        return np.cross(a, arms - centre)

    def directions(self, system, q):
        """The spin directions ``d_j`` (k, 3) at the coordinates ``q``."""
        w = self._normals(system, q)
        return w / np.linalg.norm(w, axis=1, keepdims=True)

    def levers(self, system, q):
        """The points' distances from the spin axis ``|a x c_j|`` (k,) (m): the torque of
        a unit thrust at each."""
        return np.linalg.norm(self._normals(system, q), axis=1)

    def power(self, system, q, v, thrust):
        """The thrusters' power (W), ``sum_j T_j d_j . v_j``, at the coordinates ``q`` and
        velocities ``v`` with the thrusts ``thrust`` (k,) (a run's: ``Result.inputs``)."""
        velocities = np.array([G @ v[dofs] for dofs, G in map(system.position_map,
                                                               self.points)])
        return float(np.einsum("j,ji,ji->", self._checked(thrust, "thrust"),
                               self.directions(system, q), velocities))

    def _hub_maps(self, system):
        """``(dofs, A, C)``: the hub's coordinates, its axis ``a = A q[dofs]`` and its
        centre ``x_c = C q[dofs]`` (body points: linear in its coordinates)."""
        centre = np.asarray(self.hub.center_of_mass, dtype=float)
        hub, C = system.position_map(self.hub.point(centre))
        _, tip = system.position_map(self.hub.point(centre + [1.0, 0.0, 0.0]))
        return np.asarray(hub, dtype=np.int64), np.ascontiguousarray(tip - C), \
            np.ascontiguousarray(C)

    def bind(self, system, inputs=None):
        """The load's term (compiled, ``kernels.spin_thrust``): the thrusts read once per
        step (``prepare``) from the run's values of the input (``inputs``: the run's
        ``InputTable``; None: the initial values), clipped to ``thrust_max``."""
        maps = [system.position_map(p) for p in self.points]
        dofs = np.array([d for d, _ in maps], dtype=np.int64)
        Gt = np.ascontiguousarray(np.array([G.T for _, G in maps], dtype=float))
        hub, A, C = self._hub_maps(system)
        thrust = self.thrust(0.0).copy()
        source = reader(self.fn, inputs)
        prepare = None
        if source is not None:
            def prepare(t):
                thrust[:] = self._checked(source(t), f"thrust({t!r})")
        cols = np.concatenate([dofs, np.broadcast_to(hub, (len(dofs), hub.size))], axis=1)
        return Term(kernels=((spin_thrust, (dofs, Gt, hub, A, C, thrust)),),
                    rows=dofs[:, :, None], cols=cols[:, None, :], prepare=prepare,
                    name=self.name)

    def __repr__(self):
        thrust = "thrust(t)" if self.fn is not None else self.value.tolist()
        return f"RemoteUnitThrust({len(self.points)} points, {thrust}, " \
               f"thrust_max={self.thrust_max!r})"
