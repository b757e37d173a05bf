"""Static equilibrium: Newton's method with exact tangent, load stepping with automatic
bisection, and a backtracking line search."""

import numpy as np
import scipy.sparse as sp

from ..constraints.dependence import dependence_message, dependent_constraints
from ..core.linalg import PatternSolver, SingularMatrixError
from ..core.protocols import IntegrableSystem
from ..model.state import State
from .static_states import admissible, hanging_start, unfolded, without_bending


class StaticConvergenceError(RuntimeError):
    """Newton did not converge; ``last_converged`` holds the last equilibrium reached."""

    def __init__(self, message, last_converged):
        super().__init__(message)
        self.last_converged = last_converged


def constraint_scale(system, q, lam, layout=None):
    """Scale of the constraint rows: the mean stiffness diagonal, so that both blocks of the
    KKT matrix have comparable magnitude (``layout``: a solver's, else the system as it is
    now, ``System.current_layout``)."""
    lay = system.current_layout() if layout is None else layout
    data = np.zeros(lay.nnz)
    system.evaluate(q, None, 0.0, lam, data=data, layout=lay)
    d = np.abs(lay.matrix(data).diagonal()[: system.n_dofs])
    s = float(np.mean(d)) if d.size else 1.0
    return s if s > 0 and np.isfinite(s) else 1.0


def line_search_alpha(residual, merit, q, lam, dx, r0, m0, factor, scale, max_steps=3):
    """Step length along the Newton direction: the full step unless it multiplies the scaled
    residual by more than 10 (or makes it non-finite); then safeguarded secant steps on the
    projected residual ``s(alpha) = dx . r(x + alpha dx)``, whose root is a stationary point
    of the energy along ``dx`` for conservative problems."""
    n = len(q)
    r1, f1 = residual(q + dx[:n], lam + scale * dx[n:], factor)
    m1 = merit(r1, f1)
    if np.isfinite(m1) and m1 <= 10.0 * m0:
        return 1.0
    s0 = dx @ r0
    a_lo, s_lo, alpha = 0.0, s0, 1.0
    s1 = dx @ r1
    for _ in range(max_steps):
        if not np.isfinite(s1):
            alpha *= 0.25
        elif abs(s1) <= 0.5 * abs(s0) or s1 == s_lo:
            return alpha
        else:
            alpha_new = a_lo - s_lo * (alpha - a_lo) / (s1 - s_lo)
            a_lo, s_lo = alpha, s1
            alpha = float(np.clip(alpha_new, 0.1, 1.0))
        r, _ = residual(q + alpha * dx[:n], lam + alpha * scale * dx[n:], factor)
        s1 = dx @ r
    return alpha


def solve_static(system: IntegrableSystem, load_steps=1, tol=1e-10, max_iter=30, initial=None,
                 line_search=True, max_bisections=8, method="auto",
                 return_last_converged=False, relax=True):
    """Solve ``f_int(q) - f_ext(q) + C_q^T lambda = 0``, ``C(q) = 0``.

    Parameters
    ----------
    system : System
    load_steps : int
        Number of equal load increments (the load factor goes from 1/load_steps to 1); a
        step that fails is bisected up to ``max_bisections`` times.
    tol : float
        Convergence: ``|r_q| <= tol * f_ref`` and ``|C| <= tol * L_ref`` with ``f_ref`` the
        largest of the external, internal and constraint forces and ``L_ref`` the system size;
        or a Newton correction below ``tol * L_ref``; or a correction below
        ``sqrt(tol) * L_ref`` that no longer contracts.  The last two detect the round-off
        floor: in absolute coordinates the strain carries an error of about ``1e-16 L/h``,
        so the residual of a very stiff cable stalls near ``EA * 1e-16 L/h`` before
        reaching ``tol`` at small loads.
    max_iter : int
        Newton iterations per load step.
    initial : State, optional
        Starting configuration (default: the bodies' initial coordinates, a cable whose
        ends the constraints hold closer than its length hanging instead: see Notes).
    line_search : bool
        Shorten Newton steps that blow the residual up (see ``line_search_alpha``).
    method : {"auto", "banded", "sparse"}
        Linear solver (see ``linalg.PatternSolver``).
    return_last_converged : bool
        On failure return the last converged state (with ``stats["converged"] = False``)
        instead of raising ``StaticConvergenceError``.
    relax : bool
        Retry a load step whose Newton iteration failed by pseudo-transient continuation
        (``_Newton.relax``) before bisecting it: this finds the hanging state of slack
        cables, whose straight, untensioned start has a singular tangent.

    Returns
    -------
    State
        With ``stats``: ``iterations`` (per load step), ``residual``, ``load_factor``,
        ``factorizations``, ``relaxed`` (the load factors reached by relaxation).

    Notes
    -----
    By default a cable whose ends the constraints hold closer than its length, while the
    bodies' coordinates do not satisfy them (a cable built straight and pinned with its
    far end at a point closer than its length), starts from its hanging shape
    (``hanging_start``: the catenary ``Cable.between`` builds, sagging along the net
    load on the cable).  A start that still violates the constraints (``initial=``, or
    other bodies) is solved in two stages of one continuation (``_Newton.stage``): the
    loads are applied to the system as built, with the constraints held at their initial
    values ``C(q) = C(q_0)``, then the violation is closed, ``C(q) = (1 - s) C(q_0)``,
    ``s`` from 0 to 1; only the right-hand side of the constraints moves.
    ``docs/steady.md`` validates it on the elastic catenary.

    An equilibrium in which a cable folds back within an element (``folds``: a loop the
    cable passes through, which a straight start can reach) is refused like one that does
    not converge: the load step is relaxed or bisected, and the error names the cable
    and the element.

    Examples
    --------
    A 12 m cable built straight, its far end pinned 10 m from the first: it starts from
    its hanging shape and hangs with its lowest point 3 m below the supports
    (``analytic.elastic_catenary``); the first Newton iteration has no tension to stand
    on (the truss law has no bending) and relaxation takes over:

    >>> import skfem_cable as sc
    >>> sec = sc.Section(E=1e7, A=1e-4, I=1e-20, rho=1e3)
    >>> cable = sc.Cable.straight([0, 0, 0], [12, 0, 0], 16, sec, law="truss")
    >>> system = sc.System([cable]).pin(cable.node(0)).pin(cable.node(-1), [10, 0, 0])
    >>> state = sc.solve_static(system.add_gravity([0, 0, -9.81]))
    >>> round(float(state.position(cable, 6.0)[2]), 2), state.stats["relaxed"]
    (-2.98, [1.0])
    """
    return equilibrium(system, load_steps, tol, max_iter, initial, line_search,
                       max_bisections, method, return_last_converged, relax)


def equilibrium(system: IntegrableSystem, load_steps=1, tol=1e-10, max_iter=30, initial=None,
                line_search=True, max_bisections=8, method="auto",
                return_last_converged=False, relax=True, motion=None):
    """``solve_static`` in a frame where the system moves rigidly: with ``motion`` (an
    object with ``velocity(q)``, the velocities of the rigid motion, and ``operator``,
    their constant derivative ``dv/dq``), the forces are evaluated at those velocities
    and the tangent is the total derivative (``solvers.steady``)."""
    if int(load_steps) != load_steps or load_steps < 1:
        raise ValueError(f"load_steps must be a positive integer, got {load_steps!r}")
    if not (0 < tol < 1):
        raise ValueError(f"tol must lie in (0, 1), got {tol!r}")
    newton = _Newton(system, initial, tol, max_iter, line_search, method, motion)
    q, lam = newton.q0, newton.lam0
    stats = {"iterations": [], "load_factor": [], "residual": [], "factorizations": 0,
             "relaxed": []}
    converged_state = State(system, q.copy(), lam.copy(), stats)
    # the state of the terms' data along the load path (a rod's reference frames): carried
    # to every converged load step, as a time integration carries it to every step
    hooks = [hook for term, _ in newton.lay.body_terms for hook in term.hooks]
    for hook in hooks:
        hook.start(converged_state)
    max_step = 1.0 / (load_steps * (2 if newton.closing else 1))
    done, step = 0.0, max_step
    previous = None
    bisections = 0
    while done < 1.0 - 1e-14:
        factor = min(1.0, done + step)
        qk, lamk = q.copy(), lam.copy()
        if previous is not None and done > previous[2]:
            # secant predictor from the last two equilibria
            w = (factor - done) / (done - previous[2])
            qk += w * (q - previous[0])
            lamk += w * (lam - previous[1])
        ok, it, qk1, lamk1, history = newton.solve(qk, lamk, factor)
        ok = ok and (not newton.closing or admissible(system, qk1, tol, history)) \
            and unfolded(system, qk1, history)
        if not ok and relax:
            ok, it, qk1, lamk1, more = newton.relax(qk, lamk, factor)
            history += ["relaxation"] + more[-5:]
            ok = ok and admissible(system, qk1, tol, history) \
                and unfolded(system, qk1, history)
            if ok:
                stats["relaxed"].append(factor)
        qk, lamk = qk1, lamk1
        stats["factorizations"] = newton.solver.factorizations
        if ok:
            previous = (q, lam, done)
            q, lam, done = qk, lamk, factor
            stats["iterations"].append(it)
            stats["load_factor"].append(factor)
            stats["residual"].append(newton.merit(*newton.residual(qk, lamk, factor)))
            converged_state = State(system, q.copy(), lam.copy(), stats)
            for hook in hooks:
                hook.after_step(converged_state)
            if bisections:
                step = min(2 * step, max_step)
                bisections -= 1
            continue
        if bisections < max_bisections:
            step *= 0.5
            bisections += 1
            continue
        msg = (f"static solve did not converge at load factor {factor:.6g} (load step "
               f"{len(stats['iterations']) + 1}, increment {step:.3g}): residual history "
               f"{[h if isinstance(h, str) else float(f'{h:.3e}') for h in history]}"
               + "".join(f"; {why}" for why in without_bending(system, q)))
        if return_last_converged:
            converged_state.stats["converged"] = False
            converged_state.stats["message"] = msg
            return converged_state
        raise StaticConvergenceError(msg, converged_state)
    converged_state.stats["converged"] = True
    return converged_state


class _Newton:
    """Newton's method with exact tangent for one load factor (see ``solve_static``)."""

    def __init__(self, system, initial, tol, max_iter, line_search, method, motion=None):
        self.system, self.tol, self.max_iter = system, tol, max_iter
        self.line_search, self.motion = line_search, motion
        lay = system.current_layout()
        self.lay, self.n = lay, system.n_dofs
        self.solver = PatternSolver(lay.indptr, lay.indices, method, lay.border,
                                    junctions=lay.junctions)
        pos = system.q0[system.vectors[system.vector_is_position]]
        self.L_ref = max(float(np.ptp(pos, axis=0).max()), 1e-300) if pos.size else 1.0
        self.q0 = hanging_start(system, system.q0, tol * self.L_ref) if initial is None \
            else initial.q.copy()
        self.lam0 = np.zeros(lay.n_c) if initial is None else initial.lam.copy()
        self.scale = constraint_scale(system, self.q0, self.lam0, lay)
        self.violation = system.constraint_values(self.q0, layout=lay)
        self.closing = bool(np.max(np.abs(self.violation), initial=0.0) > tol * self.L_ref)

    def stage(self, factor):
        """``(load factor, part of the initial constraint violation kept)`` at the factor
        of the continuation: the load factor itself; or, when the start violates the
        constraints, the loads applied to the system as built up to 1/2, then the
        violation closed."""
        if not self.closing:
            return factor, 0.0
        closed = max(0.0, 2.0 * factor - 1.0) ** 2
        return min(1.0, 2.0 * factor), 1.0 - closed

    def residual(self, q, lam, factor, data=None):
        load, kept = self.stage(factor)
        v = None if self.motion is None else self.motion.velocity(q)
        r, info = self.system.evaluate(q, v, 0.0, lam, load, scale=self.scale, data=data,
                                       reference_force=True, layout=self.lay)
        if kept:
            r[self.n:] -= self.scale * kept * self.violation
        if v is not None and data is not None:
            self._velocity_tangent(q, v, lam, load, data)
        return r, info["force_ref"]

    def _velocity_tangent(self, q, v, lam, factor, data):
        """Add ``(dr/dv) (dv/dq)`` of the velocities of the rigid motion: the tangent of
        ``r(q, v(q))`` is then the total derivative.  Entries outside the pattern (a
        contributor whose velocity tangent couples coordinates its stiffness does not)
        are left out: Newton then converges linearly, to the same answer."""
        lay, n = self.lay, self.n
        dv = np.zeros(lay.nnz)
        self.system.evaluate(q, v, 0.0, lam, factor, cK=0.0, cC=1.0, scale=self.scale,
                             data=dv, layout=lay)
        P = (lay.matrix(dv)[:n, :n] @ self.motion.operator).tocoo()
        key = P.row.astype(np.int64) * lay.N + P.col
        pos = np.minimum(np.searchsorted(lay.pattern.ukey, key), lay.nnz - 1)
        inside = lay.pattern.ukey[pos] == key
        np.add.at(data, pos[inside], P.data[inside])

    def merit(self, r, f_ref):
        n = self.n
        rq = np.linalg.norm(r[:n]) / max(f_ref, 1e-300)
        rc = np.linalg.norm(r[n:]) / self.scale / self.L_ref
        return max(rq, rc)


    def _singular(self, index, data):
        """The history's note of a singular matrix (``data`` on the layout's pattern): the
        dependent constraints (``constraints.dependent_constraints``), else the unknown
        ``index``."""
        lay, n = self.lay, self.n
        matrix = sp.csr_matrix((data, lay.indices, lay.indptr), shape=(lay.N, lay.N))
        names, rank = dependent_constraints(self.system, matrix[n:, :n])
        if names:
            return dependence_message(names, rank, "this state")
        where = self.system.describe_dof(index) if index >= 0 else \
            "an unknown not located (system too large)"
        return f"singular matrix at {where}"
    def solve(self, qk, lamk, factor):
        """Iterate from ``(qk, lamk)``; returns ``(converged, iterations, q, lam,
        history)``."""
        n, tol, scale = self.n, self.tol, self.scale
        history = []
        dx_prev = np.inf
        for it in range(self.max_iter + 1):
            data = scale * self.lay.linear_data
            r, f_ref = self.residual(qk, lamk, factor, data)
            m = self.merit(r, f_ref)
            history.append(m)
            if not np.isfinite(m):
                return False, it, qk, lamk, history
            if m <= tol:
                return True, it, qk, lamk, history
            if it == self.max_iter:
                return False, it, qk, lamk, history
            try:
                self.solver.factor(data)
            except SingularMatrixError as err:
                history.append(self._singular(err.index, data))
                return False, it, qk, lamk, history
            dx = self.solver.solve(-r)
            dxn = np.max(np.abs(dx[:n]))
            if self._floor(dxn, dx_prev):
                return True, it, qk + dx[:n], lamk + scale * dx[n:], history
            dx_prev = dxn
            alpha = 1.0
            if self.line_search:
                alpha = line_search_alpha(self.residual, self.merit, qk, lamk, dx, r, m,
                                          factor, scale)
            qk = qk + alpha * dx[:n]
            lamk = lamk + alpha * scale * dx[n:]
        return False, it, qk, lamk, history

    def _floor(self, dxn, dx_prev):
        """True when the Newton correction is negligible, or stopped contracting at a small
        size: the round-off floor of the residual is reached (see ``solve_static``)."""
        tol, L_ref = self.tol, self.L_ref
        return dxn <= tol * L_ref or (dxn <= np.sqrt(tol) * L_ref and dxn >= 0.5 * dx_prev)

    #: Iterations allowed to a relaxation, per Newton iteration of ``max_iter``.
    RELAX_ITERATIONS = 20
    #: Size of the first step of a relaxation, relative to the system size.
    RELAX_START = 1e-2

    #: A relaxation step is refused when it multiplies the merit by more than this.
    RELAX_GROWTH = 2.0

    #: A relaxation whose mass shift has grown to this many times its start takes steps
    #: too small to move: it stops (the load step is then bisected).
    RELAX_STALL = 1e12

    def relax(self, qk, lamk, factor):
        """Pseudo-transient continuation from ``(qk, lamk)`` (Kelley & Keyes, SIAM J.
        Numer. Anal. 35, 1998): steps ``(K + c M) dx = -r`` (constraints kept in the KKT
        system) with a mass shift ``c`` (1/s^2) that follows the residual (switched
        evolution relaxation, ``c <- c (m_k / m_{k-1})^2`` for the merit ``m``, the factor
        kept in [0.01, 100]); a step that multiplies the merit by more than
        ``RELAX_GROWTH`` is refused and the shift multiplied by 10, up to ``RELAX_STALL``
        times its start, where the relaxation stops.  With a large shift it
        is an implicit, strongly damped pseudo-dynamics (dynamic relaxation): the mass
        term keeps the tangent of a slack or compressed cable regular; as the residual
        vanishes the shift does too (below ``1e-12`` of its start it is zero) and the last
        steps are Newton's.  The first shift moves the coordinates by ``RELAX_START`` of
        the system size under the residual force, ``c = max |r_i / M_ii| / (RELAX_START
        L)``.  Returns what ``solve`` returns."""
        n, tol, scale, lay = self.n, self.tol, self.scale, self.lay
        data = scale * lay.linear_data
        r, f_ref = self.residual(qk, lamk, factor, data)
        m = self.merit(r, f_ref)
        history = [m]
        mass = lay.mass_diagonal
        accel = np.abs(r[:n][mass > 0] / mass[mass > 0])
        c0 = float(np.max(accel, initial=0.0)) / (self.RELAX_START * self.L_ref)
        c0 = c0 if np.isfinite(c0) and c0 > 0 else self.scale
        c = c0
        for it in range(self.RELAX_ITERATIONS * self.max_iter):
            if not np.isfinite(m):
                return False, it, qk, lamk, history
            if m <= np.sqrt(tol):
                # close enough for Newton's method (and its round-off floor test)
                ok, more, qk, lamk, tail = self.solve(qk, lamk, factor)
                return ok, it + more, qk, lamk, history + tail
            if c > self.RELAX_STALL * c0:
                history.append("relaxation stalled")
                return False, it, qk, lamk, history
            try:
                self.solver.factor(data + c * lay.mass_data)
            except SingularMatrixError:
                c = max(10.0 * c, 1e-6 * c0)
                continue
            dx = self.solver.solve(-r)
            q1, lam1 = qk + dx[:n], lamk + scale * dx[n:]
            data1 = scale * lay.linear_data
            r1, f1 = self.residual(q1, lam1, factor, data1)
            m1 = self.merit(r1, f1)
            if np.isfinite(m1) and m1 < self.RELAX_GROWTH * m:
                # switched evolution relaxation: the pseudo-time step grows as the
                # residual falls (Kelley & Keyes 1998, Eq. 2.3), c ~ 1 / step^2
                c *= min(max(m1 / m, 0.1), 10.0) ** 2
                c = 0.0 if c < 1e-12 * c0 else c
                qk, lamk, r, data, m = q1, lam1, r1, data1, m1
                history.append(m)
            else:
                c = max(10.0 * c, 1e-6 * c0)
        return False, it, qk, lamk, history
