"""Per-step cost of this checkout against a fixed reference commit (or any other), case by
case, side by side in one run: the guard against regressions.

The tracked cases (``CASES``: the flexible pendulum, the E-sail rig, the full-size sail,
the orbiting sail, a 10,000-element catenary and a controller run) are timed alternately
with the working tree and with a ``git worktree`` of ``--against`` (default:
``REFERENCE``; the working tree itself where it holds that commit's sources unchanged,
``--against HEAD`` in a clean checkout), each in a fresh Python process (its first
``simulate`` call, untimed, compiles and lays out), ``--repeats`` times; the table gives
the minimum ms per step of each tree, the ratio (this tree / reference) and ``SLOWER``
where the ratio exceeds ``THRESHOLD`` (1.05).  The cost per step is the difference of a
run of the case's full number of steps and one of a sixth of them, over the difference of
their steps: the setup of a ``simulate`` call (a few ms, which varies from run to run) is
not in it.  It is counted in the process's CPU time, not in wall time: on a shared
machine the time a process waits for a core is not its cost (two runs at a load of 6 on 2
cores gave wall time ratios of 1.15 and 1.70 for the E-sail rig); on a quiet machine the
two agree (one thread), and the JSON rows keep the wall time too (``wall_ms_per_step``).
Each case is built by a snippet of the API both trees are expected to share; where a tree
lacks it (orbits and controllers came after ``REFERENCE``), the case reads ``n/a`` there
and its error is printed under the table.  Every process runs on one thread
(``OPENBLAS_NUM_THREADS=1``, ``SKFEM_CABLE_THREADS=1``).  Machines are noisy: read the
ratio, not the absolute times, and quote the load (printed above and below the table).

Run ``python3 tasks.py bench --against [REF]`` (or ``skfem-cable bench --against``, or
``python benchmarks/commit_compare.py --against REF``) before every speed-relevant commit;
``--quick``: one repeat of a tenth of the steps unless ``--repeats`` or ``--steps-scale``
say otherwise; ``--cases pendulum esail``: some cases.  It is a report, not a test: it
exits 0 whatever the ratios.
"""

import argparse
import contextlib
import json
import os
import subprocess
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path

from skfem_cable.cli.bench import git_commit

ROOT = Path(__file__).resolve().parents[1]

#: The fixed reference commit: before the default assumed strain, orbits, control, threads
#: and varying laws (issue 47).
REFERENCE = "abb2314"

#: A case whose ratio (this tree / reference) exceeds this is flagged ``SLOWER``.
THRESHOLD = 1.05

#: Run in a fresh process with ``PYTHONPATH`` set to the tree under test: ``argv[1]`` is a
#: case's ``build`` snippet (run with ``sc``, the package, defined), ``argv[2]`` its number
#: of steps.  Prints one JSON line:
#: ``ms_per_step`` (the process's CPU time), ``wall_ms_per_step`` and ``newton_per_step``,
#: the times of its two runs ``runs_ms`` (CPU short and long, wall short and long) and
#: their ``steps``, or ``error`` where the tree lacks the case's API.
SNIPPET = r"""
import gc, json, sys, time
import skfem_cable as sc

build, steps = sys.argv[1], int(sys.argv[2])
case = {"sc": sc, "extra": {}}
try:
    exec(build, case)
    system, initial, dt, rho = (case[k] for k in ("system", "initial", "dt", "rho"))
    run = dict(dt=dt, rho_inf=rho, initial=initial, **case["extra"])
    sc.simulate(system, t_end=2 * dt, **run)  # compile, layout
except Exception as err:
    print(json.dumps({"error": f"{type(err).__name__}: {err}"}))
    sys.exit(0)


def timed(n):
    start, cpu = time.perf_counter(), time.process_time()
    r = sc.simulate(system, t_end=n * dt, every=n, **run)
    return time.process_time() - cpu, time.perf_counter() - start, r


short = max(1, steps // 6)
cpu_short, wall_short, _ = timed(short)
cpu, wall, r = timed(steps)
print(json.dumps({"ms_per_step": 1e3 * (cpu - cpu_short) / (steps - short),
                  "wall_ms_per_step": 1e3 * (wall - wall_short) / (steps - short),
                  "newton_per_step": r.stats["newton"] / r.stats["steps"],
                  "runs_ms": [1e3 * cpu_short, 1e3 * cpu, 1e3 * wall_short, 1e3 * wall],
                  "steps": [short, steps]}))
gc.freeze()  # a quick exit: its last garbage collections skip the package's objects
"""


@dataclass(frozen=True)
class Case:
    """A tracked case: what it is, its number of timed steps, and ``build``, Python run in
    the child process that defines ``system``, ``initial``, ``dt``, ``rho`` (``rho_inf``)
    and optionally ``extra`` (more keyword arguments of ``simulate``)."""

    title: str
    steps: int
    build: str


_ESAIL = """
from skfem_cable.scenes import esail
scene = esail.build(esail.BaselineConfig(), 10.0, 5)
system, initial, dt, rho = scene.system, scene.initial, 0.1, 0.25
"""

_FULL_SIZE = """
from skfem_cable.scenes import esail
config = esail.BaselineConfig(n_tethers=100, tether_length=20e3, spin_rate=1.2e-3)
scene = esail.build(config, 10.0, 10)
system, initial, dt, rho = scene.system, scene.initial, 5.0, 0.25
"""

_ORBIT = """
from skfem_cable.scenes import esail
scene = esail.build_orbit(esail.BaselineConfig(), 10.0, 5)
system, initial, dt, rho = scene.system, scene.initial, 0.1, 0.25
"""

_CATENARY = """
import numpy as np
from scipy.optimize import brentq
from skfem import MeshLine
n, length, span = 10000, 100.0, 80.0
a = brentq(lambda a: 2 * a * np.sinh(span / (2 * a)) - length, 1.0, 1e4)
s = np.linspace(-length / 2, length / 2, n + 1)
pos = np.column_stack([a * np.arcsinh(s / a) + span / 2, np.hypot(a, s), 0 * s])
slopes = np.column_stack([np.full_like(s, a), s, 0 * s]) / np.hypot(a, s)[:, None]
cable = sc.Cable(MeshLine(s + length / 2), sc.Section.circular(radius=0.01, E=7e10, rho=7800.0),
                 pos, slopes)
system = sc.System([cable]).pin(cable.node(0)).pin(cable.node(-1)).add_gravity([0, -9.81, 0])
initial, dt, rho = sc.solve_static(system), 1e-3, 0.8  # at rest in its equilibrium
"""

_CONTROLLER = """
from dataclasses import replace
import numpy as np
from skfem_cable.scenes import esail
config = esail.BaselineConfig()
voltages = sc.Input("voltages", np.full(config.n_tethers, config.voltage))
scene = esail.build(replace(config, voltage=voltages), 10.0, 5)


class PhaseModulation(sc.Controller):
    def update(self, t, state):
        phase = sc.sensors.tether_phase(state, scene.tethers, scene.hub)
        return {"voltages": config.voltage * (1.0 + 0.3 * np.cos(phase))}


system, initial, dt, rho = scene.system, scene.initial, 0.1, 0.25
extra = {"controllers": [PhaseModulation(dt)]}
"""

#: The tracked cases, in the order of the table.
CASES = {
    "pendulum": Case("flexible pendulum (16 elements, dt = 1 ms)", 1000, """
from skfem_cable.scenes import classics
scene = classics.pendulum(n_elements=16)
system, initial, dt, rho = scene.system, scene.initial, 1e-3, 0.8
"""),
    "esail": Case("E-sail rig (12 tethers x 5 elements, dt = 0.1 s)", 600, _ESAIL),
    "esail_full": Case("full-size sail (100 tethers of 20 km x 10 elements, dt = 5 s)", 60,
                       _FULL_SIZE),
    "esail_orbit": Case("orbiting sail (12 x 5, circular orbit of 1 AU, dt = 0.1 s)", 600,
                        _ORBIT),
    "catenary": Case("catenary (10,000 elements, 100 m over 80 m, dt = 1 ms)", 100,
                     _CATENARY),
    "controller": Case("controller run (12 x 5, voltages by tether phase every step)", 600,
                       _CONTROLLER),
}


def time_case(tree, case, steps):
    """``{"ms_per_step", "wall_ms_per_step", "newton_per_step"}`` of ``case`` (a ``Case``) over
    ``steps`` steps in a fresh process on ``tree``, or ``{"error": message}``."""
    env = dict(os.environ, PYTHONPATH=str(tree), OPENBLAS_NUM_THREADS="1",
               SKFEM_CABLE_THREADS="1")
    proc = subprocess.run([sys.executable, "-c", SNIPPET, case.build, str(steps)], env=env,
                          cwd=tree, capture_output=True, text=True)
    lines = proc.stdout.strip().splitlines()
    if proc.returncode != 0 or not lines:
        last = (proc.stderr.strip().splitlines() or ["no output"])[-1]
        return {"error": f"exit code {proc.returncode}: {last}"}
    return json.loads(lines[-1])


def fastest(runs):
    """The cost per step of ``runs`` (of ``time_case``) from the least time of their short
    runs and the least of their long runs, each over the repeats (CPU and wall), or the
    first error if none ran.  The least difference of one process's two runs would read
    low wherever one short run (the time the difference subtracts) was slowed: a run of
    the E-sail rig at ``ac1f4ad`` whose short run took 45 ms instead of 14 read 0.034 ms a
    step instead of 0.10."""
    timed = [r for r in runs if "error" not in r]
    if not timed:
        return runs[0]
    short, steps = timed[0]["steps"]
    least = [min(times) for times in zip(*(r["runs_ms"] for r in timed))]
    return dict(timed[0], ms_per_step=(least[1] - least[0]) / (steps - short),
                wall_ms_per_step=(least[3] - least[2]) / (steps - short))


def compare(against, repeats=5, cases=None):
    """``{name: (ours, theirs)}``: the fastest of ``repeats`` alternating runs of each of
    ``cases`` (``{name: (Case, steps)}``, default ``CASES`` at their steps) in this tree
    and in a tree of the commit ``against`` (``checkout``; see ``time_case``)."""
    cases = {k: (c, c.steps) for k, c in CASES.items()} if cases is None else cases
    with checkout(against) as other:
        rows = {}
        for name, (case, steps) in cases.items():
            ours, theirs = [], []
            for _ in range(repeats):
                ours.append(time_case(ROOT, case, steps))
                theirs.append(time_case(other, case, steps))
                if "error" in ours[-1] or "error" in theirs[-1]:
                    break  # nothing to compare: one run of each tells
            rows[name] = (fastest(ours), fastest(theirs))
    return rows


def git(*args, cwd=ROOT):
    """The standard output of ``git *args`` in ``cwd``, stripped."""
    return subprocess.run(["git", *args], cwd=cwd, check=True, capture_output=True,
                          text=True).stdout.strip()


def same_sources(rev, root=ROOT):
    """Whether the checkout ``root`` holds the sources of the commit ``rev``: checked out
    at ``rev``, without a change to a tracked file (the record's ``dirty``, ``git_commit``;
    an untracked file, a log or a result, changes no tracked module's imports)."""
    return (git("rev-parse", f"{rev}^{{commit}}", cwd=root) == git("rev-parse", "HEAD", cwd=root)
            and not git("status", "--porcelain", "--untracked-files=no", cwd=root))


@contextlib.contextmanager
def checkout(rev):
    """The folder of a tree of the commit ``rev``: this checkout where it holds the same
    sources (``same_sources``: its kernels are compiled already, while a worktree in a new
    folder compiles them all again, about 40 s of CPU for the pendulum), else a temporary
    worktree (``worktree``)."""
    if same_sources(rev):
        yield ROOT
        return
    with worktree(rev) as other:
        yield other


@contextlib.contextmanager
def worktree(rev):
    """A temporary ``git worktree`` of the commit ``rev`` of this repository (its path),
    removed on leaving."""
    with tempfile.TemporaryDirectory() as tmp:
        other = Path(tmp) / "reference"
        subprocess.run(["git", "worktree", "add", "--detach", str(other), rev], cwd=ROOT,
                       check=True, capture_output=True)
        try:
            yield other
        finally:
            subprocess.run(["git", "worktree", "remove", "--force", str(other)], cwd=ROOT,
                           check=False, capture_output=True)


def ratio(ours, theirs):
    """``ours / theirs`` ms per step, or ``None`` where either tree could not run it."""
    if "error" in ours or "error" in theirs:
        return None
    return ours["ms_per_step"] / theirs["ms_per_step"]


def flag(value, threshold=THRESHOLD):
    """``"SLOWER"`` for a ratio above ``threshold``, else ``""`` (also for ``None``)."""
    return "SLOWER" if value is not None and value > threshold else ""


def table_row(title, steps, ours, theirs, against):
    """One markdown row: case, steps, ms/step of each tree (``n/a``, ``n/a at REF`` where
    a tree lacks the case), ratio, Newton iterations per step of each, flag."""
    def ms(run, where=""):
        return "n/a" + where if "error" in run else f"{run['ms_per_step']:.3f}"

    def newton(run):
        return "n/a" if "error" in run else f"{run['newton_per_step']:.2f}"

    value = ratio(ours, theirs)
    shown = "" if value is None else f"{value:.3f}"
    return (f"| {title} | {steps} | {ms(ours)} | {ms(theirs, f' at {against}')} | {shown} | "
            f"{newton(ours)} / {newton(theirs)} | {flag(value)} |")


def short_commit(rev, cwd=ROOT):
    """The abbreviated hash of ``rev`` in the repository of ``cwd``."""
    return git("rev-parse", "--short", rev, cwd=cwd)


def print_table(rows, cases, against):
    """Print the markdown table of ``rows`` (``compare``'s), the errors of the cases a tree
    could not run below it."""
    print(f"| case | steps | CPU ms/step here | CPU ms/step at {against} | ratio | "
          f"Newton/step here / {against} | flag (> {THRESHOLD}) |\n"
          "|---|---|---|---|---|---|---|")
    for name, (ours, theirs) in rows.items():
        case, steps = cases[name]
        print(table_row(case.title, steps, ours, theirs, against))
    for name, (ours, theirs) in rows.items():
        for where, run in (("here", ours), (against, theirs)):
            if "error" in run:
                print(f"- {name} n/a {where}: {run['error'][:160]}")


def parse(argv=None):
    """The command line (see the module's description)."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--against", "--base", default=REFERENCE, metavar="REF",
                        help=f"commit to compare with (default: {REFERENCE})")
    parser.add_argument("--quick", action="store_true",
                        help="defaults --repeats 1 --steps-scale 0.1")
    parser.add_argument("--repeats", type=int, default=None, help="default 5")
    parser.add_argument("--steps-scale", type=float, default=None,
                        help="multiply the number of timed steps (default 1)")
    parser.add_argument("--cases", nargs="+", choices=list(CASES), default=list(CASES),
                        help="the cases to time (default: all)")
    return parser.parse_args(argv)


def main(argv=None):
    """Parse the arguments, time both trees and print the table.

    Returns
    -------
    list of dict
        Per case: ``case``, ``steps``, ``here`` and ``base`` (``ms_per_step`` and
        ``newton_per_step`` of this tree and of the reference, or ``error``), ``ratio``
        (here / reference, ``None`` where a tree lacks the case) and ``flag``.
    """
    args = parse(argv)
    repeats = args.repeats or (1 if args.quick else 5)
    scale = args.steps_scale or (0.1 if args.quick else 1.0)
    cases = {k: (CASES[k], max(6, int(CASES[k].steps * scale))) for k in args.cases}
    against = short_commit(args.against)
    head = short_commit("HEAD") + (" (modified)" if git_commit(ROOT)["dirty"] else "")
    where = " (this checkout: the same sources)" if same_sources(args.against) else ""
    print(f"this tree: {head}, reference: {against}{where}; minimum of {repeats} "
          f"alternating runs; load average {os.getloadavg()[0]:.2f}")
    rows = compare(args.against, repeats, cases)
    print_table(rows, cases, against)
    print(f"load average after: {os.getloadavg()[0]:.2f}")
    return [{"case": name, "steps": cases[name][1], "here": ours, "base": theirs,
             "ratio": ratio(ours, theirs), "flag": flag(ratio(ours, theirs))}
            for name, (ours, theirs) in rows.items()]


if __name__ == "__main__":
    main()
