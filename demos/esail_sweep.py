"""E-sail parameter study on a local Dask cluster: thrust against sailing angle and voltage.

Physics
-------
The baseline sail of Pacheco-Ramos et al. (12 tethers of 10 km, 20 kV nominal) is run for
one spin period (1571 s) at every sailing angle ``alpha`` = 0, 10, ..., 60 deg and tether
voltages 10 and 20 kV: 14 runs, one Dask task each (``sc.sweep`` on a ``LocalCluster``),
each into its own run directory.  The Coulomb force per unit length grows with the
voltage (``SolarWind.force_per_length``), so the thrust does too; tilting the sail turns
the force on each tether towards the sail normal, so the thrust magnitude falls with
``alpha`` while the thrust angle from the Sun line grows, close to ``alpha / 2`` for small
angles (a flat sail's spin average) and less at larger ones.

Run ``python demos/esail_sweep.py [--periods P] [--workers N] [--out DIR]``: the study
directory holds ``study.zarr`` (``skfem_cable.study.open_study``) and the runs; the figure
``esail_sweep.png`` shows the mean thrust magnitude and thrust angle against ``alpha``.
"""

import argparse
import time
from pathlib import Path

import numpy as np

import skfem_cable as sc
from skfem_cable.scenes.catalog import esail_scene
from skfem_cable.study import format_study

ALPHAS = tuple(range(0, 61, 10))
VOLTAGES = (10e3, 20e3)


def main(alphas=ALPHAS, voltages=VOLTAGES, periods=1.0, elements=5, out="runs/esail_sweep",
         client=None, workers=None, plot=True, progress=None):
    """Run the study into ``out`` (finished runs there are reused) on ``client`` (default:
    a local cluster of ``workers`` processes) and, with ``plot``, save ``figure`` as
    ``out/esail_sweep.png``; returns the study's dataset."""
    t_end = periods * sc.esail.BaselineConfig().spin_period
    study = sc.sweep(esail_scene, {"alpha": list(alphas), "voltage": list(voltages)},
                     client=client, store=out, workers=workers, progress=progress,
                     fixed={"t_end": t_end, "elements": elements})
    if plot:
        import matplotlib.pyplot as plt

        fig = figure(study)
        fig.savefig(Path(out) / "esail_sweep.png", dpi=120)
        plt.close(fig)
    return study


def figure(study):
    """Thrust magnitude (mN) and thrust angle (deg) against the sailing angle, one line
    per voltage, with the flat-sail rule ``alpha / 2``; returns the matplotlib figure."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(9, 3.6), constrained_layout=True)
    alpha = study.alpha.values
    for k, voltage in enumerate(study.voltage.values):
        point = study.sel(voltage=voltage)
        style = {"label": f"{voltage / 1e3:g} kV", "marker": "os^v"[k % 4],
                 "markersize": 9 - 3 * (k % 2), "fillstyle": "none" if k % 2 else "full"}
        ax1.plot(alpha, 1e3 * point.thrust_mean_N, **style)
        ax2.plot(alpha, point.thrust_angle_mean_deg, **style)
    ax2.plot(alpha, np.asarray(alpha) / 2, "k:", label="alpha / 2")
    ax1.set(xlabel="sailing angle alpha [deg]", ylabel="mean thrust |F| [mN]",
            title="thrust magnitude")
    ax2.set(xlabel="sailing angle alpha [deg]", ylabel="thrust angle from Sun line [deg]",
            title="thrust direction")
    for ax in (ax1, ax2):
        ax.grid(alpha=0.3)
        ax.legend()
    t_end = study.attrs["fixed"]["t_end"]
    fig.suptitle(f"E-sail baseline, mean over {t_end:.0f} s ({int(study.alpha.size)} x "
                 f"{int(study.voltage.size)} runs on Dask)")
    return fig


def gallery_figure(path, out=None):
    """The gallery's picture (``scripts/gallery.py``) into ``path``: ``figure`` of the
    study of ``main`` in ``out`` (default ``runs/esail_sweep`` of the repository, whose
    finished runs are reused), at 90 dpi."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out = Path(out) if out else Path(__file__).resolve().parents[1] / "runs" / "esail_sweep"
    fig = figure(main(out=str(out), plot=False))
    fig.savefig(path, dpi=90, bbox_inches="tight", pad_inches=0.05)
    plt.close(fig)


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--periods", type=float, default=1.0, help="spin periods per run")
    parser.add_argument("--workers", type=int, default=None, help="local worker processes")
    parser.add_argument("--out", default="runs/esail_sweep", help="study directory")
    args = parser.parse_args()
    start = time.perf_counter()
    ds = main(periods=args.periods, out=args.out, workers=args.workers)
    print(format_study(ds))
    print(f"{time.perf_counter() - start:.1f} s; figure {args.out}/esail_sweep.png")
