"""The ``skfem-cable`` command: ``run`` a scene, ``sweep`` it over parameters (on Dask),
``validate`` against references, ``bench``.

Run ``skfem-cable --help`` or ``skfem-cable COMMAND --help``.
"""

import argparse
import gc
import inspect
import os
import shlex
import sys
import textwrap
from contextlib import contextmanager
from pathlib import Path

from ..runner import values
from ..runner.options import FLAGS, RunOptions, add_flags

EPILOG = """examples:
  skfem-cable run pendulum --out runs/pendulum
  skfem-cable run demos/spinning_hub.toml --t-end 2 --out runs/hub --animate
  skfem-cable run pendulum --out runs/pendulum --t-end 5 --resume
  skfem-cable run tss --out runs/tss --frame lvlh
  skfem-cable sweep esail --param alpha=0,30,60 --param voltage=1e4,2e4 --t-end 600 --out runs/s
  skfem-cable validate
  skfem-cable bench kernel_cost step_cost
  skfem-cable bench --quick
  skfem-cable bench --against abb2314 --repeats 3 --cases pendulum esail
"""


def _wrap(text):
    return textwrap.fill(text, width=79)


def _is_negative_number(text):
    """Whether ``text`` is a number with a minus sign (``-1e-3``, ``-.5``, ``-inf``)."""
    if not text.startswith("-"):
        return False
    try:
        float(text)
    except ValueError:
        return False
    return True


def _glue_negative_values(argv):
    """``argv`` with each negative number that follows an option joined to it: ``--dt
    -1e-3`` as ``--dt=-1e-3``.  argparse takes an argument that starts with ``-`` and is
    not of the form ``-1`` or ``-1.5`` (an exponent, ``-inf``) for an option, and then
    reports the option's value as missing instead of checking it."""
    out = []
    for arg in argv:
        previous = out[-1] if out else ""
        if (_is_negative_number(arg) and previous.startswith("--") and previous != "--"
                and "=" not in previous):
            out[-1] = f"{previous}={arg}"
        else:
            out.append(arg)
    return out


def _check_folder(option, path):
    """Raise ``ValueError`` naming ``option`` and ``path`` unless the folder ``path``
    exists or can be created by this user (checked before any work; changes nothing)."""
    if path is None:
        return
    folder = next(p for p in (path, *path.parents) if p.exists())
    if not folder.is_dir():
        raise ValueError(f"{option} {path}: {folder} is a file, not a directory")
    if not os.access(folder, os.W_OK | os.X_OK):
        raise ValueError(f"{option} {path}: {folder} is read-only for this user; choose "
                         f"another {option}, or make it writable")


class _Parser(argparse.ArgumentParser):
    """An ``ArgumentParser`` whose ``epilog`` and options' helps may be functions that
    return them, called only when the help is shown (they may import the scenes' modules,
    the formulations, the element types)."""

    def format_help(self):
        if callable(self.epilog):
            self.epilog = self.epilog()
        for action in self._actions:
            if callable(action.help):
                action.help = action.help()
        return super().format_help()


def _sweepable_scenes():
    """The ``sweep --help`` epilog: each sweepable scene and the parameters (with their
    defaults) of its build function, the names ``--param`` takes."""
    from ..scenes.catalog import SCENES

    lines = ["sweepable scenes and their parameters (defaults):"]
    for name, entry in sorted(SCENES.items()):
        if entry.build is not None:
            params = inspect.signature(entry.builder()).parameters.values()
            lines.append(textwrap.fill(
                ", ".join(p.name if p.default is p.empty else f"{p.name}={p.default!r}"
                          for p in params), width=79,
                initial_indent=f"  {name:<16} ", subsequent_indent=" " * 19))
    return "\n".join(lines)


def build_parser():
    """The argument parser (exposed for the documentation and the tests)."""
    from ..scenes.catalog import SCENES
    from .bench import QUICK

    parser = _Parser(
        prog="skfem-cable", description=_wrap("Simulate tethers, cables and E-sails "
        "(ANCF cables, rigid bodies, generalized-alpha dynamics) and look at the results."),
        epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")

    scenes = "\n".join(f"  {name:<16} {entry.help}" for name, entry in sorted(SCENES.items()))
    run = sub.add_parser(
        "run", help="run a built-in scene or a TOML scene file into a run directory",
        description=_wrap("Run a scene. A run directory (--out) receives the run store "
        "(results.zarr, read with xarray.open_zarr or Result.load; checkpoint_*.npz; "
        "manifest.json), the VTU series series.pvd + vtu/ for ParaView, summary.json "
        "(parameters, wall time, steps, Newton statistics, key outputs) and plots/. "
        "Without --out only the summary is printed. A directory that holds another run "
        "is refused unless --overwrite (replace it) or --resume (continue it) is given. "
        "Ctrl-C or SIGTERM end a run after storing its saved steps and a checkpoint; "
        "--resume continues it bit for bit (--t-end may grow)."),
        epilog=f"scenes:\n{scenes}\n  FILE.toml        a scene file (schema: docs/scene_files.md)",
        formatter_class=argparse.RawDescriptionHelpFormatter)
    run.add_argument("scene", metavar="SCENE", help="built-in scene name or path of a .toml file")
    add_flags(run, [n for n in FLAGS if n not in ("overwrite", "resume")])
    add_flags(run.add_mutually_exclusive_group(), ("overwrite", "resume"))

    sweep = sub.add_parser(
        "sweep", help="run a scene over a grid of parameters on Dask distributed",
        description=_wrap("Run a built-in scene for every combination of the --param "
        "values, one Dask task per run, on a local cluster (--workers) or an existing one "
        "(--scheduler, started with Dask's 'dask scheduler' and 'dask worker'). DIR "
        "receives study.zarr (an xarray dataset with one dimension per --param, named as "
        "given: the runs' key numbers, status and errors) and runs/NAME/, each run's "
        "directory. Running the same command again reuses finished runs and continues "
        "interrupted ones from their checkpoints; a failed run is recorded and the others "
        "complete (exit status 1 if one failed)."),
        epilog=_sweepable_scenes,
        formatter_class=argparse.RawDescriptionHelpFormatter)
    sweep.add_argument("scene", metavar="SCENE", help="built-in scene name")
    sweep.add_argument("--param", action="append", required=True, metavar="NAME=V1,V2",
                       help="a swept parameter of the scene's build function and its values "
                       "(repeat for more dimensions), e.g. alpha=0,10,20")
    add_flags(sweep, ("t_end",), help="end time of every run: seconds, or with a suffix s, "
              "min, h, d (default: the scene's)")
    add_flags(sweep, ("out",), required=True, help="study directory to write")
    where = sweep.add_mutually_exclusive_group()
    where.add_argument("--scheduler", metavar="ADDRESS",
                       help="address of a running Dask scheduler, e.g. tcp://host:8786")
    where.add_argument("--workers", type=values.positive_int, metavar="N",
                       help="worker processes of the local cluster (default: the cores)")
    add_flags(sweep, ("progress",))
    sweep.add_argument("--plots", action="store_true", help="write each run's figures")
    add_flags(sweep, ("overwrite",),
              help="run every point again, replacing the runs already in DIR")

    val = sub.add_parser(
        "validate", help="run the validation cases and print a table against the references",
        description=_wrap("Run reduced validation cases (statics, modes, pendulum period, "
        "waves, damping) and print reference, ours, relative error and tolerance. Exit "
        "status 1 if a case fails."))
    val.add_argument("cases", nargs="*", metavar="CASE",
                     help="cases to run (default: all; see --list)")
    val.add_argument("--list", action="store_true", help="list the cases and exit")

    bench = sub.add_parser(
        "bench", help="run the benchmark scripts of benchmarks/",
        description=_wrap("Run the benchmark scripts (speed and speed-vs-error tables) of "
        "a source checkout's benchmarks/ folder, one after the other, with this Python. "
        "Each table is printed as it is computed, with a header line per benchmark and "
        "its wall time; each run writes a JSON record (machine, versions, git commit, "
        "command, wall time, figures) named <UTC time>-NAME.json into --json DIR."))
    bench.add_argument("names", nargs="*", metavar="NAME",
                       help="benchmarks to run, without .py (default: all, or with --quick "
                       "the quick set; see --list)")
    bench.add_argument("--list", action="store_true", help="list the benchmarks and exit")
    bench.add_argument(QUICK, action="store_true",
                       help="small sizes and few repeats (passed to every script); without "
                       "NAMEs the quick set, under a minute")
    bench.add_argument("--out", type=values.directory, metavar="DIR",
                       help="also save each benchmark's output as DIR/NAME.txt")
    bench.add_argument("--json", type=values.directory, metavar="DIR", default=None,
                       help="folder of the JSON records (default: benchmarks/results)")
    bench.add_argument("--against", nargs="?", const="", default=None, metavar="REF",
                       help="time the tracked cases of benchmarks/commit_compare.py in this "
                       "tree and at the commit REF (default: its fixed REFERENCE), print "
                       "each ratio and flag those above 1.05 (a report: exit status 0)")
    bench.add_argument("--cases", nargs="+", metavar="CASE",
                       help="with --against: the tracked cases to time (default: all)")
    bench.add_argument("--repeats", type=values.positive_int, metavar="N",
                       help="with --against: runs of each tree per case (default 5; "
                       "--quick: 1), the minimum reported")
    return parser


def cmd_run(args):
    from ..runner.directory import check_run_dir
    from ..runner.summary import format_summary
    from ..scenes.catalog import run_scene

    options = RunOptions.from_args(args)
    check_run_dir(args.out, args.overwrite, args.resume)  # before any work
    try:
        summary = run_scene(args.scene, options)
    except KeyboardInterrupt as err:
        return _interrupted(args, err)
    print(format_summary(summary))
    if args.out is not None:
        print(f"run directory: {args.out}")
    return 0


def _interrupted(args, err):
    """Ctrl-C, SIGTERM or SIGHUP ended ``skfem-cable run``: say what is stored and how to
    continue; the exit status is the shell's for that signal (130 for Ctrl-C)."""
    from ..io.reader import run_info
    from ..io.signals import exit_status, interrupt_signal, signal_name

    signum = interrupt_signal(err)
    lines = [f"skfem-cable run: interrupted by {signal_name(signum)}"]
    manifest = run_info(args.out) if args.out is not None else None
    if manifest is not None and manifest.get("checkpoint"):
        last = manifest["last"]
        lines[0] += (f"; {args.out} holds {manifest['saved']} saved steps up to "
                     f"t = {last['t']:.6g} s and their checkpoint")
        argv = [a for a in args.argv if a not in ("--overwrite", "--resume")]
        lines.append("continue the run with: "
                     + shlex.join(["skfem-cable", *argv, "--resume"]))
    elif args.out is not None:
        frames = _frames(args.out)
        if frames:
            lines[0] += (f"; {args.out} holds {len(frames)} ParaView frames (series.pvd) up "
                         f"to t = {frames[-1][0]:.6g} s but no run store: this run cannot be "
                         "continued")
            lines.append("run it again into another --out (or with --overwrite, which "
                         "replaces these frames)")
        else:
            lines[0] += f"; nothing was stored in {args.out} yet"
            lines.append("run it again with --overwrite")
    print("\n".join(lines), file=sys.stderr)
    return exit_status(signum)


def _frames(out):
    """The ``(time, file)`` entries of the ParaView series in ``out`` (none if it has no
    readable ``series.pvd``)."""
    from ..io.export import read_pvd

    try:
        return read_pvd(Path(out) / "series.pvd")
    except (OSError, SyntaxError):  # no file, or not XML (ElementTree's ParseError)
        return []


def cmd_sweep(args):
    from ..scenes.catalog import builder
    from ..study import format_study, parse_param, sweep

    grid = {}
    for text in args.param:
        name, values = parse_param(text)
        if name in grid:
            raise ValueError(f"--param {name} is given twice")
        grid[name] = values
    build = builder(args.scene)
    _check_folder("--out", args.out)  # before any work
    fixed = {} if args.t_end is None else {"t_end": args.t_end}
    try:
        with _client(args.scheduler) as client:
            ds = sweep(build, grid, client=client, store=args.out, fixed=fixed,
                       workers=args.workers, progress=args.progress,
                       plots=args.plots, overwrite=args.overwrite)
    except KeyboardInterrupt as err:
        return _sweep_interrupted(args, err)
    print(format_study(ds))
    print(f"study: {args.out / 'study.zarr'}")
    return 0 if (ds.status == "complete").all() else 1


def _sweep_interrupted(args, err):
    """Ctrl-C (or SIGTERM, SIGHUP) ended ``skfem-cable sweep``: say what the study holds
    and how to continue; the exit status is the shell's for that signal."""
    from ..io.signals import exit_status, interrupt_signal, signal_name
    from ..study.dataset import STUDY

    signum = interrupt_signal(err)
    line = f"skfem-cable sweep: interrupted by {signal_name(signum)}"
    study = getattr(err, "study", None)
    if study is not None:
        done = int((study.status == "complete").sum())
        line += (f"; {args.out / STUDY} holds the {done} of {study.status.size} runs "
                 "finished, the others keep their last commit")
    argv = [a for a in args.argv if a != "--overwrite"]
    print(f"{line}\ncontinue the study with: {shlex.join(['skfem-cable', *argv])}",
          file=sys.stderr)
    return exit_status(signum)


@contextmanager
def _client(address):
    """A Dask client of the scheduler at ``address`` (None: none, ``sweep`` starts a
    local cluster)."""
    if address is None:
        yield None
        return
    from dask.distributed import Client

    try:
        client = Client(address, timeout="20s")
    except OSError as err:
        raise ValueError(f"--scheduler {address}: cannot connect ({err})") from err
    with client:
        yield client


def cmd_validate(args):
    from . import validation

    if args.list:
        for case in validation.CASES:
            print(f"{case.name:<22} {case.reference}")
        return 0
    rows = validation.run(args.cases)
    print(validation.format_table(rows))
    return 0 if all(r["passed"] for r in rows) else 1


def cmd_bench(args):
    from . import bench

    if args.list:
        for name in bench.scripts():
            reason = bench.NOT_QUICK.get(name)
            print(f"{name:<24} " + ("quick set" if reason is None else
                                    f"not in the quick set: {reason}"))
        return 0
    _check_folder("--out", args.out)  # before any benchmark runs
    _check_folder("--json", args.json)
    names, script_args = _against(args)
    return bench.run(names, quick=args.quick, out=args.out,
                     json_dir=bench.RESULTS if args.json is None else args.json,
                     args=script_args)


def _against(args):
    """``(names, script arguments)`` of ``bench``: with ``--against``, the benchmark
    ``commit_compare`` with ``--against``, ``--cases`` and ``--repeats``; else the NAMEs
    and no arguments.  Raises ``ValueError`` for NAMEs with ``--against``, or ``--cases``
    or ``--repeats`` without it."""
    if args.against is None:
        if args.cases is not None or args.repeats is not None:
            raise ValueError("--cases and --repeats go with --against (the tracked cases of "
                             "benchmarks/commit_compare.py)")
        return args.names, []
    if args.names:
        raise ValueError(f"--against times the tracked cases, not benchmarks by name: drop "
                         f"{' '.join(args.names)} (or choose cases with --cases)")
    script_args = ["--against", args.against] if args.against else []
    if args.cases is not None:
        script_args += ["--cases", *args.cases]
    if args.repeats is not None:
        script_args += ["--repeats", str(args.repeats)]
    return ["commit_compare"], script_args


COMMANDS = {"run": cmd_run, "sweep": cmd_sweep, "validate": cmd_validate, "bench": cmd_bench}


def main(argv=None):
    """Entry point of ``skfem-cable``; returns the exit status.

    Called as the program (``argv`` None: the console script, ``python -m
    skfem_cable.cli``), it freezes the objects left (``gc.freeze``) on its way out: the
    interpreter's exit then frees them without its garbage collections walking each of
    them (numba's, sympy's), 0.5 of the 3 CPU s of a short run (measured)."""
    if argv is None:
        try:
            return main(sys.argv[1:])
        finally:
            gc.freeze()
    parser = build_parser()
    argv = list(argv)
    args = parser.parse_args(_glue_negative_values(argv))
    args.argv = argv
    # here, not at the top: ``--help`` does without the solvers and their kernels
    from ..control.controller import ControlError
    from ..solvers.static import StaticConvergenceError
    from ..solvers.step_control import SimulationError

    try:
        return COMMANDS[args.command](args)
    except (ValueError, OSError, ImportError, SimulationError,
            StaticConvergenceError, ControlError) as err:
        notes = "".join(f"\n  {note}" for note in getattr(err, "__notes__", ()))
        print(f"skfem-cable {args.command}: error: {err}{notes}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
