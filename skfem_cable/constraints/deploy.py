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

With a reel (``reel.Reel``) the length is a coordinate and its equation is Lagrange's for
the whole system: the inertial terms of ``T`` in ``l`` (``_Inertia``), the wound
material turning with the drum (``1/2 rho A (capacity - l) l'^2``) and riding with the
anchor, ``dU/dl`` of the elastic energy on the stretched mesh (``stretched.Stretched``) and
the weight's potential (``bind_weight``).  In equilibrium the reel then balances the
configurational force ``T lam - W`` of the material leaving it (``docs/deploy.md``).

References
----------
J. W. McIver, "Hamilton's principle for systems of changing mass", J. Eng. Math. 7
(1973) 249-261.  D. Hong, G. Ren, "A modeling of sliding joint on one-dimensional flexible
medium", Multibody Syst. Dyn. 26 (2011) 91-106 (ALE-ANCF).
"""

import numpy as np
import scipy.sparse as sp

from ..core.contract import OutOfDomain, Term
from .prescribed import Motion


class Deployment:
    """The free length ``l`` of a cable leaving a reel at its node 0 (see the module
    docstring); ``System.deploy`` builds it.  ``l`` is prescribed, ``length(t)``, or it is
    the coordinate of a ``reel.Reel`` (a body of the system), whose equation of motion
    then receives the tether's part.

    Parameters
    ----------
    cable : Cable
        Built straight or not, with node 0 at the anchor; its reference length ``L0`` is
        the mesh length (build it with the free length at the start to start
        stress-free).
    length : callable, float or None
        ``length(t)``: the prescribed free (unstretched) length (m), > 0; None with
        ``reel``.
    rate, acceleration : callable, optional
        Exact ``length'(t)`` and ``length''(t)`` (else central differences,
        ``constraints.time_derivatives``).
    anchor : body point, array_like (3,) or None
        The point the reel moves with, where the material not yet deployed sits, or the
        fixed point of a reel fixed in space (None: the origin).
    capacity : float or None
        Total length on the reel and deployed (m), >= the largest free length: the
        material on the reel, ``rho A (capacity - l)``, moves with ``anchor`` and, with a
        ``reel``, turns with the drum at the rim speed ``l'``.  None: the reel's content
        is not modelled (a prescribed length only).
    reel : int or None
        The global coordinate of the reel's length (``System.dofs(reel)[0]``) when the
        length is a reel's coordinate.
    """

    #: Memos of the last time asked and of the matrices (not in the fingerprint).
    caches = ("_last", "_matrices")

    def __init__(self, cable, length, rate=None, acceleration=None, anchor=None,
                 capacity=None, reel=None):
        self.cable = cable
        self.reel = reel
        self.length = None if reel is not None else \
            Motion(*(_vector(f) for f in (length, rate, acceleration)), name="length", size=1)
        self.L0 = float(cable.length)
        fixed = anchor is None or np.ndim(anchor) == 1
        self.anchor = None if fixed else anchor
        self.exit_point = np.zeros(3) if anchor is None else \
            np.asarray(anchor, dtype=float) if fixed else None
        if capacity is not None and not (np.isfinite(capacity) and capacity > 0):
            raise ValueError(f"capacity must be a length > 0 (m) or None, got {capacity!r}")
        if reel is not None and capacity is None:
            raise ValueError(f"deployment of {cable.name!r} from a reel needs the capacity "
                             "(the total tether length, m): the material on the drum is "
                             "part of the system whose length is a coordinate")
        self.capacity = capacity
        self._last = (None, None)
        self._matrices = None
        if reel is None:
            self.state(0.0)

    def state(self, t, q=None, v=None, a=None):
        """``(l, l', l'')`` at time ``t`` (prescribed) or at the coordinates, velocities
        and accelerations ``q, v, a`` (a reel's: ``v``, ``a`` None count as zero);
        ``ValueError`` if ``l`` leaves ``(0, capacity]``."""
        if self.reel is not None:
            if q is None:
                raise ValueError(f"the free length of {self.cable.name!r} is a reel's "
                                 "coordinate: give the coordinates q")
            i = self.reel
            values = tuple(0.0 if x is None else float(x[i]) for x in (q, v, a))
            return self._checked(t, values)
        if self._last[0] == t:  # every term of an evaluation asks at the same time
            return self._last[1]
        values = self._checked(t, tuple(float(self.length(t, k)[0]) for k in range(3)))
        self._last = (t, values)
        return values

    def _checked(self, t, values):
        """``values`` if the length lies in ``(0, capacity]``, else ``OutOfDomain`` (a
        ``ValueError``) naming the cable and the bound."""
        ell = values[0]
        full = self.capacity is not None and ell > self.capacity * (1 + 1e-12)
        if not ell > 0 or full:
            bound = "be > 0" if self.capacity is None else \
                f"lie in (0, {self.capacity:g}] (the capacity)"
            event = "the reel is empty: all its tether is paid out" if full else \
                "the tether is wound in completely"
            raise OutOfDomain(f"deployment of {self.cable.name!r}: length({t!r}) = {ell!r} m "
                              f"must {bound}: {event}")
        return values

    def paying_out(self, system, q, rate, t=0.0):
        """The velocities (n_dofs) of paying out at ``rate`` (m/s) from the shape at ``q``
        (time ``t``): the cable's mesh stretching about the anchor, positions at ``(rate /
        l) (r - r_P)`` and slopes (and higher derivatives) at ``(rate / l) r_x`` (``l`` the
        free length at ``t``, or ``q``'s with a reel, whose length gets ``rate``), so that
        the material of a straight tether moves at ``rate`` along it (the module
        docstring's ``v = S q' + c S_x q``); zero elsewhere.  Add it to the velocities of
        the rest of the motion (the anchor's)."""
        if self.anchor is None:
            anchor = self.exit_point
        else:
            pdofs, G = system.position_map(self.anchor)
            anchor = G @ q[pdofs]
        ell = self.state(t, q)[0]
        dofs = system.dofs(self.cable)
        nodes = np.asarray(q, dtype=float)[dofs].reshape(self.cable.n_nodes, -1)
        v = np.zeros(system.n_dofs)
        v[dofs] = (rate / ell) * (nodes - np.concatenate([anchor, np.zeros(nodes.shape[1] - 3)])
                                  ).ravel()
        if self.reel is not None:
            v[self.reel] = rate
        return v

    def stretch(self, t, q=None):
        """Stretch of the mesh ``lam = l / L0`` at ``t`` (and ``q`` for a reel)."""
        return self.state(t, q)[0] / self.L0

    @property
    def matrices(self):
        """``(M0, G0, K0)`` of the cable's coordinates (sparse), by its Gauss rule (exact
        for these polynomial integrands); assembled once per section of the cable."""
        if self._matrices is None or self._matrices[0] is not self.cable.section:
            self._matrices = (self.cable.section, self._assemble_matrices())
        return self._matrices[1]

    def _assemble_matrices(self):
        """``(M0, G0, K0)`` of the cable with its section now (``matrices``)."""
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

    def stowed(self, system):
        """``(mu, capacity, dofs, G^T G)`` of the material on the reel at a body anchor
        (``dofs`` None at a reel fixed in space), or None without a ``capacity``."""
        if self.capacity is None:
            return None
        mu = self.cable.section.mass_per_length
        if self.anchor is None:
            return mu, self.capacity, None, None
        pdofs, G = system.position_map(self.anchor)
        return mu, self.capacity, pdofs, G.T @ G

    def momentum(self, system, q, v, t):
        """The deployment's part of the generalized momentum ``dT/dv`` beyond the
        constant mass's ``M v`` (n_dofs): ``(lam - 1) M0 v + (l'/L0) G0 q`` on the cable,
        ``m_s v_P`` at the anchor and, with a reel, ``q'^T G0 q / L0 + l' q^T K0 q /
        (l L0) + m_s l'`` on its length."""
        ell, rate, _ = self.state(t, q, v)
        M0, G0, K0 = self.matrices
        dofs = system.dofs(self.cable)
        qc, vc = q[dofs], v[dofs]
        p = np.zeros(system.n_dofs)
        p[dofs] = (ell / self.L0 - 1.0) * (M0 @ vc) + (rate / self.L0) * (G0 @ qc)
        stowed = self.stowed(system)
        if stowed is not None and stowed[2] is not None:
            mu, capacity, pdofs, GG = stowed
            p[pdofs] += mu * (capacity - ell) * (GG @ v[pdofs])
        if self.reel is not None:     # a reel always has its content (capacity)
            p[self.reel] += (vc @ (G0 @ qc)) / self.L0 \
                + rate * (qc @ (K0 @ qc)) / (ell * self.L0) + stowed[0] * (stowed[1] - ell) * rate
        return p

    def bind(self, system):
        """The term of the inertia beyond the constant mass (``contract``): on the
        cable, at a body anchor, and with a reel on its length (``_Inertia``)."""
        inertia = _Inertia(self, system)
        return Term(add=inertia.add, rows=inertia.rows, cols=inertia.cols,
                    name=f"deployment {self.cable.name}")

    def bind_weight(self, system, g):
        """The term of the weight in the field ``g`` (m/s^2) of the mass the deployment
        adds to the constant mass: ``(lam - 1) M0 u_g`` on the cable (``u_g`` the
        coordinates of the uniform field ``g``) and ``m_s g`` at a body anchor, booked as
        external work.  With a reel the potential ``-lam u_g^T M0 q - m_s g . r_P``
        (``r_P`` the anchor, a body point or fixed) depends on the length too: its force
        ``u_g^T M0 q / L0 - mu g . r_P`` acts on the length (independent of the origin of
        the potential, as the material only moves from the drum to the tether), and the
        derivatives in the length are the tangent (symmetric)."""
        M0 = self.matrices[0]
        dofs = system.dofs(self.cable)
        u = np.zeros((self.cable.n_nodes, 6))
        u[:, :3] = g
        on_cable = M0 @ u.ravel()
        stowed = self.stowed(system)
        at_anchor = stowed is not None and stowed[2] is not None
        if at_anchor:
            mu, capacity, pdofs, _ = stowed
            Gg = system.position_map(self.anchor)[1].T @ g
        reel = self.reel
        rows = cols = None
        if reel is not None:
            line = np.concatenate([dofs] + ([pdofs] if at_anchor else []))
            slope = np.concatenate([on_cable / self.L0] + ([-mu * Gg] if at_anchor else []))
            rows = np.concatenate([line, np.full(line.size, reel)])
            cols = np.concatenate([np.full(line.size, reel), line])
            fixed = 0.0 if at_anchor else -self.cable.section.mass_per_length * (
                g @ self.exit_point)

        def add(ev, index):
            ell = self.state(ev.t, ev.q)[0]
            ev.f_ext[dofs] += (ell / self.L0 - 1.0) * on_cable
            if at_anchor:
                ev.f_ext[pdofs] += mu * (capacity - ell) * Gg
            if reel is not None:
                ev.f_ext[reel] += slope @ ev.q[line] + fixed
                ev.add_tangent(index, np.concatenate([slope, slope]), sign=-1.0)

        return Term(add=add, rows=rows, cols=cols,
                    name=f"weight of {self.cable.name}'s deployment")


class _Inertia:
    """The deployment's inertial force beyond the constant mass and its tangent blocks:
    the rows and columns of the term and ``add``.

    On the cable (Lagrange's equations of ``T``, module docstring):
    ``F_q = (lam - 1) M0 a + (l'/L0) Mv v + (l''/L0) G0 q - l'^2/(l L0) K0 q`` with
    ``Mv = M0 + G0 - G0^T``.  At a body anchor, the material on the reel:
    ``G^T G (m_s a_P + m_s' v_P)``.  With a reel, the equation of its length gets
    ``F_l = (a^T G0 q + v^T G0 v)/L0 + l'' k/(l L0) + 2 l' q^T K0 v/(l L0)
    - l'^2 k/(2 l^2 L0) - v^T M0 v/(2 L0)`` (``k = q^T K0 q``), the wound material's
    ``m_s l'' - mu l'^2 / 2 + mu |v_P|^2 / 2``, and ``F_q`` its derivatives in
    ``(l, l', l'')``."""

    def __init__(self, deployment, system):
        self.d = deployment
        self.dofs = system.dofs(deployment.cable)
        M0, G0, K0 = deployment.matrices
        Mv = (M0 + G0 - G0.T).tocsr()
        pattern = (M0 + G0 + K0).tocoo()
        self.blocks = [_on(pattern, m) for m in (M0, Mv, G0, K0)]
        # the products ``add`` (and with a reel ``_length``) reads, by the vector they
        # multiply, in one sparse product each (rows stacked: each row's sum as in its own
        # matrix)
        stacks = (((M0, G0.T), (G0, K0), (Mv, M0, K0, G0, G0 + G0.T))
                  if deployment.reel is not None else ((M0,), (G0, K0), (Mv,)))
        self.stacks = [sp.vstack(m).tocsr() for m in stacks]
        rows, cols = [self.dofs[pattern.row]], [self.dofs[pattern.col]]
        self.stowed = deployment.stowed(system)
        anchor = self.stowed is not None and self.stowed[2] is not None
        if anchor:
            pdofs = self.stowed[2]
            r2, c2 = np.meshgrid(pdofs, pdofs, indexing="ij")
            rows.append(r2.ravel())
            cols.append(c2.ravel())
        self.reel = deployment.reel
        if self.reel is not None:  # column and row of the length, and its diagonal
            line = np.concatenate([self.dofs] + ([pdofs] if anchor else []))
            ell = np.full(line.size + 1, self.reel)
            rows += [np.append(line, self.reel), ell]
            cols += [ell, np.append(line, self.reel)]
        self.rows, self.cols = np.concatenate(rows), np.concatenate(cols)

    def add(self, ev, index):
        if not ev.dynamic:
            return
        d = self.d
        L0 = d.L0
        ell, rate, acc = d.state(ev.t, ev.q, ev.v, ev.a)
        lam, nu, kappa = ell / L0, rate / L0, rate * rate / (ell * L0)
        q, v, a = ev.q[self.dofs], ev.v[self.dofs], ev.a[self.dofs]
        products = [(m @ x).reshape(-1, q.size) for m, x in zip(self.stacks, (a, q, v))]
        (M0a, *_), (G0q, K0q), (Mvv, *_) = products
        ev.f_ext[self.dofs] -= (lam - 1.0) * M0a + nu * Mvv + (acc / L0) * G0q - kappa * K0q
        b = self.blocks
        da = [(lam - 1.0) * b[0]]
        dv = [nu * b[1]]
        dq = [(acc / L0) * b[2] - kappa * b[3]]
        if self.stowed is not None and self.stowed[2] is not None:
            mu, capacity, pdofs, GG = self.stowed
            m_s = mu * (capacity - ell)
            ev.f_ext[pdofs] -= GG @ (m_s * ev.a[pdofs] - mu * rate * ev.v[pdofs])
            da.append(m_s * GG.ravel())
            dv.append(-mu * rate * GG.ravel())
            dq.append(np.zeros(GG.size))
        if self.reel is not None:
            self._length(ev, (ell, rate, acc), (q, v, a), products, (dq, dv, da))
        if ev.want_tangent:
            ev.add_tangent(index, np.concatenate(dq), np.concatenate(dv),
                           da=np.concatenate(da))

    def _length(self, ev, lengths, cable, products, blocks):
        """The reel's equation and the coupling blocks (appended to ``blocks = (dq, dv,
        da)`` in the order of the rows: the column of the length, then its row), of the
        ``products`` of ``self.stacks`` with ``cable = (q, v, a)``."""
        ell, rate, acc = lengths
        q, v, a = cable
        (M0a, G0Ta), (G0q, K0q), (Mvv, M0v, K0v, G0v, Gsv) = products
        dq, dv, da = blocks
        L0 = self.d.L0
        k, qKv = q @ K0q, q @ K0v
        lL = ell * L0
        force = (a @ G0q + v @ G0v) / L0 + acc * k / lL + 2 * rate * qKv / lL \
            - 0.5 * rate**2 * k / (ell * lL) - 0.5 * (v @ M0v) / L0
        # the column: derivatives of F_q (and of the anchor's force) in l, l', l''
        col_q = [M0a / L0 + rate**2 / (ell * lL) * K0q]
        col_v = [Mvv / L0 - 2 * rate / lL * K0q]
        col_a = [G0q / L0]
        # the row: derivatives of F_l in q, v, a
        row_q = [G0Ta / L0 + 2 * acc / lL * K0q + 2 * rate / lL * K0v
                 - rate**2 / (ell * lL) * K0q]
        row_v = [Gsv / L0 + 2 * rate / lL * K0q - M0v / L0]
        row_a = [G0q / L0]
        diag_q = -acc * k / (ell * lL) - 2 * rate * qKv / (ell * lL) + rate**2 * k / (ell**2 * lL)
        diag_v = 2 * qKv / lL - rate * k / (ell * lL)
        diag_a = k / lL
        mu, capacity, pdofs, GG = self.stowed     # a reel always has its content
        force += mu * (capacity - ell) * acc - 0.5 * mu * rate**2
        diag_q -= mu * acc
        diag_v -= mu * rate
        diag_a += mu * (capacity - ell)
        if pdofs is not None:
            vP, aP = ev.v[pdofs], ev.a[pdofs]
            force += 0.5 * mu * (vP @ (GG @ vP))
            col_q.append(-mu * (GG @ aP))
            col_v.append(-mu * (GG @ vP))
            col_a.append(np.zeros(pdofs.size))
            row_q.append(np.zeros(pdofs.size))
            row_v.append(mu * (GG @ vP))
            row_a.append(np.zeros(pdofs.size))
        ev.f_ext[self.reel] -= force
        dq += col_q + [[0.0]] + row_q + [[diag_q]]
        dv += col_v + [[0.0]] + row_v + [[diag_v]]
        da += col_a + [[0.0]] + row_a + [[diag_a]]


def constant_rate(start, rate):
    """``(length, rate, acceleration)`` of a free length ``start + rate t`` (m, m/s)."""
    return (lambda t: start + rate * t, lambda t: rate, lambda t: 0.0)


def smooth_profile(start, end, duration):
    """``(length, rate, acceleration)`` of a free length going from ``start`` to ``end``
    (m) in ``duration`` (s) with zero rate and acceleration at both ends (the quintic
    ``10 s^3 - 15 s^4 + 6 s^5`` of ``s = t / duration``), constant outside.

    Examples
    --------
    >>> from skfem_cable.constraints.deploy import smooth_profile
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
    """Mesh coordinates ``x`` of the cable's Gauss points (ne, nq)."""
    return cable.mesh.p[0, :-1, None] + cable.h[:, None] * cable.xi[None, :]


def _assemble(cable, blocks):
    """The sparse matrix (cable coordinates) of element blocks ``(ne, nf, nf)`` of the
    element's functions, on every component: ``K[3A+i, 3B+i] = blocks[A, B]``."""
    ne, nf, _ = blocks.shape
    full = np.einsum("eAB,ij->eAiBj", blocks, np.eye(3)).reshape(ne, 3 * nf, 3 * nf)
    edofs = cable.element_dofs
    rows = np.broadcast_to(edofs[:, :, None], full.shape).ravel()
    cols = np.broadcast_to(edofs[:, None, :], full.shape).ravel()
    n = cable.n_dofs
    return sp.csr_matrix((full.ravel(), (rows, cols)), shape=(n, n))


def _on(pattern, matrix):
    """The values of ``matrix`` at the entries ``(row, col)`` of the COO ``pattern``."""
    return np.asarray(matrix.tocsr()[pattern.row, pattern.col]).ravel()
