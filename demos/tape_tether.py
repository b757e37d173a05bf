"""Tape tethers: a 5 km tape in orbit and a tape spun up on a hub, against round tethers.

A tape (`sc.Rod` of `sc.Section.tape`, 2 cm x 50 um aluminium: 1.6e5 times stiffer
edgewise than flatwise, 200 times softer in torsion than the round wire of its mass) in
two settings, each beside the round aluminium tether of equal mass (radius 0.564 mm):

* **In orbit** (`skfem-cable run tape-tether`, `skfem_cable.scenes.tape_tether`): 5 km
  between two 20 kg end masses along the local vertical of a 400 km orbit, librating
  under the gravity gradient, released with one turn of twist.  Its libration is the
  round tether's (the tension, 0.2 N, makes the bending of either negligible); its twist
  swings as a torsional wave of period `2 L / c`, `c = sqrt(GJ / rho I_p)` = 15.8 m/s:
  634 s, where the round tether's would last 3 s.  The check: that period, measured
  over one orbit, against `2 L / c`.
* **On a spinning hub**: 5 m tethers clamped radially to a hub of radius 0.2 m spun up
  from rest to 2 rad/s in 3 s (the hub's motion prescribed: its clamp holds the tape's
  twist, so it passes the torque on).  The round tether lags behind the hub as a
  string (3.1 rad at 3 s); the tape laid flat in the spin plane lags far less (0.12
  rad: it bends edgewise); the tape pitched by 45 degrees bends about both principal
  axes at once: bending coupled to twist through `(EI_edge - EI_flat) kappa1 kappa2`
  twists it (up to 0.97 rad) until its soft axis takes the lag, which drives it out of
  the spin plane (0.14 m) and lets it lag as the round tether does.  The run stops at
  the end of the spin-up, before the slack tethers fold at the hub (`docs/rods.md`).

Run `python demos/tape_tether.py [picture.png]`.
"""

import sys

import numpy as np

import skfem_cable as sc
from skfem_cable.scenes import tape_tether

#: Hub radius (m), tether length (m), final spin (rad/s) and spin-up time (s).
HUB, LENGTH, SPIN, RAMP = 0.2, 5.0, 2.0, 3.0


def in_orbit(elements=16, t_end=None, dt=10.0):
    """The ``tape-tether`` scene and the round tether of equal mass (a cable) from the
    same librating start; returns the scene's numbers and the largest difference of their
    pitch angles (rad), with the histories (``t``, ``twist``, ``pitch``, ``pitch_round``)."""
    scene = tape_tether.scene(elements, t_end=t_end, dt=dt)
    settings = {k: scene.settings[k] for k in ("t_end", "dt", "rho_inf")}
    tape = sc.simulate(scene.system, initial=scene.initial, **settings)
    system, cable, orbit = tape_tether.tether(elements, tape_tether.ROUND, rod=False)
    start = tape_tether.tss.librated(system, orbit)
    wire = sc.simulate(system, initial=start, **settings)
    rod = scene.system.bodies[0]
    pitch = tape_tether.tss.attitude(orbit, rod, tape.t, tape.q[:, scene.system.dofs(rod)])[0]
    pitch_round = tape_tether.tss.attitude(orbit, cable, wire.t, wire.q[:, system.dofs(cable)])[0]
    return {**scene.outputs(tape), "pitch_difference": float(np.abs(pitch - pitch_round).max()),
            "t": tape.t, "twist": tape_tether.relative_twist(scene.system, rod, tape.q),
            "pitch": pitch, "pitch_round": pitch_round}


def hub_angle(t, k=0):
    """The hub's angle (``k = 0``), rate (1) or acceleration (2) at time ``t``: the rate
    rises from 0 to ``SPIN`` over ``RAMP`` as ``tau - sin(2 pi tau) / 2 pi``, ``tau =
    t / RAMP``, smooth at both ends, then stays."""
    tau = min(t / RAMP, 1.0)
    w = 2 * np.pi
    if k == 2:
        return SPIN / RAMP * (1 - np.cos(w * tau)) if t < RAMP else 0.0
    if k == 1:
        return SPIN * (tau - np.sin(w * tau) / w)
    ramp = SPIN * RAMP * (tau**2 / 2 + (np.cos(w * tau) - 1) / w**2)
    return ramp + SPIN * max(t - RAMP, 0.0)


def radial(t, k=0):
    """The ``k``-th time derivative of the hub's radial unit vector ``e(psi(t))``."""
    psi, rate, acc = (hub_angle(t, j) for j in range(3))
    e, n = np.array([np.cos(psi), np.sin(psi), 0.0]), np.array([-np.sin(psi), np.cos(psi), 0.0])
    return (e, rate * n, acc * n - rate**2 * e)[k]


def spun_up(section, rod=True, pitch=0.0, elements=8, t_end=RAMP, dt=5e-3):
    """A tether of ``section`` clamped radially (position and whole slope, and a rod's
    twist) to the hub, spun up (``hub_angle``); a rod's section normal turned by
    ``pitch`` (rad) from the spin axis ``z`` towards the lag direction.  Returns the
    result, the line and the system."""
    ends = ([HUB, 0, 0], [HUB + LENGTH, 0, 0])
    normal = [0.0, -np.sin(pitch), np.cos(pitch)]
    line = sc.Rod.straight(*ends, elements, section, normal=normal) if rod \
        else sc.Cable.straight(*ends, elements, section)
    system = sc.System([line])
    system.clamp(line.node(0), direction=lambda t: radial(t), slope="full",
                 position=lambda t: HUB * radial(t), velocity=lambda t: HUB * radial(t, 1),
                 acceleration=lambda t: HUB * radial(t, 2))
    return sc.simulate(system, t_end=t_end, dt=dt, rho_inf=0.8), line, system


def hub_histories(result, line, system):
    """The tip's lag angle behind the hub (rad, positive behind), its height above the
    spin plane (m) and, for a rod, its twist (rad; else zeros), over the saved steps
    (``Rod.twist`` from the initial frames carried to each step: right while the tangents
    turn by less than half a turn, as they do during the spin-up)."""
    tip = result.position(line, line.length)
    psi = np.array([hub_angle(t) for t in result.t])
    lag = np.unwrap(psi - np.arctan2(tip[:, 1], tip[:, 0]))
    dofs = system.dofs(line)
    twist = np.array([line.twist(q[dofs], line.length) for q in result.q]) \
        if hasattr(line, "twist") else np.zeros(len(result.t))
    return lag, tip[:, 2], twist


def on_hub(elements=8, t_end=RAMP, dt=5e-3):
    """The round tether, the flat tape and the tape pitched by 45 degrees spun up;
    returns ``{name: (t, lag, height, twist)}`` and the largest of each."""
    cases = {"round": (tape_tether.ROUND, False, 0.0),
             "tape, flat": (tape_tether.TAPE, True, 0.0),
             "tape, pitched 45 deg": (tape_tether.TAPE, True, np.pi / 4)}
    out = {}
    for name, (section, rod, pitch) in cases.items():
        result, line, system = spun_up(section, rod, pitch, elements, t_end, dt)
        out[name] = (result.t, *hub_histories(result, line, system))
    peaks = {f"{name} {what}": float(np.abs(h[k]).max()) for name, h in out.items()
             for k, what in ((1, "lag_max"), (2, "height_max"), (3, "twist_max"))}
    return out, peaks


def main(elements=16, t_end=None, dt=10.0):
    """The orbit's numbers (``in_orbit``): the torsional period against ``2 L / c``."""
    out = in_orbit(elements, t_end, dt)
    return {k: v for k, v in out.items() if np.ndim(v) == 0}


def ribbon_picture(ax, q, line, system, color, scale=5.0):
    """Draw the rod ``line`` of ``system`` at ``q`` seen from above (on the ``x, y``
    plane of the axes ``ax``) as the ribbon ParaView shows (``io.export.ribbon`` of
    ``Rod.show``), its width times ``scale``: a ribbon turned on edge narrows to a line."""
    from skfem_cable.io.export import ribbon

    shape = line.show(system, q, np.zeros_like(q), 0.0, points_per_element=8)
    shape.data["width"] = scale * shape.data["width"]
    p = ribbon(shape).points.reshape(-1, 2, 3)
    outline = np.concatenate([p[:, 0], p[::-1, 1]])
    ax.fill(outline[:, 0], outline[:, 1], color=color, alpha=0.8, lw=0.5)


def gallery_figure(path):
    """The gallery's picture into ``path``: the spun-up tapes drawn as ribbons (width
    x 10), their lag, height and twist against the round tether, and the twist of the
    tape in orbit."""
    import matplotlib
    import matplotlib.patches

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    hub, _ = on_hub(t_end=2.0)
    orbit = in_orbit(16)
    fig = plt.figure(figsize=(10.0, 6.4), layout="constrained")
    grid = fig.add_gridspec(2, 3)
    styles = {"round": {"color": "0.2", "ls": "--"}, "tape, flat": {"color": "tab:blue"},
              "tape, pitched 45 deg": {"color": "tab:orange"}}
    for k, (label, unit) in enumerate((("lag behind the hub", "rad"),
                                       ("height above the spin plane", "m"),
                                       ("tip twist", "rad"))):
        ax = fig.add_subplot(grid[1, k])
        for name in ("tape, flat", "tape, pitched 45 deg", "round"):
            ax.plot(hub[name][0], hub[name][k + 1], label=name, **styles[name])
        ax.set_xlabel("t [s]")
        ax.set_ylabel(f"{label} [{unit}]")
    ax.legend(fontsize=8)
    ax = fig.add_subplot(grid[0, 2])
    ax.plot(orbit["t"] / 60, orbit["twist"] / (2 * np.pi), color="tab:blue")
    ax.set_xlabel("t [min]")
    ax.set_ylabel("end-to-end twist [turns]")
    ax.set_title(f"5 km tape in orbit: torsion period {orbit['torsion_period']:.0f} s\n"
                 f"(2L/c = {orbit['torsion_period_exact']:.0f} s; one orbit shown)",
                 fontsize=9)
    ax = fig.add_subplot(grid[0, :2])
    for name, pitch in (("tape, flat", 0.0), ("tape, pitched 45 deg", np.pi / 4)):
        result, line, system = spun_up(tape_tether.TAPE, True, pitch, t_end=1.6)
        ribbon_picture(ax, result.q[-1], line, system, styles[name]["color"])
    result, line, _ = spun_up(tape_tether.ROUND, False, t_end=1.6)
    ax.plot(*result.position(line, np.linspace(0, LENGTH, 60))[-1][:, :2].T,
            **styles["round"])
    ax.add_patch(matplotlib.patches.Circle((0, 0), HUB, color="0.6"))
    ax.set_aspect("equal")
    ax.set(xlabel="x [m]", ylabel="y [m]")
    ax.set_title("spin-up about z, seen from above at t = 1.6 s: the tapes as ribbons "
                 "(width x 5), the round tether dashed", fontsize=9)
    fig.savefig(path, dpi=80)
    plt.close(fig)


if __name__ == "__main__":
    for key, value in main().items():
        print(f"{key:>24s}: {value:.6g}")
    _, peaks = on_hub()
    for key, value in peaks.items():
        print(f"{key:>36s}: {value:.4g}")
    if len(sys.argv) > 1:
        gallery_figure(sys.argv[1])
