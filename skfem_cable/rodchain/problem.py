"""The loads and the anchor motion of a rod chain: the right-hand side of Eq. 21, the
generalized forces (Eqs. 14-16) and the power of the loads that have no potential.

``Problem`` binds a ``RodChain`` to gravity, a tip force, a uniform or callable line load
and a fixed or moving anchor; ``circular_anchor`` is a ready-made anchor motion.
"""

import numpy as np

from ..kernels import rodchain as kern
from .checks import positive, vector3


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
    radius = positive("radius", radius)
    omega = float(omega)
    center = vector3("center", center)
    e3 = vector3("normal", normal)
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


def _anchor_motion(anchor):
    """``anchor(t) -> (position, velocity, acceleration)`` of ``O_0`` at the times ``t``
    (k,), each (k, 3), from None (the origin), a point or a checked callable."""
    if anchor is None:
        anchor = np.zeros(3)
    if not callable(anchor):
        point = vector3("anchor", anchor)

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


class Problem:
    """A chain with its loads and anchor motion: the right-hand side of Eq. 21.

    Parameters are those of ``RodChain.simulate``.  Attributes: ``chain``, ``gravity``,
    ``tip`` (the tip force), ``w`` (the uniform line load), ``line_load``,
    ``line_callable``, ``moving`` (the anchor is a motion), ``anchor(t)``, ``max_strain``.
    """

    def __init__(self, chain, gravity=(0.0, 0.0, 0.0), line_load=None, tip_force=None,
                 anchor=None, quadrature=3, max_strain=1.0):
        self.chain = chain
        self.gravity = vector3("gravity", gravity)
        self.tip = np.zeros(3) if tip_force is None else vector3("tip_force", tip_force)
        self.max_strain = float(max_strain)
        if not self.max_strain > 0:
            raise ValueError(f"max_strain must be > 0 (inf allowed), got {max_strain!r}")
        self.line_callable = callable(line_load)
        self.w = np.zeros(3)
        if line_load is not None and not self.line_callable:
            self.w = vector3("line_load", line_load)
        self.line_load = line_load
        if (isinstance(quadrature, bool) or not isinstance(quadrature, int | np.integer)
                or not 1 <= quadrature <= 20):
            raise ValueError(f"quadrature must be an integer in [1, 20], got {quadrature!r}")
        x, wq = np.polynomial.legendre.leggauss(int(quadrature))
        self.xi, self.wq = 0.5 * (x + 1.0), 0.5 * wq
        self.moving = callable(anchor)
        self.anchor = _anchor_motion(anchor)
        a0 = self.anchor(np.zeros(1))[2]  # validate now rather than mid-integration
        #: The loads of every time when they are constant (a fixed anchor, no callable
        #: line load), else None: ``_loads`` then costs nothing per call.
        self._constant = None
        if not (self.moving or self.line_callable):
            zero = np.zeros((chain.n, 3))
            self._constant = (self.gravity - a0[0], zero, zero)

    @property
    def does_work(self):
        """True when a load without potential acts: a line load or a moving anchor (their
        work is the run's ``external_work``)."""
        return self.moving or self.line_callable or bool(np.any(self.w != 0))

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

    def acceleration(self, t, q, v, out=None):
        """``(q'', flag)``: Eq. 21 at time ``t``; ``flag`` is ``load_vector``'s rod check.
        ``out``: an array (n, 3) to write ``q''`` into (a new one by default)."""
        c = self.chain
        g, Fx, Fxs = self._loads(t, q, v)
        out = np.empty_like(q) if out is None else out
        bad = kern.derivative(q, c.masses, c.lengths, c.EA, c.compression, c._a, c._b, g,
                              self.w, self.tip, Fx, Fxs, self.max_strain, np.empty_like(q), out)
        return out, bad

    def generalized_forces(self, t, q, v):
        """External generalized forces ``Q`` (Eq. 16 plus the anchor term), (n, 3)."""
        c = self.chain
        g, Fx, Fxs = self._loads(t, q, v)
        out = np.empty_like(q)
        kern.load_vector(q, c.masses, c.lengths, c.EA, c.compression, False, g, self.w,
                         self.tip, Fx, Fxs, np.inf, out)
        return out

    def _loads(self, t, q, v):
        """Gravity in the anchor's frame ``g - a_0(t)`` and the line-load terms
        ``(F, F*)`` of ``extra_forces`` at time ``t``."""
        if self._constant is not None:
            return self._constant
        r0, u0, a0 = self.anchor(np.array([t]))
        return (self.gravity - a0[0], *self.extra_forces(t, q, v, r0[0], u0[0]))

    def line_resultants(self, t, q, v):
        """Resultant ``sum_i F_i`` (3,) of the line loads (Eq. 14) on the chain."""
        r0, u0, _ = self.anchor(np.array([t]))
        F, _ = self.extra_forces(t, q, v, r0[0], u0[0])
        return F.sum(axis=0) + self.w * np.linalg.norm(q, axis=1).sum()

    def power(self, t, Q, V):
        """Power (W) of the loads without potential at the times ``t`` (k,) of the rod
        vectors and rates ``Q``, ``V`` (k, n, 3): the line loads and the anchor (gravity
        and the tip force are in the potential energy).

        A line load delivers ``(sum_i F_i) . u_0 + sum_i Q_i . q_i'`` (Eqs. 14-16 with the
        velocity ``u_0 + sum_{j<i} q_j' + s q_i'`` of a material point); the anchor force
        ``F_0`` (``RodChainResult.anchor_force``) delivers ``F_0 . u_0``.  With the momentum
        balance for ``F_0`` the line-load resultants cancel and the sum is
        ``u_0 . (m (a_0 - g) + sum_i c_i q_i'' - P) + sum_i Q_i . q_i'`` (``Q`` of the line
        loads alone).  The uniform load is evaluated for all times at once; a callable
        load and a moving anchor (which needs the accelerations ``q''``) time by time.
        """
        t = np.atleast_1d(np.asarray(t, dtype=float))
        p = np.zeros(t.size)
        if not self.does_work:
            return p
        c = self.chain
        if np.any(self.w != 0):  # Q_i = w (l_i / 2 + sum_{j>i} l_j)
            l = np.linalg.norm(Q, axis=-1)
            moment = 0.5 * l + (np.cumsum(l[:, ::-1], axis=1)[:, ::-1] - l)
            p += np.einsum("ki,kid,d->k", moment, V, self.w)
        r0, u0, a0 = self.anchor(t)
        for k in range(t.size):
            if self.line_callable:
                Fx, Fxs = self.extra_forces(t[k], Q[k], V[k], r0[k], u0[k])
                Qx = np.empty_like(Q[k])
                kern.load_vector(Q[k], c.masses, c.lengths, c.EA, c.compression, False,
                                 np.zeros(3), np.zeros(3), np.zeros(3), Fx, Fxs, np.inf, Qx)
                p[k] += np.sum(Qx * V[k])
            if self.moving:
                a = self.acceleration(t[k], Q[k], V[k])[0]
                p[k] += u0[k] @ (c.total_mass * (a0[k] - self.gravity)
                                 + c.first_moments @ a - self.tip)
        return p
