"""A day of the 12-tether E-sail (``esail.BaselineConfig``, 10 deg) through a stream
interface: a ``SolarWind.series`` whose density triples within 10 minutes at 12 h, the
speed held at 400 km/s (issue 51, item 5).

The paper's law scales as ``sqrt(n) u``: the thrust should jump by ``sqrt(3)``, and the
sail respond, its coning rising with the force against the same centrifugal stiffening
and its spin rate changed only by the tilt of the coned tethers.  Reported: the thrust
ratio across the interface against ``sqrt(3)`` (the same geometry, one saved step apart,
and the means of the hours before and after), the mean coning and the sail's spin rate
before and after, the wall time.  Adaptive steps at ``esail.MISSION_RTOL`` from the
sail's state under the wind (``esail.settled``; the series starts a day before t = 0 to
cover the relaxation).  ``--quick``: 2 hours, the interface at 1 h, 3 elements.

    OPENBLAS_NUM_THREADS=1 .venv/bin/python benchmarks/esail_wind_jump.py [--quick]
"""

import json
import time

import numpy as np

import skfem_cable as sc
from skfem_cable.cli.bench import RESULTS, arguments
from skfem_cable.scenes import esail

SETTINGS = {"full": {"t_end": 86400.0, "n_elements": 5},
            "quick": {"t_end": 7200.0, "n_elements": 3}}

#: The interface's duration (s) and density factor.
RAMP, FACTOR = 600.0, 3.0


def jump_wind(t_end):
    """The series: 7.3 cm^-3 until ``t_end / 2``, ``FACTOR`` times it from ``RAMP`` later,
    400 km/s throughout, from a day before t = 0 (the relaxation of ``settled``)."""
    mid = t_end / 2
    n = 7.3e6
    return sc.SolarWind.series([-86400.0, mid, mid + RAMP, t_end + 1.0],
                               [n, n, FACTOR * n, FACTOR * n], [4e5] * 4)


def run(t_end, n_elements):
    """The run and its outputs (``esail.outputs``) with the summary numbers."""
    scene = esail.build(esail.BaselineConfig(wind=jump_wind(t_end)), 10.0, n_elements)
    scene = esail.settled(scene)
    start = time.perf_counter()
    result = sc.simulate(scene.system, t_end, 1.0, initial=scene.initial, rho_inf=0.25,
                         rtol=esail.MISSION_RTOL, atol=1e-3, every=1)
    wall = time.perf_counter() - start
    out = esail.outputs(scene, result)
    t, mid = out["t"], t_end / 2
    thrust = np.linalg.norm(out["thrust"], axis=1)
    coning = np.rad2deg(out["coning"].mean(axis=1))
    spin = out["spin_rate"]
    before = (t > mid - 3600.0) & (t <= mid)
    after = (t >= t_end - 3600.0)
    k0 = int(np.searchsorted(t, mid, side="right") - 1)
    k1 = int(np.searchsorted(t, mid + RAMP))
    return {"t_end_s": t_end, "n_elements": n_elements, "steps": len(t) - 1,
            "wall_s": wall,
            "thrust_ratio_across": float(thrust[k1] / thrust[k0]),
            "thrust_ratio_hour_means": float(thrust[after].mean() / thrust[before].mean()),
            "law_ratio": float(np.sqrt(FACTOR)),
            "coning_deg_before": float(coning[before].mean()),
            "coning_deg_after": float(coning[after].mean()),
            "coning_deg_range_after": [float(coning[t > mid].min()),
                                       float(coning[t > mid].max())],
            "spin_rate_before": float(spin[before].mean()),
            "spin_rate_after": float(spin[after].mean()),
            "spin_rate_relative_change": float(spin[after].mean() / spin[before].mean() - 1)}


def main(argv=None):
    args = arguments(__doc__, "2 hours, 3 elements per tether", argv)
    row = run(**SETTINGS["quick" if args.quick else "full"])
    print(json.dumps(row, indent=2))
    RESULTS.mkdir(parents=True, exist_ok=True)
    (RESULTS / f"esail_wind_jump{'_quick' if args.quick else ''}.json").write_text(
        json.dumps(row, indent=2))
    return row


if __name__ == "__main__":
    main()
