"""Newton corrections per step of the released 100 m pendulum at 1000 to 10,000 elements,
step by step (issue 47, item 4: why the count grows with the size).

The scene and window of ``benchmarks/step_exponent.py`` (``dt = 1 ms``, the steps 2 to
201 after the release).  For each size it prints the corrections per step over the window,
how many steps took 2, 3, 4 or more, and the steps one by one as a string: the predictor
of the step (``x``: extrapolated, ``GeneralizedAlpha.predictor``; ``c``: the constant
acceleration), its corrections and ``F`` where it factored the tangent; then, for a few
steps, the scaled residual before each correction (``kernels.step._iterate``'s history)
and the coordinate where the last one was largest (``System.describe_dof``).  No timing:
the counts are the same on every run (and it runs on trees before the predictor's
choice was kept, ``GeneralizedAlpha.extrapolated``: it reads the step's predictor from
its Newton parameters).  Then, for each size, the corrections per step of full Newton
(``newton="full"``: the tangent refactored at every iterate) over the same window, and
the exponents of both counts (their least-squares slopes on the sizes, log-log): full
Newton's is the growth that belongs to the problem (the predictor's miss at the pin
grows with the mesh; no choice of stale tangent does better than the exact one),
modified Newton's adds what its stale tangent costs.  Run ``python
benchmarks/newton_count.py [--quick]`` (``--quick``: 1000 and 3200 elements).
"""

import numpy as np

import skfem_cable as sc
from skfem_cable.cli.bench import arguments
from skfem_cable.kernels import step as codes
from skfem_cable.scenes import classics
from skfem_cable.solvers.galpha import GeneralizedAlpha

SETTINGS = {"full": {"sizes": (1000, 1800, 3200, 5600, 10000)},
            "quick": {"sizes": (1000, 3200)}}

#: Time step (s) and the window: the steps ``2 .. STEPS + 1`` after the release.
DT, STEPS = 1e-3, 200

#: Steps whose residual histories are printed.
SHOWN = (10, 30, 60, 100)


class StepLog:
    """While installed, a row per call of ``GeneralizedAlpha.step`` (a step): its
    corrections and factorizations (of all its Newton iterations: the first step makes
    two, one to fit the pseudo-acceleration, ``InitialState._fit_abar``), whether its
    predictor extrapolated, the scaled residual before each correction of its last
    Newton iteration and the coordinate of the largest last one."""

    def __init__(self):
        self.rows = []
        self.original = GeneralizedAlpha.step

    def __enter__(self):
        original, rows = self.original, self.rows

        def step(integrator, h):
            stats = dict(integrator.stats)
            ok, message = original(integrator, h)
            corrections = integrator.stats["newton"] - stats["newton"]
            r, prm = integrator.compiled.arrays["r"][:integrator.n], integrator.compiled.prm
            rows.append({"corrections": corrections,
                         "factorizations": integrator.stats["factorizations"]
                         - stats["factorizations"],
                         "extrapolated": bool(prm[codes.C1] or prm[codes.C0]),
                         "history": integrator.compiled.history[:integrator.iterations].copy(),
                         "largest": int(np.argmax(np.abs(r) * integrator.res_weight))})
            return ok, message

        GeneralizedAlpha.step = step
        return self

    def __exit__(self, *exc):
        GeneralizedAlpha.step = self.original


def steps_of(n_elements, steps=STEPS, newton="modified"):
    """The system, the rows of ``StepLog`` of the release and the ``steps`` steps after it
    (in ``newton``: ``simulate``'s option), and the run's ``Result``."""
    system = classics.pendulum(n_elements=n_elements, length=100.0, radius=0.01).system
    with StepLog() as log:
        result = sc.simulate(system, t_end=(steps + 1) * DT, dt=DT, every=steps + 1,
                             newton=newton)
    return system, log.rows, result


def window_count(rows, steps):
    """The corrections per step over the window (the ``steps`` rows after the release)."""
    return float(np.mean([r["corrections"] for r in rows[1:steps + 1]]))


def pattern(rows):
    """The steps as ``x2 c4F ...`` (predictor, corrections, factored)."""
    return " ".join(("x" if r["extrapolated"] else "c") + str(r["corrections"])
                    + ("F" if r["factorizations"] else "") for r in rows)


def report(sizes, steps=STEPS, shown=SHOWN):
    """Print each size's counts, pattern and the histories of the steps ``shown``, then
    full Newton's counts and both counts' exponents; return the corrections per step of
    the window (the ``steps`` after the release) by size, ``{"modified": {n: count},
    "full": {n: count}}``."""
    per_step = {"modified": {}, "full": {}}
    for n in sizes:
        system, rows, _ = steps_of(n, steps)
        window = rows[1:steps + 1]
        counts = np.array([r["corrections"] for r in window])
        per_step["modified"][n] = window_count(rows, steps)
        spread = {k: int(np.sum(counts == k)) for k in range(1, counts.max() + 1)}
        print(f"{n} elements: {per_step['modified'][n]:.3f} corrections per step, "
              f"{sum(r['factorizations'] for r in window)} factorizations; steps by "
              f"corrections {spread}")
        print("  steps 1-80: " + pattern(rows[:80]))
        for k in shown:
            r = rows[k - 1]
            history = " ".join(f"{e:.1e}" for e in r["history"])
            print(f"  step {k}: {history}; largest at {system.describe_dof(r['largest'])}")
    for n in sizes:
        per_step["full"][n] = window_count(steps_of(n, steps, "full")[1], steps)
        print(f"{n} elements, full Newton: {per_step['full'][n]:.3f} corrections per step")
    if len(sizes) > 1:
        print("exponent of the corrections per step: " + ", ".join(
            f"{newton} Newton {np.polyfit(np.log(sizes), np.log(list(c.values())), 1)[0]:.3f}"
            for newton, c in per_step.items()))
    return per_step


def main(argv=None):
    """Parse the arguments (``--quick``) and print the report."""
    args = arguments(__doc__, "1000 and 3200 elements", argv)
    return report(**SETTINGS["quick" if args.quick else "full"])


if __name__ == "__main__":
    main()
