"""Cost of one generalized-alpha time step versus the number of elements, compiled and
Python Newton steps side by side.

A pendulum cable (100 m, pinned, released horizontally) is integrated by each path
(``simulate(..., compiled=True/False)``, the same iterates) for one step and for ``1 +
steps`` steps.  The cost of a step is the difference over ``steps``: the steps of a run,
without its setup (the layout's solver, the consistent initial state) and its first step
(the release, whose Newton refactors the tangent up to three times at 10,000 elements),
which the table prints apart as ``setup ms``.  Prints ms per step of both paths, their
ratio, Newton iterations per step, the compiled setup, the fitted growth exponents (goal:
<= 1.05; per step over all sizes and over the larger half, and per Newton iteration: in the
first 20 steps of the release the Newton count grows from 2.7 to 3.8 per step between 300
and 10,000 elements, over 400 steps it is 2.2 to 2.4 at every size from 100 on) and the
peak resident memory of the process after each size (it includes the largest run so far).
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

SETTINGS = {"full": {"sizes": (10, 30, 100, 300, 1000, 3000, 10000), "steps": 400, "repeats": 3},
            "quick": {"sizes": (10, 100, 1000, 3000), "steps": 10, "repeats": 1}}


def peak_memory_mb():
    """Peak resident memory of this process so far (MB)."""
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return peak / 2**20 if sys.platform == "darwin" else peak / 2**10


def cost_per_step(n_elements, steps=20, repeats=3):
    """``(ms/step compiled, ms/step Python, Newton/step, ms of the compiled setup and first
    step)``: minimum over ``repeats`` of runs of 1 and of ``1 + steps`` steps."""
    scene = classics.pendulum(n_elements=n_elements, length=100.0, radius=0.01)
    walls, newton = {}, {}
    for compiled in (True, False):
        sc.simulate(scene.system, t_end=1e-3, dt=1e-3, compiled=compiled)  # compile, layout
        best = {1: np.inf, 1 + steps: np.inf}
        for _ in range(repeats):
            for k in best:
                start = time.perf_counter()
                r = sc.simulate(scene.system, t_end=k * 1e-3, dt=1e-3, every=k,
                                compiled=compiled)
                best[k] = min(best[k], time.perf_counter() - start)
                newton[k] = r.stats["newton"]
        walls[compiled] = (1e3 * (best[1 + steps] - best[1]) / steps, 1e3 * best[1])
    return (walls[True][0], walls[False][0], (newton[1 + steps] - newton[1]) / steps,
            walls[True][1])


def exponent(n, y, half=True):
    """Slope of ``log y`` against ``log n`` over the larger half of the sizes (``half``)
    or over all of them."""
    n, y = np.asarray(n, float), np.asarray(y, float)
    big = n >= np.sort(n)[len(n) // 2] if half else n > 0
    return float(np.polyfit(np.log(n[big]), np.log(y[big]), 1)[0])


#: The fitted exponents: (key, label, value of a row, over the larger half only).
FITS = (("compiled", "compiled, per step", lambda r: r["compiled_ms"], True),
        ("compiled_all", "compiled, per step", lambda r: r["compiled_ms"], False),
        ("iteration", "compiled, per Newton iteration",
         lambda r: r["compiled_ms"] / r["newton_per_step"], True),
        ("python", "Python, per step", lambda r: r["python_ms"], True),
        ("setup", "setup and first step", lambda r: r["setup_ms"], True))


def table(sizes, steps=20, repeats=3):
    """Print the cost table and the growth exponents.

    Returns
    -------
    dict
        ``rows`` (per size: ``elements``, ``compiled_ms``, ``python_ms`` per step,
        ``ratio`` compiled / Python, ``newton_per_step`` (of the steps after the first),
        ``setup_ms`` (compiled: setup and first step), ``peak_mb``) and
        ``growth_exponents`` (keys of ``FITS``).
    """
    rows = []
    print(f"{'elements':>9} {'compiled ms/step':>17} {'Python ms/step':>15} {'ratio':>6} "
          f"{'Newton/step':>12} {'setup ms':>9} {'peak MB':>8}")
    for n in sizes:
        fast, slow, it, setup = cost_per_step(n, steps, repeats)
        rows.append({"elements": n, "compiled_ms": fast, "python_ms": slow,
                     "ratio": fast / slow, "newton_per_step": it, "setup_ms": setup,
                     "peak_mb": peak_memory_mb()})
        print(f"{n:9d} {fast:17.3f} {slow:15.3f} {fast / slow:6.2f} {it:12.2f} {setup:9.1f} "
              f"{rows[-1]['peak_mb']:8.0f}", flush=True)
    n = [r["elements"] for r in rows]
    slopes = {}
    for key, label, value, half in FITS:
        slopes[key] = exponent(n, [value(r) for r in rows], half)
        over = "the larger half of the sizes" if half else "all sizes"
        print(f"growth exponent, {label} ({over}): {slopes[key]:.2f}")
    return {"rows": rows, "growth_exponents": slopes}


def main(argv=None):
    """Parse the arguments (``--quick``), print the table and return its figures."""
    args = arguments(__doc__, "small sizes, one repeat", argv)
    return table(**SETTINGS["quick" if args.quick else "full"])


if __name__ == "__main__":
    main()
