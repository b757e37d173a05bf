"""Cost of the E-sail around the Sun against the same sail with the frame I fixed.

The 12-tether baseline sail (``esail.build``, 5 cable elements per tether, sailing angle
10 deg, dt = 0.1 s, rho_inf = 0.25) runs for one day twice, side by side in this process:
with the frame fixed (``esail.build``) and on the circular heliocentric orbit of 1 AU
(``esail.build_orbit``: the Sun's differential gravity on every mass point and the wind
evaluated at each Gauss point's heliocentric position, refreshed once per step).  Each wall
time is the minimum over the repeats, after a short run that compiles and lays out the
system; the table prints ms per step, Newton iterations per step and the ratio of the
orbiting run to the fixed one (goal: at most ``GOAL``).  Run ``python
benchmarks/esail_orbit_speed.py [--quick]`` (``--quick``: one hour, two repeats; the full
day takes about 15 minutes on 2 cores).
"""

import time

import numpy as np

import skfem_cable as sc
from skfem_cable.cli.bench import arguments
from skfem_cable.scenes import esail

SETTINGS = {"full": {"t_end": 86400.0, "repeats": 2},
            "quick": {"t_end": 3600.0, "repeats": 2}}

#: Goal of the ratio of the orbiting sail's wall time to the fixed sail's.
GOAL = 1.3

#: Time step (s), sailing angle (deg) and elements per tether of the runs.
DT, ALPHA, ELEMENTS = 0.1, 10.0, 5


def best_wall(scene, t_end, repeats):
    """Minimum wall time (s) over ``repeats`` runs of ``scene`` to ``t_end`` and the
    stats of the last run."""
    run = dict(dt=DT, initial=scene.initial, rho_inf=0.25, every=int(round(600 / DT)))
    sc.simulate(scene.system, t_end=10 * DT, **run)    # compile, layout
    best = np.inf
    for _ in range(repeats):
        start = time.perf_counter()
        result = sc.simulate(scene.system, t_end=t_end, **run)
        best = min(best, time.perf_counter() - start)
    return best, result.stats


def table(t_end, repeats):
    """Print the table; returns its rows and the ratio."""
    config = esail.BaselineConfig()
    cases = {"fixed frame (build)": esail.build(config, ALPHA, ELEMENTS),
             "around the Sun (build_orbit)": esail.build_orbit(config, ALPHA, ELEMENTS)}
    print(f"12 tethers x {ELEMENTS} elements, {t_end / 3600:g} h at dt = {DT} s, "
          f"minimum of {repeats}")
    print("| case | wall [s] | ms/step | Newton/step |\n|---|---|---|---|")
    rows = []
    for name, scene in cases.items():
        wall, stats = best_wall(scene, t_end, repeats)
        steps = stats["steps"]
        rows.append({"case": name, "wall_s": wall, "ms_per_step": 1e3 * wall / steps,
                     "newton_per_step": stats["newton"] / steps})
        print(f"| {name} | {wall:.1f} | {1e3 * wall / steps:.3f} | "
              f"{stats['newton'] / steps:.2f} |", flush=True)
    ratio = rows[1]["wall_s"] / rows[0]["wall_s"]
    print(f"ratio orbit / fixed: {ratio:.2f} (goal <= {GOAL})")
    return {"rows": rows, "ratio": ratio}


def main(argv=None):
    """Parse the arguments (``--quick``), print the table and return its figures."""
    args = arguments(__doc__, "one hour instead of a day, two repeats", argv)
    return table(**SETTINGS["quick" if args.quick else "full"])


if __name__ == "__main__":
    main()
