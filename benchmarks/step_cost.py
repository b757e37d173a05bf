"""Cost of one generalized-alpha time step versus the number of elements, compiled and
Python Newton steps side by side.

A pendulum cable (100 m, pinned) at fixed element length ratio is integrated for a few
steps by each path (``simulate(..., compiled=True/False)``, the same iterates); prints ms
per step of both, their ratio, Newton iterations per step, the fitted growth exponents of
the larger half of the sizes (goal: <= 1.05) and the peak resident memory of the process
after each size (it includes the largest run so far).
Run ``python benchmarks/step_cost.py``.
"""

import resource
import sys
import time

import numpy as np

import skfem_cable as sc
from skfem_cable.scenes import classics


def peak_memory_mb():
    """Peak resident memory of this process so far (MB)."""
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return peak / 2**20 if sys.platform == "darwin" else peak / 2**10


def cost_per_step(n_elements, steps=20, repeats=3):
    """``(ms/step compiled, ms/step Python, Newton/step)``: minimum over ``repeats``."""
    scene = classics.pendulum(n_elements=n_elements, length=100.0, radius=0.01)
    walls = {}
    for compiled in (True, False):
        sc.simulate(scene.system, t_end=1e-3, dt=1e-3, compiled=compiled)  # compile, layout
        best = np.inf
        for _ in range(repeats):
            start = time.perf_counter()
            r = sc.simulate(scene.system, t_end=steps * 1e-3, dt=1e-3, every=steps,
                            compiled=compiled)
            best = min(best, time.perf_counter() - start)
        walls[compiled] = 1e3 * best / steps
    return walls[True], walls[False], r.stats["newton"] / r.stats["steps"]


def exponent(n, y):
    """Slope of ``log y`` against ``log n`` over the larger half of the sizes."""
    n, y = np.asarray(n, float), np.asarray(y, float)
    big = n >= np.sort(n)[len(n) // 2]
    return float(np.polyfit(np.log(n[big]), np.log(y[big]), 1)[0])


def main(sizes=(10, 30, 100, 300, 1000, 3000, 10000), steps=20, repeats=3):
    rows = []
    print(f"{'elements':>9} {'compiled ms/step':>17} {'Python ms/step':>15} {'ratio':>6} "
          f"{'Newton/step':>12} {'peak MB':>8}")
    for n in sizes:
        fast, slow, it = cost_per_step(n, steps, repeats)
        rows.append((n, fast, slow, it, peak_memory_mb()))
        print(f"{n:9d} {fast:17.3f} {slow:15.3f} {fast / slow:6.2f} {it:12.2f} "
              f"{rows[-1][4]:8.0f}", flush=True)
    n = [r[0] for r in rows]
    for label, k in (("compiled", 1), ("Python", 2)):
        print(f"growth exponent per step, {label} (larger half of the sizes): "
              f"{exponent(n, [r[k] for r in rows]):.2f}")
    return rows


if __name__ == "__main__":
    main()
