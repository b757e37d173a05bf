"""A rod chain with end bodies, free in orbit (``OrbitingChain``): the tethered satellite
system of Ma & Wang in the frame of ``skfem_cable.space``.

The paper writes its equations in an inertial frame with ``O_0`` fixed and leaves the
external forces as general distributed loads ``f`` (Eqs. 13-16); it has no orbital frame
of its own.  Here the chain's positions are offsets ``delta`` from the reference point
``R(t)`` of an ``Orbit``, in axes parallel to the inertial ones.  That frame translates
with the acceleration ``g(R)`` of the reference point, so each mass feels the
differential gravity ``g(R + delta) - g(R)`` (``orbit.differential_gravity``) and no
other inertial force.  This is equivalent to writing the equations in the orbiting
(LVLH) frame, where the same physics appears as the gravity gradient plus the
centrifugal and Coriolis forces of the frame's rotation: the two descriptions differ by
a time-dependent rotation of the coordinates only.

The end body at ``O_0`` makes ``O_0`` free: the coordinates are ``x = (r_0, q_1 .. q_n)``,
``r_0`` the offset of ``O_0``.  In joint coordinates ``U = Phi x'`` (``Phi`` of Eq. 5 one
row larger) the kinetic energy is that of Eq. 3 for every rod plus ``m_a |U_0|^2 / 2 +
m_b |U_n|^2 / 2`` of the end bodies, so the mass matrix keeps the form ``Phi^T B^T B
Phi`` of Eq. 24 for a chain whose first "rod" is the massless offset ``r_0``, with the
end bodies as point masses on the diagonal of ``G`` (Eq. 25), and the O(n) solve of
Eqs. 28-30 applies unchanged.
"""

from dataclasses import dataclass, field

import numpy as np

from ..kernels import rodchain as kern
from .checks import positive, positive_int
from .integrate import RK4_STABILITY, RodChainDivergence

_BLOCK_STEPS = 1 << 15  # RK4 steps per compiled call (bounds the reference-point table)


def _end_masses(value):
    """Two finite masses >= 0 (kg)."""
    masses = np.array(value, dtype=float)
    if masses.shape != (2,) or not np.all(np.isfinite(masses) & (masses >= 0)):
        raise ValueError(f"end_masses must be two finite masses >= 0 (kg), got {value!r}")
    return masses


class OrbitingChain:
    """A ``RodChain`` with end bodies of masses ``end_masses = (m_a, m_b)`` at ``O_0`` and
    ``O_n``, both ends free, in the differential gravity of ``orbit``.

    Parameters
    ----------
    chain : RodChain
        The tether.
    orbit : Orbit
        The reference orbit: positions are offsets from its point ``R(t)``, axes parallel
        to the inertial ones.
    end_masses : (float, float)
        Masses of the point bodies at ``O_0`` and ``O_n`` (kg, >= 0).
    quadrature : int
        Gauss-Legendre points per rod for ``F_i``, ``F*_i`` (Eq. 14).  Two integrate
        exactly a field that is cubic along the rod; the differential gravity is linear to
        a relative ``|delta| / |R|``.
    max_strain : float
        A rod longer than ``(1 + max_strain) l0`` stops the run (``RodChainDivergence``).

    Notes
    -----
    The state is ``x = (r_0, q_1 .. q_n)``, shape (n + 1, 3), and its rate ``v``: ``r_0``
    the offset of ``O_0`` from ``R``, ``q_i`` the rod vectors.  Gravity enters as the
    distributed load of Eq. 14 with the density of the rod's mass, ``F_i = m_i int_0^1
    a(r(s)) ds``, ``F*_i = m_i int_0^1 s a(r(s)) ds`` (``a`` the differential gravity at the
    material point ``r(s) = O_{i-1} + s q_i`` of Eq. 13), and the end bodies as point loads
    ``m a`` at their joints; the generalized forces are those of Eq. 16, plus the resultant
    of all loads for ``r_0``.  The time step is the classical RK4 of ``RodChain.simulate``
    with ``R`` evaluated at every stage; an explicit method needs no tangent.
    """

    def __init__(self, chain, orbit, end_masses, quadrature=2, max_strain=1.0):
        self.chain, self.orbit = chain, orbit
        self.end_masses = _end_masses(end_masses)
        self.max_strain = positive("max_strain", max_strain)
        x, w = np.polynomial.legendre.leggauss(positive_int("quadrature", quadrature))
        self.xi, self.wq = 0.5 * (x + 1.0), 0.5 * w
        joint = np.zeros(chain.n + 1)
        joint[[0, -1]] = self.end_masses
        self._a, self._b = kern.factor_mass(np.concatenate([[0.0], chain.masses]), joint)

    @property
    def n(self):
        """Number of rods."""
        return self.chain.n

    @property
    def total_mass(self):
        return self.chain.total_mass + float(self.end_masses.sum())

    def __repr__(self):
        m_a, m_b = self.end_masses
        return f"OrbitingChain({self.chain!r}, end_masses=({m_a:g}, {m_b:g}), {self.orbit!r})"

    def _state(self, x, name):
        x = np.ascontiguousarray(x, dtype=float)
        if x.shape != (self.n + 1, 3) or not np.all(np.isfinite(x)):
            raise ValueError(f"{name} must be a finite array of shape ({self.n + 1}, 3): "
                             "the offset of O_0, then the rod vectors")
        return x

    def joints(self, x):
        """Offsets of ``O_0 .. O_n`` from the reference point, (..., n + 1, 3) from states
        (..., n + 1, 3) (velocities likewise from rates)."""
        return np.cumsum(x, axis=-2)

    def centre_of_mass(self, x):
        """Offset of the centre of mass from the reference point, (..., 3): the end bodies
        at ``O_0``, ``O_n`` and each rod's mass at its midpoint."""
        O = self.joints(x)
        rods = self.chain.masses @ (0.5 * (O[..., :-1, :] + O[..., 1:, :]))
        ends = self.end_masses[0] * O[..., 0, :] + self.end_masses[1] * O[..., -1, :]
        return (rods + ends) / self.total_mass

    def tension(self, x):
        """Axial force of each rod (..., n) (``RodChain.tension`` of the rod vectors)."""
        return self.chain.tension(np.asarray(x)[..., 1:, :])

    def solve_mass(self, rhs):
        """``M^{-1} rhs`` (Eq. 28) for the mass matrix of the state ``x``, rhs (n + 1, 3)."""
        rhs = self._state(rhs, "rhs")
        out = np.empty_like(rhs)
        kern.solve_mass(self._a, self._b, rhs, out)
        return out

    def acceleration(self, t, x):
        """``x''`` at time ``t`` (n + 1, 3); raises ``ValueError`` for a rod of zero or
        excessive length."""
        x = self._state(x, "x")
        c = self.chain
        F, Fs, work, out = (np.empty_like(x) for _ in range(4))
        bad = kern.orbit_derivative(x, c.masses, c.lengths, c.EA, c.compression,
                                    self.end_masses, self._a, self._b,
                                    self.orbit.position(float(t)), self.orbit.mu, self.xi,
                                    self.wq, self.max_strain, np.zeros(3), F, Fs,
                                    work, out)
        if bad >= 0:
            raise ValueError(f"x: rod {bad} has length {np.linalg.norm(x[bad + 1]):.6g} m, "
                             f"outside (0, {1 + self.max_strain:g} l0]")
        return out

    def stable_dt(self):
        """An RK4 step that keeps every axial mode stable: ``2 sqrt(2) / max_i sqrt(12
        E_i A_i / (l_i0 m_i))``, the free-free frequency of the stiffest single rod (Eq. 3).
        No mode of the assembled chain is faster: point masses and the free ends only add
        mass, and the highest eigenvalue of an assembly is below its elements' highest."""
        c = self.chain
        return RK4_STABILITY / float(np.sqrt(np.max(12.0 * c.EA / (c.lengths * c.masses))))

    def simulate(self, x0, v0, t_end, dt, every=1, t0=0.0):
        """Classical RK4 (compiled) from ``x0, v0`` at ``t0`` over ``t_end`` seconds.

        Parameters
        ----------
        x0, v0 : array_like (n + 1, 3)
            State ``(r_0, q_1 .. q_n)`` (m) and its rate (m/s) at ``t0``.
        t_end : float
            Duration (s), a multiple of ``dt * every``.
        dt : float
            Step (s), at most ``stable_dt()``.
        every : int
            Save every ``every``-th step.
        t0 : float
            Time (s) of the initial state on the orbit's clock.

        Returns
        -------
        OrbitingChainResult
        """
        x, v = self._state(x0, "x0").copy(), self._state(v0, "v0").copy()
        t_end, dt = positive("t_end", t_end), positive("dt", dt)
        every = positive_int("every", every)
        nsteps = int(round(t_end / dt))
        if nsteps < 1 or abs(nsteps * dt - t_end) > 1e-9 * t_end or nsteps % every:
            raise ValueError(f"t_end / dt = {t_end / dt:.12g} must be a positive integer "
                             f"multiple of every = {every}")
        if dt > self.stable_dt():
            raise ValueError(f"dt = {dt:g} s exceeds the RK4 stability limit "
                             f"{self.stable_dt():.6g} s (stable_dt())")
        nout = nsteps // every
        X = np.empty((nout + 1, self.n + 1, 3))
        V = np.empty_like(X)
        X[0], V[0] = x, v
        per_block = max(1, _BLOCK_STEPS // every)
        j = 0
        while j < nout:
            m = min(per_block, nout - j)
            self._block(x, v, t0 + j * every * dt, dt, m * every, every, X[j + 1: j + 1 + m],
                        V[j + 1: j + 1 + m])
            j += m
        times = t0 + dt * every * np.arange(nout + 1)
        return OrbitingChainResult(self, times, X, V, {"method": "rk4", "dt": dt,
                                                       "steps": nsteps, "saved": nout + 1})

    def _block(self, x, v, t_start, dt, steps, every, out_x, out_v):
        """``steps`` compiled RK4 steps from ``t_start``, ``R`` tabulated per half step."""
        c = self.chain
        rtab = np.ascontiguousarray(self.orbit.position(t_start + 0.5 * dt
                                                        * np.arange(2 * steps + 1)))
        step, rod = kern.rk4_orbit_block(x, v, dt, steps, every, c.masses, c.lengths, c.EA,
                                         c.compression, self.end_masses, self._a, self._b,
                                         rtab, self.orbit.mu, self.xi, self.wq,
                                         self.max_strain, out_x, out_v)
        if step >= 0:
            t = t_start + step * dt
            raise RodChainDivergence(
                f"orbiting rod chain diverged at t = {t:.6g} s (step {step} of the block, "
                f"dt = {dt:g} s): rod {rod} left (0, {1 + self.max_strain:g} l0]", t, step,
                rod)


@dataclass
class OrbitingChainResult:
    """Output of ``OrbitingChain.simulate``.

    Attributes
    ----------
    model : OrbitingChain
    t : ndarray (nt,)
        Saved times (s, the orbit's clock).
    x, v : ndarray (nt, n + 1, 3)
        States ``(r_0, q_1 .. q_n)`` and their rates.
    stats : dict
        ``method``, ``dt``, ``steps``, ``saved``.
    """

    model: OrbitingChain
    t: np.ndarray
    x: np.ndarray
    v: np.ndarray
    stats: dict = field(default_factory=dict)

    def __len__(self):
        return len(self.t)

    @property
    def joints(self):
        """Offsets of ``O_0 .. O_n`` from the reference point, (nt, n + 1, 3)."""
        return self.model.joints(self.x)

    @property
    def joint_velocities(self):
        """Velocities of ``O_0 .. O_n`` relative to the reference point, (nt, n + 1, 3)."""
        return self.model.joints(self.v)

    @property
    def centre_of_mass(self):
        """Offset of the centre of mass from the reference point, (nt, 3)."""
        return self.model.centre_of_mass(self.x)

    @property
    def tension(self):
        """Axial force of each rod (N), (nt, n)."""
        return self.model.tension(self.x)
