"""The time-integration driver: generalized-alpha steps from ``t_start`` to ``t_end``,
step halving on failure, and observers at the saved steps.

``simulate`` does no I/O: it keeps the saved steps in memory (an internal recorder) and
hands every saved step to the ``observers`` (``contract.Observer``), which turn them into
stores, ParaView series, progress bars, custom histories, or stop the run.  The I/O layer
``skfem_cable.io`` supplies the standard observers; ``io.run_observers`` composes them.

Examples
--------
>>> import skfem_cable as sc                                          # doctest: +SKIP
>>> result = sc.simulate(system, t_end=1.0, dt=1e-3,                  # doctest: +SKIP
...                      observers=sc.io.run_observers("runs/a", progress=True))
>>> again = sc.simulate(system, t_end=1.0, dt=1e-3,                   # doctest: +SKIP
...                     resume=sc.io.resume("runs/a"),
...                     observers=sc.io.run_observers("runs/a", restart=True))
"""

import functools
import numbers
import time

import numpy as np

from ..bodies.section import positive_int
from ..control.controller import ControlLoop, check_resumed
from ..core.contract import Run, Step
from ..core.protocols import IntegrableSystem, Observer, StepHook
from ..core.records import FIELDS, SETTINGS, settings_array, step_record
from ..kernels import compile_log
from ..results.result import Result
from .galpha import GeneralizedAlpha
from .observing import Observers
from .rectify import Rectification, check_rectify

#: Positions in ``result.SETTINGS`` that must match when a run is resumed (all but t_end).
_MATCH = [k for k, name in enumerate(SETTINGS) if name != "t_end"]


class _Recorder(Observer):
    """Keeps the saved steps in memory (the returned ``Result``), with the inputs'
    values (``records.INPUT``)."""

    def __init__(self, system, records=None):
        n, n_c = system.n_dofs, system.n_constraints
        self.shapes = {"q": (0, n), "v": (0, n), "a": (0, n), "lam": (0, n_c)}
        self.records = {name: [] for name in FIELDS}
        if records is not None:
            for name in records:
                self.records[name] = list(records[name])

    def saved(self, run, step):
        for name, value in step_record(step).items():
            self.records.setdefault(name, []).append(value)

    def arrays(self):
        return {name: np.asarray(values) if values else np.zeros(self.shapes.get(name, (0,)))
                for name, values in self.records.items()}


def _initial_arrays(system, initial):
    if initial is None:
        return system.q0.copy(), np.zeros(system.n_dofs)
    if isinstance(initial, tuple) and len(initial) == 2:
        q, v = initial
    elif hasattr(initial, "q"):
        q, v = initial.q, getattr(initial, "v", None)
    else:
        raise TypeError("initial must be a State (with q and v) or a pair (q, v), got "
                        f"{type(initial).__name__}")
    q = np.asarray(q, dtype=float)
    v = np.zeros_like(q) if v is None else np.asarray(v, dtype=float)
    if q.shape != (system.n_dofs,) or v.shape != (system.n_dofs,):
        raise ValueError(f"initial.q and initial.v must have shape ({system.n_dofs},)")
    if not (np.all(np.isfinite(q)) and np.all(np.isfinite(v))):
        raise ValueError("initial.q and initial.v must be finite")
    return q.copy(), v.copy()


#: Most steps a run may take: beyond, ``dt`` is almost surely a typo (a billion steps of
#: the smallest system take hours).
MAX_STEPS = 10**9


def _check_steps(t_start, t_end, dt, max_halvings):
    """Refuse step settings that cannot run: a step that does not advance the time in
    floating point, more than ``MAX_STEPS`` steps, ``max_halvings`` outside [0, 51] (a
    step halved 52 times is below the resolution of the time itself)."""
    if (isinstance(max_halvings, bool) or not isinstance(max_halvings, int | np.integer)
            or not 0 <= max_halvings <= 51):
        raise ValueError(f"max_halvings must be an integer in [0, 51], got {max_halvings!r}")
    n_steps = (t_end - t_start) / dt
    if n_steps > MAX_STEPS:
        raise ValueError(f"dt = {dt!r} over [{t_start}, {t_end}] means {n_steps:.3g} steps "
                         f"(at most {MAX_STEPS:.0e}): choose a larger dt")
    for t in (t_start, t_end):
        if t + dt / 2**max_halvings == t:
            raise ValueError(f"dt = {dt!r} (halved down to dt/2^{max_halvings}) does not "
                             f"advance the time t = {t} in floating point: choose a larger "
                             "dt or fewer max_halvings")


class _Clock:
    """Wall time of the time loop, and numba's compile time apart: in the whole call
    (``compile_log.seconds``: compiling, or loading compiled code from the cache) and in
    the loop."""

    def __init__(self):
        self.compile0 = compile_log.seconds()
        self.wall0 = self.compile1 = None

    def start(self):
        """Start the clock of the time loop."""
        self.wall0 = time.perf_counter()
        self.compile1 = compile_log.seconds()

    def times(self):
        """``wall_time``, ``compile_time`` and ``integration_time`` (``wall_time`` less
        the compilation in the loop) so far."""
        wall, compiled = time.perf_counter() - self.wall0, compile_log.seconds()
        return {"wall_time": wall, "compile_time": compiled - self.compile0,
                "integration_time": wall - (compiled - self.compile1)}


def _stats(integ, clock, stopped=None):
    stats = dict(integ.stats)
    stats.update(clock.times())
    stats["solver"] = integ.solver.method
    stats["path"] = integ.step_path
    stats["stopped"] = stopped
    return stats


def _reference(integ):
    """A copy of the run's reference (in orbit; else None) for its ``Result``: the
    orbit and the rebases so far, left alone by a later run on the same system."""
    reference = integ.lay.reference
    return None if reference is None else reference.copy()


def _step_hooks(system, integ, settings, rectify, controllers, t_start, dt) -> list[StepHook]:
    """What acts between steps (``start``, ``after_step``, ``next_event``, ``snapshot``,
    ``restore``): Encke's rectification of a system in orbit (``rectify``), the control
    loop of the ``controllers`` (``control.ControlLoop``), then the terms' own
    (``Term.hooks``: a rod's frames, a density sampled once per step).  Records their
    settings and counters.  A run starts from the model as given: the inputs at their initial values
    (``Layout.inputs``), in orbit the reference without rebases (``Layout.reference``);
    a resumed run then takes its checkpoint's (the hooks' ``restore``)."""
    hooks = []
    integ.lay.inputs.reset()
    reference = integ.lay.reference
    if reference is not None:
        settings["rectify"] = rectify
        reference.restore()
        rectifier = None if rectify is None else Rectification(system, rectify, t_start,
                                                                reference)
        integ.stats.update(rectifications=0, rectification="none" if rectifier is None
                           else rectifier.reason or "on")
        if rectifier is not None and rectifier.reason is None:
            hooks.append(rectifier)
    if controllers:
        hooks.append(ControlLoop(system, controllers, t_start, dt, integ.lay.inputs))
        settings["controllers"] = [f"{c.name}: every {c.sample_time:g} s, delay "
                                   f"{getattr(c, 'delay', 0.0):g} s" for c in controllers]
        integ.stats["control_updates"] = 0
    lay = integ.lay
    hooks += [hook for term, _ in lay.body_terms + lay.load_terms for hook in term.hooks]
    return hooks


def simulate(system: IntegrableSystem, t_end, dt, rho_inf=0.8, initial=None, t_start=0.0, every=1,
             observers=(), resume=None, tol=1e-11, max_iter=12, newton="modified",
             max_halvings=10, method="auto", energy_tol=0.05, compiled=None, rtol=None,
             atol=None, tol_local=None, rectify=1e-4, controllers=(),
             initial_acceleration="consistent", pseudo_acceleration="fitted"):
    """Integrate ``system`` from ``t_start`` to ``t_end`` with steps ``dt``.

    Parameters
    ----------
    system : System
    t_end, dt : float
        End time and step (s); the last step is shortened to end exactly at ``t_end``.
        With ``rtol``/``atol``, ``dt`` is the first step.
    rho_inf : float in [0, 1]
        Spectral radius at infinity (numerical damping of high frequencies).
    initial : State, optional
        Initial ``q`` and ``v`` (default: the bodies' coordinates at rest).  Velocities
        are projected onto the constraints; consistent accelerations and multipliers are
        computed.
    t_start : float
        Initial time (s).
    every : int
        Save every ``every``-th step (and the first and last).
    observers : sequence of Observer
        Called at the start, at every saved step (a ``contract.Step``) and at the end,
        also when the run fails or is interrupted (see ``contract.Observer``).  An
        observer's ``saved`` returning a true value (a message) stops the run cleanly
        after that step.  ``skfem_cable.io`` has the standard observers: ``RunStore``
        (chunked results and checkpoint), ``SeriesObserver`` (ParaView series),
        ``ProgressBar``; ``io.run_observers`` composes them.  Observers see
        ``run.settings`` with ``t_start``, ``t_end``, ``dt``, ``rho_inf``, ``every``,
        ``tol``, ``max_iter``, ``newton``, ``max_halvings``, ``method`` and ``n_steps``.
    resume : object, optional
        Continue an interrupted run: ``resume.snapshot`` (a checkpoint: the integrator's
        ``snapshot()`` with ``index``, ``settings`` and ``stat_*``) and ``resume.records``
        (the steps saved so far), e.g. ``io.resume(run_dir)``.  ``t_start``, ``dt``,
        ``rho_inf``, ``every``, ``tol`` and ``max_iter`` must match the interrupted run;
        the continuation is bit-for-bit the uninterrupted run.  Observers are not called
        at the initial state.
    tol, max_iter, newton, method, energy_tol, compiled, tol_local, initial_acceleration, \
    pseudo_acceleration
        See ``GeneralizedAlpha``; ``initial_acceleration="zero"`` starts from zero
        accelerations instead of consistent ones (Exudyn's tests do), and
        ``pseudo_acceleration="initial"`` takes ``abar_0 = a_0`` instead of fitting it to
        the first step (Exudyn's start: ``docs/peers.md``); ``energy_tol`` is the
        instability guard (on by default: a step whose energy balance grows by more than
        ``energy_tol`` times the energy content of the run is retried smaller; None
        switches it off).
    max_halvings : int
        A failed step is retried as two half steps, recursively, down to
        ``dt / 2**max_halvings``; below that ``SimulationError`` is raised.
    rtol, atol : float, optional
        Adaptive steps whose global error follows ``rtol``: each step's estimated local
        error must lie below ``(atol + rtol |q|) (rtol / 1e-3)^(1/2)`` (``atol`` in metres;
        the proportionality transform of ``GeneralizedAlpha``, 1e-3 its
        ``TOLERANCE_PIVOT``); the next step is
        ``h min(2, 0.9 r^(-1/3))`` with ``r`` the ratio of error to tolerance (kept
        unchanged when that would grow it by less than 25 %, so the factored iteration
        matrix is reused), a rejected step is retried with ``h max(0.2, 0.9 r^(-1/3))``
        (halved after a Newton failure), down to ``dt / 2**max_halvings``.  ``every``
        then counts accepted steps.  Without them the steps are fixed: bit-for-bit
        reproducible, and each one ends on ``t_start + i dt``.
    rectify : float or None
        A system in orbit: Encke's rectification (``solvers.rectify``) re-bases the
        reference orbit on the osculating orbit of the centre of mass after any step
        that leaves the centre of mass further than ``rectify |R|`` from the reference
        point, or faster than ``rectify |V|`` relative to it; None: never.  Off (and
        said in ``stats["rectification"]``) when a constraint ties the system to the
        reference point.  The rebases are the run's (``orbit.Reference``, in its
        checkpoints and its ``Result.reference``): the system's ``Orbit`` stays as
        given, every fresh run starts on it, a continued one takes the rebases from its
        checkpoint.
    controllers : sequence of control.Controller
        Closed-loop control (``control``): each controller's ``update(t, state)`` is
        called at ``t_start + k sample_time`` and the inputs (``inputs.Input``) it names
        hold its outputs from ``t + delay`` on.  With fixed steps, sample times and
        delays are multiples of ``dt``; adaptive steps end on them.  At ``t_start`` the
        first outputs apply before the run's consistent initial state is solved.  The
        held inputs, the controllers' ``memory`` and attributes of numbers and arrays and
        the delayed outputs are in the checkpoints: a controlled run continues bit for
        bit, or is refused naming the controller and what a checkpoint cannot hold or
        what differs from the run's start (``control``).

    Returns
    -------
    Result
        The saved steps (with those of the interrupted run when resuming); ``stats``
        holds ``steps``, ``rejected``, ``newton``, ``factorizations``, ``wall_time``
        (of the time loop), ``compile_time`` (numba compiling the kernels, or loading them
        from its cache, in the whole call: the first run on a machine compiles),
        ``integration_time`` (``wall_time`` less the compilation in it), ``solver``,
        ``path`` (``GeneralizedAlpha.step_path``: the compiled Newton step and its
        Python parts, or its interpreted run), ``stopped`` (the message of the observer
        that stopped the run, or None) and, with ``rtol``/``atol``, ``h_min`` and
        ``h_max``, the smallest and largest accepted steps; in orbit ``rectification``
        (``"on"``, ``"none"`` or why it is off) and ``rectifications`` (how many
        rebases); with controllers ``control_updates`` (their calls).

    Raises
    ------
    SimulationError
        A step failed at the smallest step size; its ``result`` holds the saved steps.
    system.SystemChanged
        The system changed during the run (an observer or a controller edited a load,
        a section, a constraint): the run takes the system as it is at its start
        (``System.current_layout``) and cannot take an edit midway; the message names
        what changed, the ``result`` holds the saved steps.  Checked at the end of a run
        in which Python code could have edited the system: observers, step hooks
        (controllers, rectification, terms' hooks) or a step with Python parts (terms'
        ``add`` hooks, constraints without a kernel; ``compiled=False``).  A fully
        compiled run without them runs none of it, and the check, a description of the
        system, is left out.
    """
    for name, value in (("t_end", t_end), ("dt", dt), ("t_start", t_start)):
        if isinstance(value, bool) or not isinstance(value, numbers.Real):
            raise TypeError(f"{name} must be a number (s), got {value!r}")
        if not np.isfinite(value):
            raise ValueError(f"{name} must be finite, got {value!r}")
    if not dt > 0:
        raise ValueError(f"dt must be > 0, got {dt!r}")
    if not t_end > t_start:
        raise ValueError(f"t_end must be > t_start = {t_start}, got {t_end!r}")
    positive_int("every", every)
    check_rectify(rectify)
    _check_steps(t_start, t_end, dt, max_halvings)
    clock = _Clock()
    integ = GeneralizedAlpha(system, rho_inf, tol, max_iter, newton, method, energy_tol,
                             compiled, rtol, atol, tol_local, initial_acceleration,
                             pseudo_acceleration)
    adaptive = integ.rtol is not None
    n_steps = None if adaptive else int(np.ceil((t_end - t_start) / dt - 1e-9))
    settings = {"t_start": t_start, "t_end": t_end, "dt": dt, "rho_inf": rho_inf,
                "every": int(every), "tol": tol, "max_iter": max_iter, "newton": newton,
                "max_halvings": max_halvings, "method": method, "energy_tol": energy_tol,
                "n_steps": n_steps}
    if adaptive:
        settings.update(rtol=rtol, atol=atol)
    if tol_local is not None:
        settings["tol_local"] = tol_local
    if initial_acceleration != "consistent":
        settings["initial_acceleration"] = initial_acceleration
    if pseudo_acceleration != "fitted":
        settings["pseudo_acceleration"] = pseudo_acceleration
    inputs = integ.lay.inputs  # the run's values of the inputs
    outputs = [term for term, _ in integ.lay.load_terms if term.outputs is not None]
    hooks = integ.hooks = _step_hooks(system, integ, settings, rectify, controllers,
                                      t_start, None if adaptive else dt)
    if resume is not None:
        snap = resume.snapshot
        if not np.allclose(np.asarray(snap["settings"])[_MATCH],
                           settings_array(settings)[_MATCH]):
            raise ValueError("resume: t_start, dt, rho_inf, every, tol and max_iter must "
                             "match the interrupted run")
        check_resumed(controllers, snap)
        for hook in hooks:
            hook.restore(snap)
        integ.restore(snap)
        integ.stats.update({k: int(snap["stat_" + k]) for k, v in integ.stats.items()
                            if "stat_" + k in snap and not isinstance(v, str)})
        start_index = int(snap["index"])
        recorder = _Recorder(system, resume.records)
    else:
        q, v = _initial_arrays(system, initial)
        integ.initialize(q, v, t_start)
        for hook in hooks:
            hook.start(integ)
        start_index = 0
        recorder = _Recorder(system)
    run = Run(system, integ, settings, integ.stats, resumed=resume is not None,
              make_result=functools.partial(Result, system))
    watch = Observers(run, [recorder, *(observers or ())],
                      lambda: Result(system, recorder.arrays(), _stats(integ, clock),
                                     integ.lay.description, _reference(integ)))
    clock.start()

    def save(index):
        """Hand the current state to every observer; returns a stop message or None."""
        return watch.saved(Step(index, integ.t, integ.q, integ.v, integ.a, integ.lam,
                                integ.iterations, integ.energies(), inputs.snapshot(),
                                {name: value for term in outputs
                                 for name, value in term.outputs().items()}))

    def fixed_steps(i, stop):
        while stop is None and i < n_steps:
            i += 1
            t_target = t_end if i == n_steps else t_start + i * dt
            integ.advance(t_target - integ.t, max_halvings)
            for hook in hooks:
                hook.after_step(integ)
            if i % every == 0 or i == n_steps:
                stop = save(i)
        return stop

    def adaptive_steps(i, stop):
        last = False
        while stop is None and not last:
            target = min([t_end, *(hook.next_event(integ.t) for hook in hooks)])
            last = integ.adaptive_step(target, dt, max_halvings) and target == t_end
            for hook in hooks:
                hook.after_step(integ)
            i += 1
            if i % every == 0 or last:
                stop = save(i)
        return stop

    with watch:  # whatever stops the run, the steps computed so far travel with the error
        stop = save(0) if start_index == 0 else None
        stop = (adaptive_steps if adaptive else fixed_steps)(start_index, stop)
        if observers or hooks or integ.step_path != "compiled":  # code that can edit
            system.check_unchanged(integ.lay, "during the run")  # ran: its edit refused
        run.stop_reason = stop
    return Result(system, recorder.arrays(), _stats(integ, clock, run.stop_reason),
                  integ.lay.description, _reference(integ))
