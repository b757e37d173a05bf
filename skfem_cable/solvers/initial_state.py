"""The initial state of the generalized-alpha integrator (``InitialState``, a base of
``GeneralizedAlpha``): a consistent start (velocities projected on the constraints,
accelerations and multipliers from Eq. 3), a rebase of the state (``shift``), and the
pseudo-acceleration fitted to the step (Arnold & Bruls 2007)."""

import numpy as np
import scipy.sparse as sp

from ..core.linalg import SingularMatrixError
from ..kernels.books import csr_product


def _dynamic_block(lay):
    """``(indptr, indices, entries)``: the CSR pattern of the KKT matrix's block of the
    coordinates (``[:n, :n]``), and the places of its values in the KKT values, in the
    order of its rows and columns (scipy's slice of the matrix, without its making)."""
    n = lay.N - lay.n_c
    end = lay.indptr[n]
    kept = lay.indices[:end] < n
    indptr = np.concatenate([[0], np.cumsum(kept)])[lay.indptr[: n + 1]]
    entries = np.flatnonzero(kept)
    return indptr.astype(np.int64), lay.indices[entries].astype(np.int64), entries


class InitialState:
    """``initialize``, ``shift``, ``_consistent`` and ``_fit_abar``; read and set the
    integrator's state."""

    def initialize(self, q, v, t):
        """Consistent initial state: checks ``C(q, t) = 0``, projects ``v`` onto
        ``C_q v = -C_t`` (mass-orthogonally), and solves for ``a`` and ``lambda`` from
        Eq. 3 with ``C_q a = -((C_q v)_q v + 2 C_qt v + C_tt)`` (or, with
        ``initial_acceleration="zero"``, takes ``a = 0`` and ``lambda = 0``)."""
        system, n = self.system, self.n
        C = system.constraint_values(q, t, layout=self.lay)
        if C.size and np.max(np.abs(C)) > 1e-8 * self.L_ref:
            k = int(np.argmax(np.abs(C)))
            raise ValueError(f"initial positions violate {system.describe_dof(n + k)} by "
                             f"{C[k]:.3e}; start from positions that satisfy the constraints")
        v, self.a, self.lam = self._consistent(q, v, t)
        if self.zero_start:
            self.a, self.lam = np.zeros_like(self.a), np.zeros_like(self.lam)
        self.h_factored = None
        self.t, self.q, self.v = float(t), q.copy(), v.copy()
        self.abar, self.abar_h = self.a.copy(), None  # set by the first step (_fit_abar)
        self.a_prev = self.h_prev = self.da_prev = self.h_prev2 = None
        # the books open with the forces of the consistent state: the constraint forces
        # of its multipliers and the inertia terms at its accelerations
        _, info = system.evaluate(q, v, t, self.lam, scale=self.mbar, a=self.a,
                                  layout=self.lay)
        self.__dict__.update(self._opened(info))
        self.iterations, self.newton_rate = 0, 1.0
        self.guard.reset(self.t, self.energies())

    def shift(self, dq, dv, da):
        """Change the frame of the state at the current time: coordinates ``q + dq``,
        velocities ``v + dv``, accelerations ``a + da`` (Encke's rectification moves the
        reference point, ``solvers.rectify``); the pseudo-acceleration ``abar`` and the
        last step's ``a`` move with ``a``, so the algorithm's memory of the motion, which
        damps the unresolved modes, is kept.  (Starting again from the shifted state as
        from an initial one re-excited a stiff tether's axial modes for tens of steps
        after every rebase: the consistent accelerations differ from the algorithm's by
        its damping of those modes.)  The iteration matrix is made again at the next
        step.  The books stay open: the jump of the kinetic, stored and potential energy
        that a change of frame makes is booked as external work, so the balance stays
        closed, and the guard takes the new state as its reference."""
        before = self.energies()
        self.q, self.v, self.a = self.q + dq, self.v + dv, self.a + da
        self.abar = self.abar + da
        if self.a_prev is not None:
            self.a_prev = self.a_prev + da
        self.h_factored = None
        _, info = self.system.evaluate(self.q, self.v, self.t, self.lam, scale=self.mbar,
                                       a=self.a, layout=self.lay)
        books = self._opened(info)
        after = self._energies(books)
        jump = sum(after[k] - before[k] for k in ("kinetic", "axial", "bending", "potential"))
        books.update(dissipated=self.dissipated, external_work=self.external_work + jump)
        self.__dict__.update(books)
        self.guard.reset(self.t, self.energies())

    def _consistent(self, q, v, t):
        """``(v, a, lambda)`` of the state ``(q, v, t)``: ``v`` projected onto
        ``C_q v = -C_t`` (mass-orthogonally, in the whole mass matrix: the constant one and
        a deployment's inertia, whose reel row and column move the length with the
        tether), ``a`` and ``lambda`` from Eq. 3 with ``C_q a = -((C_q v)_q v + 2 C_qt v +
        C_tt)``."""
        system, lay, n = self.system, self.lay, self.n
        data = self.base.copy()
        rest = np.zeros(n)  # accelerations: the unknowns of this solve
        system.evaluate(q, v, t, np.zeros(lay.n_c), cK=0.0, cC=0.0, scale=self.mbar,
                        data=data, a=rest, cM=1.0, layout=lay)
        rhs = np.zeros(lay.N)
        indptr, indices, entries = lay.derived("dynamic block", lambda: _dynamic_block(lay))
        csr_product(indptr, indices, data[entries], v, rhs)  # the KKT matrix's [:n, :n] v
        try:
            self.solver.factor(data)
        except SingularMatrixError as err:
            kkt = sp.csr_matrix((data, lay.indices, lay.indptr), shape=(lay.N, lay.N))
            raise self._singular_start(t, err.index, kkt[n:, :n]) from None
        self.stats["factorizations"] += 1
        rhs[n:] = -self.mbar * system.constraint_velocity_term(q, t, lay)
        v = self.solver.solve(rhs)[:n]
        r, _ = system.evaluate(q, v, t, np.zeros(lay.n_c), scale=self.mbar, a=rest, layout=lay)
        rhs = -r
        rhs[n:] = -self.mbar * system.constraint_accel_term(q, v, t, lay)
        sol = self.solver.solve(rhs)
        return v, sol[:n], self.mbar * sol[n:]

    def _fit_abar(self, h):
        """Make the pseudo-acceleration fit a step ``h``: ``abar_n = a(t_n + (alpha_m -
        alpha_f) h) + O(h^2)`` (Arnold & Bruls 2007), which the recursion keeps while the
        step is constant.  After a change of step the offset ``abar_n - a_n`` is scaled by
        ``h / h_old``.  At a start, a trial step from ``abar_0 = a_0`` gives ``a_1`` and
        the step is taken again from ``abar_0 = a_0 + (alpha_m - alpha_f) (a_1 - a_0)``
        (``a_1 - a_0 = h da/dt + O(h^2)`` where the motion is resolved, and bounded by the
        integrator's own damping where it is not; a difference quotient of the
        consistent accelerations would amplify the stiff modes and their round-off).
        With ``abar_0 = a_0`` a spinning body's kinetic energy dropped by about ``0.36
        (omega h)^2`` of itself in the first steps, and moved again at a shortened last
        step."""
        if self.abar_h is None and not self.fit_start:  # a plain start: abar_0 = a_0
            self.abar_h = h
        if self.abar_h is not None:
            if abs(h - self.abar_h) > 1e-9 * h:
                self.abar = self.a + (h / self.abar_h) * (self.abar - self.a)
                self.abar_h = h
            return
        start, steps = self._snapshot(), self.stats["steps"]
        ok, _ = self._try_step(h, fresh=True, full=self.newton == "full")
        a1 = self.a
        self.restore(start)
        self.stats["steps"] = steps
        if ok:
            self.abar = self.a + (self.alpha_m - self.alpha_f) * (a1 - self.a)
            self.abar_h = h
