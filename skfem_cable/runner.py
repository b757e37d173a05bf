"""Runs into run directories, as ``skfem-cable run`` makes them.

A run directory holds

* the run store (written during the run by ``io.RunStore``): ``results.zarr`` (the saved
  steps; ``xarray.open_zarr`` opens it, ``Result.load(run_dir, system)`` reads it back),
  ``checkpoint_NNNNNNNN.npz`` (the state at the last commit) and ``manifest.json`` (the
  commit record); continue an interrupted run with ``--resume`` or
  ``simulate(..., resume=io.resume(run_dir))``;
* the VTU series ``series.pvd`` + ``vtu/`` (written during the run by
  ``io.SeriesObserver``), which ParaView opens as an animation;
* ``summary.json``: scene, parameters, wall time (and the kernels' compile time apart),
  steps, Newton statistics, key outputs, every file of the run directory with a one-line
  description (``files.described``), the store and the files written;
* ``plots/``: energy and cable histories, tension spectra and a rendered snapshot
  (``plot``), and ``animation.gif`` on request.

``RunOptions.frame`` chooses the frame of the series and the renders (``export.FRAMES``:
``"inertial"``, or ``"lvlh"``, the orbiting frame of a system in orbit); the store holds
the computed coordinates.  The summary of a system in orbit reports the reference orbit
and the osculating orbit of the centre of mass at the first and last saved steps
(``orbit_summary``).

A directory that holds another run is not written into: ``RunOptions.overwrite`` removes
that run's files first (only files this package writes), ``RunOptions.resume`` continues
it, and only as the run it holds (``run_directory``).  A run holds the lock of its
directory (``io.lock``) from the first check to its last file: a second process writing
the same directory is refused.
"""

import json
import os
import shutil
import sys
import time
from contextlib import contextmanager
from dataclasses import dataclass, field
from fnmatch import fnmatch
from pathlib import Path

import numpy as np

from . import export, plot
from .io import RunExists, StoreError, StoreMismatch, lock, run_observers
from .io import resume as resume_run
from .io.atomic import is_temporary, write_atomic
from .io.fingerprint import system_fingerprint
from .io.jsonable import jsonable
from .io.manifest import read_manifest
from .io.store import STORE, check_fingerprint, describe_run, remove_store, run_info, store_files
from .orbit import Orbit
from .solvers.simulate import simulate
from .state import State
from .tension_guard import tension_warnings

SUMMARY = "summary.json"


@dataclass
class RunOptions:
    """Options of a run (the ``skfem-cable run`` flags); ``None`` means the scene's
    default."""

    out: Path | None = None
    t_end: float | None = None
    dt: float | None = None
    elements: int | None = None
    formulation: str | None = None
    alpha: float | None = None
    every: int | None = None
    progress: bool | None = None
    plots: bool = True
    animate: bool = False
    overwrite: bool = False
    resume: bool = False
    frame: str | None = None

    def reject(self, scene, *names):
        """Raise ``ValueError`` if one of the options ``names`` was given: it has no
        meaning for ``scene``."""
        given = [n for n in names if getattr(self, n) is not None]
        if given:
            flags = ", ".join("--" + n.replace("_", "-") for n in given)
            raise ValueError(f"scene {scene!r} does not take {flags}")

    def value(self, name, default):
        """The option ``name``, or ``default`` when it was not given."""
        value = getattr(self, name)
        return default if value is None else value


def write_summary(out, summary):
    """Write ``summary.json`` into the run directory ``out`` with ``files.described``, the
    run's files and their descriptions (``described_files``); returns its path."""
    files = summary.setdefault("files", {})
    files["described"] = {**described_files(out), SUMMARY: DESCRIPTIONS[SUMMARY]}
    path = Path(out) / SUMMARY
    write_atomic(path, (json.dumps(jsonable(summary), indent=2) + "\n").encode())
    return path


def cable_outputs(system, q, t=0.0):
    """Key numbers of every cable at coordinates ``q`` and time ``t``: tip position, root
    and peak tension, (free) length and number of elements."""
    out = {}
    state = State(system, q, t=t)
    for cable in system.cables():
        s = cable.mesh.p[0]
        tension = state.tension(cable, s)
        out[cable.name] = {"tip_position": state.position(cable, cable.length),
                           "root_tension": tension[0], "max_tension": tension.max(),
                           "length": cable.length * system.stretch(cable, t, q),
                           "elements": cable.n_elements}
    return out


def orbit_elements(orbit):
    """The elements of ``orbit`` (an ``Orbit``) for a summary: ``a`` (m), ``e``,
    ``inclination``, ``raan``, ``argp``, ``anomaly`` (the true anomaly at ``t``) and
    ``longitude`` (the true longitude ``raan + argp + anomaly`` in ``[0, 2 pi)``: well
    defined also when a nearly circular or nearly equatorial orbit leaves its terms
    ill-conditioned), all in rad, ``t`` (s, the epoch) and ``period`` (s)."""
    return {"a": orbit.a, "e": orbit.e, "inclination": orbit.inclination,
            "raan": orbit.raan, "argp": orbit.argp, "anomaly": orbit.anomaly,
            "longitude": float(np.remainder(orbit.raan + orbit.argp + orbit.anomaly,
                                            2 * np.pi)),
            "t": orbit.t0, "period": orbit.period}


def centre_of_mass_orbit(system, state):
    """The osculating orbit of the centre of mass of ``system`` (in orbit) at ``state``:
    ``Orbit.from_state(mu, R(t) + x_cm, V(t) + v_cm, t)``, with ``x_cm``, ``v_cm`` from
    ``System.centre_of_mass``."""
    v = np.zeros_like(state.q) if state.v is None else state.v
    x_cm, v_cm = system.centre_of_mass(state.q), system.centre_of_mass(v)
    reference = system.orbit
    return Orbit.from_state(reference.mu, reference.position(state.t) + x_cm,
                            reference.velocity(state.t) + v_cm, state.t)


def orbit_summary(system, first, last):
    """The orbit of a run of ``system`` (in orbit) for its summary: ``mu``, the
    ``reference`` orbit's elements and the osculating elements of the centre of mass at
    the ``first`` and ``last`` states (``start``, ``end``; ``orbit_elements``)."""
    return {"mu": system.orbit.mu, "reference": orbit_elements(system.orbit),
            "start": orbit_elements(centre_of_mass_orbit(system, first)),
            "end": orbit_elements(centre_of_mass_orbit(system, last))}


def run_outputs(result):
    """Key numbers of a dynamic run: the cables at the end and their tension extremes over
    the run, and the energy budget."""
    system = result.system
    out = {"cables": cable_outputs(system, result.q[-1], result.t[-1])}
    for cable in system.cables():
        T = result.tension(cable, cable.mesh.p[0])
        out["cables"][cable.name].update(max_tension_run=T.max(), min_tension_run=T.min())
    E = result.energy
    scale = max(np.abs(E["total"]).max(), np.abs(E["kinetic"]).max(), 1e-300)
    out["energy"] = {"total_initial": E["total"][0], "total_final": E["total"][-1],
                     "dissipated": E["dissipated"][-1],
                     "external_work": E["external_work"][-1],
                     "max_abs_balance_relative": np.abs(E["balance"]).max() / scale}
    return out


#: Drift of the energy balance, relative to the energy content, above which a run's
#: summary warns: the time step dissipated (or, within the guard, created) that much.
BALANCE_WARNING = 0.02


def run_warnings(summary):
    """Warnings about a finished dynamic run that its numbers alone would not show."""
    drift = summary["outputs"]["energy"]["max_abs_balance_relative"]
    if drift > BALANCE_WARNING:
        return [f"the energy balance drifted by {100 * drift:.3g} % of the energy content: "
                "the time step dissipates numerically (rho_inf < 1) or resolves the motion "
                "poorly; results may be far from the converged ones: reduce dt"]
    return []


def warn(message):
    """Print a warning of a run on stderr (prefixed ``skfem-cable:``)."""
    print(f"skfem-cable: {message}", file=sys.stderr)


def complete_summary(summary, result, outputs=None, warnings=()):
    """Add a scene's own key numbers ``outputs(result)`` to ``summary["outputs"]`` and the
    run's warnings (``run_warnings`` and ``warnings``), printing each."""
    if outputs is not None:
        summary["outputs"].update(outputs(result))
    summary["warnings"] = run_warnings(summary) + list(warnings)
    for warning in summary["warnings"]:
        warn(warning)


def snapshot(out, system, state, name="final.png", title=None, frame="inertial"):
    """Render ``state`` (in the output ``frame``, ``export.FRAMES``) into
    ``out/plots/name`` when off-screen rendering works; returns the path, or None (with a
    warning on stderr) when it does not."""
    ok, reason = plot.rendering_available()
    if not ok:
        warn(f"skipping the 3-D snapshot: {reason}")
        return None
    path = Path(out) / "plots" / name
    path.parent.mkdir(parents=True, exist_ok=True)
    plot.render(system, state, path, title=title, frame=frame)
    return path


def framed_title(title, frame):
    """``title`` with the line that names the output ``frame`` (``export.FRAMES``; none
    for the inertial one), or None when both are empty."""
    return "\n".join(filter(None, [title, export.FRAMES[frame].label])) or None


def run_figures(out, result, animate=False, title=None, frame="inertial"):
    """The standard figures of a dynamic run in ``out/plots`` (energies, cable histories,
    root-tension spectra, final snapshot) and ``out/animation.gif`` if ``animate``; the
    snapshot and the animation show ``title`` (a scene file's) above the time and are
    drawn in the output ``frame`` (``export.FRAMES``; ``"lvlh"`` says so on them).
    Returns the paths written."""
    plots = Path(out) / "plots"
    plots.mkdir(parents=True, exist_ok=True)
    paths = [plots / "energies.png", plots / "cables.png"]
    plot.energies(result, paths[0])
    plot.cable_histories(result, paths[1])
    if len(result) >= 16 and result.system.cables():
        signals = {c.name: result.tension(c, 0.0) for c in result.system.cables()}
        paths.append(plots / "tension_psd.png")
        plot.psd(result.t, signals, paths[-1], title="root tension", units="N")
    title = framed_title(title, frame)
    final = snapshot(out, result.system, result.state(len(result) - 1),
                     title="\n".join(filter(None, [title, f"t = {result.t[-1]:.4g} s"])),
                     frame=frame)
    if final is not None:
        paths.append(final)
        if animate:
            paths.append(Path(out) / "animation.gif")
            plot.animate(result, paths[-1], title=title, frame=frame)
    elif animate:
        warn("skipping the animation (no off-screen rendering)")
    return paths


def plot_files(out, written=()):
    """Paths (relative to the run directory ``out``, as text) of the run's figures: the
    paths ``written`` in their order, then every other file of ``out/plots`` (a scene's
    own figures, written by its ``outputs``), temporary files left out."""
    out = Path(out)
    folder = out / "plots"
    present = sorted(p for p in folder.iterdir() if p.is_file() and not is_temporary(p)
                     and not p.name.endswith(".tmp")) if folder.is_dir() else []
    return list(dict.fromkeys(p.relative_to(out).as_posix() for p in [*written, *present]))


#: Every file a run directory can hold (names and patterns relative to it), with the
#: one-line description ``summary.json`` gives it (``described_files``).
DESCRIPTIONS = {
    SUMMARY: "this summary: scene, parameters, solver statistics, key outputs, files",
    "manifest.json": "the run's manifest: status, saved steps, settings and fingerprints",
    lock.LOCK: "the lock a run holds while it writes this directory (io.lock)",
    "results.zarr": "the results store (xarray.open_zarr): every saved step's fields",
    "checkpoint_*.npz": "integrator checkpoint: a resumed run continues bit for bit",
    "series.pvd": "ParaView collection of the VTU frames (open this one in ParaView)",
    "vtu/series_*.vtu": "ParaView frames: bodies with tension, strain and velocity fields",
    "animation.gif": "animation of the run (3-D renders)",
    "animation.mp4": "animation of the run (3-D renders)",
    "esail_outputs.npz": "every E-sail output of esail.outputs, as numpy arrays",
    "plots/energies.png": "energy terms, balance residual and relative drift against time",
    "plots/cables.png": "tip displacements (spinning: in the spinning frame) and root and "
                        "peak tensions of the cables against time",
    "plots/chain.png": "rod-chain tip, tensions and energies against time",
    "plots/tension_psd.png": "power spectral density of the root tensions",
    "plots/final.png": "3-D render of the final state",
    "plots/esail_tether.png": "tether coning, lagging and stretch against time (Fig. 6)",
    "plots/esail_hub.png": "hub rates and attitudes, sail attitude (Figs. 7-8)",
    "plots/esail_forces.png": "thrust and root reactions in the orbit frame (Fig. 9)",
    "plots/esail_psd.png": "spectra of tether and hub motions, Table 2 modes marked",
    "plots/esail_coning.gif": "side view of the sail's coning, Sun direction drawn (--animate)",
}

#: Files this package writes into a run directory besides the store and the lock
#: (``--overwrite`` removes these and nothing else): names and patterns relative to it.
RUN_FILES = tuple(k for k in DESCRIPTIONS if k not in ("manifest.json", "results.zarr",
                                                       "checkpoint_*.npz", lock.LOCK)) + (
    "plots/esail_*.png", "plots/esail_*.gif")


def described_files(out):
    """``{relative path: description}`` of every file of the run in ``out`` (the VTU
    frames as one entry with their count); a file without description is listed as
    such."""
    out = Path(out)
    listed = {}
    for path in [*run_files(out), out / lock.LOCK]:
        name = path.relative_to(out).as_posix()
        if is_temporary(path) or name.endswith(".tmp") or not path.exists():
            continue
        pattern = next((k for k in DESCRIPTIONS if fnmatch(name, k)), None)
        if pattern == "vtu/series_*.vtu":
            count = len(list(out.glob(pattern)))
            listed[pattern] = f"{DESCRIPTIONS[pattern]} ({count} files)"
        else:
            listed[name] = DESCRIPTIONS.get(pattern, "written by this package")
    return listed


def run_files(out):
    """The files and folders of a run (this package's) present in the directory ``out``:
    the store (``io.store.store_files``), ``RUN_FILES`` and temporary files."""
    out = Path(out)
    if not out.is_dir():
        return []
    found = list(store_files(out))
    for pattern in RUN_FILES:
        found += sorted(out.glob(pattern))
    for folder in (out, out / "vtu", out / "plots"):
        if folder.is_dir():
            found += [p for p in sorted(folder.iterdir()) if p.is_file() and (
                is_temporary(p) or p.name.endswith((".vtu.tmp", ".pvd.tmp")))]
    return list(dict.fromkeys(found))


def remove_run(out):
    """Remove the run in ``out``: its store first (so that a half-removed run is never
    taken for a complete one), then ``run_files``; empty ``vtu/`` and ``plots/`` folders
    go too.  Files this package did not write stay.  Returns the number of entries
    removed."""
    out = Path(out)
    files = run_files(out)
    remove_store(out)
    for path in files:
        if path.is_dir():
            shutil.rmtree(path, ignore_errors=True)
        else:
            path.unlink(missing_ok=True)
    for folder in (out / "vtu", out / "plots"):
        if folder.is_dir() and not any(folder.iterdir()):
            folder.rmdir()
    return len(files)


def _describe(out):
    manifest = run_info(out)
    if manifest is None:
        names = ", ".join(p.name for p in run_files(out)[:4])
        return f"files of an earlier run: {names}"
    return describe_run(manifest)


def check_run_dir(out, overwrite=False, resume=False):
    """Raise unless a run may be written into ``out`` as asked: ``RunExists`` when it
    holds another run and neither ``overwrite`` nor ``resume`` is given, ``StoreError``
    when ``resume`` finds nothing to continue (``StoreCorrupt`` naming a damaged
    manifest) or when ``out`` cannot be written.  Changes nothing."""
    if overwrite and resume:
        raise ValueError("--overwrite and --resume exclude each other")
    if out is None:
        if resume:
            raise ValueError("--resume needs the run directory (--out DIR)")
        return
    out = Path(out)
    if out.exists() and not out.is_dir():
        raise ValueError(f"--out {out} is a file, not a directory")
    _check_writable(out, resume or overwrite)
    present = run_files(out)
    if resume:
        if read_manifest(out) is None:
            what = "a run of the old format that cannot be continued" if any(
                p.name == "checkpoint.npz" for p in present) else "no run store to continue"
            raise StoreError(f"{out} holds {what} (no manifest.json): run the scene "
                             "without --resume" + (", into another --out to keep its files"
                                                   if present else ""))
        return
    if present and not overwrite:
        raise RunExists(f"{out} already holds a run ({_describe(out)}): choose another "
                        "--out, replace it with --overwrite, or continue it with --resume")


def _check_writable(out, existing):
    """Raise ``StoreError`` unless ``out``, or the folder it would be created in, may be
    written by this user; ``existing``: the run in ``out`` is continued or replaced."""
    folder = next(p for p in (out, *out.parents) if p.exists())
    if not folder.is_dir():
        raise ValueError(f"--out {out}: {folder} is a file, not a directory")
    if os.access(folder, os.W_OK | os.X_OK):
        return
    if folder != out:
        raise StoreError(f"--out {out} cannot be created: {folder} is read-only for this "
                         "user; choose another --out, or make it writable")
    raise StoreError(f"--out {out} is read-only for this user: "
                     + ("its run cannot be continued or replaced there; make it writable, "
                        "or copy it and continue the copy" if existing else
                        "choose another --out, or make it writable"))


@contextmanager
def run_directory(options, can_resume=True):
    """Hold the run directory ``options.out`` for a run (``io.lock``; yields it as a
    ``Path``, or None without one): created if missing, checked (``check_run_dir``)
    once the lock is held, and with ``options.overwrite`` emptied of the run it held.
    The lock is held until the block ends: no other process writes the directory
    meanwhile."""
    if options.resume and not can_resume:
        raise ValueError("--resume continues time integrations only; this scene has none")
    check_run_dir(options.out, options.overwrite, options.resume)  # before creating it
    if options.out is None:
        yield None
        return
    out = Path(options.out)
    with lock.hold(out):
        check_run_dir(out, options.overwrite, options.resume)  # nobody changes it now
        if options.overwrite:
            remove_run(out)
        yield out


def _check_settings(out, manifest, solver):
    """Before a continued run: the solver settings given must be those stored (all but
    ``t_end``), else ``StoreMismatch`` naming them."""
    stored = manifest.get("settings") or {}
    differ = [k for k, v in solver.items()
              if k != "t_end" and k in stored and stored[k] != jsonable(v)]
    if differ:
        raise StoreMismatch(f"{out} was run with other settings ("
                            + ", ".join(f"{k}: stored {stored[k]!r}, given {solver[k]!r}"
                                        for k in differ)
                            + "): continue it with the settings it was started with")


#: Scene parameters a continued run may change: where the scene file is.
MOVABLE = ("file",)


def _check_frame(out, manifest, frame):
    """Before a continued run: its series must go on in the frame it was written in
    (``attrs.frame`` of the manifest, ``"inertial"`` when absent), else
    ``StoreMismatch`` naming both."""
    stored = (manifest.get("attrs") or {}).get("frame", "inertial")
    if stored != frame:
        raise StoreMismatch(f"{out} was written in the frame {stored!r}, not {frame!r}: "
                            f"continue it with --frame {stored}")


def _check_scene(out, manifest, system, parameters):
    """Before a continued run: the scene must be the stored one, its parameters (those
    the manifest records, but ``MOVABLE``; a store of an earlier version may record
    fewer) and its system (``check_fingerprint``); else ``StoreMismatch`` naming what
    differs."""
    stored = (manifest.get("attrs") or {}).get("parameters") or {}
    given = json.loads(json.dumps(jsonable(parameters or {})))
    differ = [k for k in sorted(stored) if k not in MOVABLE and stored[k] != given.get(k)]
    if not differ:
        check_fingerprint(out, manifest, system)
        return
    listed = "; ".join(f"{k}: stored {stored[k]!r}, given {given.get(k)!r}" for k in differ)
    same = (manifest.get("fingerprint") or {}).get("system") == system_fingerprint(system)
    raise StoreMismatch(f"{out} was " + ("run with other scene parameters" if same else
                                         "written by another system: its parameters differ")
                        + f" ({listed}): continue it with the scene and options it was "
                        "started with")


def run_dynamic(name, system, initial, options, defaults, parameters=None, outputs=None,
                points_per_element=8):
    """Simulate ``system`` from ``initial`` and fill the run directory ``options.out``.

    Parameters
    ----------
    name : str
        Scene name (recorded in the summary).
    system : System
    initial : State or None
    options : RunOptions
        ``t_end``, ``dt``, ``every`` override ``defaults``; ``progress`` is passed on;
        ``frame`` is the frame of the series and the renders (refused before any file
        is written when the system cannot have it: ``export.output_frame``).
    defaults : dict
        ``t_end``, ``dt``, ``every``, and optionally ``rho_inf`` and other ``simulate``
        keywords (``tol``, ``newton``, ...), ``series_every`` (a ``.vtu`` for every
        ``series_every``-th saved step, default 1), ``chunk`` (saved steps per commit of
        the run store, default 200) and ``fields`` (the fields it stores, default
        ``io.DEFAULT_FIELDS``).
    parameters : dict, optional
        Scene parameters to record in the summary; a ``title`` among them (a scene
        file's) is shown on the snapshot.
    outputs : callable, optional
        ``outputs(result) -> dict`` of scene-specific key numbers, added to the summary.
    points_per_element : int
        Cable samples per element in the VTU series.

    Returns
    -------
    summary : dict
        ``wall_time`` is the integration's over all the sessions of a continued run
        (``session_wall_time``: this one's), ``total_wall_time`` adds the rest (the
        store's setup, the summary, the figures); ``compile_time`` is this session's
        compilation of the kernels by numba (or their loading from its cache), and
        ``integration_time`` is ``wall_time`` less this session's compilation in it;
        ``frame`` the output frame; ``orbit`` (a system in orbit) is ``orbit_summary``.
    result : Result

    The run directory is held (``run_directory``) from its first check to the summary.
    ``options.resume`` continues the stored run only as it was started: the same scene
    parameters (``_check_scene``), system, solver settings (``_check_settings``) and a
    ``t_end`` not before its last stored step (``io.store.check_t_end``).
    """
    settings = dict(defaults)
    for key in ("t_end", "dt", "every"):
        settings[key] = options.value(key, defaults[key])
    export.output_frame(system, options.value("frame", "inertial"))  # before any file
    with run_directory(options) as out:
        return _run_dynamic(out, name, system, initial, options, settings, parameters,
                            outputs, points_per_element)


def _run_dynamic(out, name, system, initial, options, settings, parameters, outputs,
                 points_per_element):
    """``run_dynamic`` once the run directory ``out`` is held."""
    wall0 = time.perf_counter()
    solver = dict(settings)
    storage = {"series_every": solver.pop("series_every", 1), "chunk": solver.pop("chunk", 200),
               "fields": solver.pop("fields", None)}
    settings.pop("fields", None)
    frame = options.value("frame", "inertial")
    attrs = {"scene": name, "parameters": parameters or {}}
    if frame != "inertial":  # the store of an inertial run is as before frames existed
        attrs["frame"] = frame
    resume, before = None, 0.0  # wall time of the earlier sessions of a continued run
    if options.resume:
        _check_scene(out, read_manifest(out), system, parameters)
        _check_frame(out, read_manifest(out), frame)
        resume = resume_run(out)
        _check_settings(out, resume.manifest, solver)
        before = resume.manifest.get("wall_time", 0.0)
    observers = run_observers(out, options.progress, points_per_element=points_per_element,
                              restart=options.resume, overwrite=options.overwrite,
                              attrs=attrs, frame=frame, **storage)
    result = simulate(system, initial=initial, observers=observers, resume=resume, **solver)
    stats = result.stats
    summary = {"scene": name,
               "parameters": {**(parameters or {}), **settings},
               "wall_time": before + stats["wall_time"],
               "session_wall_time": stats["wall_time"],
               "compile_time": stats["compile_time"],
               "integration_time": before + stats["integration_time"],
               "steps": stats["steps"], "saved_steps": len(result),
               "newton": {"iterations": stats["newton"],
                          "per_step": stats["newton"] / max(stats["steps"], 1),
                          "factorizations": stats["factorizations"],
                          "rejected_steps": stats["rejected"], "solver": stats["solver"]},
               "outputs": run_outputs(result)}
    summary["frame"] = frame
    if system.orbit is not None:
        summary["orbit"] = orbit_summary(system, result.state(0), result.state(len(result) - 1))
    complete_summary(summary, result, outputs,
                     tension_warnings(result.system, result.q, result.t))
    if out is not None:
        summary["store"] = store_summary(out)
        files = {"store": STORE, "manifest": "manifest.json",
                 "checkpoint": summary["store"]["checkpoint"], "series": "series.pvd"}
        if options.plots:
            files["plots"] = plot_files(out, run_figures(out, result, options.animate,
                                                         (parameters or {}).get("title"),
                                                         frame))
        summary["files"] = files
        summary["total_wall_time"] = before + time.perf_counter() - wall0
        write_summary(out, summary)
    return summary, result


@dataclass
class RunScene:
    """A scene ready to run (``run``), and what the ``build`` function of a
    parameter study (``sweep``) returns.

    Attributes
    ----------
    name : str
        Scene name (recorded in the summary).
    system : System
    initial : State or None
    settings : dict
        The ``defaults`` of ``run_dynamic``: ``t_end``, ``dt``, ``every`` and optionally
        ``rho_inf``, other ``simulate`` keywords, ``series_every``, ``chunk``, ``fields``.
    parameters : dict
        Scene parameters recorded in the summary.
    outputs : callable, optional
        ``outputs(result) -> dict`` of the scene's key numbers (added to the summary).
    """

    name: str
    system: object
    initial: object
    settings: dict
    parameters: dict = field(default_factory=dict)
    outputs: object = None

    def run(self, options):
        """Run the scene into the run directory ``options.out`` (``run_dynamic``; the
        options override the settings); returns the summary."""
        return run_dynamic(self.name, self.system, self.initial, options, self.settings,
                           self.parameters, self.outputs)[0]


def store_summary(out):
    """What the run store of ``out`` holds (for the summary): saved steps, time span,
    fields, status, checkpoint and size on disk."""
    manifest = run_info(out) or {}
    out = Path(out)
    size = sum(p.stat().st_size for p in (out / STORE).rglob("*") if p.is_file())
    checkpoint = (manifest.get("checkpoint") or {}).get("file")
    if checkpoint and (out / checkpoint).exists():
        size += (out / checkpoint).stat().st_size
    return {"path": STORE, "saved_steps": manifest.get("saved"),
            "t": [(manifest.get("first") or {}).get("t"), (manifest.get("last") or {}).get("t")],
            "fields": manifest.get("fields"), "status": manifest.get("status"),
            "checkpoint": checkpoint, "bytes": size}


def run_static(name, system, steps, options, parameters=None, outputs=None, title=None,
               points_per_element=8):
    """Fill the run directory ``options.out`` of a static analysis.

    Parameters
    ----------
    name : str
    system : System
        The system of the last equilibrium (all ``steps`` share its bodies).
    steps : list of (float, State)
        Equilibria with the value recorded as their time in the VTU series (a load
        factor or load parameter); the last one is rendered.
    options : RunOptions
        ``frame``: the frame of the series and the snapshot (``export.FRAMES``).
    parameters, outputs : dict, optional
        Scene parameters and key numbers for the summary (the cables' tip positions and
        tensions at the last equilibrium are added; in orbit, ``orbit_summary`` of the
        first and last equilibria).
    title : str, optional
        Title of the snapshot.

    Returns
    -------
    dict
        The summary.
    """
    final = steps[-1][1]
    frame = options.value("frame", "inertial")
    moved = export.output_frame(system, frame)  # refused before any work
    summary = {"scene": name, "parameters": parameters or {},
               "outputs": {**(outputs or {}), "cables": cable_outputs(system, final.q)},
               "warnings": tension_warnings(system, final.q), "frame": frame}
    if system.orbit is not None:
        summary["orbit"] = orbit_summary(system, steps[0][1], final)
    for warning in summary["warnings"]:
        warn(warning)
    with run_directory(options, can_resume=False) as out:
        if out is None:
            return summary
        writer = export.SeriesWriter(out, system, points_per_element)
        for value, state in steps:  # turned at the state's time, not at its value
            writer.write(value, moved.configuration(state.t, state.q)[0])
        files = {"series": writer.pvd.name}
        if options.plots:
            path = snapshot(out, system, final, title=framed_title(title, frame),
                            frame=frame)
            files["plots"] = [] if path is None else [path.relative_to(out).as_posix()]
        summary["files"] = files
        write_summary(out, summary)
    return summary


def format_summary(summary):
    """A few readable lines about a finished run (what the CLI prints)."""
    lines = [f"scene {summary['scene']}"]
    if "newton" in summary:
        nw = summary["newton"]
        seconds = summary.get("integration_time", summary["wall_time"])
        lines.append(f"  {summary['steps']} steps in {seconds:.2f} s, "
                     f"{nw['per_step']:.2f} Newton iterations per step, "
                     f"{nw['rejected_steps']} rejected")
        if "compile_time" in summary:
            lines.append(f"  compiling the kernels (or loading them from the cache): "
                         f"{summary['compile_time']:.2f} s")
    elif "integration" in summary:
        it = summary["integration"]
        lines.append(f"  {it['steps']} {it['method']} steps of {it['step']:.3g} s in "
                     f"{summary['wall_time']:.2f} s")
    lines.extend(_format_tree(summary.get("outputs", {}), "  "))
    if "orbit" in summary:
        lines.append("  orbit (osculating elements of the centre of mass; m, rad, s):")
        lines.extend(_format_tree(summary["orbit"], "    "))
    store = summary.get("store")
    if store:
        lines.append(f"  store {store['path']}: {store['saved_steps']} saved steps, "
                     f"{store['bytes'] / 1e6:.3g} MB, {store['status']}")
    return "\n".join(lines)


def _format_value(value):
    value = np.asarray(value)
    if value.ndim:
        return np.array2string(value, precision=6)
    return f"{value.item():.6g}" if value.dtype.kind == "f" else str(value)


#: Printed members of a group of bodies at most (``summary.json`` keeps them all).
MAX_PRINTED = 3


def _format_tree(tree, indent):
    group = len(tree) > MAX_PRINTED + 1 and all(isinstance(v, dict) for v in tree.values())
    for k, (key, value) in enumerate(tree.items()):
        if group and k == MAX_PRINTED:
            yield f"{indent}... {len(tree) - MAX_PRINTED} more in summary.json"
            return
        if isinstance(value, dict):
            yield f"{indent}{key}:"
            yield from _format_tree(value, indent + "  ")
        elif isinstance(value, list) and value and all(isinstance(v, dict) for v in value):
            yield f"{indent}{key}:"
            columns = list(value[0])
            yield indent + "  " + " ".join(f"{c:>12}" for c in columns)
            for row in value:
                yield indent + "  " + " ".join(f"{_format_value(row[c]):>12}" for c in columns)
        else:
            yield f"{indent}{key}: {_format_value(value)}"
