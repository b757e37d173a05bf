"""Spin control with the remote units' thrusters: the paper's 12-tether E-sail on the
circular orbit of 1 AU, its sailing angle held at 30 deg (``AttitudeHold``) for a day,
spiralling outward (+30 deg, the thrust leaning forward along the orbit) and inward
(-30 deg), each with its spin free and held by ``esail.SpinController``.

Free, the spin rises outward and falls inward (Toivanen and Janhunen, J. Propulsion and
Power 29 (2013) 178-185): the modulation that turns the spin plane with the orbit's Sun
line torques the spin by ``tan(alpha)`` times the turning torque, so that a rigid flat
sail drifts at ``(1/omega) d omega/dt = Omega tan(alpha)``, about 1 % a day at 1 AU
(``docs/esail.md``, "Spin control").  Held, the remote units' thrusters (a few uN each)
cancel the drift.

Run ``python demos/esail_spin_control.py [--days D] [--out DIR]``: writes
``esail_spin_control.png`` and ``esail_spin_control.npz`` into ``DIR`` and prints the key
numbers.
"""

import argparse
import time
from pathlib import Path

import numpy as np

from skfem_cable.scenes import esail_spin

ALPHA = 30.0


def main(days=1.0, out="runs/esail_spin_control", figure=True, n_tethers=12, dt=1.0,
         every=300):
    """Run the sail outward and inward, free and held, for ``days``; returns the key
    numbers (drifts in 1/s, the largest departure from the target, CPU seconds)."""
    runs, summary = {}, {"days": days, "rigid_drift_per_s": esail_spin.rigid_drift(ALPHA)}
    for sign, way in ((1.0, "outward"), (-1.0, "inward")):
        scene, thrusters = esail_spin.spin_scene(sign * ALPHA, n_tethers)
        for controlled in (False, True):
            name = f"{way}, {'held' if controlled else 'free'}"
            start = time.process_time()
            run = esail_spin.hold_spin(scene, thrusters, days, controlled, dt=dt,
                                       every=every)
            cpu = time.process_time() - start
            runs[name] = run
            error = run["spin_rate"] / run["target"] - 1.0
            summary[name] = {"drift_per_s": esail_spin.drift_rate(run["t"], run["spin_rate"]),
                             "final_change": float(error[-1]),
                             "max_error": float(np.abs(error).max()),
                             "max_thrust_N": float(np.abs(run["thrust"]).max()),
                             "sail_angle_deg": (float(run["sail_angle"].min()),
                                                float(run["sail_angle"].max())),
                             "cpu_s": cpu}
    Path(out).mkdir(parents=True, exist_ok=True)
    np.savez(Path(out) / "esail_spin_control.npz",
             **{f"{name}_{key}": run[key] for name, run in runs.items()
                for key in ("t", "spin_rate", "target", "thrust", "sail_angle")})
    if figure:
        summary["figure"] = plot(runs, summary, Path(out) / "esail_spin_control.png")
    return summary


def plot(runs, summary, path):
    """Relative spin rate and thrust per unit against hours."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(2, 1, figsize=(7, 6.5), sharex=True)
    colours = {"outward": "C3", "inward": "C0"}
    for name, run in runs.items():
        way, held = name.split(", ")
        style = "-" if held == "held" else "--"
        hours = 24.0 * run["t"]
        ax[0].plot(hours, 100 * (run["spin_rate"] / run["target"] - 1), style,
                   color=colours[way], lw=0.9, label=name)
        if held == "held":
            ax[1].plot(hours, 1e6 * run["thrust"], color=colours[way], lw=0.9, label=name)
    t = 24.0 * runs["outward, free"]["t"]
    rigid = summary["rigid_drift_per_s"] * t * 3600.0
    ax[0].plot(t, 100 * np.expm1(rigid), "k:", lw=0.9, label="rigid flat sail, +-Omega tan(alpha)")
    ax[0].plot(t, 100 * np.expm1(-rigid), "k:", lw=0.9)
    ax[0].axhspan(-1, 1, color="0.9", zorder=0)
    ax[0].set_ylabel("spin rate / target - 1 [%]")
    ax[0].legend(fontsize=8)
    ax[1].set_ylabel("thrust per remote unit [uN]")
    ax[1].set_xlabel("hours")
    ax[1].legend(fontsize=8)
    fig.suptitle("E-sail spin at a held sailing angle of 30 deg around the Sun (1 AU)")
    fig.tight_layout()
    fig.savefig(path, dpi=95)
    plt.close(fig)
    return str(path)


def gallery_figure(path, out=None):
    """The gallery's picture (``scripts/gallery.py``) into ``path``: the figure of
    ``main`` (a day four times, about two minutes) run into ``out`` (default
    ``runs/esail_spin_control`` of the repository)."""
    import shutil

    out = (Path(out) if out else Path(__file__).resolve().parents[1] / "runs"
           / "esail_spin_control")
    main(out=str(out))
    shutil.copyfile(out / "esail_spin_control.png", path)


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--days", type=float, default=1.0, help="days to run")
    parser.add_argument("--out", default="runs/esail_spin_control", help="output directory")
    args = parser.parse_args()
    for key, value in main(args.days, args.out).items():
        print(f"{key}: {value}")
