"""Closed-loop control: a ``Controller`` reads the state at its samples and sets inputs
(``inputs.Input``), which hold between samples (zero-order hold); ``ControlLoop`` runs the
controllers of a ``simulate`` run.

**The contract.** A controller has one hook, ``update(t, state) -> dict`` (input name to
new value), a ``sample_time`` (s) and an optional ``delay`` (s).  The run calls it at ``t
= t_start + k sample_time`` (``k = 0, 1, ...``, the steps end on those times) with the
``State`` there, and the inputs take its outputs at ``t + delay``, holding them until its
next outputs are due.  A controller keeps what it remembers between samples (an
integral, a filter) in ``self.memory``, a dict of numbers and arrays: it is saved in
checkpoints with the held inputs and the outputs still delayed, so an interrupted
controlled run continues bit for bit.  A controller that raises, names an input the
system does not have or gives a value an input cannot hold stops the run with
``ControlError`` naming it; the steps so far travel with the error (``err.result``).
"""

import numpy as np

from .inputs import system_inputs
from .state import State

#: Relative tolerance of times that fall on a sample or a delay.
TIME_TOL = 1e-9


class ControlError(RuntimeError):
    """A controller failed or gave outputs the system cannot take."""


class Controller:
    """A controller: ``update(t, state)`` returns the new values of inputs by name,
    every ``sample_time`` seconds, applied ``delay`` seconds later.

    Parameters
    ----------
    sample_time : float
        Seconds between samples, > 0; a multiple of a fixed-step run's ``dt``.
    delay : float
        Seconds from a sample to its outputs taking effect, >= 0 (a multiple of ``dt``
        with fixed steps).
    name : str, optional
        For messages (default: the class name).

    Attributes
    ----------
    memory : dict
        Numbers and arrays the controller keeps between samples (saved in checkpoints).

    Examples
    --------
    A proportional-integral control of a hub's spin rate through one input:

    >>> import skfem_cable as sc
    >>> class SpinHold(sc.Controller):
    ...     def __init__(self, hub, target):
    ...         super().__init__(sample_time=1.0)
    ...         self.hub, self.target = hub, target
    ...         self.memory["integral"] = 0.0
    ...     def update(self, t, state):
    ...         error = self.target - sc.sensors.spin_rate(state, self.hub)
    ...         self.memory["integral"] += error * self.sample_time
    ...         return {"torque": 2.0 * error + 0.1 * self.memory["integral"]}
    """

    def __init__(self, sample_time, delay=0.0, name=None):
        if not (np.isfinite(sample_time) and sample_time > 0):
            raise ValueError(f"sample_time must be a finite number > 0 (s), got "
                             f"{sample_time!r}")
        if not (np.isfinite(delay) and delay >= 0):
            raise ValueError(f"delay must be a finite number >= 0 (s), got {delay!r}")
        self.sample_time, self.delay = float(sample_time), float(delay)
        self.name = name or type(self).__name__
        self.memory = {}

    def update(self, t, state):
        """The hook: new input values ``{name: value}`` at the sample time ``t`` from the
        ``State`` ``state`` (``q``, ``v``, ``lam``; read it with ``sc.sensors``)."""
        raise NotImplementedError(f"{type(self).__name__} must define update(t, state)")


class ControlLoop:
    """The controllers of a run: their samples, the held inputs and the delayed outputs.

    Parameters
    ----------
    system : System
    controllers : sequence of Controller
    t_start : float
    dt : float or None
        The fixed step (samples and delays must be multiples of it); None for adaptive
        steps (which end on the samples, ``next_event``).
    inputs : dict, optional
        The system's inputs by name (``inputs.system_inputs``, looked up when not
        given: ``simulate`` passes the ones it records).
    """

    def __init__(self, system, controllers, t_start, dt=None, inputs=None):
        self.system, self.controllers = system, list(controllers)
        self.inputs = system_inputs(system) if inputs is None else inputs
        for c in self.controllers:
            if not callable(getattr(c, "update", None)) or not hasattr(c, "sample_time"):
                raise TypeError(f"{c!r} is not a Controller (needs update(t, state) and "
                                "sample_time)")
            for what in ("sample_time", "delay"):
                value = getattr(c, what, 0.0)
                if dt is not None and value and not _multiple(value, dt):
                    raise ValueError(f"controller {c.name!r}: {what} = {value!r} s must be a "
                                     f"multiple of the step dt = {dt!r} s (the steps end on "
                                     "samples)")
        self.t_start = float(t_start)
        self.samples = np.zeros(len(self.controllers), dtype=np.int64)  # next sample k
        self.pending = []  # [time, controller index, {name: value}], in time order

    # --- the step hook (``simulate``) ---------------------------------------------------
    def start(self, integrator):
        """A fresh run (its inputs at their initial values): the controllers' first
        samples at ``t_start``; when their outputs change inputs at once, the initial
        state is solved again with them (consistent accelerations)."""
        self.samples[:] = 0
        self.pending = []
        before = {name: x.value for name, x in self.inputs.items()}
        self.after_step(integrator)
        if any(x.value is not before[name] for name, x in self.inputs.items()):
            integrator.initialize(integrator.q, integrator.v, integrator.t)

    def after_step(self, integrator):
        """At the end of a step: sample the controllers that are due, then apply the
        outputs whose time has come (in the order they were given)."""
        t, q, v, lam = integrator.t, integrator.q, integrator.v, integrator.lam
        state = None
        for k, c in enumerate(self.controllers):
            due = self.t_start + self.samples[k] * c.sample_time
            if t < due - TIME_TOL * c.sample_time:
                continue
            if state is None:
                state = State(self.system, q.copy(), lam.copy(), v=v.copy(), t=t)
            outputs = self._call(c, t, state)
            self.samples[k] += 1
            integrator.stats["control_updates"] += 1
            self.pending.append([t + getattr(c, "delay", 0.0), k, outputs])
            if len(self.pending) > 1:
                self.pending.sort(key=lambda item: item[0])
        while self.pending and t >= self.pending[0][0] - TIME_TOL * max(abs(t), 1.0):
            _, k, outputs = self.pending.pop(0)
            for name, value in outputs.items():
                self.inputs[name].value = value  # checked by _call

    def next_event(self, t):
        """The next time after ``t`` at which a controller samples or an output is
        due: where an adaptive step must end."""
        times = [self.t_start + n * c.sample_time
                 for n, c in zip(self.samples, self.controllers)]
        times += [p[0] for p in self.pending]
        later = [x for x in times if x > t * (1 + TIME_TOL) + TIME_TOL]
        return min(later, default=np.inf)

    def _call(self, controller, t, state):
        try:
            outputs = controller.update(t, state)
        except Exception as err:
            raise ControlError(f"controller {controller.name!r} failed at t = {t:.6g} s: "
                               f"{type(err).__name__}: {err}") from err
        if not isinstance(outputs, dict):
            raise ControlError(f"controller {controller.name!r} returned "
                               f"{type(outputs).__name__} at t = {t:.6g} s: update must "
                               "return a dict of input names to values")
        checked = {}
        for name, value in outputs.items():
            if name not in self.inputs:
                known = ", ".join(sorted(self.inputs)) or "none"
                raise ControlError(f"controller {controller.name!r} set the input {name!r} "
                                   f"at t = {t:.6g} s, which the system does not have "
                                   f"(its inputs: {known})")
            try:  # shape and finiteness checked now, not when applied
                checked[name] = self.inputs[name].checked(value)
            except ValueError as err:
                raise ControlError(f"controller {controller.name!r} at t = {t:.6g} s: "
                                   f"{err}") from err
        return checked

    # --- checkpoints ------------------------------------------------------------------
    def snapshot(self):
        """The loop's state for a checkpoint: the held inputs, the sample counters, the
        delayed outputs and each controller's ``memory`` (arrays keyed ``control_*``)."""
        snap = {"control_samples": self.samples.copy()}
        for name, x in self.inputs.items():
            snap[f"control_input:{name}"] = x.value.copy()
        for i, (time, k, outputs) in enumerate(self.pending):
            snap[f"control_pending:{i}:time"] = np.float64(time)
            snap[f"control_pending:{i}:controller"] = np.int64(k)
            for name, value in outputs.items():
                snap[f"control_pending:{i}:value:{name}"] = np.array(value)
        for k, c in enumerate(self.controllers):
            for key, value in c.memory.items():
                snap[f"control_memory:{k}:{key}"] = np.array(value)
        return snap

    def restore(self, snap):
        """Take the state of ``snapshot`` back (a continued run)."""
        self.samples[:] = snap["control_samples"]
        for name, x in self.inputs.items():
            x.value = np.array(snap[f"control_input:{name}"])
        pending = {}
        for key in snap:
            if key.startswith("control_pending:"):
                _, i, what = key.split(":", 2)
                entry = pending.setdefault(int(i), [0.0, 0, {}])
                if what == "time":
                    entry[0] = float(snap[key])
                elif what == "controller":
                    entry[1] = int(snap[key])
                else:
                    entry[2][what.split(":", 1)[1]] = np.array(snap[key])
        self.pending = [pending[i] for i in sorted(pending)]
        for k, c in enumerate(self.controllers):
            prefix = f"control_memory:{k}:"
            for key in snap:
                if key.startswith(prefix):
                    value = np.array(snap[key])
                    c.memory[key[len(prefix):]] = value.item() if value.ndim == 0 else value


def _multiple(value, dt):
    ratio = value / dt
    return abs(ratio - round(ratio)) <= TIME_TOL * max(ratio, 1.0) and round(ratio) >= 1
