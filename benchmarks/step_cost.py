"""Cost of one generalized-alpha time step versus the number of elements.

A pendulum cable (100 m, pinned) at fixed element length ratio is integrated for a few
steps; prints wall time per step, Newton iterations per step and the fitted growth exponent
(goal: <= 1.1).  Run ``python benchmarks/step_cost.py``.
"""

import time

import numpy as np

import skfem_cable as sc
from skfem_cable.scenes import classics


def cost_per_step(n_elements, steps=20):
    scene = classics.pendulum(n_elements=n_elements, length=100.0, radius=0.01)
    sc.simulate(scene.system, t_end=1e-3, dt=1e-3)  # compile and build the layout
    start = time.perf_counter()
    r = sc.simulate(scene.system, t_end=steps * 1e-3, dt=1e-3, every=steps)
    wall = time.perf_counter() - start
    return wall / steps, r.stats["newton"] / r.stats["steps"]


def main(sizes=(10, 30, 100, 300, 1000, 3000, 10000)):
    rows = [(n, *cost_per_step(n)) for n in sizes]
    print(f"{'elements':>9} {'ms/step':>10} {'Newton/step':>12} {'ms/iteration':>13}")
    for n, t, it in rows:
        print(f"{n:9d} {1e3 * t:10.3f} {it:12.2f} {1e3 * t / it:13.3f}")
    n = np.array([r[0] for r in rows], float)
    t = np.array([r[1] for r in rows])
    it = np.array([r[2] for r in rows])
    big = n >= np.sort(n)[len(n) // 2]  # the larger half of the sizes
    for label, y in (("step", t), ("Newton iteration", t / it)):
        slope = np.polyfit(np.log(n[big]), np.log(y[big]), 1)[0]
        print(f"growth exponent per {label} (larger half of the sizes): {slope:.2f}")
    return rows


if __name__ == "__main__":
    main()
