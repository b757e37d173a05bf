"""Inputs: named values a controller changes during a run (``Input``), and the inputs of a
system (``system_inputs``).

An ``Input`` stands wherever a scene takes a function of time: a tether voltage of
``SolarWindForce``, the torque of a reel's ``Motor``, the force of a ``PointLoad``, the
current of an ``ElectrodynamicForce``.  It is such a function, ``input(t)``, returning the
value it holds; the loads refresh it once per step (``Term.prepare``), so a controlled run
stays on the compiled Newton step.  ``control.ControlLoop`` sets the values at a
controller's samples (``Controller``).  What the input was given is its ``initial`` value
(part of a run's fingerprint); what it holds now is the run's state (``caches``: not in
the fingerprint; saved in checkpoints).
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
        Its value until a controller changes it; every run starts from it.

    Examples
    --------
    >>> import skfem_cable as sc
    >>> v = sc.Input("voltage1", 20e3)
    >>> v(0.0), v.set(15e3), v(1.0)
    (20000.0, None, 15000.0)
    """

    #: The value held during a run (its state, not its definition: ``io.fingerprint``).
    caches = ("value",)

    def __init__(self, name, value):
        if not isinstance(name, str) or not re.fullmatch(r"[A-Za-z0-9_.\-]+", name):
            raise ValueError(f"Input: name must be a non-empty string of letters, digits, "
                             f"'_', '.' and '-', got {name!r}")
        self.name = name
        self.initial = _finite(name, value)
        self.initial.setflags(write=False)
        self.value = self.initial.copy()

    def __call__(self, t):
        """The value held (a float for a scalar input)."""
        return float(self.value) if self.value.ndim == 0 else self.value.copy()

    def set(self, value):
        """Hold ``value`` from now on (the shape of the initial value, finite)."""
        self.value = self.checked(value)

    def checked(self, value):
        """``value`` as this input holds it (an array of its shape), or ``ValueError``
        naming the input."""
        value = _finite(self.name, value)
        if value.shape != self.initial.shape:
            raise ValueError(f"input {self.name!r} holds shape {self.initial.shape}, "
                             f"got a value of shape {value.shape}")
        return value

    def reset(self):
        """Hold the initial value again (the start of a run)."""
        self.value = self.initial.copy()

    def __repr__(self):
        return f"Input({self.name!r}, {self.value.tolist()!r})"


def _finite(name, value):
    try:
        out = np.array(value, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"input {name!r}: value must be a number or a vector of numbers, "
                         f"got {value!r}") from None
    if not np.all(np.isfinite(out)):
        raise ValueError(f"input {name!r}: value must be finite, got {out.tolist()!r}")
    return out


#: How deep ``system_inputs`` looks into the attributes of bodies and loads.
DEPTH = 4


def system_inputs(system):
    """The ``Input`` objects that the bodies, loads and constraints of ``system`` hold
    (in their attributes, lists, tuples and dicts, a few levels deep), by name; two
    different inputs with one name are an error."""
    found, seen = {}, set()

    def visit(obj, depth):
        if id(obj) in seen or depth > DEPTH or isinstance(obj, (str, bytes, np.ndarray)):
            return
        seen.add(id(obj))
        if isinstance(obj, Input):
            other = found.setdefault(obj.name, obj)
            if other is not obj:
                raise ValueError(f"two inputs are named {obj.name!r}: give each its own "
                                 "name")
            return
        if isinstance(obj, (list, tuple)):
            items = obj
        elif isinstance(obj, dict):
            items = obj.values()
        else:
            items = getattr(obj, "__dict__", {}).values()
        for item in items:
            visit(item, depth + 1)

    for part in (*system.bodies, *system.loads, *system.constraints):
        visit(part, 0)
    return found
