"""Static equilibrium: Newton's method with exact tangent, load stepping with automatic
bisection, and a backtracking line search."""

import numpy as np

from ..linalg import PatternSolver, SingularMatrixError
from ..state import State


class StaticConvergenceError(RuntimeError):
    """Newton did not converge; ``last_converged`` holds the last equilibrium reached."""

    def __init__(self, message, last_converged):
        super().__init__(message)
        self.last_converged = last_converged


def constraint_scale(system, q, lam):
    """Scale of the constraint rows: the mean stiffness diagonal, so that both blocks of the
    KKT matrix have comparable magnitude."""
    lay = system.layout
    data = np.zeros(lay.nnz)
    system.evaluate(q, None, 0.0, lam, data=data)
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


def solve_static(system, load_steps=1, tol=1e-10, max_iter=30, initial=None, line_search=True,
                 max_bisections=8, method="auto", return_last_converged=False):
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
        Starting configuration (default: the bodies' initial coordinates).
    line_search : bool
        Shorten Newton steps that blow the residual up (see ``line_search_alpha``).
    method : {"auto", "banded", "sparse"}
        Linear solver (see ``linalg.PatternSolver``).
    return_last_converged : bool
        On failure return the last converged state (with ``stats["converged"] = False``)
        instead of raising ``StaticConvergenceError``.

    Returns
    -------
    State
        With ``stats``: ``iterations`` (per load step), ``residual``, ``load_factor``,
        ``factorizations``.
    """
    if int(load_steps) != load_steps or load_steps < 1:
        raise ValueError(f"load_steps must be a positive integer, got {load_steps!r}")
    if not (0 < tol < 1):
        raise ValueError(f"tol must lie in (0, 1), got {tol!r}")
    newton = _Newton(system, initial, tol, max_iter, line_search, method)
    q, lam = newton.q0, newton.lam0
    stats = {"iterations": [], "load_factor": [], "residual": [], "factorizations": 0}
    converged_state = State(system, q.copy(), lam.copy(), stats)
    done, step = 0.0, 1.0 / load_steps
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
        ok, it, qk, lamk, history = newton.solve(qk, lamk, factor)
        stats["factorizations"] = newton.solver.factorizations
        if ok:
            previous = (q, lam, done)
            q, lam, done = qk, lamk, factor
            stats["iterations"].append(it)
            stats["load_factor"].append(factor)
            stats["residual"].append(newton.merit(*newton.residual(qk, lamk, factor)))
            converged_state = State(system, q.copy(), lam.copy(), stats)
            if bisections:
                step = min(2 * step, 1.0 / load_steps)
                bisections -= 1
            continue
        if bisections < max_bisections:
            step *= 0.5
            bisections += 1
            continue
        msg = (f"static solve did not converge at load factor {factor:.6g} (load step "
               f"{len(stats['iterations']) + 1}, increment {step:.3g}): residual history "
               f"{[h if isinstance(h, str) else float(f'{h:.3e}') for h in history]}"
               + "".join(f"; {why}" for why in _without_bending(system, q)))
        if return_last_converged:
            converged_state.stats["converged"] = False
            converged_state.stats["message"] = msg
            return converged_state
        raise StaticConvergenceError(msg, converged_state)
    converged_state.stats["converged"] = True
    return converged_state


def _without_bending(system, q, samples=8):
    """Why cables without bending stiffness (the truss law) may defeat a static solve:
    one sentence per such cable that is compressed or slack somewhere in the state
    ``q`` (its tangent then has no stiffness across the cable), with what to do."""
    reasons = []
    for cable in system.cables():
        if cable.bending:
            continue
        s = np.linspace(0.0, cable.length, samples * cable.n_elements + 1)
        strain = cable.strain(q[system.dofs(cable)], s)
        k = int(np.argmin(strain))
        if strain[k] <= 0.0:
            reasons.append(
                f"cable {cable.name!r} has no bending stiffness (law {cable.law.name!r}) and "
                f"is compressed or slack (strain {strain[k]:.3g} at s = {s[k]:.4g} m): "
                "without tension its stiffness across the cable vanishes and the tangent is "
                "singular; start from a stretched state (initial=) or tension it first "
                "(more load_steps, the tensioning loads applied first), give it bending "
                "(law 'cable'), or find the hanging state with simulate and damping")
    return reasons


class _Newton:
    """Newton's method with exact tangent for one load factor (see ``solve_static``)."""

    def __init__(self, system, initial, tol, max_iter, line_search, method):
        self.system, self.tol, self.max_iter = system, tol, max_iter
        self.line_search = line_search
        lay = system.layout
        self.lay, self.n = lay, system.n_dofs
        self.solver = PatternSolver(lay.indptr, lay.indices, method, lay.border)
        self.q0 = (system.q0 if initial is None else initial.q).copy()
        self.lam0 = np.zeros(lay.n_c) if initial is None else initial.lam.copy()
        self.scale = constraint_scale(system, self.q0, self.lam0)
        pos = system.q0.reshape(-1, 3)
        self.L_ref = max(float(np.ptp(pos, axis=0).max()), 1e-300)

    def residual(self, q, lam, factor, data=None):
        r, info = self.system.evaluate(q, None, 0.0, lam, factor, scale=self.scale, data=data,
                                       reference_force=True)
        return r, info["force_ref"]

    def merit(self, r, f_ref):
        n = self.n
        rq = np.linalg.norm(r[:n]) / max(f_ref, 1e-300)
        rc = np.linalg.norm(r[n:]) / self.scale / self.L_ref
        return max(rq, rc)

    def solve(self, qk, lamk, factor):
        """Iterate from ``(qk, lamk)``; returns ``(converged, iterations, q, lam,
        history)``."""
        n, tol, L_ref, scale = self.n, self.tol, self.L_ref, self.scale
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
                where = self.system.describe_dof(err.index) if err.index >= 0 else \
                    "an unknown not located (system too large)"
                history.append(f"singular matrix at {where}")
                return False, it, qk, lamk, history
            dx = self.solver.solve(-r)
            dxn = np.max(np.abs(dx[:n]))
            if dxn <= tol * L_ref or (dxn <= np.sqrt(tol) * L_ref and dxn >= 0.5 * dx_prev):
                # the correction is negligible, or stopped contracting at a small size:
                # the round-off floor of the residual is reached
                return True, it, qk + dx[:n], lamk + scale * dx[n:], history
            dx_prev = dxn
            alpha = 1.0
            if self.line_search:
                alpha = line_search_alpha(self.residual, self.merit, qk, lamk, dx, r, m,
                                          factor, scale)
            qk = qk + alpha * dx[:n]
            lamk = lamk + alpha * scale * dx[n:]
        return False, it, qk, lamk, history
