"""Growth exponent of the compiled step's cost from 1,000 to 10,000 elements, over the 200
steps after the release (issue 47), measured so that it is stable from run to run on a
shared machine.

The scene of ``benchmarks/step_cost.py``: a 100 m pendulum cable (pinned, released
horizontally, ``dt = 1 ms``), at log-spaced sizes (1000, 1800, 3200, 5600 and 10,000
elements).  How the measure is made stable:

- **CPU time** of the process (``time.process_time``), not wall time: another job on the
  same core stretches the wall time of a run, not its CPU time;
- **the steps timed one by one**: the CPU time at the start of each step of a run
  (``StepClock``) gives the cost of the steps ``2 .. 201``, the issue's window of 200
  steps after the release (no setup of a ``simulate`` call, no release step, whose Newton
  refactors several times, in it), summed in chunks of ``CHUNK`` (20) steps;
- **minimum of repeats chunk by chunk, sizes alternated**: ``rounds`` rounds each time
  every size, the order of the sizes reversed from round to round; each chunk of each
  size takes its minimum over the rounds (a spell of the machine slowed by the other
  jobs' memory traffic, which CPU time does not remove, spoils a chunk of 20 steps, not
  a whole run), the chunks' minima add up to the window's cost;
- **rounds in fresh processes** (``processes``, one after the other): the cost of the
  1000 elements moved by up to 8 % from one process to the next and stayed in every
  round of a process (where its arrays fell, presumably), so that runs of one process
  each differed by 0.02-0.04 in the exponent while their halves agreed to 0.01; the
  minimum over four processes takes the best of four such draws;
- **the slope fitted over all five sizes** (least squares of ``log cost`` on
  ``log elements``) with its standard error, and the **spread**: the slopes fitted to each
  round alone (their range), a measure of what one round would have said, and the slopes
  of the minima over the rounds of the even and of the odd processes (the **halves**: two
  measures of half the length in processes of their own, taken in the same time window;
  their difference says how far two runs of the measure would differ, the issue's
  stability to 0.02).

Twelve rounds, three in each of four processes (eight in one before, five before
that): the other jobs' memory traffic, which slows the largest sizes (out of the L3
cache) and not the smallest, comes in spells of seconds to minutes; more rounds spread
over a longer window give each chunk more chances of a quiet spell.

Prints a row per size (CPU ms per step, Newton iterations per step, ms per iteration)
and the exponents per step and per Newton iteration, and the slope between the smallest
and the largest size alone. Run ``python benchmarks/step_exponent.py [--quick]`` (about
80 s; ``--quick``: 300 to 3000 elements, 20 steps, two rounds in this process;
indicative only).
"""

import json
import os
import subprocess
import sys
import time

import numpy as np

import skfem_cable as sc
from skfem_cable.cli.bench import arguments
from skfem_cable.scenes import classics
from skfem_cable.solvers.galpha import GeneralizedAlpha

SETTINGS = {"full": {"sizes": (1000, 1800, 3200, 5600, 10000), "steps": 200, "rounds": 3,
                     "processes": 4},
            "quick": {"sizes": (300, 1000, 3000), "steps": 20, "rounds": 2, "processes": 1}}

#: Goal of the exponent per step (linear cost).
GOAL = 1.05

#: Time step of the runs (s).
DT = 1e-3

#: Steps of a timed chunk: the minimum over the rounds is taken chunk by chunk.
CHUNK = 20


class StepClock:
    """While installed, the CPU time and the Newton iterations so far at the start of
    every step of the generalized-alpha integrator (``GeneralizedAlpha.step``), in
    ``starts``: the difference of two starts is all that a step of ``simulate`` costs (its
    Newton iteration, books, guard, the loop's hooks and saving)."""

    def __init__(self):
        self.starts = []
        self.original = GeneralizedAlpha.step

    def __enter__(self):
        original, starts = self.original, self.starts

        def step(integrator, h):
            starts.append((time.process_time(), integrator.stats["newton"]))
            return original(integrator, h)

        GeneralizedAlpha.step = step
        return self

    def __exit__(self, *exc):
        GeneralizedAlpha.step = self.original


def chunk_times(system, steps, chunk):
    """CPU s of the chunks of ``chunk`` steps of the ``steps`` steps after the release
    (steps ``2 .. steps + 1`` of a run of ``steps + 2``), and their Newton iterations."""
    with StepClock() as clock:
        sc.simulate(system, t_end=(steps + 2) * DT, dt=DT, every=steps + 2)
    starts = np.array(clock.starts[1:steps + 2])  # the starts of steps 2 .. steps + 2
    return (np.diff(starts[:, 0]).reshape(-1, chunk).sum(axis=1),
            starts[-1, 1] - starts[0, 1])


def measure(sizes, steps, rounds, chunk=CHUNK):
    """CPU s of the chunks of steps after the release at each size, per round.

    Returns
    -------
    tuple
        ``(times, newton)``: ``times[r, i, c]`` the CPU s of round ``r``, size ``i``,
        chunk ``c`` (``chunk`` steps each); ``newton[i]`` the Newton iterations of the
        ``steps`` steps after the release at size ``i`` (the same in every round).
    """
    systems = [classics.pendulum(n_elements=n, length=100.0, radius=0.01).system
               for n in sizes]
    for system in systems:
        sc.simulate(system, t_end=DT, dt=DT)  # compile, layout
    times = np.empty((rounds, len(sizes), steps // chunk))
    newton = np.empty(len(sizes))
    for r in range(rounds):
        order = range(len(sizes)) if r % 2 == 0 else reversed(range(len(sizes)))
        for i in order:
            times[r, i], newton[i] = chunk_times(systems[i], steps, chunk)
    return times, newton


#: What a fresh process of ``apart`` runs: ``measure`` of this file, its arrays as JSON,
#: on the package this process imported (its folder first on the path: a child started
#: in another tree's folder imported that tree's, the current folder first on its path).
WORKER = """
import importlib.util, json, sys
sys.path.insert(0, sys.argv[3])
spec = importlib.util.spec_from_file_location("step_exponent", sys.argv[1])
module = importlib.util.module_from_spec(spec)
spec.loader.exec_module(module)
times, newton = module.measure(*json.loads(sys.argv[2]))
print(json.dumps([times.tolist(), newton.tolist()]))
"""


def apart(sizes, steps, rounds, processes):
    """``measure`` in ``processes`` fresh processes one after the other, ``rounds`` rounds
    each: the same arrays with the rounds of all, round ``r`` of process ``p`` at
    ``times[r * processes + p]`` (with an even number of processes the even rounds are
    those of the even processes, ``exponents``' halves); one process: in this one."""
    if processes == 1:
        return measure(sizes, steps, rounds)
    runs = [json.loads(subprocess.run(
        [sys.executable, "-c", WORKER, __file__, json.dumps([list(sizes), steps, rounds]),
         os.path.dirname(os.path.dirname(os.path.abspath(sc.__file__)))],
        check=True, capture_output=True, text=True).stdout.splitlines()[-1])
        for _ in range(processes)]
    return interleaved([np.array(t) for t, _ in runs]), np.array(runs[0][1])


def interleaved(runs):
    """The rounds of ``runs`` (a ``times`` array of ``measure`` per process) in one array,
    round ``r`` of process ``p`` at ``r * len(runs) + p``."""
    times = np.stack(runs, axis=1)
    return times.reshape(-1, *times.shape[2:])


def slope(sizes, costs):
    """``(slope, standard error)`` of the least-squares line of ``log costs`` on
    ``log sizes``."""
    coef, cov = np.polyfit(np.log(sizes), np.log(costs), 1, cov="unscaled")
    x, y = np.log(sizes), np.log(costs)
    dof = len(x) - 2
    residual = y - np.polyval(coef, x)
    scale = float(residual @ residual / dof) if dof > 0 else 0.0
    return float(coef[0]), float(np.sqrt(cov[0, 0] * scale))


def exponents(sizes, times, newton, steps):
    """The fitted exponents of the minima over the rounds and the range of the rounds'.

    Returns
    -------
    dict
        ``per_step`` and ``per_iteration`` (``(slope, standard error)`` of the minima),
        ``rounds_range`` (least and largest slope per step of a single round),
        ``halves`` (the slopes per step of the minima over the even rounds and over the
        odd ones, those of the even and of the odd processes, ``apart``; the even ones
        alone for a single round), ``ends`` (the slope between the first and the last
        size alone, which the count of a middle size does not move) and ``ms_per_step``
        (per size, of the minima).
    """
    def minima(t):
        return t.min(axis=0).sum(axis=1) / steps

    per_step = minima(times)
    per_round = [slope(sizes, t.sum(axis=1) / steps)[0] for t in times]
    halves = tuple(slope(sizes, minima(t))[0] for t in (times[0::2], times[1::2]) if len(t))
    return {"per_step": slope(sizes, per_step),
            "per_iteration": slope(sizes, per_step * steps / newton),
            "rounds_range": (min(per_round), max(per_round)),
            "halves": halves,
            "ends": float(np.log(per_step[-1] / per_step[0]) / np.log(sizes[-1] / sizes[0])),
            "ms_per_step": 1e3 * per_step}


def table(sizes, steps=200, rounds=3, processes=4, quick=False):
    """Measure, print the rows and the exponents, and return their figures.

    Parameters
    ----------
    sizes : sequence of int
        Numbers of elements.
    steps : int
        Timed steps after the release step.
    rounds : int
        Rounds over all sizes in each process (sizes alternated); each run takes the
        minimum over all.
    processes : int
        Fresh processes, one after the other (``apart``).
    quick : bool
        Label the exponents indicative.

    Returns
    -------
    dict
        ``rows`` (``elements``, ``ms_per_step``, ``newton_per_step``, ``ms_per_newton``),
        ``load`` (the load average before and after) and ``exponents`` (see
        ``exponents``).
    """
    load = os.getloadavg()[0]
    times, newton = apart(sizes, steps, rounds, processes)
    fit = exponents(sizes, times, newton, steps)
    rows = []
    print(f"{'elements':>9} {'CPU ms/step':>12} {'Newton/step':>12} {'ms/Newton':>10}")
    for n, ms, it in zip(sizes, fit["ms_per_step"], newton / steps):
        rows.append({"elements": n, "ms_per_step": ms, "newton_per_step": it,
                     "ms_per_newton": ms / it})
        print(f"{n:9d} {ms:12.3f} {it:12.3f} {ms / it:10.3f}")
    (s, err), (si, erri) = fit["per_step"], fit["per_iteration"]
    low, high = fit["rounds_range"]
    note = " (quick: indicative only)" if quick else (
        "" if s <= GOAL else " ABOVE THE GOAL")
    halves = " and ".join(f"{h:.3f}" for h in fit["halves"])
    print(f"exponent per step {s:.3f} +- {err:.3f} (goal <= {GOAL}){note}; single rounds "
          f"{low:.3f} to {high:.3f}; even and odd {'processes' if processes > 1 else 'rounds'} "
          f"{halves}; per Newton iteration "
          f"{si:.3f} +- {erri:.3f}; between the first and last size alone {fit['ends']:.3f}")
    print(f"({steps} steps after the release, CPU time, minimum of {processes} process(es) x "
          f"{rounds} rounds chunk by chunk of {CHUNK} steps, sizes alternated; load average "
          f"{load:.1f} before, {os.getloadavg()[0]:.1f} after)")
    return {"rows": rows, "load": (load, os.getloadavg()[0]),
            "exponents": {k: v for k, v in fit.items() if k != "ms_per_step"}}


def main(argv=None):
    """Parse the arguments (``--quick``), print the table and return its figures."""
    args = arguments(__doc__, "300 to 3000 elements, 20 steps, two rounds", argv)
    return table(**SETTINGS["quick" if args.quick else "full"],
                 quick=args.quick)


if __name__ == "__main__":
    main()
