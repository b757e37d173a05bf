"""Closed-loop control: controllers that read the state at their samples and set inputs
(``controller``: the contract, its checkpoints and failures), what they measure
(``sensors``)."""

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
