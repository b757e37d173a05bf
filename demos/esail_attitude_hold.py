"""Attitude hold around the Sun: the paper's 12-tether E-sail on the circular orbit of 1 AU
at a commanded sailing angle of 30 deg for five days, without control (the spin axis stays
fixed in inertial space and the sailing angle drifts with the orbit's turn, about 1 deg per
day) and with the phase-synchronous voltage modulation of
``scenes.esail_attitude.AttitudeHold`` (sampling every 10 s).

The spin rate drifts too.  The rigid flat-sail estimate of the drift,
``(1/omega) d omega/dt = Omega tan(alpha)`` with ``Omega`` the orbital rate, follows from
the modulation that turns the spin plane: the tethers whose voltage it raises feel the
wind's in-plane component too, along their direction of rotation, and for a flat sail
that spin torque is ``tan(alpha)`` times the turning torque (``docs/control.md``).  The
turning torque is ``h`` times the rate at which the normal actually turns, the orbit's
``Omega`` plus the rate of change of the sailing angle, so ``rigid_drift`` integrates
``tan(alpha) (Omega + alpha')`` along the run.

Run ``python demos/esail_attitude_hold.py [--days D] [--out DIR]``: writes
``esail_attitude_hold.png`` and ``esail_attitude_hold.npz`` into ``DIR`` and prints the
key numbers.
"""

import argparse
from pathlib import Path

import numpy as np

from skfem_cable.scenes.esail_attitude import hold_sail_angle
from skfem_cable.space.constants import AU, MU_SUN

ALPHA = 30.0


def drift_rate(t_days, spin):
    """Relative spin-rate drift ``(1/omega) d omega/dt`` (1/s): the slope of ``ln(omega /
    omega_0)`` against time by least squares (the spin's swing of a few per cent averages
    out over days)."""
    return float(np.polyfit(t_days * 86400.0, np.log(spin / spin[0]), 1)[0])


def rigid_drift(t_days, angle_deg, orbital_rate):
    """The rigid flat-sail drift (1/s) for the normal turning as it did: ``ln(omega /
    omega_0) = int tan(alpha) (Omega + alpha') dt`` along the run, fitted as
    ``drift_rate`` fits the measured spin."""
    t, alpha = t_days * 86400.0, np.radians(angle_deg)
    rate = np.tan(alpha) * (orbital_rate + np.gradient(alpha, t))
    growth = np.concatenate([[0.0], np.cumsum(0.5 * (rate[1:] + rate[:-1]) * np.diff(t))])
    return float(np.polyfit(t, growth, 1)[0])


def main(days=5.0, out="runs/esail_attitude_hold", figure=True, every=600, dt=1.0):
    """Run the sail free and controlled for ``days`` with steps of ``dt`` s, saving every
    ``every`` steps; returns the key numbers."""
    runs = {name: hold_sail_angle(ALPHA, days, controlled=controlled, dt=dt, every=every)
            for name, controlled in (("free", False), ("controlled", True))}
    orbital_rate = np.sqrt(MU_SUN / AU**3)
    summary = {"days": days, "rigid_drift_per_s": orbital_rate * np.tan(np.radians(ALPHA))}
    for name, run in runs.items():
        angle = run["sail_angle"]
        summary[name] = {"final_angle_deg": float(angle[-1]),
                         "max_error_deg": float(np.abs(angle - ALPHA).max()),
                         "spin_drift_per_s": drift_rate(run["t"], run["spin_rate"]),
                         "rigid_drift_as_turned_per_s": rigid_drift(run["t"], angle,
                                                                    orbital_rate),
                         "control_updates": run["result"].stats.get("control_updates", 0)}
    Path(out).mkdir(parents=True, exist_ok=True)
    np.savez(Path(out) / "esail_attitude_hold.npz",
             **{f"{name}_{key}": run[key] for name, run in runs.items()
                for key in ("t", "sail_angle", "spin_rate")})
    if figure:
        summary["figure"] = plot(runs, summary, Path(out) / "esail_attitude_hold.png")
    return summary


def plot(runs, summary, path):
    """Sailing angle and spin rate against days, free and controlled."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(2, 1, figsize=(7, 6.5), sharex=True)
    for name, run in runs.items():
        ax[0].plot(run["t"], run["sail_angle"], label=name)
        ax[1].plot(run["t"], 1e3 * run["spin_rate"], lw=0.6, label=name)
    ax[0].axhline(ALPHA, color="k", lw=0.8, ls=":", label="commanded")
    ax[0].set_ylabel("sailing angle [deg]")
    ax[0].legend()
    t = runs["free"]["t"]
    w0 = runs["free"]["spin_rate"][0]
    ax[1].plot(t, 1e3 * w0 * np.exp(summary["rigid_drift_per_s"] * t * 86400.0), "k--",
               lw=0.9, label="rigid flat sail: Omega tan(alpha)")
    ax[1].set_ylabel("spin rate [mrad/s]")
    ax[1].set_xlabel("days")
    ax[1].legend(fontsize=8)
    fig.suptitle("E-sail attitude hold at 30 deg around the Sun (12 tethers, 1 AU)")
    fig.tight_layout()
    fig.savefig(path, dpi=95)
    plt.close(fig)
    return str(path)


def gallery_figure(path, out=None):
    """The gallery's picture (``scripts/gallery.py``) into ``path``: the figure of
    ``main`` (five days twice, about four minutes) run into ``out`` (default
    ``runs/esail_attitude_hold`` of the repository)."""
    import shutil

    out = (Path(out) if out else Path(__file__).resolve().parents[1] / "runs"
           / "esail_attitude_hold")
    main(out=str(out))
    shutil.copyfile(out / "esail_attitude_hold.png", path)


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--days", type=float, default=5.0, help="days to run")
    parser.add_argument("--out", default="runs/esail_attitude_hold", help="output directory")
    args = parser.parse_args()
    for key, value in main(args.days, args.out).items():
        print(f"{key}: {value}")
