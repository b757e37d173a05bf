"""Thrust vectoring of the E-sail by voltage modulation: the thrust's angle from the wind
against the sailing angle, for constant voltages (the paper's "continuous modulation"),
the smooth modulation weighting each tether's force by ``cos(phi)^2`` and the on-off
modulation of Toivanen, Janhunen and Envall (2015) with thrusting arcs of +-45 and +-20
deg, against the rigid flat-sail model.

The paper's 12-tether sail (``scenes.esail_vectoring.thrust_vectoring``: 2 elements per
tether, dt = 1 s) runs five rotations at each sailing angle; the thrust is averaged over
the last three, from the voltages the run recorded.  The flat-sail model sums ``u - (u .
t) t`` over the tether directions ``t`` in the spin plane, weighted by each one's share of
the full force.

Run ``python demos/esail_thrust_vectoring.py [--angles 0 5 10 ...] [--out DIR]``: writes
``esail_thrust_vectoring.png`` into ``DIR`` and prints the table.
"""

import argparse
from pathlib import Path

import numpy as np

from skfem_cable.scenes.esail_vectoring import thrust_vectoring

#: The cases: label, mode and half width of the arcs (deg).
CASES = (("constant voltage", "constant", None), ("smooth, force ~ cos^2", "smooth", None),
         ("on-off, arcs +-45 deg", "on-off", 45.0), ("on-off, arcs +-20 deg", "on-off", 20.0))


def weights(mode, width, phi):
    """Each azimuth's share of the full force in the flat-sail model."""
    if mode == "smooth":
        return np.cos(phi) ** 2
    if mode == "on-off":
        return (np.abs(np.cos(phi)) >= np.cos(np.deg2rad(width))).astype(float)
    return np.ones_like(phi)


def flat_sail_angle(alpha_deg, mode="constant", width=None, n=3600):
    """Angle (deg) between the wind and the spin-averaged thrust of a rigid flat sail at
    sailing angle ``alpha_deg`` with the modulation ``mode`` (``weights``)."""
    a = np.deg2rad(alpha_deg)
    wind = np.array([-np.sin(a), 0.0, np.cos(a)])
    phi = (np.arange(n) + 0.5) * 2 * np.pi / n
    t = np.stack([np.cos(phi), np.sin(phi), np.zeros(n)], axis=1)
    force = weights(mode, width, phi) @ (wind - (t @ wind)[:, None] * t)
    return float(np.degrees(np.arccos(force @ wind / np.linalg.norm(force))))


def main(angles=(0.0, 5.0, 10.0, 15.0, 20.0, 25.0, 30.0), out="runs/esail_thrust_vectoring",
         figure=True, cases=CASES, dt=1.0, settle=2, rotations=3):
    """Thrust angles (deg) of the sail and of the flat-sail model for each of ``cases``
    (``CASES`` or some of them) and sailing angle in ``angles`` (deg), the sail run at
    steps of ``dt`` (s) for ``settle`` spin periods and the mean thrust taken over the
    next ``rotations``; writes the figure into ``out``."""
    table = {}
    for label, mode, width in cases:
        rows = []
        for alpha in angles:
            run = thrust_vectoring(alpha, mode, half_width_deg=width or 45.0, dt=dt,
                                   settle=settle, rotations=rotations)
            rows.append((alpha, run["thrust_angle_deg"], flat_sail_angle(alpha, mode, width),
                         run["thrust_N"]))
        table[label] = np.array(rows)
    for label, rows in table.items():
        print(label)
        for alpha, angle, model, thrust in rows:
            print(f"  alpha {alpha:5.1f} deg: thrust angle {angle:7.3f} deg (flat sail "
                  f"{model:7.3f}), thrust {1e3 * thrust:6.2f} mN")
    summary = {"table": table}
    if figure:
        Path(out).mkdir(parents=True, exist_ok=True)
        summary["figure"] = plot(table, Path(out) / "esail_thrust_vectoring.png")
    return summary


def plot(table, path):
    """Thrust angle and thrust against the sailing angle, the flat-sail model as
    crosses."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(1, 2, figsize=(10, 4.2))
    for label, rows in table.items():
        line, = ax[0].plot(rows[:, 0], rows[:, 1], "o-", label=label)
        ax[0].plot(rows[:, 0], rows[:, 2], "x", color="k", ms=8, mew=1.2)
        ax[1].plot(rows[:, 0], 1e3 * rows[:, 3], "o-", color=line.get_color(), label=label)
    top = max(rows[:, 0].max() for rows in table.values())
    ax[0].plot([0, top], [0, top], ":", color="k", lw=0.8, label="thrust angle = sailing angle")
    ax[0].plot([], [], "x", color="k", ms=8, mew=1.2, label="rigid flat sail")
    ax[0].set_xlabel("sailing angle [deg]")
    ax[0].set_ylabel("thrust angle from the wind [deg]")
    ax[0].legend(fontsize=8)
    ax[1].set_xlabel("sailing angle [deg]")
    ax[1].set_ylabel("thrust [mN]")
    ax[1].set_ylim(bottom=0)
    fig.suptitle("E-sail thrust vectoring by voltage modulation (12 tethers, 1 AU)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return str(path)


def gallery_figure(path, out=None):
    """The gallery's picture (``scripts/gallery.py``) into ``path``: the figure of
    ``main`` (28 runs, about a minute and a half) run into ``out`` (default
    ``runs/esail_thrust_vectoring`` of the repository)."""
    import shutil

    out = (Path(out) if out else Path(__file__).resolve().parents[1] / "runs"
           / "esail_thrust_vectoring")
    main(out=str(out))
    shutil.copyfile(out / "esail_thrust_vectoring.png", path)


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--angles", type=float, nargs="+",
                        default=[0.0, 5.0, 10.0, 15.0, 20.0, 25.0, 30.0],
                        help="sailing angles (deg)")
    parser.add_argument("--out", default="runs/esail_thrust_vectoring",
                        help="output directory")
    args = parser.parse_args()
    print("figure:", main(args.angles, args.out)["figure"])
