"""The ``[solver]``, ``[initial]`` and ``[output]`` tables of a system scene (cables and
rigid bodies): the ``simulate``, ``solve_static`` or ``solve_steady`` keywords, the initial
motion (a rigid motion, or the steady spinning state) and the VTU sampling."""

import math

import numpy as np

from ..model.state import State
from ..solvers.steady import solve_steady
from .schema import boolean, choice, count, duration, interval, vector3


def read_analysis(t):
    """``analysis`` of ``[solver]``: ``"dynamic"`` (default), ``"static"`` or ``"steady"``
    (the relative equilibrium spinning at ``omega`` about the axis through ``center``)."""
    return t.get("analysis", choice("dynamic", "static", "steady"), "dynamic")


def read_solver(t, analysis):
    """The rest of ``[solver]``: ``simulate`` keywords (dynamic; ``rectify = 0`` switches
    the rectification of an orbit off; without ``every``, ``default_every`` when the run
    starts), ``solve_static`` keywords (static) or ``solve_steady`` keywords (steady:
    ``omega`` required, ``center``); keys left out are left to the solver's defaults."""
    common = {"tol": t.get("tol", interval(1e-16, 0.1), None),
              "max_iter": t.get("max_iter", count, None)}
    if analysis == "dynamic":
        s = {"t_end": t.get("t_end", duration), "dt": t.get("dt", duration),
             "rho_inf": t.get("rho_inf", interval(0.0, 1.0), 0.8),
             "every": t.get("every", count, None),
             "newton": t.get("newton", choice("full", "modified"), None)}
        rectify = t.get("rectify", interval(0.0, 0.1), None)
        if rectify is not None:  # 0: off (simulate's None)
            s["rectify"] = rectify or None
    else:
        s = {"load_steps": t.get("load_steps", count, 1)}
        if analysis == "steady":
            s["omega"] = t.get("omega", vector3)
            s["center"] = t.get("center", vector3, np.zeros(3))
    t.finish()
    return {k: v for k, v in {**s, **common}.items() if v is not None or k == "rectify"}


#: Saved steps a scene file's run keeps at most (besides its first) over the file's
#: ``t_end`` when ``[solver]`` has no ``every``: what a user reads, not every step (a 3 h
#: run at 20 s steps: 181 saved steps and VTU files, not 541).
SAVED_STEPS = 250


def default_every(t_end, dt):
    """``every`` of a scene file without one: the smallest that saves at most
    ``SAVED_STEPS`` of the ``t_end / dt`` steps (1 for runs of at most that many);
    ``t_end`` is the file's (a ``--t-end`` beyond it saves proportionally more, and a
    continued run keeps its ``every``), ``dt`` the step of the run."""
    return max(1, math.ceil(t_end / dt / SAVED_STEPS - 1e-9))


def read_initial(t, system, analysis):
    """``[initial]``: the stress-free configuration with the velocity of a rigid motion
    (``angular_velocity`` about ``center`` plus ``velocity``; dynamic only), or with
    ``steady = true`` the relative equilibrium spinning at ``angular_velocity`` about
    ``center`` (``solve_steady``): the run starts at rest in the rotating frame.  In
    orbit, ``steady = true`` takes the orbiting frame's rate at ``t = 0`` as the default
    ``angular_velocity``: the run starts at rest in the orbiting frame."""
    q = system.q0
    if analysis != "dynamic":
        t.finish()
        return State(system, q)
    steady = t.get("steady", boolean, False)
    omega = t.get("angular_velocity", vector3, orbiting_rate(system) if steady else np.zeros(3))
    center = t.get("center", vector3, np.zeros(3))
    if steady:
        if not np.any(omega):
            t.fail("angular_velocity", "must be non-zero with steady = true", omega.tolist())
        t.finish()
        return solve_steady(system, omega, center)
    v = system.rigid_motion_velocity(q, omega, center, t.get("velocity", vector3, np.zeros(3)))
    t.finish()
    return State(system, q, v=v)


def orbiting_rate(system):
    """The angular velocity (rad/s) of the orbiting frame at ``t = 0`` for a system in
    orbit, zeros otherwise."""
    return np.zeros(3) if system.orbit is None else system.orbit.angular_velocity(0.0)


def read_output(t):
    """``[output]``: ``points_per_element`` (cable samples per element in the VTU series)."""
    ppe = t.get("points_per_element", count, 8)
    t.finish()
    return ppe
