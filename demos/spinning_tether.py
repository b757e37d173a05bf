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
from skfem_cable.results.timeseries import period
from skfem_cable.scenes import classics


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


def gallery_figure(path):
    """The gallery's picture (``scripts/gallery.py``) into ``path``: tip radius and root
    tension over 0.5 s (10 elements) against the steady values."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    spin, tip_mass = 2.0, 0.5
    scene = classics.spinning_tether(n_elements=10, spin=spin, tip_mass=tip_mass)
    cable = scene.cable
    r = sc.simulate(scene.system, t_end=0.5, dt=1e-3, rho_inf=0.9, initial=scene.initial)
    L, mu, EA = cable.length, cable.section.mass_per_length, cable.section.EA
    tip = r.position(cable, L)
    radius = np.linalg.norm(tip[:, :2], axis=1)
    omega_r = np.sqrt(EA / L / (tip_mass + mu * L / 3) - spin**2)
    T0 = tip_mass * spin**2 * L + mu * spin**2 * L**2 / 2
    fig, (a, b) = plt.subplots(1, 2, figsize=(8.0, 3.0), layout="constrained")
    a.plot(r.t, (radius - L) * 1e3)
    a.set_xlabel("t [s]")
    a.set_ylabel("tip radius - L [mm]")
    a.set_title(f"radial oscillation; spring model period {2 * np.pi / omega_r * 1e3:.1f} ms",
                fontsize=10)
    b.plot(r.t, r.tension(cable, 0.0), label="root tension")
    b.axhline(T0, color="k", ls="--", label=f"rigid T0 = {T0:.2f} N")
    b.set_xlabel("t [s]")
    b.set_ylabel("N [N]")
    b.legend(fontsize=8, loc="lower right")
    b.set_title("root tension", fontsize=10)
    fig.savefig(path, dpi=90, bbox_inches="tight", pad_inches=0.05)
    plt.close(fig)


if __name__ == "__main__":
    for key, value in main().items():
        print(f"{key:>24s}: {value:.6g}")
