"""Flexible pendulum: a cable pinned at one end, released horizontally under gravity.

A cable of length ``L = 1.2 m`` (radius 1 cm, ``E = 70 GPa``, ``rho = 7800 kg/m^3``) hangs
from a spherical joint at the origin.  It is released at rest along ``+x`` with gravity
along ``-y``.  Its gravity-to-bending ratio ``rho A g L^3 / EI = 0.08`` is small, so it
swings almost as a rigid uniform bar, whose motion is known exactly:

* it first passes the vertical after a quarter of the large-amplitude compound-pendulum
  period, ``T/4 = K(sin^2(pi/4)) / omega_0`` with ``omega_0^2 = 3 g / (2 L)``;
* at the vertical its angular velocity is ``omega^2 = 3 g / L`` (energy), so the pin
  carries gravity plus the centripetal force of the centre of mass: the axial force at the
  root is ``N = m g + m omega^2 L / 2 = 2.5 m g``.

The cable is integrated by the generalized-alpha method (``rho_inf = 0.8``); the demo
prints both numbers against the rigid values, and the energy balance (the numerical
dissipation of the bending vibrations excited at release).

Run ``python demos/pendulum.py``.
"""

import numpy as np

import skfem_cable as sc
from skfem_cable.analysis.analytic import compound_pendulum_period
from skfem_cable.results.timeseries import zero_crossings
from skfem_cable.scenes import classics

G = 9.81


def main(n_elements=16, dt=1e-3, t_end=0.7, length=1.2):
    """Simulate until ``t_end`` (past the first passage through the vertical) and return
    the key numbers as a dict."""
    scene = classics.pendulum(n_elements=n_elements, length=length, g=G)
    cable = scene.cable
    r = sc.simulate(scene.system, t_end=t_end, dt=dt, rho_inf=0.8, initial=scene.initial)
    tip_x = r.position(cable, length)[:, 0]
    crossings = zero_crossings(r.t, tip_x, r.velocity(cable, length)[:, 0])
    if len(crossings) == 0:
        raise RuntimeError(f"the pendulum did not reach the vertical before t = {t_end}")
    t_quarter = crossings[0]
    root = r.tension(cable, 0.0)
    mass = cable.section.mass_per_length * length
    E = r.energy
    return {"quarter_period": t_quarter,
            "rigid_quarter_period": compound_pendulum_period(length, np.pi / 2, G) / 4,
            "root_tension_at_vertical": float(np.interp(t_quarter, r.t, root)),
            "rigid_root_tension_at_vertical": 2.5 * mass * G,
            "energy_balance_relative": float(np.abs(E["balance"]).max()
                                             / np.abs(E["potential"]).max()),
            "newton_per_step": r.stats["newton"] / r.stats["steps"]}


def gallery_figure(path):
    """The gallery's picture (``scripts/gallery.py``) into ``path``: the shapes every 0.05 s
    until the first passage through the vertical, and the tip's horizontal position
    against the rigid bar's quarter period."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    length = 1.2
    scene = classics.pendulum(n_elements=16, length=length, g=G)
    r = sc.simulate(scene.system, t_end=0.7, dt=1e-3, rho_inf=0.8, initial=scene.initial)
    quarter = compound_pendulum_period(length, np.pi / 2, G) / 4
    fig, (a, b) = plt.subplots(1, 2, figsize=(8.0, 3.2), layout="constrained")
    s = np.linspace(0, length, 65)
    for k in range(0, len(r.t), 50):
        if r.t[k] > quarter + 1e-9:
            break
        p = r.position(scene.cable, s)[k]
        a.plot(p[:, 0], p[:, 1], color="C0", alpha=0.3 + 0.7 * r.t[k] / quarter)
    a.plot(0, 0, "ko")
    a.set_aspect("equal")
    a.set_xlabel("x [m]")
    a.set_ylabel("y [m]")
    a.set_title("shapes every 0.05 s", fontsize=10)
    b.plot(r.t, r.position(scene.cable, length)[:, 0], label="cable tip x")
    b.axvline(quarter, color="k", ls="--", label=f"rigid T/4 = {quarter:.4f} s")
    b.axhline(0, color="0.6", lw=0.8)
    b.set_xlabel("t [s]")
    b.set_ylabel("x [m]")
    b.legend(fontsize=8)
    b.set_title("first passage through the vertical", fontsize=10)
    fig.savefig(path, dpi=90, bbox_inches="tight", pad_inches=0.05)
    plt.close(fig)


if __name__ == "__main__":
    for key, value in main().items():
        print(f"{key:>32s}: {value:.6g}")
