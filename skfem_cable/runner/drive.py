"""The drivers of a run: a time integration (``run_dynamic``; a scene ready to run,
``RunScene``) or a sequence of equilibria (``run_static``) into a run directory, with its
summary, its figures and, for a time integration, what its run store holds
(``store_summary``)."""

import time
from dataclasses import dataclass, field
from pathlib import Path

from ..io import export, run_observers
from ..io.reader import run_info
from ..io.schema import STORE
from ..solvers.simulate import simulate
from .continued import resume_checked
from .directory import run_directory
from .figures import framed_title, plot_files, run_figures, snapshot
from .summary import (
    body_outputs,
    complete_summary,
    orbit_summary,
    run_outputs,
    warn,
    write_summary,
)
from .tension_guard import tension_warnings


def run_dynamic(name, system, initial, options, defaults, parameters=None, outputs=None,
                points_per_element=8, controllers=()):
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
    controllers : sequence of control.Controller
        Closed-loop control of the system's inputs (``simulate``).

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
    parameters, system, frame, ``points_per_element`` and solver settings
    (``continued.resume_checked``) and a ``t_end`` not before its last stored step
    (``io.resume.check_t_end``).
    """
    settings = dict(defaults)
    for key in ("t_end", "dt", "every"):
        settings[key] = options.value(key, defaults[key])
    export.output_frame(system, options.value("frame", "inertial"))  # before any file
    with run_directory(options) as out:
        return _run_dynamic(out, name, system, initial, options, settings, parameters,
                            outputs, points_per_element, controllers)


def _run_dynamic(out, name, system, initial, options, settings, parameters, outputs,
                 points_per_element, controllers):
    """``run_dynamic`` once the run directory ``out`` is held."""
    wall0 = time.perf_counter()
    solver = dict(settings)
    storage = {"series_every": solver.pop("series_every", 1), "chunk": solver.pop("chunk", 200),
               "fields": solver.pop("fields", None)}
    settings.pop("fields", None)
    frame = options.value("frame", "inertial")
    attrs = {"scene": name, "parameters": parameters or {},
             "points_per_element": points_per_element}
    if frame != "inertial":  # the store of an inertial run is as before frames existed
        attrs["frame"] = frame
    resume, before = None, 0.0  # wall time of the earlier sessions of a continued run
    if options.resume:
        resume = resume_checked(out, system, parameters, frame, solver, points_per_element)
        before = resume.manifest.get("wall_time", 0.0)
    observers = run_observers(out, options.progress, points_per_element=points_per_element,
                              restart=options.resume, overwrite=options.overwrite,
                              attrs=attrs, frame=frame, **storage)
    result = simulate(system, initial=initial, observers=observers, resume=resume,
                      controllers=controllers, **solver)
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
        summary["orbit"] = orbit_summary(system, result.state(0), result.state(len(result) - 1),
                                         result.reference)
        summary["orbit"].update(rectification=stats["rectification"],
                                rectifications=stats["rectifications"])
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
               "outputs": {**(outputs or {}), **body_outputs(system, final.q)},
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
