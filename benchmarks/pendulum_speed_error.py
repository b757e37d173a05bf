"""Speed against error for the flexible pendulum (issue: dynamics).

Steel-like cable, E = 7e10 Pa, radius 1 cm, L = 1.2 m, pinned, released horizontal at
rest, rho_inf = 0.8.  The reference tip position at t = 1 s comes from 32 elements and
dt = 2.5e-5 s.  Prints, for each (elements, dt): the tip error, wall time and Newton
iterations, so a user can pick the cheapest setting for an accuracy; then the same for
adaptive steps (``rtol = atol``, first step 1e-3 s): the speed-error front of fixed
against adaptive steps.
Run ``python benchmarks/pendulum_speed_error.py [--quick]`` (``--quick``: 4 and 8
elements, two steps, two tolerances, reference 16 elements and dt = 2.5e-4 s).
"""

import time

import numpy as np

import skfem_cable as sc
from skfem_cable.cli.bench import arguments
from skfem_cable.scenes import classics

SETTINGS = {
    "full": {"elements": (4, 8, 16, 32), "steps": (4e-3, 2e-3, 1e-3, 5e-4, 2.5e-4),
             "reference": (32, 2.5e-5), "tolerances": (1e-3, 1e-4, 1e-5, 1e-6, 1e-7)},
    "quick": {"elements": (4, 8), "steps": (2e-3, 1e-3), "reference": (16, 2.5e-4),
              "tolerances": (1e-4, 1e-6)},
}


def tip(n_elements, dt, **adaptive):
    scene = classics.pendulum(n_elements=n_elements)
    options = adaptive or {"tol": 1e-10}
    start = time.perf_counter()
    r = sc.simulate(scene.system, t_end=1.0, dt=dt, rho_inf=0.8, every=10**6, **options)
    wall = time.perf_counter() - start
    return r.position(scene.cable, 1.2)[-1], wall, r.stats["newton"]


def table(elements, steps, reference, tolerances):
    """Print the fixed-step and adaptive tables.

    Returns
    -------
    dict
        ``reference`` (the reference tip, m) and ``rows``: per setting ``elements``,
        ``dt`` (fixed steps) or ``tol`` (adaptive, ``rtol = atol``), ``error`` (tip error
        at t = 1 s, m), ``wall_s`` and ``newton`` (iterations).
    """
    tip(4, 1e-2)  # compile
    ref, ref_wall, _ = tip(*reference)
    print(f"reference ({reference[0]} elements, dt={reference[1]}): tip at t=1 s = {ref} "
          f"({ref_wall:.1f} s)")
    rows = []
    for label, key, values in (("dt", "dt", steps), ("rtol=atol", "tol", tolerances)):
        print(f"{'elements':>9} {label:>9} {'tip error [m]':>14} {'wall [s]':>9} "
              f"{'Newton':>8}")
        for n in elements:
            for value in values:
                adaptive = {"rtol": value, "atol": value} if key == "tol" else {}
                x, wall, newton = tip(n, 1e-3 if adaptive else value, **adaptive)
                err = float(np.linalg.norm(x - ref))
                rows.append({"elements": n, key: value, "error": err, "wall_s": wall,
                             "newton": newton})
                print(f"{n:9d} {value:9.1e} {err:14.3e} {wall:9.3f} {newton:8d}")
    return {"reference": ref, "rows": rows}


def main(argv=None):
    """Parse the arguments (``--quick``), print the tables and return their figures."""
    args = arguments(__doc__, "a few small settings", argv)
    return table(**SETTINGS["quick" if args.quick else "full"])


if __name__ == "__main__":
    main()
