"""Electric solar-wind sail: the baseline of Pacheco-Ramos et al. (Table 1).

Physics
-------
A cylindrical hub (2 m x 1 m radius, 884 kg/m^3; a rigid body in natural coordinates)
spins at 4e-3 rad/s about its axis ``X_B``.  Twelve aluminium tethers of 10 km
(``A = 4.28e-3 mm^2``), each of five ANCF cable elements with Kelvin-Voigt damping, are
pinned to its rim and carry 1.5 kg remote units; they start radial, stretched by the steady
rotating-cable solution, the whole sail in rigid rotation.  At 20 kV the solar wind (400
km/s, 7.3 protons/cm^3, radial from the Sun at 1 AU) pushes each tether with
``0.18 (V0 - V1) sqrt(eps0 m_p n0) u_perp = 4.49e-7 N/m`` perpendicular to it: about
54 mN in all.  The sail axis is tilted by the sailing angle ``alpha`` from the Sun line,
so the thrust turns by about ``alpha / 2``, the tethers cone at the spin frequency and lag
in their plane at the first bending frequency.  Generalized-alpha (rho_inf = 0.25,
dt = 0.1 s) integrates three spin periods (4712 s, 47,124 steps).  The tethers are in the
paper's formulation (``formulation="paper"``, every term on the 5-point Gauss rule), as the
paper computed them; the library's default formulation changes the thrust, coning and
frequencies by less than their discretisation error (``docs/locking.md``).

Run ``python demos/esail_baseline.py [--alpha DEG] [--periods P] [--out DIR]``: the run
directory holds the ParaView series (``series.pvd``), the results (chunks), the paper's
figures (``plots/``), every output of ``esail.outputs`` (``esail_outputs.npz``) and
``summary.json``.
"""

import argparse
import time

from skfem_cable.runner import RunOptions, format_summary
from skfem_cable.scenes import catalog, esail


def main(alpha=10.0, periods=3.0, elements=5, out="runs/esail", plots=True, progress=None):
    """Run the baseline sail into ``out`` (replacing an earlier run there); returns the
    summary (dict) of the run."""
    cfg = esail.BaselineConfig()
    options = RunOptions(out=out, alpha=alpha, elements=elements, formulation="paper",
                         t_end=periods * cfg.spin_period, progress=progress, plots=plots,
                         overwrite=True)
    return catalog.run_scene("esail", options)


def gallery_figure(path, out=None):
    """The gallery's picture (``scripts/gallery.py``) into ``path``: the thrust angle over
    three spin periods with the tolerance band, and the coning angle of the twelve tethers,
    from the run in ``out`` (default ``runs/esail`` of the repository), reused when it
    holds a complete run of ``main``'s defaults and made by ``main`` otherwise."""
    import json
    from pathlib import Path

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    run = Path(out) if out else Path(__file__).resolve().parents[1] / "runs" / "esail"
    summary = run / "summary.json"
    ok = summary.is_file() and json.loads(summary.read_text()).get("steps") == 47124
    if not ok:
        main(out=str(run), plots=False)
    outputs = np.load(run / "esail_outputs.npz")
    t = outputs["t"] / 3600
    fig, (a, b) = plt.subplots(1, 2, figsize=(8.5, 3.0), layout="constrained")
    a.axhspan(4.9, 5.1, color="0.85", label="5 deg +- 0.1 deg")
    a.plot(t, np.rad2deg(outputs["thrust_angle"]), label="thrust angle")
    a.set_ylim(4.8, 5.2)
    a.set_xlabel("t [h]")
    a.set_ylabel("deg")
    a.legend(fontsize=8)
    a.set_title("thrust angle from the Sun line, alpha = 10 deg", fontsize=10)
    b.plot(t, np.rad2deg(outputs["coning"]), lw=0.8)
    b.set_xlabel("t [h]")
    b.set_ylabel("deg")
    b.set_title("coning angle of the 12 tethers", fontsize=10)
    fig.savefig(path, dpi=90, bbox_inches="tight", pad_inches=0.05)
    plt.close(fig)


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--alpha", type=float, default=10.0, help="sailing angle (deg)")
    parser.add_argument("--periods", type=float, default=3.0, help="spin periods to run")
    parser.add_argument("--out", default="runs/esail", help="run directory")
    args = parser.parse_args()
    start = time.perf_counter()
    summary = main(args.alpha, args.periods, out=args.out)
    print(format_summary(summary))
    print(f"total time {time.perf_counter() - start:.1f} s; open {args.out}/series.pvd in "
          "ParaView")
