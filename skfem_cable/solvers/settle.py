"""Dynamic relaxation by numerical dissipation: a system's state with the transients of
its faster modes damped out, as the start of a long run.

A run that starts from a state out of balance with its loads (an E-sail spun up without
the wind, then the wind switched on) rings in its undamped modes for as long as it runs,
and adaptive steps must follow the ringing (``docs/benchmarks.md``, "Mission-length
runs").  ``settle`` integrates the system with long fixed steps at ``rho_inf = 0``, where
the generalized-alpha method annihilates what it cannot resolve (Chung & Hulbert 1993):
the spectral radius of a step is 0.91 at ``omega h = 1``, 0.71 at 2 and 0.24 at 10, so a
mode of ``omega h >= 1`` keeps less than 1e-3 of its amplitude after 75 steps; at
``omega h = 0.1`` it is 0.99995.  The slow motion the loads drive (a forced response well
below ``1 / h``) is integrated to second order and kept.  MoorDyn finds its initial
conditions the same way, by a dynamic relaxation with added damping before the run.
"""

import numpy as np

from ..core.protocols import IntegrableSystem
from .simulate import simulate


def settle(system: IntegrableSystem, duration, dt, initial=None, t_start=0.0, **options):
    """The state of ``system`` after ``duration`` of steps ``dt`` at ``rho_inf = 0``
    (module docstring).

    Parameters
    ----------
    system : System
    duration, dt : float
        The time to settle over and its fixed step (s): modes with ``omega dt`` above
        about 1 lose a factor 1e3 in 75 steps.
    initial : State, optional
        Where to start (``simulate``'s ``initial``).
    t_start : float
        The time at the start (s).
    **options
        Further ``simulate`` options (``rho_inf`` defaults to 0 and ``newton`` to
        ``"full"``; only the last step is saved).  Full Newton, because the steps are
        long by design: the tangent of a spinning stiff tether turns within them, and
        modified Newton's stale or predicted tangent contracts slowly (``esail.settled``
        on ``FULL_SIZE``: 3.5 corrections a step instead of 6.8, 6 steps retried instead
        of 22, 3.1 s instead of 4.6 on two threads).

    Returns
    -------
    State
        The settled state, at ``t = t_start + duration`` (its ``t``).

    Raises
    ------
    ValueError
        ``duration`` or ``dt`` not a finite number > 0, or ``dt`` longer than
        ``duration``.
    """
    for name, value in (("duration", duration), ("dt", dt)):
        if not (np.isfinite(value) and value > 0):
            raise ValueError(f"{name} must be a finite number > 0, got {value!r}")
    if dt > duration:
        raise ValueError(f"dt must be at most duration ({duration!r}), got {dt!r}")
    steps = int(np.ceil(duration / dt))
    result = simulate(system, t_start + duration, dt, initial=initial, t_start=t_start,
                      every=steps + 1, **{"rho_inf": 0.0, "newton": "full", **options})
    return result.state(-1)
