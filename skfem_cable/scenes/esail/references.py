"""Closed-form and reduced references of the E-sail: rigid coning and the spinning tether's
stretch and modes."""

import numpy as np

from ...bodies.cable import Cable
from ...model.state import State
from ...model.system import System
from .config import BaselineConfig
from .rig import build, rotating_cable_stretch


def rigid_coning(config, out, tether=0):
    """Coning angle of a rigid tether from the pendulum equation Eq. 83,
    ``gamma'' + gamma omega_1^2 (1 + eps) = -M_c3^B / ((m_u + m_t/3) L0^2)`` with
    ``eps = 3 R (2 m_u + m_t) / (2 L0 (3 m_u + m_t))`` (Eq. 84), driven by the simulated
    spin rate ``omega_1`` and Coulomb moment of the tether; starts in the spin plane at
    rest relative to the hub.  Returns ``gamma(t)`` at ``out["t"]``."""
    from scipy.integrate import solve_ivp

    t = out["t"]
    L0, R, mu = config.tether_length, config.hub_radius, config.remote_mass
    mt = config.section.mass_per_length * L0
    eps = 3 * R * (2 * mu + mt) / (2 * L0 * (3 * mu + mt))
    inertia = (mu + mt / 3) * L0**2
    w1 = out["omega_B"][:, 0]
    Mz = out["coulomb_moment_B"][:, tether, 2]

    def rhs(s, y):
        w = np.interp(s, t, w1)
        return [y[1], -y[0] * w * w * (1 + eps) - np.interp(s, t, Mz) / inertia]

    sol = solve_ivp(rhs, (t[0], t[-1]), [0.0, 0.0], t_eval=t, rtol=1e-10, atol=1e-14,
                    max_step=(t[1] - t[0]) * 5)
    return sol.y[0]


def spinning_tether(config, n_elements=5, formulation=None):
    """One tether of the sail in the frame rotating with the nominal spin about x: pinned
    at the hub rim (to ground), its remote unit at the tip, centrifugal loads, starting
    from the analytic steady stretch (the system of Table 2's frequencies);
    ``formulation``: see ``Cable``."""
    from skfem import MeshLine

    sec, L = config.section, config.tether_length
    s = np.linspace(0.0, L, int(n_elements) + 1)
    r, lam = rotating_cable_stretch(s, config.hub_radius, L, sec.EA, sec.mass_per_length,
                                    config.remote_mass, config.spin_rate)
    e = np.array([0.0, 1.0, 0.0])
    cable = Cable(MeshLine(s), sec, r[:, None] * e, lam[:, None] * e, name="tether1",
                  formulation=formulation)
    system = System([cable]).pin(cable.node(0)).add_point_mass(cable.node(-1),
                                                               config.remote_mass)
    system.add_centrifugal([config.spin_rate, 0.0, 0.0])
    return system


def spinning_modes(config, alpha_deg=0.0, n_elements=5, kind="cable", k=200):
    """Natural frequencies (Hz) of the whole sail about its steady spin, in the frame
    rotating with the nominal spin (``modes(..., spin=...)``): the initial state of
    ``build`` is the steady state (the centrifugal, elastic and joint forces balance to
    round-off; the joint and hub multipliers follow by least squares).  The Coulomb force
    is left out (sail off)."""
    from ...solvers.modal import modes

    cfg = BaselineConfig(**{**config.__dict__, "voltage": 0.0})
    scene = build(cfg, alpha_deg, n_elements, kind)
    system = scene.system
    q = system.q0
    C_I_B = scene.hub.rotation(q[system.dofs(scene.hub)])
    omega = C_I_B @ np.array([cfg.spin_rate, 0.0, 0.0])
    system.add_centrifugal(omega)
    lay = system.layout
    n = system.n_dofs
    r, _ = system.evaluate(q, None, 0.0, np.zeros(lay.n_c))
    J = lay.matrix(lay.linear_data).toarray()[n:, :n]
    for j in lay.nonlinear:
        d = lay.cdofs[j]
        J[np.ix_(lay.crows[j], d)] = system.constraints[j].jacobian(q[d])
    lam = np.linalg.lstsq(J.T, -r[:n], rcond=None)[0]
    return modes(system, State(system, q, lam), k=k, spin=omega, shapes=False)[0]
