"""Deploying and retrieving a cable through an anchor: a variable-length cable whose mesh
stretches with the free length (``System.deploy``).

Formulation
-----------
The free part of a tether of length ``l(t)`` (unstretched material length) is the material
interval ``s in [L_tot - l(t), L_tot]``: material leaves (enters) the reel at the anchor and
the tip is a material point.  The cable keeps its nodes: they are points of a *mesh* that
stretches uniformly with the free length (an arbitrary Lagrangian-Eulerian description in
which the material coordinates of the nodes follow ``l(t)``, as in the variable-length
ALE-ANCF elements of the literature, but slaved to the length instead of being unknowns, so
that the coordinates and the sparsity pattern stay fixed and no element is inserted or
removed).  With ``x in [0, L0]`` the mesh coordinate of the cable as built (``L0`` its
length, ``x = 0`` at the anchor) and ``lam(t) = l(t) / L0`` the stretch of the mesh, a
material point sits at ``x`` with ``dx/dt = c(x, t) = (l'/l) (L0 - x)`` (zero at the tip,
``l' / lam`` at the anchor).  The coordinates are the positions and the mesh slopes
``r_x = lam r_s`` of the nodes, so that the shape functions of the cable as built still
interpolate the current shape (``cable.interpolate`` gives positions at mesh coordinates).

The material velocity is ``v = S q' + c S_x q``; the kinetic energy of the free part,
``T = 1/2 int rho A |v|^2 lam dx``, is

    T = 1/2 lam q'^T M0 q' + (l'/L0) q'^T G0 q + 1/2 l'^2 / (l L0) q^T K0 q,

with the constant matrices ``M0 = int rho A S^T S dx`` (the cable's mass matrix),
``G0 = int rho A (L0 - x) S^T S_x dx`` and ``K0 = int rho A (L0 - x)^2 S_x^T S_x dx``.
Lagrange's equations give the inertial force

    F_in = lam M0 a + (l'/L0) (M0 + G0 - G0^T) v + (l''/L0 G0 - l'^2/(l L0) K0) q,

linear in ``(q, v, a)`` with coefficients that depend on time only.  The material
crossing the anchor carries momentum and energy: Hamilton's principle for a domain with
inflow (McIver 1973) adds a boundary term ``rho A (v . dr) (flux)`` at the anchor, which
vanishes because the anchor's position is prescribed (``dr = 0``) — the anchor's reaction
(the pin's multipliers) carries the tension and the momentum flux.  The elastic forces use
the material derivatives ``r_s = r_x / lam``, ``r_ss = r_xx / lam^2`` and the material
length element ``lam dx``: the cable's law kernel runs on its tables rescaled at each time
(``Cable.bind``).  The material still on the reel, ``rho A (capacity - l)``, moves with
the anchor (a point of a body such as a hub): its kinetic energy ``1/2 m_s(t) |v_P|^2``
adds ``m_s a_P + m_s' v_P`` at the anchor (the reel's own spin is not modelled).

References
----------
J. W. McIver, "Hamilton's principle for systems of changing mass", J. Eng. Math. 7
(1973) 249-261.  D. Hong, G. Ren, "A modeling of sliding joint on one-dimensional flexible
medium", Multibody Syst. Dyn. 26 (2011) 91-106 (ALE-ANCF).
"""

from functools import cached_property

import numpy as np
import scipy.sparse as sp

from .constraints import Motion
from .contract import Term


class Deployment:
    """The free length ``l(t)`` of a cable leaving a reel at its node 0 (see the module
    docstring); ``System.deploy`` builds it.

    Parameters
    ----------
    cable : Cable
        Built straight or not, with node 0 at the anchor; its reference length ``L0`` is
        the mesh length (build it with the free length at the start, ``length(t0)``, to
        start stress-free).
    length : callable or float
        ``length(t)``: the free (unstretched) length (m), > 0.
    rate, acceleration : callable, optional
        Exact ``length'(t)`` and ``length''(t)`` (else central differences,
        ``constraints.time_derivatives``).
    anchor : body point or None
        The point the reel moves with, where the material not yet deployed sits (None:
        a reel fixed in space).
    capacity : float or None
        Total length on the reel and deployed (m), >= the largest free length: the
        material on the reel, ``rho A (capacity - l)``, moves with ``anchor``.  None:
        the reel's content is not modelled (a reel fixed in space, or a hub whose mass
        includes it).
    """

    def __init__(self, cable, length, rate=None, acceleration=None, anchor=None,
                 capacity=None):
        self.cable = cable
        self.length = Motion(*(_vector(f) for f in (length, rate, acceleration)),
                             name="length", size=1)
        self.L0 = float(cable.length)
        self.anchor = anchor
        if capacity is not None and not (np.isfinite(capacity) and capacity > 0):
            raise ValueError(f"capacity must be a length > 0 (m) or None, got {capacity!r}")
        self.capacity = capacity
        self._last = (None, None)
        self.state(0.0)

    def state(self, t):
        """``(l, l', l'')`` at ``t``; ``ValueError`` if ``l`` leaves ``(0, capacity]``."""
        if self._last[0] == t:  # every term of an evaluation asks at the same time
            return self._last[1]
        ell, rate, acc = (float(self.length(t, k)[0]) for k in range(3))
        if not ell > 0 or (self.capacity is not None and ell > self.capacity * (1 + 1e-12)):
            bound = "be > 0" if self.capacity is None else \
                f"lie in (0, {self.capacity:g}] (the capacity)"
            raise ValueError(f"deployment of {self.cable.name!r}: length({t!r}) = {ell!r} m "
                             f"must {bound}")
        self._last = (t, (ell, rate, acc))
        return ell, rate, acc

    def stretch(self, t):
        """Stretch of the mesh ``lam = l(t) / L0``."""
        return self.state(t)[0] / self.L0

    @cached_property
    def matrices(self):
        """``(M0, G0, K0)`` of the cable's coordinates (sparse), by its Gauss rule (exact
        for these polynomial integrands)."""
        cable = self.cable
        mu = cable.section.mass_per_length
        x = _gauss_points(cable)
        w = cable.weights
        S, Sx = cable.S, cable.Sx
        arm = self.L0 - x
        blocks = (np.einsum("eg,egA,egB->eAB", mu * w, S, S),
                  np.einsum("eg,egA,egB->eAB", mu * w * arm, S, Sx),
                  np.einsum("eg,egA,egB->eAB", mu * w * arm**2, Sx, Sx))
        return tuple(_assemble(cable, b) for b in blocks)

    def momentum(self, system, q, v, t):
        """The deployment's part of the generalized momentum ``dT/dv`` beyond the
        constant mass's ``M v`` (n_dofs): ``(lam - 1) M0 v + (l'/L0) G0 q`` on the cable
        and ``m_s v_P`` at the anchor."""
        ell, rate, _ = self.state(t)
        M0, G0, _ = self.matrices
        dofs = system.dofs(self.cable)
        p = np.zeros(system.n_dofs)
        p[dofs] = (ell / self.L0 - 1.0) * (M0 @ v[dofs]) + (rate / self.L0) * (G0 @ q[dofs])
        if self.capacity is not None and self.anchor is not None:
            pdofs, G = system.position_map(self.anchor)
            m_s = self.cable.section.mass_per_length * (self.capacity - ell)
            p[pdofs] += m_s * (G.T @ (G @ v[pdofs]))
        return p

    def weight(self, system, g, t):
        """The generalized weight (n_dofs) in the field ``g`` (m/s^2) of the mass the
        deployment adds to the constant mass at ``t``: ``(lam - 1) M0 u_g`` on the cable
        (``u_g`` the coordinates of the uniform field ``g``) and ``m_s(t) g`` at the
        anchor."""
        ell = self.state(t)[0]
        M0 = self.matrices[0]
        dofs = system.dofs(self.cable)
        u = np.zeros((self.cable.n_nodes, 6))
        u[:, :3] = g
        f = np.zeros(system.n_dofs)
        f[dofs] = (ell / self.L0 - 1.0) * (M0 @ u.ravel())
        if self.capacity is not None and self.anchor is not None:
            pdofs, G = system.position_map(self.anchor)
            f[pdofs] += self.cable.section.mass_per_length * (self.capacity - ell) * (G.T @ g)
        return f

    def bind(self, system):
        cable = self.cable
        dofs = system.dofs(cable)
        M0, G0, K0 = self.matrices
        Mv = (M0 + G0 - G0.T).tocsr()
        pattern = (M0 + G0 + K0).tocoo()
        rows, cols = dofs[pattern.row], dofs[pattern.col]
        blocks = [_on(pattern, m) for m in (M0, Mv, G0, K0)]
        stowed = None
        if self.capacity is not None and self.anchor is not None:
            pdofs, G = system.position_map(self.anchor)
            GG = G.T @ G
            stowed = (pdofs, GG)
            r2, c2 = np.meshgrid(pdofs, pdofs, indexing="ij")
            rows, cols = np.concatenate([rows, r2.ravel()]), np.concatenate([cols, c2.ravel()])
        mu = cable.section.mass_per_length
        L0 = self.L0

        def add(ev, index):
            if not ev.dynamic:
                return
            ell, rate, acc = self.state(ev.t)
            lam, nu, kappa = ell / L0, rate / L0, rate * rate / (ell * L0)
            q, v, a = ev.q[dofs], ev.v[dofs], ev.a[dofs]
            force = (lam - 1.0) * (M0 @ a) + nu * (Mv @ v) + (acc / L0) * (G0 @ q) \
                - kappa * (K0 @ q)
            ev.f_ext[dofs] -= force
            da = [(lam - 1.0) * blocks[0]]
            dv = [nu * blocks[1]]
            dq = [(acc / L0) * blocks[2] - kappa * blocks[3]]
            if stowed is not None:
                pdofs, GG = stowed
                m_s, dm_s = mu * (self.capacity - ell), -mu * rate
                ev.f_ext[pdofs] -= GG @ (m_s * ev.a[pdofs] + dm_s * ev.v[pdofs])
                da.append(m_s * GG.ravel())
                dv.append(dm_s * GG.ravel())
                dq.append(np.zeros(GG.size))
            if ev.want_tangent:
                ev.add_tangent(index, np.concatenate(dq), np.concatenate(dv),
                               da=np.concatenate(da))

        return Term(add=add, rows=rows, cols=cols, name=f"deployment {cable.name}")


def constant_rate(start, rate):
    """``(length, rate, acceleration)`` of a free length ``start + rate t`` (m, m/s)."""
    return (lambda t: start + rate * t, lambda t: rate, lambda t: 0.0)


def smooth_profile(start, end, duration):
    """``(length, rate, acceleration)`` of a free length going from ``start`` to ``end``
    (m) in ``duration`` (s) with zero rate and acceleration at both ends (the quintic
    ``10 s^3 - 15 s^4 + 6 s^5`` of ``s = t / duration``), constant outside.

    Examples
    --------
    >>> from skfem_cable.deploy import smooth_profile
    >>> length, rate, acceleration = smooth_profile(10.0, 50.0, 60.0)
    >>> float(length(30.0)), float(rate(0.0)), float(acceleration(60.0))
    (30.0, 0.0, 0.0)
    """
    if not duration > 0:
        raise ValueError(f"duration must be > 0 (s), got {duration!r}")
    change = end - start

    def s(t):
        return np.clip(t / duration, 0.0, 1.0)

    return (lambda t: start + change * s(t) ** 3 * (10 - 15 * s(t) + 6 * s(t) ** 2),
            lambda t: change / duration * 30 * s(t) ** 2 * (1 - s(t)) ** 2,
            lambda t: change / duration**2 * 60 * s(t) * (1 - s(t)) * (1 - 2 * s(t)))


def _vector(fn):
    """A scalar function of time (or a number, or None) as ``Motion`` takes it."""
    if fn is None or not callable(fn):
        return None if fn is None else np.atleast_1d(np.asarray(fn, dtype=float))
    return lambda t: np.atleast_1d(np.asarray(fn(t), dtype=float))


def _gauss_points(cable):
    """Mesh coordinates ``x`` of the cable's Gauss points (ne, nq): the Hermite
    interpolation of the nodes' reference arc lengths (exact: ``x`` is linear)."""
    x = cable.mesh.p[0]
    xe = np.stack([x[:-1], np.ones_like(cable.h), x[1:], np.ones_like(cable.h)], axis=1)
    return np.einsum("egA,eA->eg", cable.S, xe)


def _assemble(cable, blocks):
    """The sparse matrix (cable coordinates) of element blocks ``(ne, 4, 4)`` of the
    Hermite functions, on every component: ``K[3A+i, 3B+i] = blocks[A, B]``."""
    ne = blocks.shape[0]
    full = np.einsum("eAB,ij->eAiBj", blocks, np.eye(3)).reshape(ne, 12, 12)
    edofs = cable.element_dofs
    rows = np.broadcast_to(edofs[:, :, None], full.shape).ravel()
    cols = np.broadcast_to(edofs[:, None, :], full.shape).ravel()
    n = cable.n_dofs
    return sp.csr_matrix((full.ravel(), (rows, cols)), shape=(n, n))


def _on(pattern, matrix):
    """The values of ``matrix`` at the entries ``(row, col)`` of the COO ``pattern``."""
    return np.asarray(matrix.tocsr()[pattern.row, pattern.col]).ravel()
