"""Tether as a chain of straight elastic rods joined by frictionless spherical hinges
(Ma & Wang, "An Efficient Model of Tethers for Tethered Satellite Systems";
``shared/papers/rod-chain-tether-On.md``), with the O(n) solve of the constant mass matrix.

The generalized coordinates are the rod vectors ``q_i = O_{i-1} -> O_i`` (no angles).  The
anchor ``O_0`` is fixed or follows a prescribed motion; ``O_n`` is free.  The equations of
motion, three decoupled copies of Eq. 18 (Eq. 20), are

    M q'' + K(q) q = Q_F F + F*  - c a_0(t),

with the constant mass matrix ``M`` (Eqs. 6-8), the diagonal ``K`` of axial factors
``k_i`` (Eq. 12), the generalized forces of distributed loads (Eqs. 14-16) and, for a
moving anchor, the inertial load of its acceleration ``a_0`` weighted by the first-moment
coefficients ``c_i = m_i / 2 + sum_{j>i} m_j``.  ``M^{-1}`` is applied in O(n) through
``M = Phi^T B^T B Phi`` (Eqs. 22-30).  See ``docs/rodchain.md``.
"""

from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
from scipy.integrate import solve_ivp

from .kernels import rodchain as kern

METHODS = ("rk4", "RK45", "DOP853")
RK4_STABILITY = 2.0 * np.sqrt(2.0)  # RK4 is stable on the imaginary axis for |h w| <= 2 sqrt 2
_BLOCK_STEPS = 1 << 15  # RK4 steps per compiled call (bounds the anchor-field table)


class RodChainDivergence(RuntimeError):
    """A time integration left the admissible states (non-finite or over-stretched rod).

    Attributes ``t`` (s), ``step`` (index of the failing step, or None for adaptive
    methods) and ``rod`` (0-based index of the offending rod) locate the failure.
    """

    def __init__(self, message, t, step=None, rod=None):
        super().__init__(message)
        self.t = t
        self.step = step
        self.rod = rod


def _positive_array(name, value, n=None):
    try:
        arr = np.array(value, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be an array of positive reals, got {value!r}") from None
    if arr.ndim != 1 or arr.size == 0:
        raise ValueError(f"{name} must be a non-empty 1-D array, got shape {arr.shape}")
    if n is not None and arr.size != n:
        raise ValueError(f"{name} must have one entry per rod ({n}), got {arr.size}")
    if not np.all(np.isfinite(arr) & (arr > 0)):
        raise ValueError(f"{name} must be finite and > 0, got {value!r}")
    return arr


def _positive(name, value):
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a real number > 0, got {value!r}") from None
    if not (np.isfinite(v) and v > 0):
        raise ValueError(f"{name} must be finite and > 0, got {value!r}")
    return v


def _vector3(name, value):
    try:
        v = np.array(value, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a finite 3-vector, got {value!r}") from None
    if v.shape != (3,) or not np.all(np.isfinite(v)):
        raise ValueError(f"{name} must be a finite 3-vector, got {value!r}")
    return v


def circular_anchor(radius, omega, center=(0.0, 0.0, 0.0), normal=(0.0, 0.0, 1.0), phase=0.0):
    """Anchor motion on a circle: an attachment point on a spinning hub or a circular orbit.

    ``O_0(t) = center + radius (cos(omega t + phase) e1 + sin(omega t + phase) e2)`` with
    ``e1`` the unit projection of the x axis on the plane normal to ``normal`` (of the y
    axis when ``normal`` is close to x) and ``e2 = normal x e1``: the point turns about
    ``normal`` at the angular rate ``omega`` (rad/s, any sign); for ``normal = z`` it starts
    at ``center + radius x``.

    Returns
    -------
    callable
        ``motion(t) -> (position, velocity, acceleration)`` for an array ``t`` of shape
        ``(k,)``, each result of shape ``(k, 3)``; the form ``simulate(anchor=...)`` expects.
    """
    radius = _positive("radius", radius)
    omega = float(omega)
    center = _vector3("center", center)
    e3 = _vector3("normal", normal)
    if not np.linalg.norm(e3) > 0:
        raise ValueError("normal must be a non-zero 3-vector")
    e3 = e3 / np.linalg.norm(e3)
    ref = np.eye(3)[0] if abs(e3[0]) < 0.9 else np.eye(3)[1]
    e1 = ref - (ref @ e3) * e3
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(e3, e1)

    def motion(t):
        th = omega * np.asarray(t, dtype=float)[:, None] + phase
        c, s = np.cos(th), np.sin(th)
        r = radius * (c * e1 + s * e2)
        v = radius * omega * (-s * e1 + c * e2)
        return center + r, v, -omega**2 * r

    return motion


class _Problem:
    """A chain with its loads and anchor motion: the right-hand side of Eq. 21."""

    def __init__(self, chain, gravity=(0.0, 0.0, 0.0), line_load=None, tip_force=None,
                 anchor=None, quadrature=3, max_strain=1.0):
        self.chain = chain
        self.gravity = _vector3("gravity", gravity)
        self.tip = np.zeros(3) if tip_force is None else _vector3("tip_force", tip_force)
        self.max_strain = float(max_strain)
        if not self.max_strain > 0:
            raise ValueError(f"max_strain must be > 0 (inf allowed), got {max_strain!r}")
        self.line_callable = callable(line_load)
        self.w = np.zeros(3)
        if line_load is not None and not self.line_callable:
            self.w = _vector3("line_load", line_load)
        self.line_load = line_load
        if (isinstance(quadrature, bool) or not isinstance(quadrature, int | np.integer)
                or not 1 <= quadrature <= 20):
            raise ValueError(f"quadrature must be an integer in [1, 20], got {quadrature!r}")
        x, wq = np.polynomial.legendre.leggauss(int(quadrature))
        self.xi, self.wq = 0.5 * (x + 1.0), 0.5 * wq
        # anchor(t) -> position, velocity, acceleration of O_0 at the times t (k,), each (k, 3)
        self.anchor = self._anchor_motion(anchor)
        self.anchor(np.zeros(1))  # validate now rather than mid-integration

    @staticmethod
    def _anchor_motion(anchor):
        if anchor is None:
            anchor = np.zeros(3)
        if not callable(anchor):
            point = _vector3("anchor", anchor)

            def fixed(t):
                z = np.zeros((np.size(t), 3))
                return z + point, z, z

            return fixed

        def checked(t):
            t = np.atleast_1d(np.asarray(t, dtype=float))
            try:
                out = tuple(np.asarray(x, dtype=float) for x in anchor(t))
            except Exception as exc:
                raise ValueError("anchor must map an array of times (k,) to (position, "
                                 f"velocity, acceleration), each (k, 3); calling it failed: "
                                 f"{exc}") from exc
            if len(out) != 3 or any(x.shape != (t.size, 3) for x in out):
                raise ValueError("anchor must map an array of times (k,) to (position, "
                                 "velocity, acceleration), each of shape (k, 3)")
            if not all(np.all(np.isfinite(x)) for x in out):
                raise ValueError(f"anchor returned non-finite values at t = {t}")
            return out

        return checked

    def field(self, t):
        """Mass-proportional load field ``g - a_0(t)`` (k, 3): gravity plus the inertial
        load of the anchor acceleration."""
        return self.gravity - self.anchor(t)[2]

    def extra_forces(self, t, q, v, r0, u0):
        """``F_i`` and ``F*_i`` of Eq. 14 for the callable line load by Gauss quadrature
        over each rod (zeros without one)."""
        n = q.shape[0]
        if not self.line_callable:
            return np.zeros((n, 3)), np.zeros((n, 3))
        start = r0 + np.cumsum(q, axis=0) - q
        ustart = u0 + np.cumsum(v, axis=0) - v
        xi = self.xi[None, :, None]
        r = start[:, None, :] + xi * q[:, None, :]
        u = ustart[:, None, :] + xi * v[:, None, :]
        f = np.asarray(self.line_load(t, r, u), dtype=float)
        if f.shape != r.shape:
            raise ValueError(f"line_load(t, r, v) must return an array of shape {r.shape} "
                             f"(force per unit current length), got {f.shape}")
        l = np.linalg.norm(q, axis=1)[:, None]
        F = l * np.einsum("g,igd->id", self.wq, f)
        Fs = l * np.einsum("g,igd->id", self.wq * self.xi, f)
        return F, Fs

    def acceleration(self, t, q, v):
        """``(q'', flag)``: Eq. 21 at time ``t``; ``flag`` is ``load_vector``'s rod check."""
        c = self.chain
        r0, u0, a0 = self.anchor(np.array([t]))
        Fx, Fxs = self.extra_forces(t, q, v, r0[0], u0[0])
        out = np.empty_like(q)
        g = self.gravity - a0[0]
        bad = kern.derivative(q, c.masses, c.lengths, c.EA, c.compression, c._a, c._b, g,
                              self.w, self.tip, Fx, Fxs, self.max_strain, np.empty_like(q), out)
        return out, bad

    def generalized_forces(self, t, q, v):
        """External generalized forces ``Q`` (Eq. 16 plus the anchor term), (n, 3)."""
        c = self.chain
        r0, u0, a0 = self.anchor(np.array([t]))
        Fx, Fxs = self.extra_forces(t, q, v, r0[0], u0[0])
        out = np.empty_like(q)
        kern.load_vector(q, c.masses, c.lengths, c.EA, c.compression, False,
                         self.gravity - a0[0], self.w, self.tip, Fx, Fxs, np.inf, out)
        return out


@dataclass
class RodChainResult:
    """Output of ``RodChain.simulate`` at the times ``t`` (nt,).

    Attributes
    ----------
    t : ndarray (nt,)
    rods, rod_velocities : ndarray (nt, n, 3)
        Rod vectors ``q_i = O_{i-1} -> O_i`` and their time derivatives.
    joints, joint_velocities : ndarray (nt, n + 1, 3)
        Positions and velocities of ``O_0 .. O_n`` in the inertial frame.
    tension : ndarray (nt, n)
        Axial force of each rod, ``k_i l_i`` (Eq. 12), positive in tension.
    energy : dict of ndarray (nt,)
        ``"kinetic"`` (Eq. 4, inertial frame), ``"elastic"`` (Eq. 10), ``"potential"``
        (gravity and the constant tip force) and their sum ``"total"``.  Uniform or callable
        line loads and a moving anchor do work that ``"total"`` does not contain.
    stats : dict
        ``method``, ``steps`` (RK4) or ``nfev`` (adaptive), ``dt``.
    """

    t: np.ndarray
    rods: np.ndarray
    rod_velocities: np.ndarray
    joints: np.ndarray
    joint_velocities: np.ndarray
    tension: np.ndarray
    energy: dict
    stats: dict
    _problem: _Problem = field(repr=False)

    @property
    def free_end(self):
        """Trajectory of ``O_n``, (nt, 3)."""
        return self.joints[:, -1]

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
        p, c = self._problem, self._problem.chain
        a0 = p.anchor(self.t)[2]
        qdd = self.accelerations()
        line = np.zeros((self.t.size, 3))
        for k, (t, q, v) in enumerate(zip(self.t, self.rods, self.rod_velocities, strict=True)):
            r0, u0, _ = p.anchor(np.array([t]))
            F, _ = p.extra_forces(t, q, v, r0[0], u0[0])
            line[k] = F.sum(axis=0) + p.w * np.linalg.norm(q, axis=1).sum()
        m = c.total_mass
        return (m * a0 + np.einsum("i,kid->kd", c.first_moments, qdd)
                - m * p.gravity - p.tip - line)


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

    def __init__(self, masses, lengths, EA, compression=True):
        self.masses = _positive_array("masses", masses)
        n = self.masses.size
        self.lengths = _positive_array("lengths", lengths, n)
        self.EA = _positive_array("EA", EA, n)
        if not isinstance(compression, bool | np.bool_):
            raise ValueError(f"compression must be True or False, got {compression!r}")
        self.compression = bool(compression)
        self._a, self._b = kern.factor_mass(self.masses)
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
        if isinstance(n, bool) or not isinstance(n, int | np.integer) or n < 1:
            raise ValueError(f"n must be an integer >= 1, got {n!r}")
        n = int(n)
        mass, length = _positive("mass", mass), _positive("length", length)
        EA = _positive("E", E) * _positive("A", A)
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
        return _Problem(self, **loads).generalized_forces(float(t), q, v)

    def acceleration(self, q, v=None, t=0.0, **loads):
        """Rod-vector accelerations ``M^{-1} (Q - K q)`` (Eqs. 21, 29), (n, 3); ``loads`` as
        in ``generalized_forces``."""
        q = self._state(q, "q")
        v = np.zeros_like(q) if v is None else self._state(v, "v")
        acc, bad = _Problem(self, max_strain=np.inf, **loads).acceleration(float(t), q, v)
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
        g = _vector3("gravity", gravity)
        O = self.joints(q, origin)
        centroid = 0.5 * (O[..., :-1, :] + O[..., 1:, :])
        V = -np.einsum("i,...id,d->...", self.masses, centroid, g)
        if tip_force is not None:
            V = V - O[..., -1, :] @ _vector3("tip_force", tip_force)
        return V

    # --- statics and stability ------------------------------------------------------------------
    def static_equilibrium(self, gravity, tip_force=None):
        """Rod vectors of the static equilibrium under gravity and a tip force (n, 3).

        With ``q'' = 0`` Eq. 18 reads ``k_i q_i = Q_i = c_i g + P``: rod ``i`` is aligned with
        ``Q_i`` and stretched to ``l_i = l_i0 (1 + |Q_i| / E_i A_i)`` (exact, O(n)).
        """
        Q = np.outer(self.first_moments, _vector3("gravity", gravity))
        if tip_force is not None:
            Q += _vector3("tip_force", tip_force)
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

    # --- time integration ----------------------------------------------------------------------
    def simulate(self, q0, v0, t_end, dt, *, gravity=(0.0, 0.0, 0.0), method="rk4",
                 line_load=None, tip_force=None, anchor=None, quadrature=3, output_every=1,
                 rtol=1e-8, atol=1e-10, max_strain=1.0, check_stability=True):
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

        Returns
        -------
        RodChainResult
        """
        q0 = self._state(q0, "q0")
        v0 = self._state(v0, "v0")
        t_end, dt = _positive("t_end", t_end), _positive("dt", dt)
        if method not in METHODS:
            raise ValueError(f"method must be one of {METHODS}, got {method!r}")
        if (isinstance(output_every, bool) or not isinstance(output_every, int | np.integer)
                or output_every < 1):
            raise ValueError(f"output_every must be an integer >= 1, got {output_every!r}")
        every = int(output_every)
        nsteps = int(round(t_end / dt))
        if nsteps < 1 or abs(nsteps * dt - t_end) > 1e-9 * t_end or nsteps % every:
            raise ValueError(f"t_end / dt = {t_end / dt:.12g} must be a positive integer "
                             f"multiple of output_every = {every}")
        rtol, atol = _positive("rtol", rtol), _positive("atol", atol)
        problem = _Problem(self, gravity, line_load, tip_force, anchor, quadrature, max_strain)
        t = dt * every * np.arange(nsteps // every + 1)
        t[-1] = t_end
        if method == "rk4":
            if check_stability and dt > self.stable_dt():
                raise ValueError(f"dt = {dt:g} s exceeds the RK4 stability limit of the axial "
                                 f"modes, chain.stable_dt() = {self.stable_dt():.6g} s; use a "
                                 "smaller dt, an adaptive method, or check_stability=False")
            run = self._rk4_python if problem.line_callable else self._rk4_compiled
            q, v = run(problem, q0, v0, dt, nsteps, every)
            stats = {"method": method, "dt": dt, "steps": nsteps}
        else:
            q, v, stats = self._adaptive(problem, q0, v0, t, method, rtol, atol)
        r0, u0, _ = problem.anchor(t)
        energy = {
            "kinetic": self.kinetic_energy(v, u0),
            "elastic": self.elastic_energy(q),
            "potential": self.potential_energy(q, problem.gravity, r0, problem.tip),
        }
        energy["total"] = energy["kinetic"] + energy["elastic"] + energy["potential"]
        return RodChainResult(t=t, rods=q, rod_velocities=v, joints=self.joints(q, r0),
                              joint_velocities=self.joints(v, u0), tension=self.tension(q),
                              energy=energy, stats=stats, _problem=problem)

    def _diverged(self, problem, q, t, step, rod, dt):
        l = np.linalg.norm(q[rod])
        msg = (f"rod-chain integration diverged at t = {t:.6g} s"
               + (f" (step {step}, dt = {dt:g} s)" if step is not None else "")
               + f": rod {rod} has length {l:.6g} m, rest length {self.lengths[rod]:.6g} m "
               f"(admissible: (0, {1 + problem.max_strain:g} l0], finite). "
               f"RK4 is stable for dt below about {self.stable_dt():.3g} s.")
        return RodChainDivergence(msg, t, step, rod)

    def _rk4_compiled(self, problem, q0, v0, dt, nsteps, every):
        nout = nsteps // every
        Q = np.empty((nout + 1, self.n, 3))
        V = np.empty_like(Q)
        Q[0], V[0] = q0, v0
        q, v = q0.copy(), v0.copy()
        per_block = max(1, _BLOCK_STEPS // every)
        j = 0
        while j < nout:
            m = min(per_block, nout - j)
            s0, steps = j * every, m * every
            gtab = np.ascontiguousarray(problem.field(dt * (s0 + 0.5 * np.arange(2 * steps + 1))))
            step, rod = kern.rk4_block(q, v, dt, steps, every, self.masses, self.lengths, self.EA,
                                       self.compression, self._a, self._b, gtab, problem.w,
                                       problem.tip, problem.max_strain, Q[j + 1: j + 1 + m],
                                       V[j + 1: j + 1 + m])
            if step >= 0:
                raise self._diverged(problem, q, (s0 + step) * dt, s0 + step, rod, dt)
            j += m
        return Q, V

    def _rk4_python(self, problem, q0, v0, dt, nsteps, every):
        """Classical RK4 with the right-hand side evaluated in Python (callable loads)."""
        Q = np.empty((nsteps // every + 1, self.n, 3))
        V = np.empty_like(Q)
        Q[0], V[0] = q0, v0
        q, v = q0.copy(), v0.copy()
        h = 0.5 * dt
        for s in range(nsteps):
            t = s * dt
            a1, bad = problem.acceleration(t, q, v)
            if bad >= 0:
                raise self._diverged(problem, q, t, s, bad, dt)
            q2, v2 = q + h * v, v + h * a1
            a2 = problem.acceleration(t + h, q2, v2)[0]
            q3, v3 = q + h * v2, v + h * a2
            a3 = problem.acceleration(t + h, q3, v3)[0]
            q4, v4 = q + dt * v3, v + dt * a3
            a4 = problem.acceleration(t + dt, q4, v4)[0]
            q = q + dt / 6 * (v + 2 * v2 + 2 * v3 + v4)
            v = v + dt / 6 * (a1 + 2 * a2 + 2 * a3 + a4)
            if (s + 1) % every == 0:
                Q[(s + 1) // every], V[(s + 1) // every] = q, v
        bad = problem.acceleration(nsteps * dt, q, v)[1]
        if bad >= 0:
            raise self._diverged(problem, q, nsteps * dt, nsteps, bad, dt)
        return Q, V

    def _adaptive(self, problem, q0, v0, t, method, rtol, atol):
        n3 = 3 * self.n

        def rhs(time, y):
            q = y[:n3].reshape(self.n, 3)
            v = y[n3:].reshape(self.n, 3)
            return np.concatenate([y[n3:], problem.acceleration(time, q, v)[0].ravel()])

        with np.errstate(all="ignore"):  # trial stages may overflow; the result is checked
            sol = solve_ivp(rhs, (0.0, t[-1]), np.concatenate([q0.ravel(), v0.ravel()]),
                            method=method, t_eval=t, rtol=rtol, atol=atol)
        if sol.status != 0:
            raise RodChainDivergence(f"solve_ivp ({method}) stopped at t = {sol.t[-1]:.6g} s: "
                                     f"{sol.message}", float(sol.t[-1]))
        Q = np.ascontiguousarray(sol.y[:n3].T.reshape(-1, self.n, 3))
        V = np.ascontiguousarray(sol.y[n3:].T.reshape(-1, self.n, 3))
        l = np.linalg.norm(Q, axis=-1)
        ok = np.isfinite(V).all(axis=(1, 2)) & np.all(
            (l > 0) & (l <= (1 + problem.max_strain) * self.lengths), axis=1)
        if not ok.all():
            k = int(np.argmin(ok))
            rod = int(np.argmin((l[k] > 0) & (l[k] <= (1 + problem.max_strain) * self.lengths)))
            raise self._diverged(problem, Q[k], float(t[k]), None, rod, None)
        return Q, V, {"method": method, "rtol": rtol, "atol": atol, "nfev": sol.nfev}
