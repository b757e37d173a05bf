"""The chain of elastic rods (Ma & Wang, Sect. 2): its constant mass matrix and the O(n)
solve (Eqs. 6-8, 22-30), forces (Eqs. 10-16), energies, statics, the RK4 stability limit,
and ``simulate`` (``integrate``)."""

import numpy as np
import scipy.sparse as sp

from ..kernels import rodchain as kern
from .checks import positive, positive_array, positive_int, vector3
from .integrate import METHODS, RK4_STABILITY, integrate
from .orbiting import OrbitingChain
from .problem import Problem


class RodChain:
    """Chain of ``n`` straight elastic rods, ``O_0`` anchored, ``O_n`` free (Sect. 2).

    Parameters
    ----------
    masses : array_like (n,)
        Rod masses ``m_i`` (kg), > 0; each rod is uniform.
    lengths : array_like (n,)
        Rest lengths ``l_i0`` (m), > 0.
    EA : array_like (n,)
        Axial stiffnesses ``E_i A_i`` (N), > 0.
    compression : bool
        ``True`` (default, the paper's Eq. 12): a rod shorter than its rest length pushes
        with ``EA (l0 - l) / l0`` like a bar.  ``False``: a slack rod (``l < l0``) carries
        no force, as a real tether; the force stays continuous at ``l = l0``.

    Notes
    -----
    Rods carry only axial force; there is no bending or torsion and the hinges are
    frictionless, so without damping the energy is conserved for conservative loads.
    """

    #: Values derived from the others (not in a run's fingerprint, ``io.fingerprint``).
    caches = ("_max_frequency",)

    def __init__(self, masses, lengths, EA, compression=True):
        self.masses = positive_array("masses", masses)
        n = self.masses.size
        self.lengths = positive_array("lengths", lengths, n)
        self.EA = positive_array("EA", EA, n)
        if not isinstance(compression, bool | np.bool_):
            raise ValueError(f"compression must be True or False, got {compression!r}")
        self.compression = bool(compression)
        self._a, self._b = kern.factor_mass(self.masses, np.zeros(n))
        self._max_frequency = None
        tail = np.concatenate([np.cumsum(self.masses[::-1])[::-1][1:], [0.0]])
        # c_i = m_i / 2 + sum_{j>i} m_j: Q_i = c_i g for gravity (Eq. 16)
        self.first_moments = 0.5 * self.masses + tail
        for arr in (self.masses, self.lengths, self.EA, self.first_moments, self._a, self._b):
            arr.setflags(write=False)  # the factorisation depends on them

    @classmethod
    def uniform(cls, n, mass, length, E, A, compression=True):
        """``n`` identical rods, each of mass ``mass`` (kg), rest length ``length`` (m),
        Young's modulus ``E`` (Pa) and cross-section ``A`` (m^2)."""
        n = positive_int("n", n)
        mass, length = positive("mass", mass), positive("length", length)
        EA = positive("E", E) * positive("A", A)
        return cls(np.full(n, mass), np.full(n, length), np.full(n, EA), compression)

    @property
    def n(self):
        return self.masses.size

    @property
    def total_mass(self):
        return float(self.masses.sum())

    @property
    def rest_length(self):
        return float(self.lengths.sum())

    def __repr__(self):
        return (f"RodChain(n={self.n}, mass={self.total_mass:g} kg, "
                f"length={self.rest_length:g} m, compression={self.compression})")

    # --- mass matrix ------------------------------------------------------------------------
    def mass_matrix(self):
        """Dense ``M`` (n, n) from Eq. 8: ``M_ii = m_i/3 + sum_{k>i} m_k``,
        ``M_ij = m_k/2 + sum_{l>k} m_l`` with ``k = max(i, j)``.  For checks only: O(n^2)."""
        k = np.maximum.outer(np.arange(self.n), np.arange(self.n))
        M = self.first_moments[k]
        M[np.diag_indices(self.n)] -= self.masses / 6.0
        return M

    def mass_factor(self):
        """Lower-bidiagonal ``B`` (sparse CSR) with ``M = Phi^T B^T B Phi`` (Eqs. 24-27)."""
        return sp.diags([self._a, self._b[:-1]], [0, -1], format="csr")

    def solve_mass(self, rhs):
        """``M^{-1} rhs`` in O(n) (Eqs. 28-30) without forming ``M``.

        Parameters
        ----------
        rhs : array_like (n,) or (n, k)

        Returns
        -------
        ndarray of the shape of ``rhs``
        """
        b = np.asarray(rhs, dtype=float)
        if b.ndim not in (1, 2) or b.shape[0] != self.n:
            raise ValueError(f"rhs must have shape ({self.n},) or ({self.n}, k), got {b.shape}")
        if not np.all(np.isfinite(b)):
            raise ValueError("rhs must be finite")
        b2 = np.ascontiguousarray(b.reshape(self.n, -1))
        out = np.empty_like(b2)
        kern.solve_mass(self._a, self._b, b2, out)
        return out.reshape(b.shape)

    # --- forces -----------------------------------------------------------------------------
    def _rods(self, q, name="q"):
        q = np.asarray(q, dtype=float)
        if q.shape[-2:] != (self.n, 3):
            raise ValueError(f"{name} must have shape (..., {self.n}, 3), got {q.shape}")
        return q

    def _state(self, q, name):
        q = np.ascontiguousarray(self._rods(q, name))
        if q.ndim != 2 or not np.all(np.isfinite(q)):
            raise ValueError(f"{name} must be a finite array of shape ({self.n}, 3)")
        return q

    def tension(self, q):
        """Axial force ``EA (l - l0) / l0`` of each rod (..., n), positive in tension
        (zero for a slack rod without ``compression``)."""
        l = np.linalg.norm(self._rods(q), axis=-1)
        T = self.EA * (l - self.lengths) / self.lengths
        return T if self.compression else np.maximum(T, 0.0)

    def strain(self, q):
        """Engineering strain ``(l - l0) / l0`` of each rod (..., n) (negative when the rod
        is shorter than at rest, also for slack rods without ``compression``)."""
        l = np.linalg.norm(self._rods(q), axis=-1)
        return (l - self.lengths) / self.lengths

    def elastic_force(self, q):
        """``k_i q_i`` (Eq. 12), (..., n, 3): the elastic generalized force is its negative."""
        q = self._rods(q)
        return (self.tension(q) / np.linalg.norm(q, axis=-1))[..., None] * q

    def generalized_forces(self, q, v=None, t=0.0, **loads):
        """External generalized forces ``Q_i = F*_i + sum_{j>i} F_j`` (Eq. 16), (n, 3),
        including the inertial load ``-c_i a_0(t)`` of a moving anchor.  ``loads``: the
        keywords ``gravity, line_load, tip_force, anchor, quadrature`` of ``simulate``."""
        q = self._state(q, "q")
        v = np.zeros_like(q) if v is None else self._state(v, "v")
        return Problem(self, **loads).generalized_forces(float(t), q, v)

    def acceleration(self, q, v=None, t=0.0, **loads):
        """Rod-vector accelerations ``M^{-1} (Q - K q)`` (Eqs. 21, 29), (n, 3); ``loads`` as
        in ``generalized_forces``."""
        q = self._state(q, "q")
        v = np.zeros_like(q) if v is None else self._state(v, "v")
        acc, bad = Problem(self, max_strain=np.inf, **loads).acceleration(float(t), q, v)
        if bad >= 0:
            raise ValueError(f"q: rod {bad} has zero length, its force direction is undefined")
        return acc

    # --- kinematics and energies --------------------------------------------------------------
    def joints(self, q, origin=(0.0, 0.0, 0.0)):
        """Joint positions ``O_0 .. O_n`` (..., n + 1, 3) from rod vectors (..., n, 3) and
        ``O_0`` (``origin``, (3,) or (..., 3)); joint velocities likewise from ``q'``."""
        q = self._rods(q)
        o = np.broadcast_to(np.asarray(origin, dtype=float), q.shape[:-2] + (3,))
        return np.concatenate([o[..., None, :], o[..., None, :] + np.cumsum(q, axis=-2)],
                              axis=-2)

    def kinetic_energy(self, v, anchor_velocity=(0.0, 0.0, 0.0)):
        """Eq. 4 in O(n), in the inertial frame when ``O_0`` moves with ``anchor_velocity``:
        ``sum_i m_i/2 (|U_{i-1} + v_i/2|^2 + |v_i|^2/12)``, ``U_{i-1}`` the velocity of
        ``O_{i-1}``.  ``v``: (..., n, 3); returns (...)."""
        v = self._rods(v, "v")
        U = self.joints(v, anchor_velocity)[..., :-1, :]
        mid = U + 0.5 * v
        return 0.5 * np.sum(self.masses * (np.sum(mid * mid, -1) + np.sum(v * v, -1) / 12), -1)

    def elastic_energy(self, q):
        """Eq. 10, ``sum_i EA_i (l_i - l_i0)^2 / (2 l_i0)`` (slack rods store nothing without
        ``compression``), (...)."""
        l = np.linalg.norm(self._rods(q), axis=-1)
        d = l - self.lengths if self.compression else np.maximum(l - self.lengths, 0.0)
        return np.sum(0.5 * self.EA * d * d / self.lengths, axis=-1)

    def potential_energy(self, q, gravity, origin=(0.0, 0.0, 0.0), tip_force=None):
        """Potential of gravity, ``-sum_i m_i g . (O_{i-1} + q_i / 2)``, and of a constant
        force ``P`` at ``O_n``, ``-P . O_n`` (zero at the origin), (...)."""
        g = vector3("gravity", gravity)
        O = self.joints(q, origin)
        centroid = 0.5 * (O[..., :-1, :] + O[..., 1:, :])
        V = -np.einsum("i,...id,d->...", self.masses, centroid, g)
        if tip_force is not None:
            V = V - O[..., -1, :] @ vector3("tip_force", tip_force)
        return V

    # --- statics and stability ------------------------------------------------------------------
    def static_equilibrium(self, gravity, tip_force=None):
        """Rod vectors of the static equilibrium under gravity and a tip force (n, 3).

        With ``q'' = 0`` Eq. 18 reads ``k_i q_i = Q_i = c_i g + P``: rod ``i`` is aligned with
        ``Q_i`` and stretched to ``l_i = l_i0 (1 + |Q_i| / E_i A_i)`` (exact, O(n)).
        """
        Q = np.outer(self.first_moments, vector3("gravity", gravity))
        if tip_force is not None:
            Q += vector3("tip_force", tip_force)
        T = np.linalg.norm(Q, axis=1)
        if np.any(T == 0):
            raise ValueError("static_equilibrium needs a load that tensions every rod "
                             "(c_i g + tip_force != 0 for all i)")
        return (self.lengths * (1 + T / self.EA) / T)[:, None] * Q

    def max_frequency(self):
        """Highest axial natural frequency (rad/s) of the straight chain, an upper bound for
        every configuration with rods longer than ``l0 / 2`` (the rod Hessian of Eq. 10 is
        ``EA/l0`` along the rod and ``T/l`` across it).

        Computed in O(n) by bisection with Sturm counts of the tridiagonal joint-coordinate
        pencil (``count_axial_below``) below the bound ``max_i sqrt(12 E_i A_i / (l_i0
        m_i))``, the free-free frequency of one rod with the consistent mass of Eq. 3.
        """
        if self._max_frequency is None:
            k = self.EA / self.lengths
            upper = float(np.max(12.0 * k / self.masses))
            self._max_frequency = float(np.sqrt(kern.max_axial_eigenvalue(k, self.masses,
                                                                          upper)))
        return self._max_frequency

    def stable_dt(self):
        """Largest RK4 step that keeps all axial modes stable, ``2 sqrt(2) / max_frequency``
        (RK4 is stable on the imaginary axis for ``|omega dt| <= 2 sqrt(2)``)."""
        return RK4_STABILITY / self.max_frequency()

    def in_orbit(self, orbit, end_masses, quadrature=2, max_strain=1.0):
        """This chain with end bodies of masses ``end_masses = (m_a, m_b)`` (kg) at ``O_0``
        and ``O_n``, both ends free, in the differential gravity of ``orbit``: an
        ``OrbitingChain`` (positions are offsets from the orbit's reference point)."""
        return OrbitingChain(self, orbit, end_masses, quadrature, max_strain)

    # --- time integration ----------------------------------------------------------------------
    def simulate(self, q0, v0, t_end, dt, *, gravity=(0.0, 0.0, 0.0), method="rk4",
                 line_load=None, tip_force=None, anchor=None, quadrature=3, output_every=1,
                 rtol=1e-8, atol=1e-10, max_strain=1.0, check_stability=True, observers=(),
                 resume=None):
        """Integrate Eq. 21 from rod vectors ``q0`` and velocities ``v0`` over ``[0, t_end]``.

        Parameters
        ----------
        q0, v0 : array_like (n, 3)
            Initial rod vectors ``O_{i-1} -> O_i`` (m) and their rates (m/s), relative to the
            anchor.
        t_end : float
            Final time (s), > 0; a multiple of ``dt * output_every``.
        dt : float
            ``"rk4"``: the fixed step (s), at most ``stable_dt()`` (axial modes).
            Adaptive methods: the spacing of the output grid, the solver picks its steps.
        gravity : array_like (3,)
            Uniform gravitational acceleration (m/s^2): ``F_i = m_i g``, ``F*_i = m_i g / 2``.
        method : {"rk4", "RK45", "DOP853"}
            Fixed-step classical Runge-Kutta (compiled loop) or ``scipy.integrate.solve_ivp``
            with ``rtol``, ``atol``.
        line_load : None, array_like (3,) or callable
            Distributed force per unit *current* length (N/m), as in Eq. 14: a uniform vector
            ``w`` (``F_i = w l_i``, ``F*_i = w l_i / 2``) or ``f(t, r, v)`` evaluated at the
            material points ``r`` with velocities ``v`` (arrays (n, quadrature, 3)) returning
            the same shape, integrated by Gauss-Legendre quadrature on each rod.  With a
            callable, the ``"rk4"`` time loop runs in Python (slower per step).
        tip_force : array_like (3,), optional
            Constant point force at ``O_n`` (N): ``Q_i += P`` for all ``i``.
        anchor : None, array_like (3,) or callable
            ``O_0`` fixed at the origin, at a point, or moving: ``motion(t) -> (position,
            velocity, acceleration)`` for ``t`` of shape (k,), each (k, 3) (see
            ``circular_anchor``).  Its acceleration ``a_0`` enters as the load
            ``-c_i a_0`` (a uniform field ``-a_0`` added to gravity).
        quadrature : int
            Gauss points per rod for a callable ``line_load``.
        output_every : int
            Store every ``output_every``-th step (RK4) or grid point.
        rtol, atol : float
            Tolerances of the adaptive methods.
        max_strain : float
            A rod longer than ``(1 + max_strain) l0``, of zero length or non-finite stops
            the integration with ``RodChainDivergence``.
        check_stability : bool
            ``"rk4"`` only: reject ``dt > stable_dt()`` with ``ValueError`` (above the limit
            the highest axial modes grow without bound, or until nonlinear effects bound them
            at a meaningless amplitude).
        observers : sequence of Observer
            ``contract.Observer`` objects, called as by ``skfem_cable.simulate``: ``start``
            with a ``contract.Run`` (``system``: this chain, ``integrator``: the
            ``integrate.Integration``, ``settings``: ``t_start``, ``t_end``, ``dt``,
            ``every``, ``method``, ``n_steps``, ...); ``saved`` with a ``contract.Step`` at
            the initial state and every saved step (``q``, ``v``, ``a``: rod vectors, rates
            and accelerations flattened to (3 n,); ``energies``); a true return value stops
            the run cleanly after that step (``stats["stopped"]``); ``finish`` at the end,
            also after a failure.  The compiled RK4 runs in blocks and calls ``saved`` for
            the saved steps of a block after the block (see ``integrate``).  ``run.system``
            is the chain's ``stored.ChainSystem``: ``io.RunStore`` stores the run.
        resume : io.Resume, optional
            Continue the run stored by an ``io.RunStore`` (``io.resume(path)``) from its
            last checkpoint, bit for bit: the same chain, ``q0``, loads and settings (all
            but ``t_end``), else ``io.StoreMismatch``.  Observers are not called at the
            steps before it; the result holds the whole run.

        Returns
        -------
        RodChainResult
        """
        q0 = self._state(q0, "q0")
        v0 = self._state(v0, "v0")
        t_end, dt = positive("t_end", t_end), positive("dt", dt)
        if method not in METHODS:
            raise ValueError(f"method must be one of {METHODS}, got {method!r}")
        every = positive_int("output_every", output_every)
        nsteps = int(round(t_end / dt))
        if nsteps < 1 or abs(nsteps * dt - t_end) > 1e-9 * t_end or nsteps % every:
            raise ValueError(f"t_end / dt = {t_end / dt:.12g} must be a positive integer "
                             f"multiple of output_every = {every}")
        rtol, atol = positive("rtol", rtol), positive("atol", atol)
        problem = Problem(self, gravity, line_load, tip_force, anchor, quadrature, max_strain)
        if method == "rk4" and check_stability and dt > self.stable_dt():
            raise ValueError(f"dt = {dt:g} s exceeds the RK4 stability limit of the axial "
                             f"modes, chain.stable_dt() = {self.stable_dt():.6g} s; use a "
                             "smaller dt, an adaptive method, or check_stability=False")
        return integrate(self, problem, q0, v0, t_end, dt, nsteps, every, method,
                         None if method == "rk4" else rtol, None if method == "rk4" else atol,
                         observers, resume)
