"""Spinning tether with a tip mass: centrifugal stiffening and conservation laws.

An aluminium tether (``L = 10 m``, radius 0.5 mm, ``E = 70 GPa``) is pinned at the origin
and carries a 0.5 kg tip mass.  At ``t = 0`` it is straight and unstretched along ``+x`` and
spins rigidly about ``z`` at ``Omega = 2 rad/s``.  Nothing holds it in its stretched steady
state, so the centrifugal force stretches it and the tip mass oscillates radially about that
state; the root tension oscillates about the rigid-cable value

    T_0 = m Omega^2 L + rho A Omega^2 L^2 / 2,

and the radial oscillation has, for a light tether, the frequency of a spring
``k = EA / L`` carrying the tip mass plus a third of the tether in the rotating frame,
``omega_r^2 = k / (m + rho A L / 3) - Omega^2``.  There is no damping and no torque about
``z``, so the energy and the angular momentum about ``z`` stay constant up to the time
discretisation.

Run ``python demos/spinning_tether.py``.
"""

import numpy as np

import skfem_cable as sc
from skfem_cable.scenes import classics
from skfem_cable.timeseries import period


def main(n_elements=10, t_end=2.0, dt=1e-3, spin=2.0, tip_mass=0.5):
    """Simulate the released spinning tether; returns the key numbers as a dict."""
    scene = classics.spinning_tether(n_elements=n_elements, spin=spin, tip_mass=tip_mass)
    cable, system = scene.cable, scene.system
    r = sc.simulate(system, t_end=t_end, dt=dt, rho_inf=0.9, initial=scene.initial)
    L, mu, EA = cable.length, cable.section.mass_per_length, cable.section.EA
    tip = r.position(cable, L)
    tip_v = r.velocity(cable, L)
    radius = np.linalg.norm(tip[:, :2], axis=1)
    radial_speed = np.einsum("ti,ti->t", tip[:, :2], tip_v[:, :2]) / radius
    omega_r = np.sqrt(EA / L / (tip_mass + mu * L / 3) - spin**2)
    Hz = np.array([system.angular_momentum(q, v)[2] for q, v in zip(r.q, r.v)])
    E = r.energy["total"]
    return {"root_tension_mean": float(r.tension(cable, 0.0).mean()),
            "root_tension_rigid": tip_mass * spin**2 * L + mu * spin**2 * L**2 / 2,
            "radial_period": period(r.t, radius - radius.mean(), radial_speed),
            "radial_period_spring": 2 * np.pi / omega_r,
            "angular_momentum_drift": float(np.abs(Hz / Hz[0] - 1).max()),
            "energy_drift": float(np.abs(E / E[0] - 1).max())}


if __name__ == "__main__":
    for key, value in main().items():
        print(f"{key:>24s}: {value:.6g}")
