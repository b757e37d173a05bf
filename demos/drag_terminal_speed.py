"""A velocity-dependent load: a free cable falling under gravity with linear viscous drag.

A free, horizontal cable (length 2 m, radius 1 mm, steel) falls from rest under gravity
``g`` along ``-y``, with the drag ``f = -c v`` per metre of cable (``c`` in N s/m^2), a
``LineLoad`` whose force depends on the velocity at every Gauss point.  Every point obeys
``rho A v' = -rho A g - c v``, so the cable stays straight and reaches the terminal speed

    v_T = rho A g / c

with the time constant ``tau = rho A / c``.  The demo integrates 40 time constants and
returns the fall speed against ``v_T``; the load's exact Jacobian ``dv = -c I`` enters the
iteration matrix (with ``exact_jacobian=False`` the documented finite-difference Jacobian
is used instead, to the same answer).

Run ``python demos/drag_terminal_speed.py``.
"""

import numpy as np

import skfem_cable as sc

G = 9.81


# --8<-- [start:linear_drag]
def linear_drag(c):
    """``LineLoad`` callables of ``f = -c v``: the force and its exact velocity Jacobian."""

    def force(x, v, t):
        return -c * v

    def dv(x, v, t):
        return np.broadcast_to(-c * np.eye(3), v.shape + (3,))

    return force, dv
# --8<-- [end:linear_drag]


def main(n_elements=4, tau=0.05, periods=40, steps_per_tau=10, exact_jacobian=True):
    """Fall speed after ``periods`` time constants, the terminal speed, and the work the
    drag did (negative)."""
    section = sc.Section.circular(radius=1e-3, E=2e11, rho=7850.0)
    cable = sc.Cable.straight([0, 0, 0], [2, 0, 0], n_elements, section)
    c = section.mass_per_length / tau
    force, dv = linear_drag(c)
    system = sc.System([cable]).add_gravity([0, -G, 0])
    system.add_load(sc.LineLoad(cable, force, dv=dv if exact_jacobian else None))
    result = sc.simulate(system, t_end=periods * tau, dt=tau / steps_per_tau, rho_inf=0.8)
    speed = -result.velocity(cable, cable.mesh.p[0])[-1, :, 1]
    return {"fall_speed": float(speed.mean()), "spread": float(np.ptp(speed)),
            "terminal_speed": section.mass_per_length * G / c,
            "drag_work": float(result.energy["external_work"][-1]),
            "energy_balance": float(result.energy["balance"][-1])}


def gallery_figure(path):
    """The gallery's picture (``scripts/gallery.py``) into ``path``: the fall speed
    against the exact ``v_T (1 - exp(-t / tau))``."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    tau = 0.05
    section = sc.Section.circular(radius=1e-3, E=2e11, rho=7850.0)
    cable = sc.Cable.straight([0, 0, 0], [2, 0, 0], 4, section)
    c = section.mass_per_length / tau
    force, dv = linear_drag(c)
    system = sc.System([cable]).add_gravity([0, -G, 0])
    system.add_load(sc.LineLoad(cable, force, dv=dv))
    r = sc.simulate(system, t_end=40 * tau, dt=tau / 10, rho_inf=0.8)
    speed = -r.velocity(cable, 1.0)[:, 1]
    vT = section.mass_per_length * G / c
    fine = np.linspace(0, r.t[-1], 400)
    fig, ax = plt.subplots(1, 1, figsize=(5.5, 3.2), layout="constrained")
    ax.plot(fine, vT * (1 - np.exp(-fine / tau)), "k-", lw=0.8, label="v_T (1 - exp(-t/tau))")
    ax.plot(r.t, speed, ".", ms=4, label="cable (mid-point)")
    ax.set_xlabel("t [s]")
    ax.set_ylabel("fall speed [m/s]")
    ax.legend(fontsize=8)
    ax.set_title(f"linear drag: final speed / v_T - 1 = {speed[-1] / vT - 1:.1e}",
                 fontsize=10)
    fig.savefig(path, dpi=90, bbox_inches="tight", pad_inches=0.05)
    plt.close(fig)


if __name__ == "__main__":
    for key, value in main().items():
        print(f"{key:>16s}: {value:.12g}")
