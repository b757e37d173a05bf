"""Parameter studies on Dask distributed: ``sweep`` runs every point of a grid as one task
(``client.map`` of ``task.run_point``), each into its own run directory of the study, on a
given cluster or a ``LocalCluster`` it starts, and gathers the small records the tasks
return into the study's dataset (``dataset``).  Ctrl-C stops a study cleanly: the dataset
of the points finished so far is written, the others are ``interrupted`` (their run
directories keep their last commit, and the same call continues them), and the workers of
a ``LocalCluster``, which leave Ctrl-C to this process, are stopped quietly."""

import logging
import os
import signal
import time
import uuid
from contextlib import contextmanager, nullcontext, suppress
from pathlib import Path

import numpy as np

from ..io import signals
from ..io.progress import Progress
from ..util.jsonable import jsonable
from . import grid as grids
from .dataset import RUNS, STUDY, dataset, write_study
from .task import run_point


def sweep(build, grid, run=None, client=None, store="runs/study", fixed=None,
          overwrite=False, workers=None, progress=None, plots=False):
    """Run a parameter study on Dask distributed and return its dataset.

    Parameters
    ----------
    build : callable
        ``build(**params) -> runner.RunScene``: the scene of one point (system, initial
        state, solver settings, parameters, outputs).  The contract: a module-level
        function (workers import it by name), deterministic (the same parameters give the
        same scene in every process), taking the parameters as keywords; it is called in
        the worker, so the scene is never shipped.
    grid : dict or list of dict
        ``{name: [values]}`` (the outer product, one dimension per name) or a list of
        ``{name: value}`` (one dimension ``run``), see ``grid.points``.
    run : callable, optional
        ``run(scene, options) -> summary``, a module-level function that runs a scene into
        ``options.out`` (``runner.RunOptions``); default ``scene.run(options)``.
    client : dask.distributed.Client, optional
        The cluster to run on; default a ``LocalCluster`` of ``workers`` processes with
        one thread each, closed at the end.
    store : path
        The study's directory (``study.zarr`` and ``runs/``).
    fixed : dict, optional
        Parameters of ``build`` common to every point (not dimensions).
    overwrite : bool
        Run every point again, replacing its run directory; by default a point whose run
        is finished with the same scene is reused and an interrupted one continued.
    workers : int, optional
        Processes of the local cluster (default: the cores, at most the points).
    progress : bool, optional
        Progress bar over the tasks on stderr (None: when stderr is a terminal).
    plots : bool
        Write each run's figures.

    Returns
    -------
    xarray.Dataset
        The study (also written to ``store/study.zarr``).

    Raises
    ------
    KeyboardInterrupt
        Ctrl-C (or ``SIGTERM`` in a run of this process): ``store/study.zarr`` holds the
        points finished before it, the others with the status ``interrupted``; the
        exception's ``study`` is that dataset.

    Examples
    --------
    >>> from skfem_cable.scenes.catalog import pendulum_scene
    >>> ds = sweep(pendulum_scene, {"elements": [4, 8]},       # doctest: +SKIP
    ...            fixed={"t_end": 0.5}, store="runs/pendulum-study")
    >>> ds.energy_max_abs_balance_relative.sel(elements=8)     # doctest: +SKIP
    """
    fixed = dict(fixed or {})
    dims, pts, coords = grids.points(grid)
    clash = sorted(set(fixed) & {n for _, p in pts for n in p})
    if clash:
        raise ValueError(f"parameter {clash[0]!r} is both fixed and swept")
    grids.check_names(build, [*fixed, *pts[0][1]])
    if workers is not None and (int(workers) != workers or workers < 1 or client is not None):
        raise ValueError(f"workers must be a positive integer, without client (which has "
                         f"its own), got {workers!r}")
    store = Path(store).resolve()
    names = [grids.run_name(build, {**p, **fixed}) for _, p in pts]

    def study(records):
        ds = dataset(dims, coords, [i for i, _ in pts], records,
                     [f"{RUNS}/{n}" for n in names])
        ds.attrs.update(build=grids.build_name(build), fixed=jsonable(fixed),
                        directory=str(store), created=time.strftime("%Y-%m-%dT%H:%M:%S%z"))
        write_study(ds, store / STUDY)
        return ds

    with _cluster(client, workers, len(pts)) as c:
        try:
            records = _gather(c, build, run, [{**fixed, **p} for _, p in pts],
                              [store / RUNS / n for n in names], overwrite, plots, progress)
        except KeyboardInterrupt as err:
            err.study = study(err.records)
            raise
    return study(records)


@contextmanager
def _cluster(client, workers, n_tasks):
    """``client``, or a client of a new ``LocalCluster`` (closed on exit)."""
    if client is not None:
        yield client
        return
    from dask.distributed import Client, LocalCluster

    n = workers or max(1, min(n_tasks, os.cpu_count() or 1))
    with signals.ignored(signal.SIGINT):  # the workers inherit it: Ctrl-C is this process's
        cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                               dashboard_address=None)
    c = Client(cluster)
    interrupted = False
    try:
        yield c
    except KeyboardInterrupt:
        interrupted = True  # busy workers are stopped: what they log about it is expected
        with suppress(Exception):
            c.run(_silence, "distributed")
        raise
    finally:
        with _silenced("distributed") if interrupted else nullcontext():
            c.close()
            cluster.close()


def _silence(name):
    """Silence the logger ``name`` (and its children) of this process."""
    logging.getLogger(name).setLevel(logging.CRITICAL + 1)


@contextmanager
def _silenced(name):
    """The logger ``name`` (and its children) quiet inside the block."""
    logger = logging.getLogger(name)
    level = logger.level
    _silence(name)
    try:
        yield
    finally:
        logger.setLevel(level)


def _gather(client, build, run, params, dirs, overwrite, plots, progress):
    """Submit one task per point and collect the records as they come (a task the cluster
    lost for good is a failed record)."""
    from dask.distributed import as_completed

    token = uuid.uuid4().hex[:8]
    futures = client.map(run_point, [build] * len(params), params, dirs, run=run,
                         overwrite=overwrite, plots=plots,
                         key=[f"skfem-cable-sweep-{token}-{d.name}" for d in dirs])
    index = {f.key: k for k, f in enumerate(futures)}
    records = [None] * len(futures)
    bar = Progress(0, len(futures), progress, label="runs")
    failed = 0
    try:
        for done, future in enumerate(as_completed(futures), 1):
            try:
                record = future.result()
            except Exception as err:  # the task itself records failures: this is the cluster
                record = _record("failed", f"{type(err).__name__}: {err}")
            records[index[future.key]] = record
            failed += record["status"] != "complete"
            bar.update(done, f"{failed} failed" if failed else "")
            future.release()
    except KeyboardInterrupt as err:
        err.records = [r or _record("interrupted", "the study was interrupted before this "
                                    "run finished; run the study again to continue it")
                       for r in records]
        raise
    finally:
        bar.close()
    return records


def _record(status, error):
    """The record of a point whose task returned none."""
    return {"status": status, "error": error, "reused": False, "numbers": {},
            "t_last": np.nan, "task_wall_time": np.nan}


