"""Speed against error for the flexible pendulum (issue: dynamics).

Steel-like cable, E = 7e10 Pa, radius 1 cm, L = 1.2 m, pinned, released horizontal at
rest, rho_inf = 0.8.  The reference tip position at t = 1 s comes from 32 elements and
dt = 2.5e-5 s.  Prints, for each (elements, dt): the tip error, wall time and Newton
iterations, so a user can pick the cheapest setting for an accuracy; then the same for
adaptive steps (``rtol = atol``, first step 1e-3 s): the speed-error front of fixed
against adaptive steps.
Run ``python benchmarks/pendulum_speed_error.py``.
"""

import time

import numpy as np

import skfem_cable as sc
from skfem_cable.scenes import classics


def tip(n_elements, dt, **adaptive):
    scene = classics.pendulum(n_elements=n_elements)
    options = adaptive or {"tol": 1e-10}
    start = time.perf_counter()
    r = sc.simulate(scene.system, t_end=1.0, dt=dt, rho_inf=0.8, every=10**6, **options)
    wall = time.perf_counter() - start
    return r.position(scene.cable, 1.2)[-1], wall, r.stats["newton"]


def main(elements=(4, 8, 16, 32), steps=(4e-3, 2e-3, 1e-3, 5e-4, 2.5e-4),
         reference=(32, 2.5e-5), tolerances=(1e-3, 1e-4, 1e-5, 1e-6, 1e-7)):
    """Rows ``(elements, dt, error, wall, Newton)``; adaptive rows carry ``dt = -tol``."""
    tip(4, 1e-2)  # compile
    ref, ref_wall, _ = tip(*reference)
    print(f"reference ({reference[0]} elements, dt={reference[1]}): tip at t=1 s = {ref} "
          f"({ref_wall:.1f} s)")
    print(f"{'elements':>9} {'dt':>9} {'tip error [m]':>14} {'wall [s]':>9} {'Newton':>8}")
    rows = []
    for n in elements:
        for dt in steps:
            x, wall, newton = tip(n, dt)
            err = float(np.linalg.norm(x - ref))
            rows.append((n, dt, err, wall, newton))
            print(f"{n:9d} {dt:9.1e} {err:14.3e} {wall:9.3f} {newton:8d}")
    print(f"{'elements':>9} {'rtol=atol':>9} {'tip error [m]':>14} {'wall [s]':>9} "
          f"{'Newton':>8}")
    for n in elements:
        for tol in tolerances:
            x, wall, newton = tip(n, 1e-3, rtol=tol, atol=tol)
            err = float(np.linalg.norm(x - ref))
            rows.append((n, -tol, err, wall, newton))
            print(f"{n:9d} {tol:9.1e} {err:14.3e} {wall:9.3f} {newton:8d}")
    return ref, rows


if __name__ == "__main__":
    main()
