"""Closed-loop control: a ``Controller`` reads the state at its samples and sets inputs
(``inputs.Input``), which hold between samples (zero-order hold); ``ControlLoop`` runs the
controllers of a ``simulate`` run.

**The contract.** A controller has one hook, ``update(t, state) -> dict`` (input name to
new value), a ``sample_time`` (s) and an optional ``delay`` (s).  The run calls it at ``t
= t_start + k sample_time`` (``k = 0, 1, ...``, the steps end on those times) with the
``State`` there, and the inputs take its outputs at ``t + delay``, holding them until its
next outputs are due.  An input takes the outputs of one controller: a second controller
setting it is refused (``ControlError``, at the first samples of the run).

**Checkpoints.** A controller keeps what it remembers between samples (an integral, a
filter) in ``self.memory``, a dict of numbers, strings and arrays, or in attributes of
such values: checkpoints save both with the held inputs and the outputs still delayed,
so an interrupted controlled run continues bit for bit.  Its other attributes (the
bodies it reads, a scene, a function) are its definition: a checkpoint records their
digest (``io.fingerprint.digest``), and a continuation is refused
(``io.StoreMismatch``) when one of them changed during the run (a list it appends to, an
object it updates: a checkpoint cannot hold them) or when the controller given to the
continuation is not the one the run started with (its class's code, its attributes and
memory at the start: a changed gain or target).  Attributes named in the controller's
``caches`` (a tuple of names: memos that do not change its outputs) are neither saved nor
checked.

**Failures.** A controller that raises, names an input the system does not have or gives
a value an input cannot hold stops the run with ``ControlError`` naming it; the steps so
far travel with the error (``err.result``).  A controller that is not one (no
``update``, no ``sample_time``: its ``__init__`` did not call ``super().__init__``),
a ``sample_time`` or ``delay`` that is not a number of seconds, or a ``memory`` holding
other values is refused at the start naming the controller and the parameter
(``check_controller``).
"""

import numbers
import traceback
from pathlib import Path

import numpy as np

from ..bodies.section import real_number
from ..io.manifest import StoreMismatch
from ..model.fingerprint import code_digest, digest
from ..model.state import State

#: Relative tolerance of times that fall on a sample or a delay.
TIME_TOL = 1e-9


class ControlError(RuntimeError):
    """A controller failed, gave outputs the system cannot take, or set an input another
    controller sets."""


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
        Numbers, strings and arrays the controller keeps between samples (saved in
        checkpoints, as are its attributes of such values).

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
        self.name = name or type(self).__name__
        self.sample_time = _seconds(self.name, "sample_time", sample_time, positive=True)
        self.delay = _seconds(self.name, "delay", delay, positive=False)
        self.memory = {}

    def update(self, t, state):
        """The hook: new input values ``{name: value}`` at the sample time ``t`` from the
        ``State`` ``state`` (``q``, ``v``, ``lam``; read it with ``sc.sensors``)."""
        raise NotImplementedError(f"{type(self).__name__} must define update(t, state)")


def check_controller(controller):
    """Refuse what is not a controller, naming it and the parameter: ``TypeError`` without
    ``update(t, state)`` or ``sample_time`` (its ``__init__`` did not call
    ``super().__init__``), ``ValueError`` for a ``sample_time`` or ``delay`` that is not
    a number of seconds (> 0, >= 0) and ``TypeError`` for a ``memory`` that is not a dict
    of numbers, strings and arrays."""
    name = _name(controller)
    if not callable(getattr(controller, "update", None)):
        raise TypeError(f"controller {name!r} ({type(controller).__qualname__}) has no "
                        "update(t, state) method: a controller is a Controller subclass "
                        "defining it")
    if not hasattr(controller, "sample_time"):
        raise TypeError(f"controller {name!r} has no sample_time: its __init__ must call "
                        "super().__init__(sample_time, delay=0.0)")
    _seconds(name, "sample_time", controller.sample_time, positive=True)
    _seconds(name, "delay", getattr(controller, "delay", 0.0), positive=False)
    _check_memory(controller)


def check_resumed(controllers, snap):
    """``StoreMismatch`` unless ``controllers`` are as many as the checkpoint ``snap`` of
    the run to continue was taken with (none: a run without control)."""
    stored = len(snap["control_samples"]) if "control_samples" in snap else 0
    if stored != len(controllers):
        raise StoreMismatch(f"the run was started with {stored} controllers, given "
                            f"{len(controllers)}: continue it with the controllers it was "
                            "started with")


def _name(controller):
    """A controller's name for messages (its class's when it has none)."""
    return getattr(controller, "name", None) or type(controller).__name__


def _seconds(name, what, value, positive):
    """``value`` (s) as a float, or ``ValueError`` naming the controller and ``what``:
    a finite number, > 0 when ``positive``, else >= 0 (``section.real_number``)."""
    return real_number(f"controller {name!r}: {what}", value, allow_zero=not positive,
                       hint=" (s)")


def _check_memory(controller, error=TypeError):
    """``error`` naming the controller and the entry unless its ``memory`` (when it has
    one) is a dict of what a checkpoint holds."""
    memory = getattr(controller, "memory", {})
    if not isinstance(memory, dict):
        raise error(f"controller {_name(controller)!r}: memory must be a dict of "
                        f"numbers, strings and arrays, got {type(memory).__name__}")
    for key, value in memory.items():
        if not _is_value(value):
            raise error(f"controller {_name(controller)!r}: memory[{key!r}] holds a "
                            f"{type(value).__name__}; memory holds numbers, strings and "
                            "arrays (saved in checkpoints): keep one entry per number or "
                            "array")


def _is_value(x):
    """Whether a checkpoint holds ``x`` itself: a number, a string or an array of them."""
    return isinstance(x, (numbers.Number, str, np.generic, np.ndarray)) \
        and not np.asarray(x).dtype.hasobject


def _attributes(controller):
    """A controller's attributes but ``memory`` and those its ``caches`` names."""
    skip = {"memory", *getattr(controller, "caches", ())}
    return {k: v for k, v in getattr(controller, "__dict__", {}).items() if k not in skip}


def _record(value, system):
    """What a checkpoint keeps of ``value``: the value itself (an array) or, for another
    object, its digest (bytes)."""
    return np.array(value) if _is_value(value) else np.bytes_(_digest(value, system))


def _digest(value, system):
    """The type and the digest of an attribute's value (bytes)."""
    return f"{type(value).__qualname__} {digest(value, system)}".encode()


def _same(a, b):
    """Whether two recorded values are bit for bit the same."""
    a, b = np.asarray(a), np.asarray(b)
    return a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()


def _restored(value, before):
    """A saved attribute ``value`` (an array) in the type the attribute had before."""
    if isinstance(before, np.ndarray):
        return np.array(value)
    if isinstance(before, np.generic):
        return value[()]
    return value.item() if value.ndim == 0 else np.array(value)


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
    inputs : inputs.InputTable, optional
        The run's values of the system's inputs, which the controllers set (default:
        the table of the system's binding, ``Layout.inputs``, that its terms read).
    """

    def __init__(self, system, controllers, t_start, dt=None, inputs=None):
        self.system, self.controllers = system, list(controllers)
        self.inputs = system.current_layout().inputs if inputs is None else inputs
        for c in self.controllers:
            check_controller(c)
            for what in ("sample_time", "delay"):
                value = getattr(c, what, 0.0)
                if dt is not None and value and not _multiple(value, dt):
                    raise ValueError(f"controller {_name(c)!r}: {what} = {value!r} s must be "
                                     f"a multiple of the step dt = {dt!r} s (the steps end on "
                                     "samples)")
        self.t_start = float(t_start)
        self.samples = np.zeros(len(self.controllers), dtype=np.int64)  # next sample k
        self.pending = []  # [time, controller index, {name: value}], in time order
        self.writers = {}  # input name: the index of the controller that sets it
        self.definitions = [self._definition(c) for c in self.controllers]

    def _definition(self, controller):
        """What defines ``controller`` at the start of the run, as a checkpoint keeps it:
        its class and its code (a digest), its attributes and memory entries."""
        cls = type(controller)
        out = {"(class)": np.array(f"{cls.__module__}.{cls.__qualname__}"),
               "(code)": np.array(code_digest(cls, self.system, stop=(Controller,)))}
        out.update({k: _record(v, self.system) for k, v in _attributes(controller).items()})
        out.update({f"memory[{k!r}]": _record(v, self.system)
                    for k, v in getattr(controller, "memory", {}).items()})
        return out

    # --- the step hook (``protocols.StepHook``, called by ``simulate``) ------------------
    def start(self, integrator):
        """A fresh run (its inputs at their initial values): the controllers' first
        samples at ``t_start``; when their outputs change inputs at once, the initial
        state is solved again with them (consistent accelerations)."""
        self.samples[:] = 0
        self.pending, self.writers = [], {}
        before = self.inputs.changes
        self.after_step(integrator)
        if self.inputs.changes != before:
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
            self._claim(k, outputs, t)
            self.samples[k] += 1
            integrator.stats["control_updates"] += 1
            self.pending.append([t + getattr(c, "delay", 0.0), k, outputs])
            if len(self.pending) > 1:
                self.pending.sort(key=lambda item: item[0])
        while self.pending and t >= self.pending[0][0] - TIME_TOL * max(abs(t), 1.0):
            _, k, outputs = self.pending.pop(0)
            for name, value in outputs.items():
                self.inputs.set(name, value)

    def next_event(self, t):
        """The next time after ``t`` at which a controller samples or an output is
        due: where an adaptive step must end."""
        times = [self.t_start + n * c.sample_time
                 for n, c in zip(self.samples, self.controllers)]
        times += [p[0] for p in self.pending]
        later = [x for x in times if x > t * (1 + TIME_TOL) + TIME_TOL]
        return min(later, default=np.inf)

    def _claim(self, k, outputs, t):
        """The inputs ``outputs`` names are set by the ``k``-th controller alone, else
        ``ControlError`` naming both controllers and the input."""
        for name in outputs:
            first = self.writers.setdefault(name, k)
            if first != k:
                a, b = (f"controllers[{i}] {_name(self.controllers[i])!r}" for i in (first, k))
                raise ControlError(f"{a} and {b} both set the input {name!r} (at t = "
                                   f"{t:.6g} s): an input takes the outputs of one "
                                   "controller; give each its own input")

    def _call(self, controller, t, state):
        name = _name(controller)
        try:
            outputs = controller.update(t, state)
        except Exception as err:
            where = traceback.extract_tb(err.__traceback__)[-1]
            raise ControlError(f"controller {name!r} failed at t = {t:.6g} s: "
                               f"{type(err).__name__}: {err} ({Path(where.filename).name}, "
                               f"line {where.lineno}, in {where.name})") from err
        if not isinstance(outputs, dict):
            raise ControlError(f"controller {name!r} returned "
                               f"{type(outputs).__name__} at t = {t:.6g} s: update must "
                               "return a dict of input names to values")
        checked = {}
        for key, value in outputs.items():
            if key not in self.inputs.inputs:
                known = ", ".join(sorted(self.inputs.inputs)) or "none"
                raise ControlError(f"controller {name!r} set the input {key!r} "
                                   f"at t = {t:.6g} s, which the system does not have "
                                   f"(its inputs: {known}): a body or load reading an "
                                   "Input declares it in its inputs()")
            try:  # shape and finiteness checked now, not when applied
                checked[key] = self.inputs.inputs[key].checked(value)
            except ValueError as err:
                raise ControlError(f"controller {name!r} at t = {t:.6g} s: {err}") from err
        return checked

    # --- checkpoints ------------------------------------------------------------------
    def snapshot(self):
        """The loop's state for a checkpoint (arrays keyed ``control_*``): the held
        inputs, the sample counters, the delayed outputs, which controller sets which
        input, and each controller's definition at the start (``_definition``), memory,
        attributes of numbers, strings and arrays, and the digests of its other
        attributes."""
        snap = {"control_samples": self.samples.copy()}
        for k, definition in enumerate(self.definitions):
            snap.update({f"control_start:{k}:{key}": x for key, x in definition.items()})
        for name, value in self.inputs.values.items():
            snap[f"control_input:{name}"] = value.copy()
        for name, k in self.writers.items():
            snap[f"control_writer:{name}"] = np.int64(k)
        for i, (time, k, outputs) in enumerate(self.pending):
            snap[f"control_pending:{i}:time"] = np.float64(time)
            snap[f"control_pending:{i}:controller"] = np.int64(k)
            for name, value in outputs.items():
                snap[f"control_pending:{i}:value:{name}"] = np.array(value)
        for k, c in enumerate(self.controllers):
            _check_memory(c, ControlError)  # an update may have put another value
            for key, value in getattr(c, "memory", {}).items():
                snap[f"control_memory:{k}:{key}"] = np.array(value)
            for key, value in _attributes(c).items():
                kind = "attribute" if _is_value(value) else "fixed"
                snap[f"control_{kind}:{k}:{key}"] = _record(value, self.system)
        return snap

    def restore(self, snap):
        """Take the state of ``snapshot`` back (a continued run), once the controllers
        are those the run started with and their state is all in it (``StoreMismatch``
        naming the controller and the attribute otherwise)."""
        for k, c in enumerate(self.controllers):
            self._check_definition(k, c, snap)
            self._check_fixed(k, c, snap)
        self.samples[:] = snap["control_samples"]
        for name in self.inputs.values:
            self.inputs.set(name, np.array(snap[f"control_input:{name}"]))
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
        self.writers = {name: int(value) for name, value in _entries(snap, "control_writer:")}
        for k, c in enumerate(self.controllers):
            for key, value in _entries(snap, f"control_memory:{k}:"):
                value = np.array(value)
                c.memory[key] = value.item() if value.ndim == 0 else value
            for key, value in _entries(snap, f"control_attribute:{k}:"):
                setattr(c, key, _restored(np.asarray(value), getattr(c, key, None)))

    def _check_definition(self, k, controller, snap):
        """``StoreMismatch`` unless the ``k``-th controller is defined as the one the
        checkpointed run started with (a checkpoint of an earlier version may not say)."""
        stored, given = dict(_entries(snap, f"control_start:{k}:")), self.definitions[k]
        if not stored:
            return
        differ = [key for key in sorted(set(stored) | set(given))
                  if key not in stored or key not in given
                  or not _same(stored[key], given[key])]
        if differ:
            raise StoreMismatch(
                f"the run was started with another controller {_name(controller)!r} "
                f"(controllers[{k}]): " + "; ".join(_difference(key, stored, given)
                                                     for key in differ)
                + ": continue it with the controllers it was started with (the same "
                "code and parameters), or run it again")

    def _check_fixed(self, k, controller, snap):
        """``StoreMismatch`` naming the attribute of the ``k``-th controller, other than
        a number or an array, that changed during the checkpointed run: the checkpoint
        cannot hold it, so the continuation would not be the run."""
        attributes = _attributes(controller)
        for key, value in _entries(snap, f"control_fixed:{k}:"):
            value = bytes(np.asarray(value)[()])
            if key in attributes and value == _digest(attributes[key], self.system):
                continue
            raise StoreMismatch(
                f"controller {_name(controller)!r} (controllers[{k}]) changed its attribute "
                f"{key!r} during the run: it held a {value.decode().split()[0]}, "
                "which a checkpoint cannot save (numbers, strings and arrays), so the "
                "continuation would not be the run.  Keep what changes between samples in "
                "self.memory or in attributes of numbers and arrays (or name a memo that "
                "does not change the outputs in the controller's caches), and run it again")


def _entries(snap, prefix):
    """``(key, value)`` of the entries of ``snap`` whose keys start with ``prefix``, the
    prefix taken off."""
    return [(key[len(prefix):], snap[key]) for key in snap if key.startswith(prefix)]


def _difference(key, stored, given):
    """One changed entry of a controller's definition, for a message."""
    if key not in stored or key not in given:
        return f"{key}: {'not in the run' if key not in stored else 'not given'}"
    if key == "(code)":
        return "its class's code differs"
    old, new = np.asarray(stored[key]), np.asarray(given[key])
    if "S" in (old.dtype.kind, new.dtype.kind):  # a digest: the object differs
        return f"{key} differs"
    return f"{key}: stored {_show(old)}, given {_show(new)}"


def _show(value):
    """A recorded value for a message."""
    return repr(value.item()) if value.ndim == 0 else np.array2string(value, threshold=6)


def _multiple(value, dt):
    ratio = value / dt
    return abs(ratio - round(ratio)) <= TIME_TOL * max(ratio, 1.0) and round(ratio) >= 1
