"""Time integration of a rod chain (Eq. 21): classical RK4 in compiled blocks (or in
Python with a callable line load) and the adaptive ``scipy.integrate`` methods, with the
observers of ``contract.Observer``.

Observers see the run as ANCF runs do: ``start(run)`` with a ``contract.Run`` whose
``system`` is the chain and whose ``integrator`` is the ``Integration``; ``saved(run,
step)`` with a ``contract.Step`` at the initial state and every saved step (``q``, ``v``,
``a``: the rod vectors, their rates and accelerations flattened to ``(3 n,)``; ``lam``
empty; ``iterations`` 0; ``energies`` with the keys of ``result.ENERGIES``); a true value
returned by ``saved`` stops the run after that step; ``finish(run, error)`` at the end,
also after a failure.  The compiled RK4 advances a block of steps per call, so observers
hear of the saved steps of a block when the block is done (blocks of at most 32768 steps
and about 4e6 rod-steps, a fraction of a second); the Python RK4 and the adaptive methods
call them as each saved step is reached.  A stop ends the result at the stop step.  With
observers every saved step costs one evaluation of the accelerations and of the energies
(some 30 us for a short chain): save sparsely when the chain is short and the step small.

A run continues from any of its saved steps bit for bit (``resume``): the run's
``system`` (a ``stored.ChainSystem``) is what ``io.RunStore`` labels and fingerprints,
and ``Integration.snapshot`` is the checkpoint of the saved step being handed out (rod
vectors, rates, the work so far and, for an adaptive method, the state of scipy's
stepper).  RK4 steps are counted from the start of the run, so the loads' time table and
hence every step are those of the uninterrupted run; the work adds up step by step in the
same order.
"""

import functools
import time

import numpy as np

from ..core.contract import Run, Step
from ..core.records import ENERGIES
from ..io.matching import check_fingerprint
from ..kernels import rodchain as kern
from ..results.result import Result
from ..solvers.observing import Observers
from .export import ChainSeriesWriter
from .result import RodChainResult, energies
from .stored import ChainSystem

METHODS = ("rk4", "RK45", "DOP853")
RK4_STABILITY = 2.0 * np.sqrt(2.0)  # RK4 is stable on the imaginary axis for |h w| <= 2 sqrt 2
_BLOCK_STEPS = 1 << 15  # RK4 steps per compiled call (bounds the anchor-field table)
_BLOCK_WORK = 1 << 22  # rod-steps per compiled call (observers hear of every block)
#: The state of a scipy Runge-Kutta stepper after a step (``K_extended``: DOP853's
#: stages, of which ``K`` is a view; RK45 has ``K`` only).
_STEPPER = ("t", "y", "f", "h_abs", "h_previous", "t_old", "y_old", "nfev")


def rk4_step(chain, output_dt, safety=0.7):
    """Largest RK4 step ``output_dt / k`` (integer ``k``) below ``safety *
    chain.stable_dt()``: saved steps every ``k`` steps fall on the grid ``output_dt``."""
    return output_dt / np.ceil(output_dt / (safety * chain.stable_dt()))


class RodChainDivergence(RuntimeError):
    """A time integration left the admissible states (non-finite or over-stretched rod).

    Attributes ``t`` (s), ``step`` (index of the failing step, or None for adaptive
    methods) and ``rod`` (0-based index of the offending rod) locate the failure;
    ``result`` holds the saved steps before it (a ``RodChainResult``).
    """

    def __init__(self, message, t, step=None, rod=None):
        super().__init__(message)
        self.t = t
        self.step = step
        self.rod = rod


def divergence(chain, problem, q, t, step, rod, dt):
    """The ``RodChainDivergence`` of rod ``rod`` in the rod vectors ``q`` at time ``t``."""
    l = np.linalg.norm(q[rod])
    msg = (f"rod-chain integration diverged at t = {t:.6g} s"
           + (f" (step {step}, dt = {dt:g} s)" if step is not None else "")
           + f": rod {rod} has length {l:.6g} m, rest length {chain.lengths[rod]:.6g} m "
           f"(admissible: (0, {1 + problem.max_strain:g} l0], finite). "
           f"RK4 is stable for dt below about {chain.stable_dt():.3g} s.")
    return RodChainDivergence(msg, t, step, rod)


class Integration:
    """A rod-chain time integration as observers see it (``contract.Run.integrator``).

    Attributes
    ----------
    chain : RodChain
    problem : Problem
        The loads and the anchor motion.
    method : str
    dt : float
        RK4 step, or the spacing of the output grid of an adaptive method (s).
    every : int
        Saved every ``every``-th step (RK4) or grid point.
    times : ndarray
        Times of the saved steps.
    t : float
        Time of the last state computed; ``q``, ``v`` (n, 3) that state.
    stats : dict
        ``method``, ``dt``, ``steps``, ``nfev``, ``saved``; adaptive: ``rtol``, ``atol``.
    saved : (Q, V, work, power)
        The saved rod vectors, rates (nt, n, 3), the work of the run and the power of its
        loads (nt,).
    at : int
        The saved step being handed to the observers (``snapshot`` is its checkpoint).
    """

    def __init__(self, chain, problem, method, dt, every, times, saved, rtol=None,
                 atol=None):
        self.chain, self.problem = chain, problem
        self.method, self.dt, self.every, self.times = method, dt, every, times
        self.saved, self.at = saved, 0
        self.rtol, self.atol = rtol, atol
        self.t, self.q, self.v = 0.0, None, None
        self.stepper, self._stepper_state = None, None
        self.stats = {"method": method, "dt": dt, "steps": 0, "nfev": 0, "saved": 0}
        if method != "rk4":
            self.stats.update(rtol=rtol, atol=atol)

    def anchor(self, t):
        """Position, velocity and acceleration of the anchor ``O_0`` at time ``t``, (3,)."""
        return tuple(x[0] for x in self.problem.anchor(np.array([float(t)])))

    def snapshot(self):
        """The checkpoint of the saved step ``at``: its time ``t``, rod vectors ``q``,
        rates ``v``, the ``work`` so far, the loads' ``power`` and, once an adaptive
        method has stepped, the stepper's state (``stepper_*``; the step that reached
        ``at`` also covers the saved steps up to the next step's start)."""
        Q, V, work, power = self.saved
        k = self.at
        snap = {"t": np.float64(self.times[k]), "q": Q[k].copy(), "v": V[k].copy(),
                "work": np.float64(work[k]), "power": np.float64(power[k])}
        if self.stepper is not None and self.stepper.t_old is not None:
            arrays = ("K_extended",) if hasattr(self.stepper, "K_extended") else ("K",)
            snap.update({"stepper_" + a: np.copy(getattr(self.stepper, a))
                         for a in _STEPPER + arrays})
        return snap

    def restore(self, resume):
        """Continue from the checkpoint and saved steps of ``resume`` (``io.Resume``):
        fill the saved steps so far and return the index of the last one."""
        snap, records = resume.snapshot, resume.records
        Q, V, work, power = self.saved
        index = int(snap["index"])
        k = index // self.every
        if k * self.every != index or len(records["t"]) != k + 1 or k >= self.times.size:
            raise ValueError(f"resume: the checkpoint is at step {index} with "
                             f"{len(records['t'])} saved steps, which is not a saved step of "
                             f"this run (every {self.every} steps, up to saved step "
                             f"{self.times.size - 1})")
        self.times[:k + 1] = records["t"]
        Q[:k + 1] = np.asarray(records["q"]).reshape(k + 1, self.chain.n, 3)
        V[:k + 1] = np.asarray(records["v"]).reshape(k + 1, self.chain.n, 3)
        work[:k + 1] = records["external_work"]
        Q[k], V[k] = snap["q"], snap["v"]  # also when the store left them out
        work[k], power[k] = snap["work"], snap["power"]
        self.t, self.q, self.v, self.at = float(snap["t"]), Q[k], V[k], k
        self.stats.update(steps=int(snap["stat_steps"]), nfev=int(snap["stat_nfev"]),
                          saved=k + 1)
        if "stepper_t" in snap:
            self._stepper_state = {key[8:]: snap[key] for key in snap
                                   if key.startswith("stepper_")}
        return k

    def series_writer(self, run_dir, writer, append=False, frame="inertial", **detail):
        """The writer of the run's ParaView series (``io.SeriesObserver``): the chain's
        joints with the anchor of the run (``rodchain.export.ChainSeriesWriter``, not the
        writer of a system of bodies ``writer`` that the observer offers), in the
        inertial frame only."""
        if frame != "inertial":
            raise ValueError(f"a rod-chain run is written in the inertial frame, not "
                             f"{frame!r}")
        return ChainSeriesWriter(run_dir, self.chain, append=append, anchor=self.anchor)

    def outputs(self, Q, V, start=0):
        """Fill ``Q[start + 1:], V[start + 1:]`` (saved rod vectors and rates from those
        of the saved step ``start``), yielding the ranges ``(k0, k1)`` of saved steps
        filled and checked."""
        if self.method == "rk4":
            run = self._rk4_python if self.problem.line_callable else self._rk4_compiled
        else:
            run = self._adaptive
        yield from run(Q, V, start)

    def _count(self, steps, nfev_per_step=4):
        self.stats["steps"] += steps
        self.stats["nfev"] += nfev_per_step * steps

    def _rk4_compiled(self, Q, V, start):
        c, p, dt, every = self.chain, self.problem, self.dt, self.every
        nout = Q.shape[0] - 1
        q, v = Q[start].copy(), V[start].copy()
        per_block = max(1, min(_BLOCK_STEPS, _BLOCK_WORK // c.n) // every)
        j = start
        while j < nout:
            m = min(per_block, nout - j)
            s0, steps = j * every, m * every
            gtab = np.ascontiguousarray(p.field(dt * (s0 + 0.5 * np.arange(2 * steps + 1))))
            step, rod = kern.rk4_block(q, v, dt, steps, every, c.masses, c.lengths, c.EA,
                                       c.compression, c._a, c._b, gtab, p.w, p.tip,
                                       p.max_strain, Q[j + 1: j + 1 + m], V[j + 1: j + 1 + m])
            if step >= 0:  # the state after ``step`` steps failed; those before are good
                self._count(step)
                self.t, self.q, self.v = (s0 + step) * dt, q, v
                valid = max(0, (step - 1) // every)
                if valid:
                    yield j + 1, j + 1 + valid
                raise divergence(c, p, q, (s0 + step) * dt, s0 + step, rod, dt)
            self._count(steps)
            self.t, self.q, self.v = self.times[j + m], Q[j + m], V[j + m]
            yield j + 1, j + 1 + m
            j += m

    def _rk4_python(self, Q, V, start):
        """Classical RK4 with the right-hand side evaluated in Python (callable loads)."""
        c, p, dt, every = self.chain, self.problem, self.dt, self.every
        nsteps = (Q.shape[0] - 1) * every
        q, v = Q[start].copy(), V[start].copy()
        h = 0.5 * dt
        pending = None  # a saved step is handed out once the next step has checked it
        for s in range(start * every, nsteps):
            t = s * dt
            a1, bad = p.acceleration(t, q, v)
            if bad >= 0:
                raise divergence(c, p, q, t, s, bad, dt)
            if pending is not None:
                yield pending, pending + 1
                pending = None
            q2, v2 = q + h * v, v + h * a1
            a2 = p.acceleration(t + h, q2, v2)[0]
            q3, v3 = q + h * v2, v + h * a2
            a3 = p.acceleration(t + h, q3, v3)[0]
            q4, v4 = q + dt * v3, v + dt * a3
            a4 = p.acceleration(t + dt, q4, v4)[0]
            q = q + dt / 6 * (v + 2 * v2 + 2 * v3 + v4)
            v = v + dt / 6 * (a1 + 2 * a2 + 2 * a3 + a4)
            self._count(1)
            self.t, self.q, self.v = (s + 1) * dt, q, v
            if (s + 1) % every == 0:
                k = (s + 1) // every
                Q[k], V[k] = q, v
                self.t = self.times[k]
                pending = k
        bad = p.acceleration(nsteps * dt, q, v)[1]
        if bad >= 0:
            raise divergence(c, p, q, nsteps * dt, nsteps, bad, dt)
        if pending is not None:
            yield pending, pending + 1

    def _adaptive(self, Q, V, start):
        """``scipy.integrate.RK45`` / ``DOP853`` stepped as ``solve_ivp`` does, the saved
        steps from the dense output of the step that reaches them."""
        c, p, times = self.chain, self.problem, self.times
        n, n3 = c.n, 3 * c.n

        def rhs(t, y):
            dy = np.empty_like(y)
            dy[:n3] = y[n3:]
            p.acceleration(t, y[:n3].reshape(n, 3), y[n3:].reshape(n, 3),
                           dy[n3:].reshape(n, 3))
            return dy

        y0 = np.concatenate([Q[start].ravel(), V[start].ravel()])
        limit = (1 + p.max_strain) * c.lengths
        import scipy.integrate  # here, not at import (0.2 s)

        with np.errstate(all="ignore"):  # trial stages may overflow; the result is checked
            solver = getattr(scipy.integrate, self.method)(rhs, times[start], y0, times[-1],
                                            rtol=self.rtol, atol=self.atol)
        if self._stepper_state is not None:
            _set_stepper(solver, self._stepper_state)
        self.stepper = solver
        k = start + 1
        while k < times.size:
            with np.errstate(all="ignore"):
                message = solver.step()
            self.stats["steps"] += 1
            self.stats["nfev"] = solver.nfev
            if solver.status == "failed":
                raise RodChainDivergence(f"{self.method} stopped at t = {solver.t:.6g} s: "
                                         f"{message}", float(solver.t))
            k1 = int(np.searchsorted(times, solver.t, side="right"))
            if solver.status == "finished":
                k1 = times.size
            if k1 > k:
                with np.errstate(all="ignore"):
                    y = solver.dense_output()(times[k:k1]).T
                Q[k:k1] = y[:, :n3].reshape(-1, n, 3)
                V[k:k1] = y[:, n3:].reshape(-1, n, 3)
                l = np.linalg.norm(Q[k:k1], axis=-1)
                good = (l > 0) & (l <= limit)
                ok = np.isfinite(V[k:k1]).all(axis=(1, 2)) & good.all(axis=1)
                self.t, self.q, self.v = solver.t, Q[k1 - 1], V[k1 - 1]
                if not ok.all():
                    bad = k + int(np.argmin(ok))
                    if bad > k:
                        yield k, bad
                    rod = int(np.argmin(good[bad - k]))
                    raise divergence(c, p, Q[bad], float(times[bad]), None, rod, None)
                yield k, k1
                k = k1


def _set_stepper(solver, state):
    """Put a scipy Runge-Kutta ``solver`` in the ``state`` of ``Integration.snapshot``
    (the stage arrays in place: DOP853's ``K`` is a view of ``K_extended``)."""
    for name, value in state.items():
        if name in ("K", "K_extended"):
            getattr(solver, name)[...] = value
        elif name in ("y", "f", "y_old"):
            setattr(solver, name, np.array(value))
        else:
            setattr(solver, name, value.item())


def integrate(chain, problem, q0, v0, t_end, dt, nsteps, every, method, rtol=None, atol=None,
              observers=(), resume=None):
    """Integrate ``problem`` from ``q0, v0`` (checked by ``RodChain.simulate``) over
    ``nsteps`` steps of ``dt`` (RK4) or grid intervals (adaptive), saving every
    ``every``-th; returns a ``RodChainResult``.  See the module docstring for observers.
    ``resume`` (``io.resume(path)``) continues a stored run of the same system and
    settings (``io.fingerprint.check_fingerprint``) from its last checkpoint; observers
    then hear of the steps after it only."""
    times = dt * every * np.arange(nsteps // every + 1)
    times[-1] = t_end
    Q = np.empty((times.size, chain.n, 3))
    V = np.empty_like(Q)
    Q[0], V[0] = q0, v0
    power, work = np.zeros(times.size), np.zeros(times.size)
    integ = Integration(chain, problem, method, dt, every, times, (Q, V, work, power), rtol,
                        atol)
    integ.q, integ.v = Q[0], V[0]
    settings = {"t_start": 0.0, "t_end": t_end, "dt": dt, "every": every, "method": method,
                "n_steps": nsteps, "rtol": rtol, "atol": atol,
                "max_strain": problem.max_strain}
    system = ChainSystem(chain, problem, q0)
    start = 0
    if resume is not None:
        if resume.manifest:
            check_fingerprint(resume.path, resume.manifest, system, settings)
        start = integ.restore(resume)
    run = Run(system, integ, settings, integ.stats, resumed=resume is not None,
              make_result=functools.partial(Result, system))
    wall0 = time.perf_counter()
    count = start + 1
    watch = Observers(run, observers, lambda: result(count))

    def book(k0, k1):
        """The work of the loads without potential up to the saved steps k0..k1-1
        (trapezoidal rule, added step by step: the same sums in any batches)."""
        if problem.does_work:
            power[k0:k1] = problem.power(times[k0:k1], Q[k0:k1], V[k0:k1])
            j = max(k0, 1)
            steps = 0.5 * (power[j:k1] + power[j - 1:k1 - 1]) * np.diff(times[j - 1:k1])
            work[j - 1:k1] = np.cumsum(np.concatenate(([work[j - 1]], steps)))
        integ.stats["saved"] = k1

    def notify(k0, k1):
        """Hand the saved steps k0..k1-1 to the observers: ``(stop message, step)``."""
        if not watch.observers:
            return None, None
        E = energies(chain, problem, times[k0:k1], Q[k0:k1], V[k0:k1], work[k0:k1])
        for k in range(k0, k1):
            integ.at = k
            a = problem.acceleration(times[k], Q[k], V[k])[0]
            stop = watch.saved(Step(k * every, float(times[k]), Q[k].reshape(-1),
                                    V[k].reshape(-1), a.reshape(-1), np.zeros(0), 0,
                                    {name: float(E[name][k - k0]) for name in ENERGIES}))
            if stop is not None:
                return stop, k
        return None, None

    def result(count, stop=None):
        stats = dict(integ.stats, saved=count, wall_time=time.perf_counter() - wall0,
                     stopped=stop)
        cut = (lambda x: x[:count].copy()) if count < times.size else (lambda x: x)
        return RodChainResult(chain, problem, cut(times), cut(Q), cut(V), cut(work), stats)

    with watch:
        stop = at = None
        if resume is None:
            book(0, 1)
            stop, at = notify(0, 1)
        if stop is None:
            batches = integ.outputs(Q, V, start)
            try:
                for k0, k1 in batches:
                    book(k0, k1)
                    count = k1
                    stop, at = notify(k0, k1)
                    if stop is not None:
                        break
            finally:
                batches.close()
        if stop is not None:
            count = at + 1
            integ.t, integ.q, integ.v = float(times[at]), Q[at], V[at]
            integ.stats["saved"] = count
        run.stop_reason = stop
    return result(count, stop)
