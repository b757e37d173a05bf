"""What a cold kernel cache costs (issue 47, must-show 5): the CPU seconds numba spends
compiling, by kind of compiled code, and their LLVM part (``kernels.compile_log.Recorder``).

Without ``--suite``: a fresh process with an empty cache (a temporary
``SKFEM_CABLE_CACHE``) runs a pinned 4-element cable in water (Morison drag) for 3 steps,
the first system of a process (the package's kernels, the law's and the drag's modules,
the Newton step compiled once per machine and the system's terms module), then the cable
with two drag loads: a new sequence of term kernels, none of them new, so its terms module
alone (what every further distinct system of a test session costs, its new kernels
apart).

``--suite DIR``: the records of a test session run with ``SKFEM_CABLE_COMPILE_LOG=DIR``
(``tests/compile_recorder.py``): compile seconds by kind, the distinct Newton-step and law
modules, the functions compiled by more than one process (each worker compiles what the
cache lacks when it needs it), and the tests that compiled most.

    SKFEM_CABLE_COMPILE_LOG=/tmp/log python3 tasks.py test
    python benchmarks/compile_cost.py --suite /tmp/log
"""

import argparse
import json
import os
import subprocess
import sys
import tempfile
from collections import defaultdict
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

#: The child: compiles the first system and a second terms module, prints JSON.
CHILD = """
import json, time
from skfem_cable.kernels.compile_log import Recorder
import skfem_cable as sc

recorder = Recorder().install()

def run(n_drags):
    cable = sc.Cable.straight([0, 0, 0], [1.0, 0, 0], n_elements=4,
                              section=sc.Section.circular(radius=0.01, E=7e10, rho=7800.0))
    system = sc.System([cable]).pin(cable.node(0)).add_gravity([0, -9.81, 0])
    for k in range(n_drags):
        system.add_load(sc.MorisonDrag(cable, rho=1000.0, cd_normal=1.2 + k,
                                       cd_tangential=0.1, diameter=0.02))
    start = time.thread_time()
    sc.simulate(system, t_end=3e-3, dt=1e-3)
    return time.thread_time() - start, recorder.take()

first = run(1)
print(json.dumps({"first system": first, "another system": run(2)}))
"""

#: The kinds of compiled function, by the start of their module's name.
KINDS = (("skfem_cable_step_", "the Newton step"), ("skfem_cable_terms_", "terms modules"),
         ("skfem_cable_law_", "law modules"),
         ("skfem_cable_line_", "line-load modules"), ("skfem_cable.", "package kernels"))


def kind(function):
    """The kind of a compiled function's name (``KINDS``; else numba's and others)."""
    return next((k for prefix, k in KINDS if function.startswith(prefix)), "numba and others")


def module_of(function):
    return function.rsplit(".", 1)[0]


def fresh():
    """``{part: (CPU seconds, compiles)}`` of the two runs of ``CHILD``."""
    with tempfile.TemporaryDirectory() as cache:
        env = dict(os.environ, SKFEM_CABLE_CACHE=cache, PYTHONPATH=str(ROOT))
        done = subprocess.run([sys.executable, "-c", CHILD], env=env, cwd=ROOT, check=True,
                              capture_output=True, text=True)
    return json.loads(done.stdout.strip().splitlines()[-1])


def by_kind(compiles):
    """``{kind: [seconds, llvm seconds]}`` of ``[function, seconds, llvm]`` rows."""
    sums = defaultdict(lambda: [0.0, 0.0])
    for function, seconds, llvm in compiles:
        sums[kind(function)][0] += seconds
        sums[kind(function)][1] += llvm
    return dict(sums)


def print_kinds(title, cpu, compiles):
    sums = by_kind(compiles)
    total = sum(s for s, _ in sums.values())
    llvm = sum(v for _, v in sums.values())
    print(f"\n{title}: {cpu:.1f} s CPU, of which compiling {total:.1f} s "
          f"(LLVM {llvm:.1f} s)\n\n| kind | compile s | LLVM s |\n|---|---|---|")
    for name, (seconds, lv) in sorted(sums.items(), key=lambda kv: -kv[1][0]):
        print(f"| {name} | {seconds:.1f} | {lv:.1f} |")
    return {"part": title, "cpu": cpu, "compile": total, "llvm": llvm,
            "by_kind": {k: v[0] for k, v in sums.items()}}


def read_suite(folder):
    """``{worker: [record, ...]}`` of a session's records (``tests/compile_recorder.py``)."""
    return {path.stem.removeprefix("compile-"): [json.loads(line) for line in
                                                 path.read_text().splitlines()]
            for path in sorted(Path(folder).glob("compile-*.jsonl"))}


def suite(folder, top=20):
    """Print and return the summary of a session's records."""
    workers = read_suite(folder)
    compiles = [c for records in workers.values() for r in records for c in r["compiles"]]
    cpu = sum(records[-1]["cpu"] for records in workers.values() if records)
    row = print_kinds(f"test session ({len(workers)} workers' CPU)", cpu, compiles)
    where = defaultdict(set)
    for name, records in workers.items():
        for r in records:
            for function, _, _ in r["compiles"]:
                where[function].add(name)
    twice = sum(s for function, s, _ in compiles if len(where[function]) > 1) / 2
    modules = {k: len({module_of(f) for f, _, _ in compiles if kind(f) == k})
               for k in ("the Newton step", "terms modules", "law modules")}
    print(f"\ndistinct modules compiled: {modules}; seconds of functions compiled in more "
          f"than one worker, per extra worker: {twice:.1f} s")
    tests = sorted(((sum(s for _, s, _ in r["compiles"]), r["test"])
                    for records in workers.values() for r in records), reverse=True)
    print(f"\n| test (top {top} by compile s) | compile s |\n|---|---|")
    for seconds, test in tests[:top]:
        print(f"| {test} | {seconds:.1f} |")
    schedule(workers)
    return [dict(row, modules=modules, duplicated=twice)]


def schedule(workers):
    """Print when each worker ended (its last record's ``wall``, from the earliest end)
    with its CPU and its children's: the schedule is balanced when they end together
    (records without ``wall``, from before it was recorded, print nothing)."""
    ends = {name: records[-1] for name, records in workers.items()
            if records and "wall" in records[-1]}
    if not ends:
        return
    first = min(r["wall"] for r in ends.values())
    print("\n| worker | ends after the first (s) | CPU s | children's CPU s |\n|---|---|---|---|")
    for name, r in ends.items():
        print(f"| {name} | {r['wall'] - first:.1f} | {r['cpu']:.1f} | {r['children']:.1f} |")


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--suite", metavar="DIR",
                        help="sum up the records of a test session instead")
    parser.add_argument("--quick", action="store_true",
                        help="the same (the fresh process takes about 30 s of CPU)")
    args = parser.parse_args(argv)
    if args.suite:
        return suite(args.suite)
    return [print_kinds(part, cpu, compiles) for part, (cpu, compiles) in fresh().items()]


if __name__ == "__main__":
    main(sys.argv[1:])
