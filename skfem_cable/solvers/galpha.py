"""Generalized-alpha integration of the index-3 DAE (paper Sect. 2, Eqs. 1-3, 12-15).

    M q'' + f(q, q', t) + C_q^T lambda = 0,   C(q) = 0,

with ``f`` the internal (elastic + damping) minus the external forces, by the method of
Arnold & Bruls (2007): pseudo-accelerations ``abar`` with
``(1 - alpha_m) abar_{n+1} + alpha_m abar_n = (1 - alpha_f) a_{n+1} + alpha_f a_n``,
``q_{n+1} = q_n + h v_n + h^2 ((1/2 - beta) abar_n + beta abar_{n+1})`` and
``v_{n+1} = v_n + h ((1 - gamma) abar_n + gamma abar_{n+1})``; the equations hold exactly
at ``t_{n+1}``, so the position constraints are satisfied at every step.

Newton's iteration matrix is ``S_t = [[M beta' + C_t gamma' + K_t, C_q^T], [C_q, 0]]``
(Eq. 13), ``beta' = (1 - alpha_m) / (beta h^2 (1 - alpha_f))``, ``gamma' = gamma/(beta h)``.
For conditioning independent of ``h`` (Bottasso, Bauchau & Cardona 2008) the dynamic rows
are divided by ``beta'`` and the constraint rows and multipliers scaled by the mean nodal
mass ``m``: the matrix solved is ``[[M + C_t gamma'/beta' + K_t/beta', m C_q^T], [m C_q, 0]]``
with unknowns ``(dq, dlambda / (beta' m))``; its entries do not grow as ``h -> 0``.
"""

import numpy as np

from ..core.contract import OutOfDomain
from ..core.linalg import PatternSolver, ordering_of, thread_count
from ..core.protocols import IntegrableSystem, StepHook
from ..kernels import step as codes
from ..kernels.error import error_ratio
from .books import Books
from .checkpoint import Checkpoint
from .compiled import CompiledNewton, python_parts
from .diagnosis import Diagnosis
from .guard import EnergyGuard, refusal
from .initial_state import InitialState
from .newton_choice import NewtonChoice
from .step_control import StepControl


def galpha_parameters(rho_inf):
    """``alpha_m, alpha_f, gamma, beta`` from the spectral radius at infinity (paper,
    Sect. 2 "DAE integration"; Chung & Hulbert 1993)."""
    if not 0.0 <= rho_inf <= 1.0:
        raise ValueError(f"rho_inf must lie in [0, 1], got {rho_inf!r}")
    alpha_m = (2.0 * rho_inf - 1.0) / (rho_inf + 1.0)
    alpha_f = rho_inf / (rho_inf + 1.0)
    gamma = 0.5 + alpha_f - alpha_m
    beta = 0.25 * (gamma + 0.5) ** 2
    return alpha_m, alpha_f, gamma, beta


def _total_mass(system, lay):
    """The mass of ``system`` in translation (the mass matrix of ``lay`` on a unit
    velocity of the whole system)."""
    unit = system.rigid_motion_velocity(system.q0, (0, 0, 0), velocity=(1, 0, 0))
    return float(unit @ (lay.mass @ unit))


class GeneralizedAlpha(StepControl, Diagnosis, InitialState, NewtonChoice, Books,
                       Checkpoint):
    """Integrator state and one step of the generalized-alpha method.

    Parameters
    ----------
    system : System
    rho_inf : float in [0, 1]
        Spectral radius at infinite frequency (1: no numerical dissipation).
    tol : float
        Newton converges when the error left after a correction ``dx_k``, estimated as
        ``eta_k |dx_k|`` from the measured contraction ``theta_k = |dx_k| / |dx_(k-1)|``,
        ``eta_k = theta_k / (1 - theta_k)`` (the first correction of a step: the last step's
        ``eta`` relaxed to ``eta^0.8``, at least 0.1; ``kernels.step``), or when the scaled
        residual (``r_q / S_ii`` with ``S`` the iteration matrix, and the constraint
        violation, both in units of the coordinates) and the last correction are below
        ``tol`` times the coordinate scale (system size for positions, 1 for slopes).
        After an exact-tangent correction, residual and correction below ``1e3 tol`` that
        stopped contracting are accepted as the round-off floor.  The
        default 1e-11 keeps the Newton error below the truncation error of slow, large
        systems (a correction ``dq`` left in place is a velocity error ``gamma' dq``).
    max_iter : int
        Newton iterations per step.
    newton : {"modified", "full"}
        ``"modified"`` (default) reuses the factorization across iterations and steps while
        Newton contracts by at least ``1/4`` per iteration and, from the fourth correction
        of a step on, while the next correction is predicted to end the iteration
        (``eta^2 |dx| <= tol``: a factorization costs several corrections); it refactors
        otherwise (and retries a failed step with a fresh tangent), and for a while
        factors the tangent at the start of every step where the stale one keeps failing
        (``_choose_newton``: long steps of stiff spinning cables); ``"full"`` refactors
        every iteration.
        Modified Newton pays when the tangent changes slowly (the E-sail: 7 factorizations
        in 2000 steps, 5x faster); for a fast-rotating stiff cable it needs about twice the
        iterations of full Newton for the same wall time.
    method : {"auto", "banded", "sparse"}
        Linear solver of the iteration matrix.
    energy_tol : float or None
        Instability guard (``guard.EnergyGuard``): a step whose energy balance grows by
        more than ``energy_tol`` times the energy content of the run is rejected (the
        driver retries it smaller).  None switches the guard off.
    tol_local : float or None
        With a value (e.g. 1e-2), Newton also stops once the scaled residual and the last
        correction are below ``tol_local`` times the step's estimated local error
        (``local_error`` at the current iterate, in units of the coordinate scale): more
        iterations cannot make the step's positions more accurate (the flexible pendulum,
        16 elements at ``tol = 1e-10``: 3505 corrections instead of 3838, the same tip
        error).  The energy books then close only
        to about that share of the local error instead of round-off, which the instability
        guard may see as growth on long undamped runs; None (default): ``tol`` alone.
    rtol, atol : float or None
        Error control (both or neither), aimed at the global error: a step is accepted
        only if its estimated local error (``local_error``) is below ``s (atol + rtol
        |q|)`` with ``s = (rtol / TOLERANCE_PIVOT)^(1/2)``, in every 3-vector of
        coordinates (a position, a slope; ``atol`` in metres, ``atol / L`` for the slopes,
        ``L`` the system's size), the error and ``|q|`` taken as the vector's length: the
        control does not depend on the frame, and a slope component passing through zero
        keeps its vector's tolerance (per component, the steps of a spinning E-sail dipped
        tenfold there).  ``s`` is a tolerance proportionality transform (RADAU5 transforms
        its own tolerances so, Hairer & Wanner 1996, Sec. IV.8): steps whose local error,
        ``O(h^3)``, is held to ``tol`` leave a global error ``O(h^2) = O(tol^(2/3))``, so
        the steps hold it to ``tol^(3/2) TOLERANCE_PIVOT^(-1/2)`` and the global error
        follows ``rtol``.  Measured against fixed-step references
        (``benchmarks/adaptive_fronts.py``): the 6-element flexible
        pendulum's positions within 6.9 to 4.4 ``rtol`` from 1e-4 to 1e-7 (without the
        transform 6.6 to 118), the 12-tether E-sail's spin rate, coning and thrust within
        9.2 to 7.6 ``rtol`` from 1e-5 to 1e-8 over a spin period.  Above ``rtol = 1e-3``
        the steps can outgrow the modes the motion drives, whose numerical dissipation
        the estimate does not see: check the energy balance (``docs/theory.md``, "Loose
        tolerances").
        ``error_ratio`` is the largest ratio of error to tolerance, which the driver uses
        to choose the next step.  Newton then stops at a hundredth of ``rtol`` and
        ``atol`` (``tol`` is a floor): iterating further cannot make the step more
        accurate (to a hundredth of the transformed tolerances: 70 % more corrections at
        ``rtol = 1e-7`` and the same errors).
    initial_acceleration : {"consistent", "zero"}
        The accelerations of the initial state: solved from the equations of motion and
        the constraints (default; the pseudo-acceleration then fitted to the first step,
        ``_fit_abar``), or zero, with zero pseudo-acceleration and multipliers, as Exudyn
        starts when ``computeInitialAccelerations`` is off (its test suite's setting):
        the first steps then carry the start-up error of a wrong initial acceleration,
        which the algorithm's damping removes.
    pseudo_acceleration : {"fitted", "initial"}
        The pseudo-acceleration of a consistent start: fitted to the first step
        (default, ``_fit_abar``: second order from the first step), or the initial
        acceleration itself, ``abar_0 = a_0`` (Arnold & Bruls' plain start, which Exudyn
        takes: first order in the first step).  With ``initial_acceleration="zero"`` it
        starts at zero.
    compiled : bool or None
        The Newton iteration is one definition (``kernels.step``), generated per system
        and run in one compiled call (``solvers.compiled``); a term with a Python ``add``
        hook, a nonlinear constraint without kernel and a sparse LU are called back from
        it (``numba.objmode``), the rest stays compiled.  None and True (default: None)
        run it compiled; False runs the same generated source interpreted (a debugging
        mode, with the same iterates).  ``step_path`` says which, and what is Python.
    """

    def __init__(self, system: IntegrableSystem, rho_inf=0.8, tol=1e-11, max_iter=12,
                 newton="modified", method="auto", energy_tol=0.05, compiled=None,
                 rtol=None, atol=None, tol_local=None, initial_acceleration="consistent",
                 pseudo_acceleration="fitted"):
        if newton not in ("modified", "full"):
            raise ValueError(f"newton must be 'modified' or 'full', got {newton!r}")
        if initial_acceleration not in ("consistent", "zero"):
            raise ValueError("initial_acceleration must be 'consistent' or 'zero', got "
                             f"{initial_acceleration!r}")
        if pseudo_acceleration not in ("fitted", "initial"):
            raise ValueError("pseudo_acceleration must be 'fitted' or 'initial', got "
                             f"{pseudo_acceleration!r}")
        self.zero_start = initial_acceleration == "zero"
        self.fit_start = not self.zero_start and pseudo_acceleration == "fitted"
        if not 0 < tol < 1:
            raise ValueError(f"tol must lie in (0, 1), got {tol!r}")
        if int(max_iter) != max_iter or max_iter < 1:
            raise ValueError(f"max_iter must be a positive integer, got {max_iter!r}")
        self.system = system
        self.guard = EnergyGuard(energy_tol)
        self.rho_inf = float(rho_inf)
        self.alpha_m, self.alpha_f, self.gamma, self.beta = galpha_parameters(rho_inf)
        self.tol, self.max_iter, self.newton = tol, int(max_iter), newton
        if tol_local is not None and not (np.isfinite(tol_local) and 0 < tol_local < 1):
            raise ValueError(f"tol_local must lie in (0, 1) or be None, got {tol_local!r}")
        self.tol_local = tol_local
        lay = system.current_layout()
        self.lay = lay
        self.n = system.n_dofs
        ordering = lay.derived("ordering", lambda: ordering_of(lay.indptr, lay.indices,
                                                               lay.border, lay.junctions))
        self.solver = lay.derived(  # the layout's solver, never factored: its plan, once
            ("solver", method, thread_count()),
            lambda: PatternSolver(lay.indptr, lay.indices, method, lay.border,
                                  junctions=lay.junctions, ordering=ordering)).renewed()
        self.mbar = float(np.mean(lay.mass_diagonal))
        if not self.mbar > 0:
            raise ValueError("the system has no mass")
        self.base = lay.mass_data + self.mbar * lay.linear_data
        self.xscale = lay.coordinate_scale
        self.inv_xscale = 1.0 / self.xscale
        self.L_ref = lay.length_scale
        self.total_mass = lay.derived("total mass", lambda: _total_mass(system, lay))
        # the scaled residual: dynamic rows divided by the diagonal of the iteration matrix
        # (a Jacobi estimate of the correction, in units of the coordinates; refreshed at
        # every factorization, the mass diagonal before the first, the mean mass where a
        # coordinate's inertia is all in terms, as a reel's may be) and constraint rows in
        # units of the coordinates, both divided by the coordinate scale
        self.diag_index = lay.diagonal_index[: self.n]
        mass = np.where(lay.mass_diagonal > 0, lay.mass_diagonal, self.mbar)
        self.res_weight = 1.0 / (mass * self.xscale)
        self.con_weight = 1.0 / (self.mbar * self.L_ref)
        self.h_factored = None
        self.h_next = None  # the step the driver chose next (adaptive steps)
        # the last two steps (predicted_acceleration)
        self.a_prev = self.h_prev = self.da_prev = self.h_prev2 = None
        self.abar_h = None  # the step the pseudo-acceleration fits (_fit_abar)
        self.newton_rate = 1.0  # Newton's contraction estimate of the last step
        # modified Newton's choice (_choose_newton)
        self.fresh_steps = self.strikes = self.tangent_age = 0
        self.energy_depends_on_time = any(
            term.energy_rate is not None for term, _ in lay.body_terms + lay.load_terms)
        self.energy_changes = any(
            term.energy_change is not None for term, _ in lay.body_terms + lay.load_terms)
        self.stats = {"steps": 0, "rejected": 0, "newton": 0, "factorizations": 0}
        self._error_control(rtol, atol)
        self.hooks: list[StepHook] = []  # simulate's (their state joins the snapshot)
        self.checks = tuple(term.check for term, _ in lay.body_terms + lay.load_terms
                            if term.check is not None)  # guard.refusal
        self.compiled = self._compiled_newton(compiled)

    def _error_control(self, rtol, atol):
        """Tolerances of the local error per coordinate (the requested ones scaled by the
        proportionality transform, ``rtol, atol`` in the class docstring), and the Newton
        tolerance they imply."""
        # the constant of the leading term of the local error (local_error)
        self.error_constant = abs(self.beta - 1.0 / 6.0 + 0.5 * (self.alpha_m - self.alpha_f))
        self.rtol, self.atol = rtol, atol
        self.error_ratio = None
        if rtol is None and atol is None:
            return
        for name, value in (("rtol", rtol), ("atol", atol)):
            if value is None or not (np.isfinite(value) and value > 0):
                raise ValueError(f"{name} must be a number > 0 (error control needs rtol "
                                 f"and atol), got {value!r}")
        if rtol >= 1:
            raise ValueError(f"rtol must be < 1, got {rtol!r}")
        scale = np.sqrt(rtol / self.TOLERANCE_PIVOT)
        self.rtol_local = scale * rtol
        self.atol_q = scale * atol * self.xscale / self.L_ref
        self.scalars = np.setdiff1d(np.arange(self.n), self.system.vectors)
        self.tol = max(self.tol, 1e-2 * min(rtol, atol / self.L_ref))

    def _compiled_newton(self, compiled):
        if compiled not in (None, True, False):
            raise ValueError(f"compiled must be None, True or False, got {compiled!r}")
        parts = python_parts(self.system, self.solver)
        self.step_path = "python (compiled=False)" if compiled is False else \
            "compiled" + (f" (Python: {'; '.join(parts)})" if parts else "")
        return CompiledNewton(self, jit=compiled is not False)

    def _coefficients(self, h):
        bp = (1.0 - self.alpha_m) / (self.beta * h * h * (1.0 - self.alpha_f))
        return bp, self.gamma / (self.beta * h)

    def _factor(self, q, v, t, lam, h, a, data=None):
        """Factor the iteration matrix at ``(q, v, t, lam, a)`` for step ``h``."""
        if data is None:
            bp, gp = self._coefficients(h)
            data = self.base.copy()
            self.system.evaluate(q, v, t, lam, cK=1.0 / bp, cC=gp / bp, scale=self.mbar,
                                 data=data, a=a, cM=1.0, layout=self.lay)
        self.solver.factor(data)
        self.compiled.refresh()
        self.stats["factorizations"] += 1
        self.res_weight[:] = 1.0 / (np.abs(data[self.diag_index]) * self.xscale)
        self.h_factored = h
        self.factored_at = {"q": q.copy(), "v": v.copy(), "t": t, "lam": lam.copy(), "h": h,
                            "a": a.copy()}

    def series_writer(self, run_dir, writer, append=False, frame="inertial", **detail):
        """The writer of the run's ParaView series (``io.SeriesObserver``): ``writer``
        (the series writer of a system of bodies that the observer gives,
        ``export.SeriesWriter``: solvers write no files) of the system in ``frame``,
        turning in orbit with the run's reference (``detail``: ``points_per_element``)."""
        return writer(run_dir, self.system, append=append, frame=frame,
                      reference=self.lay.reference, **detail)

    # --- one step ---------------------------------------------------------------------------
    def step(self, h):
        """Advance by ``h``; returns ``(success, message)`` and updates the state only on
        success (scipy ``OdeSolver`` style), in its arrays (``q``, ``v``, ``lam``, ...:
        copy what you keep)."""
        self.error_ratio = None
        self._fit_abar(h)
        fresh, full = self.fresh_tangent, self.newton == "full"
        factorizations = self.stats["factorizations"]
        ok, msg = self._try_step(h, fresh=fresh, full=full)
        if not ok and not fresh and self.error_ratio is None:
            ok, msg = self._try_step(h, fresh=True)
        if ok and not full:
            self._choose_newton(fresh, self.stats["factorizations"] - factorizations)
        return ok, msg

    def local_error(self, h, q1, a1):
        """Estimated local error of the coordinates of a step ``h`` ending at
        ``(q1, a1)``: ``e = (beta - 1/6 + (alpha_m - alpha_f)/2) h^2 (abar_(n+1) -
        abar_n)``, the leading term of the update ``q_(n+1) = q_n + h v_n + h^2 ((1/2 -
        beta) abar_n + beta abar_(n+1))`` against the Taylor series of the exact motion,
        with ``abar_n = a(t_n + (alpha_m - alpha_f) h) + O(h^2)`` and ``abar_(n+1) -
        abar_n = h dddq + O(h^2)`` (Newmark's estimate of Zienkiewicz & Xie 1991, for the
        pseudo-accelerations of Arnold & Bruls 2007)."""
        return self.error_constant * h * h * (self._next_abar(a1) - self.abar)

    #: The ``rtol`` at which the local error's tolerance is the requested one
    #: (``_error_control``); RADAU5's transform ``0.1 rtol^(2/3)`` also leaves 1e-3 as it is.
    TOLERANCE_PIVOT = 1e-3

    #: Newton iterations of the last step up to which the motion counts as smooth enough
    #: for an extrapolated predictor (``predictor``).
    SMOOTH_ITERATIONS = 3

    def predicted_acceleration(self, h):
        """Newton's starting acceleration for a step ``h``: ``a_n + c1 (a_n - a_(n-1)) +
        c0 (a_(n-1) - a_(n-2))`` with ``(c1, c0) = predictor(h)``."""
        c1, c0 = self.predictor(h)
        if c1 == 0.0 and c0 == 0.0:
            return self.a.copy()
        da_prev = self.da_prev if self.da_prev is not None else np.zeros_like(self.a)
        return self.a + c1 * (self.a - self.a_prev) + c0 * da_prev

    def predictor(self, h):
        """The coefficients ``(c1, c0)`` of ``predicted_acceleration``: the acceleration
        of the motion ``a(t) = m + b t + s (-rho_inf)^k`` (step ``k``) through the last
        three accelerations, ``c1 = kappa - rho_inf``, ``c0 = kappa rho_inf`` with
        ``kappa = (h + rho_inf h_n) / (h_n + rho_inf h_(n-1))``: linear extrapolation of
        the resolved motion, and of the unresolved modes the sequence ``(-rho_inf)^k``
        that the method leaves of them (all three roots of its amplification matrix
        tend to ``-rho_inf`` as ``omega h`` grows, Chung & Hulbert 1993).  At constant
        steps ``a_(n+1) = (2 - rho_inf) a_n + (2 rho_inf - 1) a_(n-1) - rho_inf
        a_(n-2)``, the predictor of characteristic polynomial ``(z - 1)^2 (z +
        rho_inf)``; ``rho_inf = 0`` gives linear extrapolation.  Of a ringing mode it
        misses the next acceleration by a fifth of the constant predictor's miss, linear
        extrapolation by twice it.  The release of the 100 m pendulum sets its elements
        next to the pin ringing for some 80 steps: over its first 200 steps 2.42 Newton
        corrections per step instead of 2.77 at 10,000 elements, 2.33 instead of 2.45 at
        1000 (``benchmarks/step_cost.py``: the cost per step now grows as ``n^1.01``).
        After a start: the constant acceleration, ``(0, 0)``; after one step: linear
        extrapolation, ``(h / h_n, 0)``; after a step of more than
        ``SMOOTH_ITERATIONS`` Newton iterations that factored its tangent: the constant
        acceleration (on coarse steps of a stiff spinning tether an extrapolation
        overshoots).  A step on a tangent kept from earlier steps (``tangent_age > 0``,
        ``NewtonChoice``) counts the tangent's drift as much as the predictor's miss,
        and keeps the extrapolation: the ringing's steps at 10,000 elements took 4-5
        corrections on the release's tangent, switched to the constant acceleration,
        missed by 4 times more (5.5e-4 against 1.4e-4 at step 20) and stayed slow.  Over
        the 200 steps after the release, 426, 427, 430, 465 and 478 corrections at 1000,
        1800, 3200, 5600 and 10,000 elements became 423, 425, 429, 452 and 465, with the
        same factorizations."""
        if self.a_prev is None or (self.iterations > self.SMOOTH_ITERATIONS
                                   and self.tangent_age == 0):
            return 0.0, 0.0
        if self.da_prev is None:
            return h / self.h_prev, 0.0
        rho = self.rho_inf
        kappa = (h + rho * self.h_prev) / (self.h_prev + rho * self.h_prev2)
        return kappa - rho, kappa * rho

    def _next_abar(self, a1):
        """The pseudo-acceleration at the end of a step ending with acceleration ``a1``:
        ``(1 - alpha_m) abar_(n+1) = (1 - alpha_f) a_(n+1) + alpha_f a_n - alpha_m abar_n``."""
        return codes.pseudo_acceleration(a1, self.a, self.abar, self.alpha_m, self.alpha_f)

    def _try_step(self, h, fresh, full=False):
        """One Newton iteration of a step ``h``, from a fresh tangent if ``fresh``, in full
        Newton if ``full``."""
        # the factored matrix fits while the step is the same up to round-off (the macro
        # steps t_i - t_(i-1) of simulate differ in the last bits)
        need = fresh or self.h_factored is None or abs(self.h_factored - h) > 1e-9 * h
        try:
            return self._newton_step(h, need, full)
        except OutOfDomain as exc:  # an iterate left a term's domain: retry smaller
            return False, f"t={self.t + h:.6g}, h={h:.3g}: {exc}"

    def _newton_step(self, h, need, full):
        """The Newton iteration of the step (``solvers.compiled``, in one call) and its
        acceptance."""
        t1 = self.t + h
        status, it, factored, corrected, singular = self.compiled.iterate(self, h, t1, need,
                                                                          full)
        stats, arrays = self.stats, self.compiled.arrays
        stats["newton"] += corrected
        stats["factorizations"] += factored
        if factored:  # the step's arrays fq, fv, flam hold the state of its last factor
            self.h_factored = h
            self.factored_at = {"q": arrays["fq"], "v": arrays["fv"], "t": t1,
                                "lam": arrays["flam"], "h": h}
        if status == codes.SINGULAR:
            self.h_factored = None
            return False, self._singular(t1, h, singular)
        if status != codes.CONVERGED:
            what = "non-finite residual" if status == codes.NON_FINITE else "no convergence"
            return False, self._diagnose(t1, h, list(arrays["history"][:it + 1]),
                                         arrays["r"], what)
        return self._accept(t1, h, arrays, it, self.compiled.prm[codes.RATE])

    def _keep_forces(self, end):
        """The forces of the books at the end of an accepted step, from the step's arrays
        ``end``, into the state's: the damping and external forces only if some term
        writes them (``Layout.writes``; else they stay zero, a pass fewer over each, out
        of the L2 cache on large systems)."""
        writes = self.lay.writes
        if "f_damping" in writes:
            self.fd[...] = end["fd"]
        if "f_ext" in writes:
            self.fnc[...] = end["f_ext"]
        self.fcon[...] = end["f_con"]

    def _accept(self, t1, h, end, iterations, rate):
        """Book the energies of a converged step (with the step's arrays ``end``,
        ``CompiledNewton.arrays``: its end ``q1, v1, a1, lam1, abar1``, the forces of its
        last residual, its elastic energy and the compiled books), apply the terms'
        checks (``guard.refusal``) and, last, the instability guard (``EnergyGuard.admit``)
        and, if they pass, make the step's end the current state (copied into its arrays:
        only an accepted step's); ``rate`` is its Newton contraction estimate
        (``newton_rate``)."""
        q1, v1 = end["q1"], end["v1"]
        if self.checks:
            refused = refusal(self.checks, self.q, q1)
            if refused is not None:
                return False, f"t={t1:.6g}, h={h:.3g}: {refused}"
        if self.rtol is not None:
            self.error_ratio = error_ratio(self.q, q1, end["abar1"], self.abar,
                                           self.error_constant * h * h, self.system.vectors,
                                           self.scalars, self.atol_q, self.rtol_local)
            if not self.error_ratio <= 1.0:
                return False, (f"t={t1:.6g}, h={h:.3g}: local error {self.error_ratio:.3g} "
                               "times the tolerance")
        dissipated, external, kinetic, potential, energy_rate = self._step_books(
            end["books"], q1, t1)
        axial, bending = end["energy"].tolist()
        self.guard.set_scale(self.total_mass, self.L_ref, h)
        grown = self.guard.admit(t1, (kinetic, axial, bending, potential, dissipated,
                                      external))
        if grown is not None:
            return False, self._diagnose_growth(t1, h, v1, grown)
        # the step's end becomes the state, written into the state's arrays in place (the
        # compiled step overwrites its own at its next call; observers copy what they
        # keep, contract.Step): fresh copies cost the rig 3-5 us more a step (allocating
        # and freeing nine arrays with the caches cold after the compiled call)
        self.t = t1
        self.q[...], self.v[...], self.lam[...] = q1, v1, end["lam1"]
        self.abar[...] = end["abar1"]
        if self.a_prev is not None:  # (np.subtract allocates da_prev when there is none)
            self.da_prev = np.subtract(self.a, self.a_prev, out=self.da_prev)
            self.h_prev2 = self.h_prev
        a = np.empty_like(self.a) if self.a_prev is None else self.a_prev  # now free
        a[...] = end["a1"]
        self.a_prev, self.h_prev, self.a = self.a, h, a
        self._keep_forces(end)
        self.elastic[...] = end["energy"]
        self.dissipated, self.external_work = dissipated, external
        self.kinetic, self.potential, self.energy_rate = kinetic, potential, energy_rate
        self.iterations, self.newton_rate = iterations, rate
        self.stats["steps"] += 1
        return True, "converged"
