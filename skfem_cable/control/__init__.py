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

from .controller import (
    TIME_TOL,
    ControlError,
    Controller,
    ControlLoop,
    check_controller,
    check_resumed,
)

__all__ = [
    "ControlError",
    "ControlLoop",
    "Controller",
    "TIME_TOL",
    "check_controller",
    "check_resumed",
]
