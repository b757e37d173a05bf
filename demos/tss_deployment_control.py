"""Deploying a tethered subsatellite from 10 m to 10 km: Rupp's tension law against a brake.

A 100 kg subsatellite is paid out from a reel on a 1000 kg mother in a circular 400 km
orbit (``skfem_cable.scenes.tss_deployment``: ANCF tether of 20 elements whose mesh
stretches with the free length, the reel's length a coordinate, the central body's
differential gravity on the moving mass).  The reel's motor is commanded every 10 s by
Rupp's length-rate tension law about an exponential deployment rounded off at 10 km;
the Coriolis force swings the tether about 12 deg behind the local vertical while it
pays out, and the law damps that libration through the length once the deployment
slows.  With a constant brake instead (0.14 N m s/m, chosen so that the subsatellite
reaches about 8 km in five orbits) the deployment never stops: the gravity gradient
grows with the length faster than a viscous brake can hold it.

Run ``python demos/tss_deployment_control.py [--orbits N] [--out DIR]``: writes
``tss_deployment_control.png`` (length, rate and libration against orbits, with the
command), ``tss_deployment_lvlh.png`` (the tether in the orbiting frame when it pays out
fastest, swung back by the Coriolis force) and
``tss_deployment_control.npz`` into ``DIR`` and prints the key numbers.
"""

import argparse
from pathlib import Path

import numpy as np

from skfem_cable import plot
from skfem_cable.scenes import tss_deployment as tss


def main(orbits=6.0, out="runs/tss_deployment_control", dt=10.0, elements=20, figure=True):
    """Deploy under Rupp's law for ``orbits`` orbits and with the brake for five (or
    ``orbits`` if fewer: it runs out of tether soon after); returns the key numbers."""
    controlled, parts = tss.deploy_subsatellite(True, orbits, dt, elements)
    braked, braked_parts = tss.deploy_subsatellite(False, min(orbits, 5.0), dt, elements)
    runs = {"Rupp's law": tss.histories(controlled, parts),
            "constant brake": tss.histories(braked, braked_parts)}
    orbit = parts["orbit"]
    law = runs["Rupp's law"]
    command = tss.commanded_length(law["t"], orbit.mean_motion)[0]
    brake = runs["constant brake"]
    summary = {
        "final_length_m": float(law["length"][-1]),
        "command_m": float(command[-1]),
        "length_error": float(law["length"][-1] / command[-1] - 1),
        "final_pitch_deg": float(np.degrees(law["pitch"][-1])),
        "largest_pitch_deg": float(np.degrees(np.abs(law["pitch"]).max())),
        "brake_final_length_m": float(brake["length"][-1]),
        "brake_final_rate_m_s": float(brake["rate"][-1]),
        "brake_final_pitch_deg": float(np.degrees(brake["pitch"][-1])),
        "steps": controlled.stats["steps"], "path": controlled.stats["path"]}
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    np.savez(out / "tss_deployment_control.npz",
             **{f"{name.split()[-1]}_{key}": run[key] for name, run in runs.items()
                for key in ("t", "length", "rate", "pitch")})
    if figure:
        draw(runs, orbit, out / "tss_deployment_control.png")
        fastest = int(np.argmax(law["rate"]))
        plot.render(controlled.system, controlled.state(fastest),
                    out / "tss_deployment_lvlh.png", frame="lvlh", window_size=(640, 640),
                    title=f"orbiting frame at {law['t'][fastest] / orbit.period:.2f} orbits, "
                          f"paying out at {law['rate'][fastest]:.2f} m/s: "
                          f"{law['length'][fastest] / 1e3:.2f} km, pitch "
                          f"{np.degrees(law['pitch'][fastest]):+.1f} deg")
    return summary


def draw(runs, orbit, path):
    """Length (log scale, with the command), rate and in-plane libration against orbits."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(3, 1, figsize=(7.5, 7.5), sharex=True, layout="constrained")
    for name, run in runs.items():
        orbits = run["t"] / orbit.period
        ax[0].semilogy(orbits, run["length"], label=name)
        ax[1].plot(orbits, run["rate"], label=name)
        ax[2].plot(orbits, np.degrees(run["pitch"]), label=name)
    t = runs["Rupp's law"]["t"]
    ax[0].semilogy(t / orbit.period, tss.commanded_length(t, orbit.mean_motion)[0], "k:",
                   lw=1, label="command")
    ax[0].set_ylabel("free length [m]")
    ax[1].set_ylabel("rate [m/s]")
    ax[2].set_ylabel("in-plane libration [deg]")
    ax[2].axhline(np.degrees(-0.5 * np.arcsin(4 * tss.RATE / 3)), color="0.5", lw=0.8,
                  ls="--", label="sin 2 theta = -4 k / 3")
    ax[2].set_xlabel("orbits")
    ax[0].legend(fontsize=8)
    ax[2].legend(fontsize=8)
    fig.suptitle("Tethered subsatellite deployed from 10 m to 10 km (400 km orbit)",
                 fontsize=10)
    fig.savefig(path, dpi=80)
    plt.close(fig)


def gallery_figure(path, out=None):
    """The gallery's picture (``scripts/gallery.py``) into ``path``: the figure of
    ``main`` (about half a minute) run into ``out`` (default
    ``runs/tss_deployment_control`` of the repository)."""
    import shutil

    out = (Path(out) if out else Path(__file__).resolve().parents[1] / "runs"
           / "tss_deployment_control")
    main(out=str(out))
    shutil.copyfile(out / "tss_deployment_control.png", path)


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--orbits", type=float, default=6.0, help="orbits to run")
    parser.add_argument("--out", default="runs/tss_deployment_control",
                        help="output directory")
    args = parser.parse_args()
    for key, value in main(args.orbits, args.out).items():
        print(f"{key}: {value}")
