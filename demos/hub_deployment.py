"""A spinning hub deploys four tethers: the angular momentum spreads out.

A hub (a cylinder spinning at 1 rad/s about its axis, no external load) carries four reels
on its rim.  Each reel pays out a tether with a 1 kg end mass from 10 m to 50 m along a
smooth (quintic) length profile while the reels' content moves with the hub
(``System.deploy(..., capacity=...)``).  The Coriolis force makes the tethers lag and
their tension brakes the hub.  The tethers are pinned at the rim, so the tension is the
only torque between hub and tethers: after the deployment the hub keeps turning faster
than the fan of tethers (the fan would need the hub's whole angular momentum to turn at
``H / I``), and the two exchange angular momentum through the tension as the roots swing
round the rim.  The total angular momentum is conserved to the integrator's accuracy
(second order in the step).

``main`` returns the drift of the angular momentum, the spin rate of the hub and the
rotation rate of the fan (of the end masses), and the run.
"""

import numpy as np

import skfem_cable as sc
from skfem_cable.constraints.deploy import smooth_profile

SECTION = sc.Section.circular(5e-4, 1e11, 1000.0)     # 0.8 g/m, EA = 79 kN


def build(n_elements=8, l0=10.0, l1=50.0, duration=60.0, capacity=60.0, radius=1.0,
          tip_mass=1.0, omega=1.0):
    """The hub and its four tethers, spinning at ``omega`` (rad/s) about the hub axis
    (``x``); returns ``(system, hub, tethers, initial state)``."""
    hub = sc.RigidBody.cylinder(radius=radius, height=0.5, density=1000.0)
    length = smooth_profile(l0, l1, duration)
    tethers = []
    for k in range(4):
        e = np.array([0.0, np.cos(k * np.pi / 2), np.sin(k * np.pi / 2)])
        tethers.append(sc.Cable.straight(radius * e, (radius + l0) * e, n_elements,
                                         SECTION, name=f"tether{k}"))
    system = sc.System([hub, *tethers])
    for tether in tethers:
        system.deploy(tether, hub.point(tether.q0[:3]), *length, capacity=capacity)
        system.add_point_mass(tether.node(-1), tip_mass)
    v = system.rigid_motion_velocity(system.q0, [omega, 0, 0])
    return system, hub, tethers, sc.State(system, system.q0, v=v)


def main(n_elements=8, l1=50.0, duration=60.0, hold=30.0, dt=0.05, capacity=60.0):
    """Deploy to ``l1`` in ``duration`` s and hold ``hold`` s; returns the largest
    relative drift of the angular momentum about the spin axis, the time, the spin rate
    of the hub and the rotation rate of the fan, and the run."""
    system, hub, tethers, initial = build(n_elements, l1=l1, duration=duration,
                                          capacity=capacity)
    r = sc.simulate(system, t_end=duration + hold, dt=dt, rho_inf=0.8, initial=initial,
                    every=4)
    H = np.array([system.angular_momentum(q, v, t=t)[0] for q, v, t in zip(r.q, r.v, r.t)])
    d = system.dofs(hub)
    tip = r.position(tethers[0], tethers[0].length)
    fan = np.gradient(np.unwrap(np.arctan2(tip[:, 2], tip[:, 1])), r.t)
    return {"momentum_drift": float(np.abs(H / H[0] - 1).max()), "t": r.t,
            "hub_rate": hub.angular_velocity(r.q[:, d], r.v[:, d])[:, 0], "fan_rate": fan,
            "result": r}


def gallery_figure(path):
    """The gallery's picture (``scripts/gallery.py``) into ``path``: the spin rate of the
    hub and the rotation rate of the fan of tethers while they are deployed."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out = main()
    fig, ax = plt.subplots(1, 1, figsize=(6.5, 3.0), layout="constrained")
    ax.plot(out["t"], out["hub_rate"], label="hub")
    ax.plot(out["t"], out["fan_rate"], label="fan of tethers (end masses)")
    ax.axvline(60.0, color="k", lw=0.6, ls=":")
    ax.set(xlabel="t [s]", ylabel="rotation rate [rad/s]")
    ax.set_title(f"Deployment 10 m -> 50 m in 60 s; angular momentum drift "
                 f"{out['momentum_drift']:.1e}", fontsize=10)
    ax.legend(fontsize=8)
    fig.savefig(path, dpi=90, bbox_inches="tight", pad_inches=0.05)
    plt.close(fig)


if __name__ == "__main__":
    import sys

    out = main()
    print(f"angular momentum drift {out['momentum_drift']:.2e}; at the end the hub turns "
          f"at {out['hub_rate'][-1]:.3f} rad/s, the fan at {out['fan_rate'][-1]:.3f} rad/s")
    if len(sys.argv) > 1:
        from skfem_cable import plot

        plot.animate(out["result"], sys.argv[1], view="axial", max_frames=60,
                     window_size=(640, 480),
                     title="Four tethers deployed from a spinning hub, 10 m -> 50 m")
