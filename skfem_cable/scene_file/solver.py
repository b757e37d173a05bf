"""The ``[solver]``, ``[initial]`` and ``[output]`` tables of a system scene (cables and
rigid bodies): the ``simulate`` or ``solve_static`` keywords, the initial motion and the
VTU sampling."""

import numpy as np

from ..state import State
from .schema import choice, count, interval, positive, vector3


def read_analysis(t):
    """``analysis`` of ``[solver]``: ``"dynamic"`` (default) or ``"static"``."""
    return t.get("analysis", choice("dynamic", "static"), "dynamic")


def read_solver(t, analysis):
    """The rest of ``[solver]``: ``simulate`` keywords (dynamic) or ``solve_static``
    keywords (static); keys left out are left to the solver's defaults."""
    common = {"tol": t.get("tol", interval(1e-16, 0.1), None),
              "max_iter": t.get("max_iter", count, None)}
    if analysis == "dynamic":
        s = {"t_end": t.get("t_end", positive), "dt": t.get("dt", positive),
             "rho_inf": t.get("rho_inf", interval(0.0, 1.0), 0.8),
             "every": t.get("every", count, 1),
             "newton": t.get("newton", choice("full", "modified"), None)}
    else:
        s = {"load_steps": t.get("load_steps", count, 1)}
    t.finish()
    return {k: v for k, v in {**s, **common}.items() if v is not None}


def read_initial(t, system, analysis):
    """``[initial]``: the stress-free configuration with the velocity of a rigid motion
    (``angular_velocity`` about ``center`` plus ``velocity``; dynamic only)."""
    q = system.q0
    if analysis == "static":
        t.finish()
        return State(system, q)
    v = system.rigid_motion_velocity(q, t.get("angular_velocity", vector3, np.zeros(3)),
                                     t.get("center", vector3, np.zeros(3)),
                                     t.get("velocity", vector3, np.zeros(3)))
    t.finish()
    return State(system, q, v=v)


def read_output(t):
    """``[output]``: ``points_per_element`` (cable samples per element in the VTU series)."""
    ppe = t.get("points_per_element", count, 8)
    t.finish()
    return ppe
