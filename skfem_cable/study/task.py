"""One point of a parameter study, run as one task on a Dask worker: it builds the scene,
runs it into its own run directory (or finds it finished there, or continues it from its
checkpoint) and returns a small record (status, error, key numbers) — never the arrays,
which stay in the run store.

A run directory is **finished and the same** when its ``summary.json`` holds the study's
record ``sweep`` with the point's parameters and a fingerprint equal to the scene's now:
the system (``io.fingerprint``), the solver settings and ``t_end``.  A directory with a
store and a checkpoint but no such summary (a worker was killed, the study interrupted, or
``t_end`` grew) is continued from the checkpoint bit for bit (``RunOptions.resume``); a
store written by another system or other settings is an error naming ``overwrite``.  A
``summary.json`` that cannot be read (truncated) is no record: the run is continued from
its store, which writes the summary again.  The task holds the lock of the run directory
(``io.lock``, waiting for it), so that two attempts at the same point (Dask may start a
task again when it believes a worker lost) never write it at once.
"""

import json
import time
from pathlib import Path

import numpy as np

from ..io import lock
from ..io.manifest import StoreMismatch, read_manifest
from ..io.reader import run_info
from ..model.fingerprint import settings_fingerprint, system_fingerprint
from ..runner.directory import SUMMARY, run_files
from ..runner.options import RunOptions
from ..runner.summary import write_summary
from ..util.jsonable import jsonable

#: Top-level entries of a summary that become the study's numbers (besides ``outputs``).
STATS = ("wall_time", "total_wall_time", "steps", "saved_steps", "newton")


def fingerprint(scene):
    """What makes a finished run the same as ``scene``: the fingerprints of its system and
    of its settings, and ``t_end``."""
    settings = dict(getattr(scene, "settings", None) or {})
    return {"system": system_fingerprint(scene.system),
            "settings": settings_fingerprint(settings), "t_end": settings.get("t_end")}


def numbers(summary, own_outputs):
    """The key numbers of a run for the study's dataset: ``STATS`` and ``outputs`` of its
    ``summary`` flattened (``newton_per_step``; ``outputs`` without its prefix), numbers
    and numeric vectors only; the per-cable numbers only when the scene has no
    ``own_outputs``."""
    tree = {k: summary[k] for k in STATS if k in summary}
    outputs = dict(summary.get("outputs") or {})
    if own_outputs:
        outputs.pop("cables", None)
    flat = {}
    _flatten({**tree, **outputs}, "", flat)
    return flat


def _flatten(tree, prefix, flat):
    for key, value in tree.items():
        name = f"{prefix}{key}"
        if isinstance(value, dict):
            _flatten(value, name + "_", flat)
            continue
        array = np.asarray(value)
        if array.ndim <= 1 and array.dtype.kind in "iufb" and array.size:
            flat[name] = array.astype(float).tolist() if array.ndim else float(array)


def _finished(run_dir, params, fp):
    """The summary of ``run_dir`` if it holds the finished run of ``params`` with the
    fingerprint ``fp``; None if it holds no finished run of them, one with another
    ``t_end`` or a summary that cannot be read; ``StoreMismatch`` if the scene changed
    since."""
    path = run_dir / SUMMARY
    try:
        summary = json.loads(path.read_text())
    except (OSError, ValueError):  # none, or truncated: the store tells what is done
        return None
    record = summary.get("sweep") or {}
    stored = record.get("fingerprint") or {}
    if record.get("parameters") != jsonable(params):
        return None
    if stored == fp:
        return summary
    if {k: stored.get(k) for k in ("system", "settings")} == {k: fp[k] for k in
                                                              ("system", "settings")}:
        return None  # only t_end differs: continue (or shorten: an error) from the store
    raise StoreMismatch(f"{run_dir} holds a finished run of these parameters by another "
                        "scene (its system or solver settings differ: the build function or "
                        "the code changed): run the study with overwrite=True (--overwrite)")


def _how(run_dir, overwrite):
    """``RunOptions`` keywords to write ``run_dir``: continue the store it holds (with a
    checkpoint), replace what it holds otherwise, or start afresh; ``StoreCorrupt`` for a
    damaged manifest (the point fails, naming it, and its steps are kept)."""
    if overwrite or not run_files(run_dir):
        return {"overwrite": overwrite}
    manifest = read_manifest(run_dir)  # a damaged one is an error, its data are kept
    if manifest is not None and manifest.get("checkpoint"):
        return {"resume": True}
    return {"overwrite": True}  # a start that committed nothing: no data to keep


def run_point(build, params, run_dir, run=None, overwrite=False, plots=False):
    """Run the point ``params`` of a study into ``run_dir`` (the task of ``sweep``).

    Parameters
    ----------
    build : callable
        ``build(**params)`` returns the scene (``runner.RunScene``, or what ``run``
        takes: an object with ``system`` and ``settings``).
    params : dict
    run_dir : path
    run : callable, optional
        ``run(scene, options) -> summary`` (``options``: ``runner.RunOptions`` with
        ``out = run_dir``); default ``scene.run(options)``.
    overwrite : bool
        Replace what ``run_dir`` holds instead of reusing or continuing it.
    plots : bool
        Write the run's figures.

    Returns
    -------
    dict
        ``status`` (``"complete"`` or ``"failed"``), ``error`` (``""`` or the exception as
        text), ``reused`` (the run was finished before), ``numbers`` (``numbers``),
        ``t_last`` (time of the last stored step, NaN without store), ``task_wall_time``.
        Any exception of the build or the run is recorded, not raised; the run store keeps
        the steps committed before it.
    """
    wall0 = time.perf_counter()
    run_dir = Path(run_dir)
    record = {"status": "complete", "error": "", "reused": False, "numbers": {}}
    with lock.hold(run_dir, wait=True):
        try:
            scene = build(**params)
            fp = fingerprint(scene)
            summary = None if overwrite else _finished(run_dir, params, fp)
            record["reused"] = summary is not None
            if summary is None:
                options = RunOptions(out=run_dir, progress=False, plots=plots,
                                     **_how(run_dir, overwrite))
                summary = (scene.run(options) if run is None else run(scene, options))
                summary["sweep"] = {"parameters": params, "fingerprint": fp}
                write_summary(run_dir, summary)
            record["numbers"] = numbers(summary, getattr(scene, "outputs", None) is not None)
        except Exception as err:
            record.update(status="failed", error=f"{type(err).__name__}: {err}")
        manifest = run_info(run_dir) or {}
    record["t_last"] = float((manifest.get("last") or {}).get("t", np.nan))
    record["task_wall_time"] = time.perf_counter() - wall0
    return record
