"""Where the windless E-sail rig's time goes: the rig that ``benchmarks/peers.py`` times
against Exudyn (``peers.esail_ours``: a rigid hub, 12 tethers of 10 km x 5 elements on
spherical pins, 1.5 kg tip masses, no solar wind; ``dt = 0.1 s``, ``rho_inf = 0.25``,
``tol = 1e-11``), profiled in a fresh process (one thread, CPU time, minimum of repeats):

- **the start of a run**: a ``simulate`` call of one step (building the integrator,
  describing the system, the consistent initial state, the first step's fitted
  pseudo-acceleration);
- **the run that peers.py times**: a ``simulate`` call of 400 steps saving the last,
  per step (its start included, as in peers.py);
- **the step**: the difference of a run of ``steps`` steps and one of a sixth of them;
  the compiled Newton call inside it (a wrapper of its entry point,
  ``lib/step_parts.Probe``), and the Python of the step (the step less the call);
- **the compiled parts**, each alone in a compiled loop (``lib/step_parts.py``): the
  tethers' law kernel (a residual per evaluation, with its tangent per factorization),
  the band factorization and a band solve (per correction); the rest of the call (the
  constraints, ``M a``, the predictor, updates and tests, the books' sums, the unboxing
  of the state) is the call less these.

``python benchmarks/rig_profile.py`` (about a minute; ``--quick``: 120 steps, two
repeats).  With ``RIG_PROFILE_AGAINST=/path/to/checkout`` the same profile of that
checkout is printed beside it (a tree with ``benchmarks/peers.py``'s ``esail_ours`` and
``benchmarks/lib/step_parts.py``).  ``docs/benchmarks.md`` ("Where the E-sail step's
time went") has the table.
"""

import json
import os
import subprocess
import sys
from pathlib import Path

from skfem_cable.cli.bench import arguments

ROOT = Path(__file__).resolve().parents[1]

SETTINGS = {"full": {"steps": 600, "repeats": 5}, "quick": {"steps": 120, "repeats": 2}}

#: Run in a fresh process with ``PYTHONPATH`` on the tree under test: ``argv[1:3]`` the
#: steps and repeats; prints one JSON line (microseconds, milliseconds for the calls).
PROFILE = r"""
import json, sys, time
import numpy as np
sys.path[:0] = ["benchmarks", "benchmarks/lib"]
import skfem_cable as sc
from skfem_cable.scenes import esail
import peers
from step_parts import Probe, compiled_parts

steps, repeats = int(sys.argv[1]), int(sys.argv[2])
short = steps // 6
system, hub, tethers, initial = peers.esail_ours(esail.BaselineConfig(), 5)
run = dict(dt=0.1, rho_inf=0.25, initial=initial, tol=1e-11)
sc.simulate(system, t_end=0.2, **run)  # compile, layout
probe = Probe(timed=True)


def simulate(k):
    probe.reset()
    start = time.process_time_ns()
    result = sc.simulate(system, t_end=k * 0.1, every=k, **run)
    return time.process_time_ns() - start, probe.call_ns, probe.evaluations, result


def best(k, n=repeats):
    return min(simulate(k)[0] for _ in range(max(n, 3)))


start_ms, peers_us = 1e-6 * best(1, 10), 1e-3 * best(400) / 400
step_us = 1e-3 * (best(steps) - best(short)) / (steps - short)
probe.__enter__()
calls = {}
for _ in range(repeats):
    for k in (short, steps):
        _, call, evaluations, result = simulate(k)
        calls[k] = min(calls.get(k, np.inf), call)
call_us = 1e-3 * (calls[steps] - calls[short]) / (steps - short)
n = result.stats["steps"]
counts = {"evaluations": evaluations / n, "corrections": result.stats["newton"] / n,
          "factorizations": result.stats["factorizations"] / n}
parts = compiled_parts(probe.newton, probe.integrator, repeats)
print(json.dumps({"start_ms": start_ms, "peers_us": peers_us, "step_us": step_us,
                  "call_us": call_us, "counts": counts, **parts}))
"""


def profile(tree, steps, repeats):
    """The figures of ``PROFILE`` in a fresh process on ``tree`` (one thread)."""
    env = dict(os.environ, PYTHONPATH=str(tree), OPENBLAS_NUM_THREADS="1",
               SKFEM_CABLE_THREADS="1")
    proc = subprocess.run([sys.executable, "-c", PROFILE, str(steps), str(repeats)],
                          env=env, cwd=tree, capture_output=True, text=True)
    if proc.returncode != 0:
        raise RuntimeError(f"the profile in {tree} failed: {proc.stderr.strip()[-400:]}")
    return json.loads(proc.stdout.strip().splitlines()[-1])


def rows(p):
    """``[(part, us per step)]`` of a profile ``p``."""
    c = p["counts"]
    out = [("tethers' law: residual", c["evaluations"]
            * sum(k["residual_us"] for k in p["kernels"])),
           ("tangent and band factorization", c["factorizations"]
            * (sum(k["tangent_us"] for k in p["kernels"]) + p["factor_us"])),
           ("band solve", c["corrections"] * p["solve_us"])]
    out.append(("rest of the compiled call (constraints, M a, predictor, updates, tests, "
                "books' sums, unboxing)", p["call_us"] - sum(us for _, us in out)))
    out += [("**compiled call**", p["call_us"]),
            ("**Python of the step**", p["step_us"] - p["call_us"]),
            ("**step**", p["step_us"]),
            ("start of a run (ms: a 1-step simulate call)", p["start_ms"]),
            ("**per step of the 400-step run of peers.py**", p["peers_us"])]
    return out


def table(steps=600, repeats=5, quick=False):
    """Profile this tree (and ``RIG_PROFILE_AGAINST``, if set); print the table.

    Returns
    -------
    dict
        ``{"here": profile, "against": profile or None, "load": (before, after)}``.
    """
    load = os.getloadavg()[0]
    other = os.environ.get("RIG_PROFILE_AGAINST")
    theirs = profile(Path(other), steps, repeats) if other else None
    ours = profile(ROOT, steps, repeats)
    print(f"windless E-sail rig, {steps} steps, minimum of {repeats}; load average "
          f"{load:.2f} before, {os.getloadavg()[0]:.2f} after"
          + (" (quick: indicative only)" if quick else ""))
    for name, p in (("here", ours), ("against", theirs)):
        if p is not None:
            c = p["counts"]
            print(f"{name}: {c['evaluations']:.3f} evaluations, {c['corrections']:.3f} "
                  f"corrections, {c['factorizations']:.4f} factorizations per step")
    base = dict(rows(theirs)) if theirs else {}
    print(f"| part | us/step here |{' us/step against |' if theirs else ''}\n|---|---|"
          + ("---|" if theirs else ""))
    for part, us in rows(ours):
        print(f"| {part} | {us:.1f} |" + (f" {base[part]:.1f} |" if theirs else ""))
    return {"here": ours, "against": theirs, "load": (load, os.getloadavg()[0])}


def main(argv=None):
    """Parse the arguments (``--quick``), print the table and return its figures."""
    args = arguments(__doc__, "120 steps, two repeats", argv)
    return table(**SETTINGS["quick" if args.quick else "full"], quick=args.quick)


if __name__ == "__main__":
    main()
