"""A rod-chain run into a run directory, as ``skfem-cable run`` makes them for cable
runs (``runner.run_dynamic``): the run store (``io.RunStore``: ``results.zarr``, the
checkpoint and the manifest), the VTU series ``series.pvd`` + ``vtu/`` (written during
the run by ``io.SeriesObserver``), ``summary.json`` (parameters, wall time, steps, key
outputs, energy budget, the store) and ``plots/`` (``plots.run_figures``).  ``--resume``
continues an interrupted run bit for bit; ``SIGTERM`` and ``SIGHUP`` end it like Ctrl-C
(the store commits its pending steps)."""

import numpy as np

from ..io import run_observers
from ..io.schema import STORE
from ..runner.continued import resume_checked
from ..runner.directory import register_files, run_directory
from ..runner.drive import store_summary
from ..runner.summary import complete_summary, warn, write_summary
from .integrate import rk4_step
from .plots import run_figures
from .stored import ChainSystem

# the rod chain's own figure (``plots.run_figures``), for the summary of its runs
register_files({"plots/chain.png": "rod-chain tip, tensions and energies against time"},
               after="plots/cables.png")

#: Simulate keywords a run takes from ``defaults`` besides ``t_end`` and ``dt``.
SOLVER_KEYS = ("method", "rtol", "atol", "max_strain")


def time_grid(chain, t_end, dt, method="rk4", step=None):
    """The step and the saved-step stride of a run saving every ``dt`` (s) up to
    ``t_end``: ``(step, every)``.  RK4: ``step`` (default ``rk4_step(chain, dt)``) must
    divide ``dt``; adaptive methods: ``(dt, 1)``."""
    if method != "rk4":
        return dt, 1
    step = rk4_step(chain, dt) if step is None else step
    every = max(1, int(round(dt / step)))
    if abs(every * step - dt) > 1e-9 * dt:
        raise ValueError(f"the saved-step spacing dt = {dt:g} s must be a multiple of the RK4 "
                         f"step {step:g} s")
    if abs(round(t_end / dt) * dt - t_end) > 1e-9 * t_end:
        raise ValueError(f"t_end = {t_end:g} s must be a multiple of the saved-step spacing "
                         f"dt = {dt:g} s")
    return step, every


def chain_outputs(result):
    """Key numbers of a rod-chain run: the chain at the end and its extremes over the run,
    and the energy budget (the keys of ``runner.run_outputs``' ``energy``)."""
    chain = result.chain
    speed = np.linalg.norm(result.joint_velocities[:, -1], axis=-1)
    strain = result.strain
    E = result.energy
    scale = max(np.abs(E["total"]).max(), np.abs(E["kinetic"]).max(), 1e-300)
    return {"chain": {"rods": chain.n, "rest_length": chain.rest_length,
                      "mass": chain.total_mass, "free_end": result.free_end[-1],
                      "max_free_end_speed": speed.max(),
                      "root_tension": result.tension[-1, 0],
                      "max_tension_run": result.tension.max(),
                      "min_tension_run": result.tension.min(),
                      "max_strain_run": strain.max(), "min_strain_run": strain.min()},
            "energy": {"total_initial": E["total"][0], "total_final": E["total"][-1],
                       "dissipated": E["dissipated"][-1],
                       "external_work": E["external_work"][-1],
                       "max_abs_balance_relative": np.abs(E["balance"]).max() / scale}}


def run_chain(name, chain, initial, options, defaults, loads=None, parameters=None,
              outputs=None, observers=()):
    """Simulate ``chain`` from ``initial`` and fill the run directory ``options.out``.

    Parameters
    ----------
    name : str
        Scene name (recorded in the summary).
    chain : RodChain
    initial : (ndarray, ndarray)
        Rod vectors and their rates (n, 3).
    options : runner.RunOptions
        ``t_end`` and ``dt`` (the spacing of the saved steps) override ``defaults``;
        ``--every`` and ``--alpha`` are refused; ``--resume`` continues the stored run
        (the same scene parameters, chain, loads and settings, ``runner.resume_checked``).
    defaults : dict
        ``t_end``, ``dt`` (saved-step spacing), and optionally ``method``, ``step`` (the
        RK4 step, default ``rk4_step(chain, dt)``), ``series_every`` (a ``.vtu`` for every
        ``series_every``-th saved step and the last, default 1), ``rtol``, ``atol``,
        ``max_strain``, ``chunk`` (saved steps per commit of the store, default 200).
    loads : dict, optional
        ``RodChain.simulate`` keywords: ``gravity``, ``tip_force``, ``line_load``,
        ``anchor``, ``quadrature``.
    parameters : dict, optional
        Scene parameters to record in the summary.
    outputs : callable, optional
        ``outputs(result) -> dict`` of scene-specific key numbers, added to the summary.
    observers : sequence of Observer
        Added after the series and the progress bar.

    Returns
    -------
    summary : dict
    result : RodChainResult
    """
    options.reject(name, "every", "formulation")
    if options.value("frame", "inertial") != "inertial":
        raise ValueError(f"scene {name!r} is a rod-chain run, written in the inertial frame: "
                         f"--frame {options.frame} has no meaning for it")
    t_end = options.value("t_end", defaults["t_end"])
    dt = options.value("dt", defaults["dt"])
    method = defaults.get("method", "rk4")
    step, every = time_grid(chain, t_end, dt, method, defaults.get("step"))
    series_every = defaults.get("series_every", 1)
    solver = {k: defaults[k] for k in SOLVER_KEYS if k in defaults}
    loads = dict(loads or {})
    scene = dict(parameters or {})
    parameters = {**scene, "t_end": t_end, "dt": dt, "method": method,
                  "series_every": series_every}
    with run_directory(options) as out:
        resume, before = None, 0.0
        if options.resume:
            system = ChainSystem.of(chain, initial[0], **loads,
                                    **{k: solver[k] for k in ("max_strain",) if k in solver})
            resume = resume_checked(out, system, scene, "inertial",
                                    {**solver, "dt": step, "every": every})
            before = resume.manifest.get("wall_time", 0.0)
        watch = run_observers(out, options.progress, series_every, restart=options.resume,
                              chunk=defaults.get("chunk", 200), overwrite=options.overwrite,
                              attrs={"scene": name, "parameters": scene})
        result = chain.simulate(*initial, t_end, step, output_every=every, **solver, **loads,
                                observers=[*watch, *observers], resume=resume)
        stats = result.stats
        summary = {"scene": name, "parameters": parameters,
                   "wall_time": before + stats["wall_time"],
                   "session_wall_time": stats["wall_time"], "saved_steps": len(result),
                   "integration": {"method": method, "step": step, "steps": stats["steps"],
                                   "nfev": stats["nfev"], "stable_dt": chain.stable_dt(),
                                   "stopped": stats["stopped"]},
                   "outputs": chain_outputs(result)}
        complete_summary(summary, result, outputs)
        if out is not None:
            summary["store"] = store_summary(out)
            files = {"store": STORE, "manifest": "manifest.json",
                     "checkpoint": summary["store"]["checkpoint"], "series": "series.pvd"}
            if options.plots:
                paths, skipped = run_figures(out, result)
                if skipped:
                    warn(f"skipping the 3-D snapshot: {skipped}")
                files["plots"] = [p.relative_to(out).as_posix() for p in paths]
            if options.animate:
                warn("no animation of rod-chain runs (the VTU series animates in ParaView)")
            summary["files"] = files
            write_summary(out, summary)
    return summary, result
