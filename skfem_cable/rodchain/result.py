"""The saved steps of a rod-chain run (``RodChainResult``) and one configuration of the
chain (``ChainState``), with the names of the cable ``Result`` where they mean the same:
``t``, ``q``, ``v``, ``energy``, ``stats``, ``position``, ``velocity``, ``state(i)``,
``len(result)``."""

from dataclasses import dataclass

import numpy as np

#: Keys of ``RodChainResult.energy`` (those of ``Result.energy``).
ENERGY_KEYS = ("kinetic", "axial", "bending", "elastic", "potential", "dissipated",
               "external_work", "total", "balance")


def energies(chain, problem, t, rods, rod_velocities, external_work=None):
    """Energy histories (J) at the times ``t`` (nt,) of rod vectors and velocities
    (nt, n, 3), as a dict with ``ENERGY_KEYS``.

    ``kinetic`` is Eq. 4 in the inertial frame, ``axial`` = ``elastic`` Eq. 10 (rods carry
    no bending: ``bending`` is zero), ``potential`` that of gravity and the tip force,
    ``dissipated`` zero (the model has no damping), ``external_work`` the work of the line
    loads and of a moving anchor (``external_work``, default zero), ``total`` = kinetic +
    elastic + potential and ``balance`` = total + dissipated - external_work minus its
    value at the first time.
    """
    t = np.asarray(t, dtype=float)
    r0, u0, _ = problem.anchor(t)
    kinetic = chain.kinetic_energy(rod_velocities, u0)
    elastic = chain.elastic_energy(rods)
    potential = chain.potential_energy(rods, problem.gravity, r0, problem.tip)
    zero = np.zeros(t.shape)
    work = zero.copy() if external_work is None else np.asarray(external_work, dtype=float)
    total = kinetic + elastic + potential
    budget = total - work
    return {"kinetic": kinetic, "axial": elastic, "bending": zero, "elastic": elastic,
            "potential": potential, "dissipated": zero.copy(), "external_work": work,
            "total": total, "balance": budget - budget[:1]}


@dataclass
class ChainState:
    """One configuration of a chain: time ``t``, rod vectors ``rods`` and their rates
    ``rod_velocities`` (n, 3), the anchor position ``origin`` and velocity
    ``origin_velocity`` (3,)."""

    chain: object
    t: float
    rods: np.ndarray
    rod_velocities: np.ndarray
    origin: np.ndarray
    origin_velocity: np.ndarray

    @property
    def q(self):
        """The rod vectors flattened, (3 n,) (``contract.Step.q`` of a rod-chain run)."""
        return self.rods.reshape(-1)

    @property
    def v(self):
        return self.rod_velocities.reshape(-1)

    @property
    def joints(self):
        """Joint positions ``O_0 .. O_n``, (n + 1, 3)."""
        return self.chain.joints(self.rods, self.origin)

    @property
    def joint_velocities(self):
        return self.chain.joints(self.rod_velocities, self.origin_velocity)

    @property
    def tension(self):
        """Axial force of each rod (N), (n,)."""
        return self.chain.tension(self.rods)

    @property
    def strain(self):
        """Engineering strain ``(l - l0) / l0`` of each rod, (n,)."""
        return self.chain.strain(self.rods)


class RodChainResult:
    """Output of ``RodChain.simulate`` at the saved times ``t`` (nt,).

    Attributes
    ----------
    chain : RodChain
        Also ``system`` (the name of the cable ``Result``).
    t : ndarray (nt,)
    rods, rod_velocities : ndarray (nt, n, 3)
        Rod vectors ``q_i = O_{i-1} -> O_i`` and their time derivatives; ``q``, ``v``:
        the same flattened, (nt, 3 n).
    joints, joint_velocities : ndarray (nt, n + 1, 3)
        Positions and velocities of ``O_0 .. O_n`` in the inertial frame (``positions``,
        ``velocities``).
    tension : ndarray (nt, n)
        Axial force of each rod, ``k_i l_i`` (Eq. 12), positive in tension.
    energy : dict of ndarray (nt,)
        The keys of the cable ``Result.energy``: ``"kinetic"`` (Eq. 4, inertial frame),
        ``"elastic"`` = ``"axial"`` (Eq. 10), ``"bending"`` (zero), ``"potential"``
        (gravity and the constant tip force), ``"dissipated"`` (zero: no damping),
        ``"external_work"`` (work of the line loads and of a moving anchor, by the
        trapezoidal rule over the saved steps: accurate when they resolve the motion),
        ``"total"`` = kinetic + elastic + potential and ``"balance"`` = total + dissipated
        - external_work, minus its initial value (zero up to the time discretisation).
    stats : dict
        ``method``, ``dt``, ``steps`` (RK4 steps or accepted adaptive steps), ``nfev``
        (right-hand sides), ``saved``, ``wall_time`` (s), ``stopped`` (the message of the
        observer that stopped the run, or None); adaptive runs add ``rtol``, ``atol``.
    """

    def __init__(self, chain, problem, t, rods, rod_velocities, external_work=None,
                 stats=None):
        self.chain = chain
        self._problem = problem
        self.t = np.asarray(t, dtype=float)
        self.rods = np.asarray(rods, dtype=float)
        self.rod_velocities = np.asarray(rod_velocities, dtype=float)
        r0, u0, _ = problem.anchor(self.t)
        self.joints = chain.joints(self.rods, r0)
        self.joint_velocities = chain.joints(self.rod_velocities, u0)
        self.tension = chain.tension(self.rods)
        self.energy = energies(chain, problem, self.t, self.rods, self.rod_velocities,
                               external_work)
        self.stats = dict(stats or {})

    def __repr__(self):
        return (f"RodChainResult({len(self)} saved steps, t = {self.t[0]:g}..{self.t[-1]:g}"
                f" s, {self.chain!r})")

    def __len__(self):
        return len(self.t)

    @property
    def system(self):
        """The chain (``Result.system`` of cable runs)."""
        return self.chain

    @property
    def q(self):
        """Rod vectors flattened, (nt, 3 n): ``contract.Step.q`` of every saved step."""
        return self.rods.reshape(len(self), -1)

    @property
    def v(self):
        return self.rod_velocities.reshape(len(self), -1)

    @property
    def positions(self):
        """Joint positions (nt, n + 1, 3) (= ``joints``)."""
        return self.joints

    @property
    def velocities(self):
        """Joint velocities (nt, n + 1, 3) (= ``joint_velocities``)."""
        return self.joint_velocities

    @property
    def strain(self):
        """Engineering strain of each rod, (nt, n)."""
        return self.chain.strain(self.rods)

    @property
    def free_end(self):
        """Trajectory of ``O_n``, (nt, 3)."""
        return self.joints[:, -1]

    def _along(self, points, rates, s):
        s = np.asarray(s, dtype=float)
        S = np.concatenate([[0.0], np.cumsum(self.chain.lengths)])
        if np.any((s < 0) | (s > S[-1] * (1 + 1e-12))):
            raise ValueError(f"s must lie in [0, {S[-1]:g}] (reference arc length), got {s}")
        i = np.clip(np.searchsorted(S, s, side="right") - 1, 0, self.chain.n - 1)
        xi = ((s - S[i]) / self.chain.lengths[i])[..., None]
        return points[:, i] + xi * rates[:, i]

    def position(self, s):
        """Positions ``(nt,) + s.shape + (3,)`` of the material points at reference arc
        lengths ``s`` (m from the anchor; rods are straight and uniformly stretched)."""
        return self._along(self.joints, self.rods, s)

    def velocity(self, s):
        """Velocities of the material points at reference arc lengths ``s``."""
        return self._along(self.joint_velocities, self.rod_velocities, s)

    def state(self, i):
        """The ``i``-th saved step as a ``ChainState``."""
        i = range(len(self))[i]
        r0, u0, _ = self._problem.anchor(self.t[i: i + 1])
        return ChainState(self.chain, float(self.t[i]), self.rods[i], self.rod_velocities[i],
                          r0[0], u0[0])

    def accelerations(self):
        """Rod-vector accelerations at the output times from Eq. 21, (nt, n, 3)."""
        p = self._problem
        return np.stack([p.acceleration(t, q, v)[0]
                         for t, q, v in zip(self.t, self.rods, self.rod_velocities,
                                            strict=True)])

    def anchor_force(self):
        """Force exerted by the anchor on the tether, (nt, 3), from the momentum balance
        ``d/dt (m u_0 + sum_i c_i q_i') = F_0 + m g + P + sum_i F_i`` (``m`` total mass,
        ``c_i`` first moments, ``F_i`` line-load resultants of Eq. 14)."""
        p, c = self._problem, self.chain
        a0 = p.anchor(self.t)[2]
        qdd = self.accelerations()
        line = np.array([p.line_resultants(t, q, v)
                         for t, q, v in zip(self.t, self.rods, self.rod_velocities,
                                            strict=True)]).reshape(-1, 3)
        m = c.total_mass
        return (m * a0 + np.einsum("i,kid->kd", c.first_moments, qdd)
                - m * p.gravity - p.tip - line)
