"""Cost of one generalized-alpha time step versus the number of elements, the Newton step
compiled and interpreted side by side.

A pendulum cable (100 m, pinned, released horizontally) is integrated by each run of the
one Newton step (``simulate(..., compiled=True/False)``: compiled, or the same generated
source interpreted, the debugging mode since issue 46; the same iterates) for one step and for ``1 +
steps`` steps, each the minimum over repeats.  The cost of a step is the difference over
``steps``: the steps of a run, without its setup (the layout's solver, the consistent
initial state) and its first step (the release, whose Newton refactors the tangent up to
three times at 10,000 elements), which the table prints apart as ``setup ms``.  ``steps``
is raised (the table prints it) until that difference exceeds ``SPAN`` (0.2 s) in both
paths, far above the scatter of the setup, so no step's cost is lost in it.  Prints ms per
step of both paths, their ratio, Newton iterations per step, the compiled setup, the fitted
growth exponents (goal: <= 1.05; per step over all sizes and over the larger half, and per
Newton iteration: in the first 20 steps of the release the Newton count grows from 2.7 to
3.8 per step between 300 and 10,000 elements, over 400 steps it is 2.2 to 2.4 at every size
from 100 on) and the peak resident memory of the process after each size (it includes the
largest run so far).  Run ``python benchmarks/step_cost.py [--quick]`` (``--quick``: 10 to
3000 elements, at least 10 steps, two repeats; its exponents are indicative only: the first
steps of the release need more Newton iterations on fine meshes).
"""

import math
import resource
import sys
import time

import numpy as np

import skfem_cable as sc
from skfem_cable.cli.bench import arguments
from skfem_cable.scenes import classics

SETTINGS = {"full": {"sizes": (10, 30, 100, 300, 1000, 3000, 10000), "steps": 400, "repeats": 3},
            "quick": {"sizes": (10, 100, 1000, 3000), "steps": 10, "repeats": 2,
                      "quick": True}}

#: Least wall time in s by which a run of ``1 + steps`` steps must outlast the run of one
#: step: well above the scatter of the setup, so that their difference is a step's cost.
SPAN = 0.2

#: Goal of the growth exponents of the compiled step (linear cost).
GOAL = 1.05

#: Time step of the runs (s).
DT = 1e-3


def peak_memory_mb():
    """Peak resident memory of this process so far (MB)."""
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return peak / 2**20 if sys.platform == "darwin" else peak / 2**10


def best_walls(system, compiled, steps, repeats):
    """Wall times in s (minimum over ``repeats``) and Newton iterations of runs of 1 and of
    ``1 + steps`` steps of ``system``, keyed by the number of steps."""
    sc.simulate(system, t_end=DT, dt=DT, compiled=compiled)  # compile, layout
    walls, newton = {1: np.inf, 1 + steps: np.inf}, {}
    for _ in range(repeats):
        for k in walls:
            start = time.perf_counter()
            r = sc.simulate(system, t_end=k * DT, dt=DT, every=k, compiled=compiled)
            walls[k] = min(walls[k], time.perf_counter() - start)
            newton[k] = r.stats["newton"]
    return walls, newton


def more_steps(steps, measured, span):
    """The steps expected to take ``1.2 span`` s, when ``steps`` took ``measured`` s (at
    most ten times ``steps``; ten times when ``measured`` is lost in the scatter)."""
    if measured <= 0:
        return 10 * steps
    return max(steps + 1, min(10 * steps, math.ceil(1.2 * steps * span / measured)))


def cost_per_step(n_elements, steps=20, repeats=3, span=SPAN):
    """``(ms/step compiled, ms/step Python, Newton/step, ms of the compiled setup and first
    step, steps)``: differences of the minima over ``repeats`` of runs of 1 and of
    ``1 + steps`` steps, ``steps`` raised until both paths' differences exceed ``span`` s."""
    scene = classics.pendulum(n_elements=n_elements, length=100.0, radius=0.01)
    while True:
        runs = {c: best_walls(scene.system, c, steps, repeats) for c in (True, False)}
        spans = {c: walls[1 + steps] - walls[1] for c, (walls, _) in runs.items()}
        if min(spans.values()) >= span:
            break
        steps = more_steps(steps, min(spans.values()), span)
    walls, newton = runs[True]
    return (1e3 * spans[True] / steps, 1e3 * spans[False] / steps,
            (newton[1 + steps] - newton[1]) / steps, 1e3 * walls[1], steps)


def exponent(n, y, half=True):
    """Slope of ``log y`` against ``log n`` over the larger half of the sizes (``half``)
    or over all of them; ``None`` (no fit) when one of those ``y`` is not positive."""
    n, y = np.asarray(n, float), np.asarray(y, float)
    big = n >= np.sort(n)[len(n) // 2] if half else n > 0
    if big.sum() < 2 or not (y[big] > 0).all():
        return None
    return float(np.polyfit(np.log(n[big]), np.log(y[big]), 1)[0])


#: The fitted exponents: (key, label, value of a row, over the larger half only, held to
#: ``GOAL``).
FITS = (("compiled", "compiled, per step", lambda r: r["compiled_ms"], True, True),
        ("compiled_all", "compiled, per step", lambda r: r["compiled_ms"], False, True),
        ("iteration", "compiled, per Newton iteration",
         lambda r: r["compiled_ms"] / r["newton_per_step"], True, True),
        ("python", "Python, per step", lambda r: r["python_ms"], True, False),
        ("setup", "setup and first step", lambda r: r["setup_ms"], True, False))


def verdict(slope, goal, quick):
    """How a fitted exponent reads: ``slope`` (``None``: not fitted), against ``GOAL``
    when ``goal``, indicative only in a ``quick`` run."""
    if slope is None:
        return "not fitted (a time is not positive)"
    if quick:
        return f"{slope:.2f}, indicative (quick mode)"
    if not goal:
        return f"{slope:.2f}"
    return f"{slope:.2f} (goal <= {GOAL}{'' if slope <= GOAL else ': ABOVE THE GOAL'})"


def table(sizes, steps=20, repeats=3, quick=False, span=SPAN):
    """Print the cost table and the growth exponents.

    Parameters
    ----------
    sizes : sequence of int
        Numbers of elements.
    steps : int
        Least number of timed steps (raised until a run outlasts the setup by ``span``).
    repeats : int
        Runs of each length; the minimum wall time counts.
    quick : bool
        Label the exponents indicative (a quick run is too short to judge them).
    span : float
        Least wall time in s of the timed steps.

    Returns
    -------
    dict
        ``rows`` (per size: ``elements``, ``steps`` timed, ``compiled_ms``,
        ``python_ms`` per step, ``ratio`` compiled / Python, ``newton_per_step`` (of the
        steps after the first), ``setup_ms`` (compiled: setup and first step),
        ``peak_mb``) and ``growth_exponents`` (keys of ``FITS``; ``None`` if not fitted).
    """
    rows = []
    print(f"{'elements':>9} {'steps':>6} {'compiled ms/step':>17} {'Python ms/step':>15} "
          f"{'ratio':>6} {'Newton/step':>12} {'setup ms':>9} {'peak MB':>8}")
    for n in sizes:
        fast, slow, it, setup, timed = cost_per_step(n, steps, repeats, span)
        rows.append({"elements": n, "steps": timed, "compiled_ms": fast, "python_ms": slow,
                     "ratio": fast / slow, "newton_per_step": it, "setup_ms": setup,
                     "peak_mb": peak_memory_mb()})
        print(f"{n:9d} {timed:6d} {fast:17.3f} {slow:15.3f} {fast / slow:6.2f} {it:12.2f} "
              f"{setup:9.1f} {rows[-1]['peak_mb']:8.0f}", flush=True)
    n = [r["elements"] for r in rows]
    slopes = {}
    for key, label, value, half, goal in FITS:
        slopes[key] = exponent(n, [value(r) for r in rows], half)
        over = "the larger half of the sizes" if half else "all sizes"
        print(f"growth exponent, {label} ({over}): {verdict(slopes[key], goal, quick)}")
    if quick:
        print(f"(quick mode: early steps of the release, up to {max(n)} elements; the goal "
              f"<= {GOAL} of the compiled step is judged by the full run)")
    return {"rows": rows, "growth_exponents": slopes}


def main(argv=None):
    """Parse the arguments (``--quick``), print the table and return its figures."""
    args = arguments(__doc__, "10 to 3000 elements, at least 10 steps, two repeats", argv)
    return table(**SETTINGS["quick" if args.quick else "full"])


if __name__ == "__main__":
    main()
