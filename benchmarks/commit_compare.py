"""Per-step cost of this checkout against another commit, side by side in one run.

The E-sail rig (12 tethers x 5 elements, rigid hub, solar wind, ``dt = 0.1 s``) and the
flexible pendulum (16 elements, ``dt = 1e-3 s``) are timed alternately with the working
tree and with a ``git worktree`` of ``--base`` (default: ``HEAD~1``), each in a fresh
Python process (numba caches warm: one untimed run first), ``--repeats`` times; the table
gives the minimum ms per step of each and the ratio (this tree / base).  The cost per
step is the difference of a run of the full number of steps and one of a sixth of them,
over the difference of their steps: the setup of a ``simulate`` call (a few ms, which
varies from run to run) is not in it; before, it was (up to 3 % on the E-sail's 600
steps).  Machines are noisy: read the ratio, not the absolute times.

Run ``python benchmarks/commit_compare.py --base 0e078c5`` (``--quick``: one repeat of a
tenth of the steps unless ``--repeats`` or ``--steps-scale`` say otherwise; ``--cases
pendulum``: one case).
"""

import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

#: Timed in a subprocess with ``PYTHONPATH`` set to the tree under test; uses only the API
#: both trees share (``simulate(system, t_end=, dt=, rho_inf=, initial=)``).
SNIPPET = r"""
import json, sys, time
import skfem_cable as sc
from skfem_cable.scenes import classics, esail

case, steps = sys.argv[1], int(sys.argv[2])
if case == "esail":
    cfg = esail.BaselineConfig()
    scene = esail.build(cfg, alpha_deg=10.0, n_elements=5, kind="cable")
    system, initial, dt, rho = scene.system, scene.initial, 0.1, 0.25
else:
    scene = classics.pendulum(n_elements=16)
    system, initial, dt, rho = scene.system, scene.initial, 1e-3, 0.8
sc.simulate(system, t_end=2 * dt, dt=dt, rho_inf=rho, initial=initial)  # compile, layout


def run(n):
    start = time.perf_counter()
    r = sc.simulate(system, t_end=n * dt, dt=dt, rho_inf=rho, initial=initial, every=n)
    return time.perf_counter() - start, r


short = max(1, steps // 6)
wall_short, _ = run(short)
wall, r = run(steps)
print(json.dumps({"ms_per_step": 1e3 * (wall - wall_short) / (steps - short),
                  "newton_per_step": r.stats["newton"] / r.stats["steps"]}))
"""

CASES = {"esail": 600, "pendulum": 1000}


def time_case(tree, case, steps):
    env = dict(os.environ, PYTHONPATH=str(tree))
    out = subprocess.run([sys.executable, "-c", SNIPPET, case, str(steps)], env=env,
                         cwd=tree, check=True, capture_output=True, text=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def compare(base, repeats=5, cases=CASES):
    """``{case: (ours, theirs)}`` minimum ms/step over ``repeats`` alternating runs."""
    with tempfile.TemporaryDirectory() as tmp:
        other = Path(tmp) / "base"
        subprocess.run(["git", "worktree", "add", "--detach", str(other), base], cwd=ROOT,
                       check=True, capture_output=True)
        try:
            rows = {}
            for case, steps in cases.items():
                ours, theirs = [], []
                for _ in range(repeats):
                    ours.append(time_case(ROOT, case, steps))
                    theirs.append(time_case(other, case, steps))
                rows[case] = (min(ours, key=lambda r: r["ms_per_step"]),
                              min(theirs, key=lambda r: r["ms_per_step"]))
        finally:
            subprocess.run(["git", "worktree", "remove", "--force", str(other)], cwd=ROOT,
                           check=False, capture_output=True)
    return rows


def main(argv=None):
    """Parse the arguments, time both trees and print the table.

    Returns
    -------
    list of dict
        Per case: ``case``, ``steps``, ``ms_per_step`` and ``newton_per_step`` of this
        tree (``here``) and of ``base``, and ``ratio`` (here / base).
    """
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--base", default="HEAD~1", help="commit to compare with")
    parser.add_argument("--quick", action="store_true",
                        help="defaults --repeats 1 --steps-scale 0.1")
    parser.add_argument("--repeats", type=int, default=None, help="default 5")
    parser.add_argument("--steps-scale", type=float, default=None,
                        help="multiply the number of timed steps (default 1)")
    parser.add_argument("--cases", nargs="+", choices=sorted(CASES), default=list(CASES),
                        help="the cases to time (default: all)")
    args = parser.parse_args(argv)
    repeats = args.repeats or (1 if args.quick else 5)
    scale = args.steps_scale or (0.1 if args.quick else 1.0)
    cases = {k: max(2, int(CASES[k] * scale)) for k in args.cases}
    rows = compare(args.base, repeats, cases)
    print(f"{'case':>10} {'ms/step here':>13} {'ms/step base':>13} {'ratio':>7} "
          f"{'Newton/step':>12}")
    for case, (ours, theirs) in rows.items():
        print(f"{case:>10} {ours['ms_per_step']:13.3f} {theirs['ms_per_step']:13.3f} "
              f"{ours['ms_per_step'] / theirs['ms_per_step']:7.3f} "
              f"{ours['newton_per_step']:6.2f}/{theirs['newton_per_step']:.2f}")
    return [{"case": case, "steps": cases[case], "here": ours, "base": theirs,
             "ratio": ours["ms_per_step"] / theirs["ms_per_step"]}
            for case, (ours, theirs) in rows.items()]


if __name__ == "__main__":
    main()
