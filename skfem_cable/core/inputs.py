"""Inputs: named values a controller changes during a run (``Input``), the inputs a
system declares (``system_inputs``) and the values they hold during a run
(``InputTable``, the run's state).

An ``Input`` stands wherever a scene takes a function of time: a tether voltage of
``SolarWindForce``, the torque of a reel's ``Motor``, the force of a ``PointLoad``, the
current of an ``ElectrodynamicForce``.  It is the input's definition: its name and its
``initial`` value (part of a run's fingerprint), which it keeps.  A part that reads an
input declares it (``inputs()``: the ``Input`` objects it reads, ``declared``), and the
system collects the declarations (``system_inputs``); nothing is found by looking
through attributes.

**A run's values are the run's.**  Each run holds an ``InputTable`` (``Layout.inputs``,
the binding a solver takes at its start): one array per declared input, starting at its
initial value.  ``control.ControlLoop`` sets them at a controller's samples
(``Controller``), checkpoints save them, the run's ``Result.inputs`` records them; the
terms read them through the binding (``InputTable.reader``: a part declaring inputs is
bound with ``bind(system, inputs=table)``), refreshed once per step (``Term.prepare``),
so a controlled run stays on the compiled Newton step.  Outside a run (a load's
``force(t)``, ``voltages(t)``, a static solve) an input holds its initial value.
"""

import re

import numpy as np


class Input:
    """A named input: a number or a vector that a controller may change during a run.

    Parameters
    ----------
    name : str
        The name controllers give it in their outputs (unique in a system).
    value : float or array_like
        Its initial value: every run starts from it, and it is what the input holds
        outside a run (a controller's values are the run's, ``InputTable``).

    Examples
    --------
    >>> import skfem_cable as sc
    >>> v = sc.Input("voltage1", 20e3)
    >>> v(0.0), v.inputs() == (v,)
    (20000.0, True)
    """

    def __init__(self, name, value):
        if not isinstance(name, str) or not re.fullmatch(r"[A-Za-z0-9_.\-]+", name):
            raise ValueError(f"Input: name must be a non-empty string of letters, digits, "
                             f"'_', '.' and '-', got {name!r}")
        self.name = name
        self.initial = _finite(name, value)
        self.initial.setflags(write=False)

    @property
    def value(self):
        """The initial value (read-only): a run's values are its ``InputTable``'s."""
        return self.initial

    def __call__(self, t):
        """The initial value (a float for a scalar input): a run reads its own value
        through its table (``reading``)."""
        return float(self.initial) if self.initial.ndim == 0 else self.initial.copy()

    def inputs(self):
        """The inputs this function of time reads: itself (``declared``)."""
        return (self,)

    def reading(self, table):
        """This input as a run reads it: the value it holds in the run's ``table``
        (``InputTable.held``)."""
        return table.held(self)

    def checked(self, value):
        """``value`` as this input holds it (an array of its shape), or ``ValueError``
        naming the input."""
        value = _finite(self.name, value)
        if value.shape != self.initial.shape:
            raise ValueError(f"input {self.name!r} holds shape {self.initial.shape}, "
                             f"got a value of shape {value.shape}")
        return value

    def __repr__(self):
        return f"Input({self.name!r}, {self.initial.tolist()!r})"


def declared(*sources):
    """The inputs that ``sources`` read (functions of time, numbers, arrays): those each
    source declares with ``inputs()`` (an ``Input`` declares itself, a function of time
    built on inputs its own; other sources none)."""
    return tuple(x for source in sources for x in getattr(source, "inputs", tuple)())


def reader(source, table):
    """``source`` (a function of time, a number, ...) as a run of ``table`` (an
    ``InputTable``; None: outside a run) reads it: a source with ``reading(table)`` (an
    ``Input``, a function built on inputs) reads the run's values; any other is
    itself."""
    reading = getattr(source, "reading", None)
    return source if table is None or reading is None else reading(table)


class InputTable:
    """The values of a system's inputs during one run: the run's state, not the inputs'.

    Parameters
    ----------
    inputs : dict
        The declared inputs by name (``system_inputs``).

    Attributes
    ----------
    values : dict
        One array per input, by name, updated in place (the terms' readers hold them).
    changes : int
        How many values were set since the last ``reset`` (what ``ControlLoop.start``
        compares).
    """

    def __init__(self, inputs):
        self.inputs = dict(inputs)
        self.values = {name: x.initial.copy() for name, x in self.inputs.items()}
        self._names = {id(x): name for name, x in self.inputs.items()}
        self.changes = 0

    def reset(self):
        """Every input back to its initial value (the start of a run)."""
        for name, x in self.inputs.items():
            self.values[name][...] = x.initial
        self.changes = 0

    def set(self, name, value):
        """Hold ``value`` (checked: ``Input.checked``) in the input ``name`` from now on."""
        self.values[name][...] = self.inputs[name].checked(value)
        self.changes += 1

    def held(self, x):
        """The function of time reading the value the input ``x`` holds in this table (a
        float for a scalar input, a copy of a vector), as ``Input.__call__`` reads its
        initial value; an input the system does not declare reads its initial value."""
        name = self._names.get(id(x))
        if name is None:
            return x
        held = self.values[name]
        return (lambda t: float(held)) if held.ndim == 0 else (lambda t: held.copy())

    def snapshot(self):
        """Copies of the values, by name."""
        return {name: value.copy() for name, value in self.values.items()}


def _finite(name, value):
    try:
        out = np.array(value, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"input {name!r}: value must be a number or a vector of numbers, "
                         f"got {value!r}") from None
    if not np.all(np.isfinite(out)):
        raise ValueError(f"input {name!r}: value must be finite, got {out.tolist()!r}")
    return out


def system_inputs(system):
    """The inputs the bodies, loads and constraints of ``system`` declare (their
    ``inputs()``), by name; two different inputs with one name are an error."""
    found = {}
    for part in (*system.bodies, *system.loads, *system.constraints):
        for x in declared(part):
            other = found.setdefault(x.name, x)
            if other is not x:
                raise ValueError(f"two inputs are named {x.name!r}: give each its own "
                                 "name")
    return found
