"""Run the benchmark scripts of a source checkout's ``benchmarks/`` folder
(``skfem-cable bench``), streaming their tables and writing one JSON record per run.

Each script runs in its own unbuffered Python process (``python -u -m skfem_cable.cli.bench
SCRIPT ROWS [ARGS]``), which imports the script, calls its ``main(ARGS)`` and writes the
rows it returns into the JSON file ``ROWS``.  The parent relays the script's output line by
line as it is printed and then writes the record of the run, ``<UTC time>-<name>.json``:
machine, Python and package versions, git commit, command, wall time and the figures (the
rows), so that results can be compared over time.
"""

import argparse
import importlib.util
import json
import os
import platform
import shlex
import socket
import subprocess
import sys
import tempfile
import time
from datetime import datetime, timezone
from importlib import metadata
from pathlib import Path

from ..util.atomic import write_atomic
from ..util.jsonable import jsonable

ROOT = Path(__file__).resolve().parents[2]

#: The benchmark scripts (a source checkout's ``benchmarks/``).
BENCHMARKS = ROOT / "benchmarks"

#: Default folder of the JSON records (git-ignored).
RESULTS = BENCHMARKS / "results"

#: Benchmarks left out of the default ``--quick`` set (they still accept ``--quick``), and
#: why: their quick variants take from 25 s to 3 minutes on 2 cores.
NOT_QUICK = {
    "commit_compare": "about 80 s quick: six cases in fresh processes, here and in a git "
                      "worktree of the reference commit (bench --against)",
    "adaptive_fronts": "about 40 s quick: a fixed 0.025 s reference and eight runs of the "
                       "12-tether sail",
    "compile_cost": "about 40 s: a fresh process compiles a system and a second Newton "
                    "step from an empty kernel cache",
    "esail_full": "about 15 s quick: the full-size sail (100 tethers) built and run five "
                  "times over 300 s",
    "esail_floor": "about 20 s quick: the machine's peaks in a fresh process, the E-sail "
                   "rig's parts each in a compiled loop",
    "esail_profile": "about a minute quick: the E-sail rig's step profiled in fresh "
                     "processes, here and in a git worktree of the reference commit",
    "esail_report": "about 2 minutes quick: E-sail runs over a spin period",
    "rig_profile": "about 30 s quick: the windless E-sail rig's run and step profiled in "
                   "a fresh process",
    "laws": "about 3 minutes quick: a git worktree, fresh processes with cold caches",
    "locking": "about 2.5 minutes quick: 512-element references, E-sail runs",
    "mooring_moordyn": "a peer code (optional extra), transient runs of both codes",
    "peers": "about 25 s quick: peer codes (optional extra), reference runs",
    "peer_suites": "about 10 s: the peers' own test cases in the peer codes (optional "
                   "extra) and ours",
    "sweep_efficiency": "about 3 minutes quick: 8 E-sail runs serial, on a new and on a "
                        "running 2-worker cluster",
}

#: Distributions whose versions go into the records.
PACKAGES = ("numpy", "scipy", "numba", "scikit-fem", "skfem_cable")

#: The option of every benchmark script (and of ``skfem-cable bench``): small sizes and
#: few repeats.
QUICK = "--quick"


def scripts(folder=BENCHMARKS):
    """The benchmark scripts.

    Parameters
    ----------
    folder : Path
        Folder of the scripts.

    Returns
    -------
    dict
        ``{name: path}`` of the ``*.py`` files, sorted by name.

    Raises
    ------
    FileNotFoundError
        Without scripts (outside a source checkout).
    """
    found = {p.stem: p for p in sorted(Path(folder).glob("*.py"))}
    if not found:
        raise FileNotFoundError(f"no benchmark scripts in {folder} (they are part of a "
                                "source checkout)")
    return found


def selection(available, names, quick):
    """The benchmarks to run.

    Parameters
    ----------
    available : dict
        ``{name: path}`` of ``scripts``.
    names : list of str
        Requested names; empty for the default set.
    quick : bool
        The default set is then the quick set (without ``NOT_QUICK``).

    Returns
    -------
    list of str

    Raises
    ------
    ValueError
        For an unknown name.
    """
    unknown = [n for n in names if n not in available]
    if unknown:
        raise ValueError(f"unknown benchmark {unknown[0]!r}: use one of {', '.join(available)}")
    if names:
        return list(names)
    return [n for n in available if not (quick and n in NOT_QUICK)]


def machine():
    """Host name, CPU count and platform of this machine."""
    return {"hostname": socket.gethostname(), "cpu_count": os.cpu_count(),
            "platform": platform.platform(), "processor": platform.machine()}


def versions():
    """Versions of Python and of ``PACKAGES`` (``None`` when not installed)."""
    out = {"python": platform.python_version()}
    for name in PACKAGES:
        try:
            out[name] = metadata.version(name)
        except metadata.PackageNotFoundError:
            out[name] = None
    return out


def git_commit(root=ROOT):
    """``{"commit": hash, "dirty": bool}`` of the checkout, or ``None`` without git."""
    def git(*args):
        return subprocess.run(["git", *args], cwd=root, capture_output=True, text=True,
                              check=True).stdout.strip()

    try:
        return {"commit": git("rev-parse", "HEAD"),
                "dirty": bool(git("status", "--porcelain", "--untracked-files=no"))}
    except (OSError, subprocess.CalledProcessError):
        return None


def stream(command, sink):
    """Run ``command`` and pass each line of its standard output to ``sink`` as soon as it
    is printed (standard error is inherited).

    Returns
    -------
    int
        The exit status.
    """
    with subprocess.Popen(command, stdout=subprocess.PIPE, text=True, bufsize=1) as proc:
        for line in proc.stdout:
            sink(line)
    return proc.returncode


def run_script(path, args, sink):
    """Run one benchmark script in an unbuffered child process.

    Parameters
    ----------
    path : Path
        The script; it defines ``main(argv)`` returning its rows as plain data.
    args : list of str
        Arguments of ``main``.
    sink : callable
        Receives each printed line.

    Returns
    -------
    returncode : int
    wall : float
        Wall time in s, with the interpreter's start-up.
    rows : object
        What ``main`` returned (``None`` if it failed).
    """
    with tempfile.TemporaryDirectory(prefix="skfem_cable-bench-") as tmp:
        rows_file = Path(tmp) / "rows.json"
        start = time.perf_counter()
        returncode = stream([sys.executable, "-u", "-m", __name__, str(path), str(rows_file),
                             *args], sink)
        wall = time.perf_counter() - start
        rows = json.loads(rows_file.read_text()) if rows_file.exists() else None
    return returncode, wall, rows


def record(name, path, args, started, returncode, wall, rows):
    """The JSON record of one benchmark run (see the module's description)."""
    try:
        script = path.relative_to(ROOT)
    except ValueError:
        script = path
    return {"benchmark": name, "started": started.isoformat(timespec="seconds"),
            "command": shlex.join(["python", str(script), *args]), "returncode": returncode,
            "wall_s": wall, "machine": machine(), "versions": versions(),
            "git": git_commit(), "figures": rows}


def save_record(folder, rec, started):
    """Write ``rec`` atomically into ``folder/<UTC time>-<name>.json``; returns the path."""
    path = Path(folder) / f"{started.strftime('%Y%m%dT%H%M%SZ')}-{rec['benchmark']}.json"
    write_atomic(path, (json.dumps(jsonable(rec), indent=1) + "\n").encode())
    return path


def run(names=(), quick=False, out=None, json_dir=RESULTS, args=()):
    """Run benchmarks one after the other, printing their output as it comes.

    Parameters
    ----------
    names : sequence of str
        Benchmarks to run (default: all; with ``quick``, the quick set).
    quick : bool
        Pass ``--quick`` to every script.
    out : Path, optional
        Also save each benchmark's output as ``out/NAME.txt``.
    json_dir : Path
        Folder of the JSON records.
    args : sequence of str
        More arguments passed to every script (after ``--quick``).

    Returns
    -------
    int
        0 if every benchmark succeeded, else 1.
    """
    available = scripts()
    chosen = selection(available, list(names), quick)
    if quick and not names:
        print(f"== quick set: {', '.join(chosen)} (left out, run them by name: "
              f"{', '.join(n for n in available if n in NOT_QUICK)})", flush=True)
    args = [QUICK] * quick + list(args)
    status, start = 0, time.perf_counter()
    for i, name in enumerate(chosen, 1):
        status |= run_one(name, available[name], args, f"[{i}/{len(chosen)}]", out, json_dir)
    print(f"== {len(chosen)} benchmark(s) in {time.perf_counter() - start:.1f} s", flush=True)
    return status


def run_one(name, path, args, counter, out, json_dir):
    """Run one benchmark, save its output and record; returns 0 on success, else 1."""
    print(f"== {counter} {shlex.join([name, *args])}", flush=True)
    lines = []

    def sink(line):
        lines.append(line)
        print(line, end="", flush=True)

    started = datetime.now(timezone.utc)
    returncode, wall, rows = run_script(path, args, sink)
    if out is not None:
        write_atomic(Path(out) / f"{name}.txt", "".join(lines).encode())
    saved = save_record(json_dir, record(name, path, args, started, returncode, wall, rows),
                        started)
    print(f"== {name}: {wall:.1f} s, record {saved}", flush=True)
    if returncode != 0:
        print(f"benchmark {name} failed with exit code {returncode}", file=sys.stderr)
        return 1
    return 0


def _child(argv):
    """In the child process: ``SCRIPT ROWS [ARGS]``, call the script's ``main(ARGS)`` and
    write its rows as JSON into ``ROWS``."""
    path, rows_file, args = Path(argv[0]), Path(argv[1]), argv[2:]
    sys.path.insert(0, str(path.parent))  # as ``python SCRIPT`` would
    spec = importlib.util.spec_from_file_location(f"benchmark_{path.stem}", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    rows = module.main(args)
    write_atomic(rows_file, json.dumps(jsonable(rows)).encode())
    return 0


if __name__ == "__main__":
    sys.exit(_child(sys.argv[1:]))


def timings(function, repeats):
    """The wall times (s) of ``repeats`` calls of ``function()``, in order."""
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        function()
        times.append(time.perf_counter() - start)
    return times


def largest_differences(run, reference):
    """The largest difference over a run of each output from a reference run's, relative
    to the reference's largest magnitude (a value crossing zero is not divided by its
    zero).  ``run`` and ``reference`` are ``(t, y)``: times (nt,) and outputs (nt, k); the
    run's are interpolated linearly to the reference's times."""
    import numpy as np

    (t, y), (t_ref, y_ref) = run, reference
    at = np.stack([np.interp(t_ref, t, column) for column in np.transpose(y)], axis=1)
    return np.abs(at - y_ref).max(axis=0) / np.abs(y_ref).max(axis=0)


def largest_position_error(result, reference, cable, s):
    """The largest distance over a run between the points at reference arc lengths ``s``
    of ``cable`` in ``result`` and in a ``reference`` run of finer steps, whose positions
    are interpolated to the run's times with their velocities (cubic Hermite: between
    steps of 2.5e-5 s of the flexible pendulum, some 1e-12 m)."""
    import numpy as np
    from scipy.interpolate import CubicHermiteSpline

    at = CubicHermiteSpline(reference.t, reference.position(cable, s),
                            reference.velocity(cable, s), axis=0)
    return float(np.linalg.norm(result.position(cable, s) - at(result.t), axis=-1).max())


def arguments(doc, quick_help, argv=None):
    """The command line of a benchmark script whose only option is ``--quick``
    (described by ``quick_help``); ``doc`` is the script's docstring.  Returns the parsed
    arguments."""
    parser = argparse.ArgumentParser(description=doc.splitlines()[0])
    parser.add_argument(QUICK, action="store_true", help=quick_help)
    return parser.parse_args(argv)
