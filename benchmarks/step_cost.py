"""Cost of one generalized-alpha time step versus the number of elements, compiled and
Python Newton steps side by side.

A pendulum cable (100 m, pinned) at fixed element length ratio is integrated for a few
steps by each path (``simulate(..., compiled=True/False)``, the same iterates); prints ms
per step of both, their ratio, Newton iterations per step, the fitted growth exponents of
the larger half of the sizes (goal: <= 1.05) and the peak resident memory of the process
after each size (it includes the largest run so far).
Run ``python benchmarks/step_cost.py [--quick]`` (``--quick``: 10 to 3000 elements, 10
steps, one repeat).
"""

import resource
import sys
import time

import numpy as np

import skfem_cable as sc
from skfem_cable.bench import arguments
from skfem_cable.scenes import classics

SETTINGS = {"full": {"sizes": (10, 30, 100, 300, 1000, 3000, 10000), "steps": 20, "repeats": 3},
            "quick": {"sizes": (10, 100, 1000, 3000), "steps": 10, "repeats": 1}}


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


def table(sizes, steps=20, repeats=3):
    """Print the cost table and the growth exponents.

    Returns
    -------
    dict
        ``rows`` (per size: ``elements``, ``compiled_ms``, ``python_ms`` per step,
        ``ratio`` compiled / Python, ``newton_per_step``, ``peak_mb``) and
        ``growth_exponents`` (``compiled``, ``python``).
    """
    rows = []
    print(f"{'elements':>9} {'compiled ms/step':>17} {'Python ms/step':>15} {'ratio':>6} "
          f"{'Newton/step':>12} {'peak MB':>8}")
    for n in sizes:
        fast, slow, it = cost_per_step(n, steps, repeats)
        rows.append({"elements": n, "compiled_ms": fast, "python_ms": slow,
                     "ratio": fast / slow, "newton_per_step": it, "peak_mb": peak_memory_mb()})
        print(f"{n:9d} {fast:17.3f} {slow:15.3f} {fast / slow:6.2f} {it:12.2f} "
              f"{rows[-1]['peak_mb']:8.0f}", flush=True)
    n = [r["elements"] for r in rows]
    slopes = {}
    for label, key in (("compiled", "compiled_ms"), ("Python", "python_ms")):
        slope = slopes[label.lower()] = exponent(n, [r[key] for r in rows])
        print(f"growth exponent per step, {label} (larger half of the sizes): {slope:.2f}")
    return {"rows": rows, "growth_exponents": slopes}


def main(argv=None):
    """Parse the arguments (``--quick``), print the table and return its figures."""
    args = arguments(__doc__, "small sizes, one repeat", argv)
    return table(**SETTINGS["quick" if args.quick else "full"])


if __name__ == "__main__":
    main()
