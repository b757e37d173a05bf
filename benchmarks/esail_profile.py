"""Where the E-sail step's time went: a profile of the E-sail rig's step in this tree and
at the reference commit (issue 47, "where the time went").

The rig of ``benchmarks/commit_compare.py`` (``esail.build(BaselineConfig(), 10 deg, 5)``,
``dt = 0.1 s``, ``rho_inf = 0.25``) runs in a fresh process of each tree (this one and a
``git worktree`` of ``commit_compare.REFERENCE``, one thread, CPU time), which measures
with the API both trees share:

- **the step**: CPU time per step, the difference of a run of ``steps`` steps and one of a
  sixth of them (the setup of a ``simulate`` call left out), minimum of ``repeats``;
- **the compiled call** (the Newton iteration, with the unboxing of its arguments): the
  CPU time inside it, measured by a wrapper of the compiled function installed on each
  ``CompiledNewton`` after its first call (same difference of two runs); the Python of a
  step is the step less the call;
- **the counts**: residual evaluations (rows of the Newton history), corrections and
  factorizations per step;
- **the compiled parts**, each alone in a compiled loop (minimum of repeats): every term
  kernel of the system without and with its tangent (``Term.kernels``), the bordered band
  factorization and a band solve (``kernels.bordered``); per step, times their counts (a
  residual per evaluation, a tangent and a factorization per factorization, a solve per
  correction); the rest of the call (constraints, ``M a``, the updates and convergence
  tests of the iteration, the unboxing) is the call less these;
- **the Python of a step**, split by ``cProfile`` (the difference of the per-function
  times of the two runs: the setup left out) into the books, the instability guard,
  the copies of the state, the preparation of the compiled call and the step control and
  driver, scaled to the measured Python time (the profiler's own cost inflates each call
  alike);
- where the tree has it, the solar wind's kernel without the distance scaling
  (``exponent=0``: ``kernels.coulomb.point_uniform``) on the same tethers, for the cost
  of the scaling.

Run ``python benchmarks/esail_profile.py`` (about 3 minutes; ``--quick``: 120 steps and two
repeats, indicative only).  ``docs/benchmarks.md`` ("Where the E-sail step's time went")
gives the table and the cause of each difference.
"""

import json
import os
import subprocess
import sys
from pathlib import Path

from skfem_cable.cli.bench import arguments

sys.path.insert(0, str(Path(__file__).resolve().parent))
from commit_compare import REFERENCE, ROOT, short_commit, worktree  # noqa: E402

SETTINGS = {"full": {"steps": 600, "repeats": 5}, "quick": {"steps": 120, "repeats": 2}}

#: Run in a fresh process with ``PYTHONPATH`` on the tree under test: ``argv[1:3]`` the
#: steps and repeats, ``argv[3]`` the folder of the timing of the parts
#: (``lib/step_parts.py``); prints one JSON line (per step, microseconds).
PROFILE = r"""
import cProfile, json, pstats, sys, time
import numpy as np
import skfem_cable as sc
from skfem_cable.scenes import esail

steps, repeats = int(sys.argv[1]), int(sys.argv[2])
sys.path.insert(0, sys.argv[3])  # this tree's timing, whichever tree is measured
import step_parts
from step_parts import NO_INDEX, Probe, compiled_parts, cpu_us, evaluation

short = steps // 6
scene = esail.build(esail.BaselineConfig(), 10.0, 5)
run = dict(dt=0.1, rho_inf=0.25, initial=scene.initial)
sc.simulate(scene.system, t_end=0.2, **run)  # compile, layout
probe = Probe(timed=True)  # the compiled call's CPU time and the evaluations


def simulate(k, profile=None):
    probe.reset()
    start = time.process_time_ns()
    if profile is not None:
        profile.enable()
    result = sc.simulate(scene.system, t_end=k * 0.1, every=k, **run)
    if profile is not None:
        profile.disable()
    return time.process_time_ns() - start, probe.call_ns, probe.evaluations, result


best = {}
for _ in range(repeats):
    for k in (short, steps):
        best[k] = min(best.get(k, np.inf), simulate(k)[0])
step_us = 1e-3 * (best[steps] - best[short]) / (steps - short)
probe.__enter__()  # for the rest of the process
calls = {}
for _ in range(repeats):
    for k in (short, steps):
        _, call, evaluations, result = simulate(k)
        calls[k] = min(calls.get(k, np.inf), call)
call_us = 1e-3 * (calls[steps] - calls[short]) / (steps - short)
n = result.stats["steps"]
counts = {"evaluations": evaluations / n, "corrections": result.stats["newton"] / n,
          "factorizations": result.stats["factorizations"] / n}

# the Python of a step, by cProfile: per-function times of the long run less the short's
GROUPS = (("books", ("books.py", "_step_books", "_energies", "_open")),
          ("guard", ("guard.py",)),
          ("copies of the state", ("method 'copy'", "numpy.copy", "method 'tolist'")),
          ("the compiled call's preparation", ("compiled.py", "predictor", "extrapolation",
                                               "_coefficients")))
per_function = {}
for k, sign in ((steps, 1.0), (short, -1.0)):
    profile = cProfile.Profile()
    simulate(k, profile)
    for (path, line, name), row in pstats.Stats(profile).stats.items():
        if path in ("<string>", step_parts.__file__):
            continue  # the probe's own wrappers
        key = f"{path}:{name}"
        per_function[key] = per_function.get(key, 0.0) + sign * row[2]
shares = dict.fromkeys([g for g, _ in GROUPS] + ["step control and driver"], 0.0)
for key, seconds in per_function.items():
    group = next((g for g, marks in GROUPS if any(m in key for m in marks)),
                 "step control and driver")
    shares[group] += max(seconds, 0.0)
total = sum(shares.values())
python_us = step_us - call_us
python = {g: python_us * s / total for g, s in shares.items()}


parts = compiled_parts(probe.newton, probe.integrator, repeats)
a = probe.newton.arrays
extra = {}
try:  # the solar wind without the distance scaling, on the same tethers
    cfg = scene.config
    uniform = sc.SolarWindForce(scene.tethers, cfg.voltage, cfg.wind,
                                sun_position=-np.asarray(scene.R0), exponent=0.0)
    (function, pack), = uniform.bind(scene.system).kernels
    extra["solar wind, exponent 0, residual"] = cpu_us(
        function, (pack, NO_INDEX, evaluation(a, a["nodata"])), repeats=repeats)
except Exception as err:  # a tree without the exponent
    extra["error"] = f"{type(err).__name__}: {err}"
print(json.dumps({"step_us": step_us, "call_us": call_us, "counts": counts, **parts,
                  "python": python, "extra": extra}))
"""


def profile(tree, steps, repeats):
    """The figures of ``PROFILE`` in a fresh process on ``tree`` (one thread)."""
    env = dict(os.environ, PYTHONPATH=str(tree), OPENBLAS_NUM_THREADS="1",
               SKFEM_CABLE_THREADS="1")
    proc = subprocess.run([sys.executable, "-c", PROFILE, str(steps), str(repeats),
                           str(Path(__file__).resolve().parent / "lib")],
                          env=env, cwd=tree, capture_output=True, text=True)
    if proc.returncode != 0:
        raise RuntimeError(f"the profile in {tree} failed: {proc.stderr.strip()[-400:]}")
    return json.loads(proc.stdout.strip().splitlines()[-1])


def label(name):
    """A term's name, a merged term's (``"tether1 + tether2 + ..."``) shortened."""
    names = name.split(" + ")
    return name if len(names) < 3 else f"{names[0]} + ... + {names[-1]} ({len(names)} cables)"


def rows(p):
    """``[(part, us per step)]`` of a profile ``p``: the compiled parts times their counts,
    the rest of the call, the Python of the step by group, the step."""
    c = p["counts"]
    out = []
    for k in p["kernels"]:
        out.append((f"{label(k['term'])}: residual", c["evaluations"] * k["residual_us"]))
    tangent = sum(k["tangent_us"] for k in p["kernels"])
    out += [("tangent evaluation (all terms)", c["factorizations"] * tangent),
            ("band factorization", c["factorizations"] * p["factor_us"]),
            ("band solve", c["corrections"] * p["solve_us"])]
    out.append(("rest of the compiled call (constraints, M a, updates, tests, unboxing)",
                p["call_us"] - sum(us for _, us in out)))
    out.append(("**compiled call**", p["call_us"]))
    out += [(f"Python: {group}", us) for group, us in p["python"].items()]
    out.append(("**Python of the step**", p["step_us"] - p["call_us"]))
    out.append(("**step**", p["step_us"]))
    return out


def table(steps=600, repeats=5, quick=False):
    """Profile this tree and ``REFERENCE``; print the side-by-side table.

    Returns
    -------
    dict
        ``{"here": profile, "reference": profile, "load": (before, after)}`` (the
        figures of ``PROFILE``).
    """
    against = short_commit(REFERENCE)
    load = os.getloadavg()[0]
    with worktree(REFERENCE) as other:
        theirs = profile(other, steps, repeats)
    ours = profile(ROOT, steps, repeats)
    print(f"E-sail rig, {steps} steps, minimum of {repeats}; here {short_commit('HEAD')}, "
          f"reference {against}; load average {load:.2f} before, "
          f"{os.getloadavg()[0]:.2f} after" + (" (quick: indicative only)" if quick else ""))
    for name, p in (("here", ours), (against, theirs)):
        c = p["counts"]
        print(f"{name}: {c['evaluations']:.3f} evaluations, {c['corrections']:.3f} "
              f"corrections, {c['factorizations']:.4f} factorizations per step")
    print(f"| part | us/step at {against} | us/step here | here - {against} |\n"
          "|---|---|---|---|")
    theirs_rows = dict(rows(theirs))
    for part, us in rows(ours):
        base = theirs_rows.get(part)
        shown = "n/a" if base is None else f"{base:.1f}"
        diff = "" if base is None else f"{us - base:+.1f}"
        print(f"| {part} | {shown} | {us:.1f} | {diff} |")
    for part in theirs_rows.keys() - dict(rows(ours)).keys():
        print(f"| {part} | {theirs_rows[part]:.1f} | n/a | |")
    for name, p in (("here", ours), (against, theirs)):
        for what, value in p["extra"].items():
            print(f"- {name}: {what}: {value if isinstance(value, str) else f'{value:.2f} us'}")
    return {"here": ours, "reference": theirs, "load": (load, os.getloadavg()[0])}


def main(argv=None):
    """Parse the arguments (``--quick``), print the table and return its figures."""
    args = arguments(__doc__, "120 steps, two repeats", argv)
    return table(**SETTINGS["quick" if args.quick else "full"], quick=args.quick)


if __name__ == "__main__":
    main()
