"""Raw results of a run on disk, written as it goes: the observer ``RunStore``.

A run directory's store is three things (``docs/output.md``):

``results.zarr/``
    A Zarr (v3) group that xarray opens as a Dataset (``xarray.open_zarr``): ``time``
    is the dimension of the saved steps and a coordinate; ``q``, ``v`` (``time, dof``),
    ``lam`` (``time, multiplier``), ``iterations``, the energies, the step numbers
    ``step`` and the solver counters ``stat_*`` are variables (``a`` on request: the
    ``fields`` option); the attributes hold the scene parameters, the settings, the
    bodies' coordinate ranges and the constraints' labels.  Chunks of ``chunk`` saved
    steps, float64, compressed (Blosc/Zstandard after a transpose that puts each
    coordinate's history together) and checksummed (CRC32C).

    **Labels** (``io.labels``), so that plain xarray shows what is what: with ``q``, the
    positions of the bodies' points ``r(time, body, node, component)`` (a cable's nodes,
    with their reference arc length ``s(body, node)``; a rigid body's base points; NaN
    where a body has fewer points than the most).  ``body`` and ``component`` (``x y
    z``) are dimensions, hence indexes that ``xarray.open_zarr`` builds by itself:
    ``ds.sel(body="tether3", component="x")`` works without this library.  Zarr keeps
    no other index (a pandas MultiIndex cannot be stored), so ``dof`` and
    ``multiplier`` carry non-index coordinates (``dof_body``, ``dof_node``,
    ``dof_component``, ``dof_label``; ``constraint``, ``equation``; named apart from the
    dimensions of ``r``), selected after ``ds.set_xindex([...])``.  The labels are
    written once, when the store is created; a commit appends ``r`` with the other
    arrays (Zstandard level 1: it repeats values of ``q``).  Units and long names
    follow CF (``units``, ``long_name``, ``standard_name`` for ``time``).  Stores written
    before the labels have none; they load and continue in their own layout.
``checkpoint_NNNNNNNN.npz``
    The integrator's ``snapshot()`` at the last committed step ``NNNNNNNN``: everything a
    bit-for-bit continuation needs (also what ``fields`` leaves out).
``manifest.json``
    The commit record (``io.manifest``): fingerprint of the system and settings, the
    number of committed saved steps, the checkpoint's name and SHA-256, the status.

**Crash consistency.** A commit (every ``chunk`` saved steps, and at the end of the run
whatever ended it) appends the steps to the Zarr arrays, then writes the checkpoint, then
the manifest; every file is written to a temporary name, flushed to disk and renamed
(``io.atomic``).  The manifest is written last, so a writer stopped at any moment (signal,
full disk, power cut) leaves a directory whose manifest describes complete data: readers
use the first ``saved`` steps of the arrays and ignore anything a broken commit appended
after them, and a continued run first truncates the arrays to ``saved``.  The Zarr writes
go through zarr directly rather than ``Dataset.to_zarr(append_dim=...)`` for that reason:
the order of the writes (arrays, consolidated metadata, checkpoint, manifest) is ours, and
so is the repair before a continuation; xarray reads the result (``open_zarr``), and its
consolidated metadata (rewritten at each commit, after the arrays) shows it only complete
commits too.  While the run goes, ``SIGTERM`` and ``SIGHUP`` end it like Ctrl-C (then
``finish`` commits the pending steps), and signals wait until a commit is complete
(``io.signals``).
"""

import asyncio
import hashlib
import io
import json
import shutil
import time
import warnings
from collections.abc import Callable
from contextlib import ExitStack
from dataclasses import dataclass, field
from pathlib import Path
from typing import NamedTuple

import numpy as np

from ..contract import Observer
from ..result import ENERGIES, FIELDS, Result, settings_array, step_record
from . import lock, signals
from .atomic import atomic_store, is_temporary, remove_temporaries, write_atomic
from .fingerprint import outline, settings_fingerprint, system_fingerprint
from .jsonable import jsonable
from .labels import POSITION, Points, dof_labels, multiplier_labels
from .manifest import (
    MANIFEST,
    RunExists,
    StoreCorrupt,
    StoreError,
    StoreMismatch,
    read_manifest,
    write_manifest,
)

#: The Zarr group of a run directory.
STORE = "results.zarr"

#: Fields stored by default (``result.FIELDS`` but the accelerations ``a``).
DEFAULT_FIELDS = ("t", "q", "v", "lam", "iterations") + ENERGIES

#: Solver counters stored at every saved step (variables ``stat_<name>``).
COUNTERS = ("steps", "rejected", "newton", "factorizations")

#: The files of the format before the Zarr store (read by ``Result.load``).
LEGACY_CHECKPOINT = "checkpoint.npz"
LEGACY_CHUNKS = "chunk_*.npz"

_VARIABLE = {"t": "time"}  # field -> variable name where they differ
_FIELD = {"time": "t"}

_DOF_COORDS = ("dof_body", "dof_node", "dof_component", "dof_label")
_MULTIPLIER_COORDS = ("constraint", "equation")

#: CF-style attributes of the variables and coordinates (``units`` as UDUNITS strings).
_ATTRS = {
    "time": {"standard_name": "time", "long_name": "time", "units": "s", "axis": "T"},
    "step": {"long_name": "step number (0: the initial state)", "units": "1"},
    "q": {"long_name": "generalized coordinates",
          "comment": "positions in m, slopes in 1 (dof_component x y z or dx dy dz)"},
    "v": {"long_name": "generalized velocities (time derivatives of q)",
          "comment": "m s-1 for positions, s-1 for slopes"},
    "a": {"long_name": "generalized accelerations (second time derivatives of q)",
          "comment": "m s-2 for positions, s-2 for slopes"},
    "lam": {"long_name": "Lagrange multipliers (constraint reactions)"},
    "r": {"long_name": "position of the body's points (cable nodes, rigid base points)",
          "units": "m"},
    "iterations": {"long_name": "Newton iterations of the step", "units": "1"},
    **{e: {"long_name": f"{e.replace('_', ' ')} energy", "units": "J"} for e in ENERGIES},
    **{"stat_" + c: {"long_name": f"{c} so far (solver counter)", "units": "1"}
       for c in COUNTERS},
    "body": {"long_name": "body (System.bodies, name)"},
    "node": {"long_name": "point of the body (cable node, rigid base point)", "units": "1"},
    "component": {"long_name": "Cartesian component (inertial frame)"},
    "s": {"long_name": "reference arc length of the cable node", "units": "m"},
    "dof_body": {"long_name": "body of the coordinate"},
    "dof_node": {"long_name": "point of the body the coordinate belongs to (-1: none)",
                 "units": "1"},
    "dof_component": {"long_name": "component of the coordinate (x y z: position, dx dy "
                                   "dz: slope, else the body's name of it)"},
    "dof_label": {"long_name": "the body's description of the coordinate"},
    "constraint": {"long_name": "constraint of the multiplier"},
    "equation": {"long_name": "equation of the constraint"},
}

#: The coordinates written once, at creation, along each dimension of the variables
#: (xarray shows them through each variable's ``coordinates`` attribute).
_COORDINATES = {"dof": _DOF_COORDS, "multiplier": _MULTIPLIER_COORDS, "node": ("s",)}


def chunk_name(k):
    """File name of the ``k``-th chunk of the old format."""
    return f"chunk_{k:05d}.npz"


def checkpoint_name(index):
    """File name of the checkpoint at step ``index``."""
    return f"checkpoint_{int(index):08d}.npz"


def check_fields(fields):
    """``fields`` (names of ``result.FIELDS``, None for ``DEFAULT_FIELDS``) as a tuple in
    the order of ``FIELDS``, with ``t``."""
    if fields is None:
        return DEFAULT_FIELDS
    if isinstance(fields, str):
        fields = [fields]
    unknown = [f for f in fields if f not in FIELDS]
    if unknown:
        raise ValueError(f"unknown field {unknown[0]!r}: fields are {', '.join(FIELDS)}")
    return tuple(f for f in FIELDS if f in fields or f == "t")


def _layout(system):
    """Attributes describing the coordinates and multipliers of ``system``."""
    bodies, offset = [], 0
    for body in system.bodies:
        bodies.append({"name": getattr(body, "name", None), "class": type(body).__name__,
                       "first_dof": offset, "n_dofs": int(body.n_dofs)})
        offset += body.n_dofs
    constraints, k = [], 0
    for c in system.constraints:
        constraints.append({"name": c.name, "first": k, "n_eq": int(c.n_eq),
                            "labels": list(getattr(c, "labels", []))})
        k += c.n_eq
    return {"bodies": bodies, "constraints": constraints}


class _Variable(NamedTuple):
    """A variable of the store: the record ``key`` its values come from, its ``dims``,
    the ``tail`` of its shape after ``time``, its ``dtype``, for a variable derived
    from another ``derive`` (the block of ``key`` to the block of this variable), and
    its Zstandard ``level``."""

    key: str
    dims: tuple
    tail: tuple
    dtype: str
    derive: Callable | None = None
    level: int = 5

    def block(self, records):
        """The values of the saved steps ``records``, ``(len(records), *tail)``."""
        values = np.asarray([r[self.key] for r in records], dtype=self.dtype)
        if self.derive is not None:
            return self.derive(values)
        return values.reshape(len(records), *self.tail)


def _variables(system, fields):
    """``{variable: _Variable}`` of a store; the positions ``r`` (``labels.Points``) come
    with ``q``."""
    n, m = system.n_dofs, system.n_constraints
    spec = {"time": _Variable("t", ("time",), (), "float64"),
            "step": _Variable("index", ("time",), (), "int64")}
    for f in fields:
        if f in ("q", "v", "a"):
            spec[f] = _Variable(f, ("time", "dof"), (n,), "float64")
        elif f == "lam":
            spec[f] = _Variable(f, ("time", "multiplier"), (m,), "float64")
        elif f == "iterations":
            spec[f] = _Variable(f, ("time",), (), "int64")
        elif f != "t":
            spec[f] = _Variable(f, ("time",), (), "float64")
    points = Points(system)
    if "q" in fields and points:  # q's positions again: level 1, a third of the time
        spec["r"] = _Variable("q", ("time", "body", "node", "component"),
                              points.index.shape, "float64", points.positions, level=1)
    for c in COUNTERS:
        spec["stat_" + c] = _Variable("stat_" + c, ("time",), (), "int64")
    return spec


def _coordinates(system, variables):
    """``{name: (dims, values)}`` of the labels of the dimensions of ``variables``:
    written once, when the store is created."""
    dims = {d for var in variables.values() for d in var.dims}
    out = {}
    if "dof" in dims:
        out.update({"dof_" + k: (("dof",), v) for k, v in dof_labels(system).items()})
    if "multiplier" in dims:
        out.update({k: (("multiplier",), v) for k, v in multiplier_labels(system).items()})
    if "body" in dims:
        points = Points(system)
        out.update(body=(("body",), np.array(points.bodies, dtype=str)),
                   node=(("node",), np.arange(points.index.shape[1])),
                   component=(("component",), np.array(POSITION, dtype=str)),
                   s=(("body", "node"), points.arc_length))
    return out


def _coordinate_names(dims):
    """The ``coordinates`` attribute of a variable of ``dims`` (CF: its labels)."""
    return " ".join(c for d in dims for c in _COORDINATES.get(d, ()))


def _codecs(ndim, level=5):
    """``(filters, compressors)`` of an array of ``ndim`` dimensions, time first."""
    from zarr.codecs import BloscCodec, Crc32cCodec, TransposeCodec

    if ndim >= 2:  # each coordinate's history together: ~1.3x better than row order
        return ([TransposeCodec(order=(*range(1, ndim), 0))],
                [BloscCodec(cname="zstd", clevel=level, shuffle="bitshuffle"), Crc32cCodec()])
    return [], [BloscCodec(cname="zstd", clevel=level, shuffle="shuffle"), Crc32cCodec()]


def _sync(coro):
    """Run a zarr coroutine on zarr's event loop (consolidated-metadata warnings off:
    zarr-python reads and writes it; other v3 readers ignore it)."""
    from zarr.core.sync import sync

    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message=".*[Cc]onsolidated metadata")
        return sync(coro)


async def _gather(coros):
    """Await all of ``coros`` (none is left running), then raise the first failure."""
    results = await asyncio.gather(*coros, return_exceptions=True)
    for r in results:
        if isinstance(r, BaseException):
            raise r
    return results


#: Write every chunk, also one that holds only the fill value (zarr skips those by
#: default): a committed step always has its chunk file, so a missing file is damage.
_WRITE_ALL = {"write_empty_chunks": True}


async def _create_group(root, system, variables, chunk, attrs):
    import zarr.api.asynchronous as za

    store = atomic_store(root)
    group = await za.open_group(store=store, mode="w", zarr_format=3, attributes=attrs)
    arrays = {}
    for name, var in variables.items():
        filters, compressors = _codecs(len(var.dims), var.level)
        fill = np.nan if var.dtype == "float64" else 0
        attributes = dict(_ATTRS.get(name, {}))
        if _coordinate_names(var.dims):
            attributes["coordinates"] = _coordinate_names(var.dims)
        arrays[name] = await group.create_array(
            name, shape=(0, *var.tail), chunks=(chunk, *(max(s, 1) for s in var.tail)),
            dtype=var.dtype, fill_value=fill, dimension_names=var.dims, filters=filters,
            compressors=compressors, attributes=attributes)
        arrays[name] = arrays[name].with_config(_WRITE_ALL)
    await _gather([_write_coordinate(group, name, dims, values) for name, (dims, values)
                   in _coordinates(system, variables).items()])
    await za.consolidate_metadata(store)
    return arrays


async def _write_coordinate(group, name, dims, values):
    """Create and fill the array ``name`` of the labels ``values`` (written once)."""
    strings = values.dtype.kind in "UT"
    fill = "" if strings else np.nan if values.dtype.kind == "f" else -1
    arr = await group.create_array(
        name, shape=values.shape, chunks=tuple(max(s, 1) for s in values.shape),
        dtype=str if strings else values.dtype, fill_value=fill, dimension_names=dims,
        attributes=_ATTRS.get(name, {}))
    if values.size:
        await arr.with_config(_WRITE_ALL).setitem(..., values)


async def _open_arrays(root, names, saved):
    """The arrays ``names`` of the store at ``root``, truncated to ``saved`` steps (what a
    broken commit appended is dropped)."""
    import zarr.api.asynchronous as za

    store = atomic_store(root)
    group = await za.open_group(store=store, mode="r+", use_consolidated=False)
    arrays = {}
    for name in names:
        arr = await group.getitem(name)
        if arr.shape[0] < saved:
            raise StoreCorrupt(f"{root / name} has {arr.shape[0]} steps but the manifest "
                               f"committed {saved}: the store was damaged after the run",
                               root / name)
        if arr.shape[0] != saved:
            await arr.resize((saved, *arr.shape[1:]))
        arrays[name] = arr.with_config(_WRITE_ALL)
    await za.consolidate_metadata(store)
    return arrays


async def _append(root, arrays, start, blocks):
    import zarr.api.asynchronous as za

    async def one(arr, block):
        stop = start + len(block)
        await arr.resize((stop, *arr.shape[1:]))
        await arr.setitem(slice(start, stop), block)

    await _gather([one(arrays[name], block) for name, block in blocks.items()])
    await za.consolidate_metadata(atomic_store(root))


def store_files(run_dir):
    """The files and folders of the store (new and old format) present in ``run_dir``."""
    run_dir = Path(run_dir)
    found = [run_dir / n for n in (MANIFEST, STORE, LEGACY_CHECKPOINT)
             if (run_dir / n).exists()]
    found += sorted(run_dir.glob("checkpoint_*.npz")) + sorted(run_dir.glob(LEGACY_CHUNKS))
    return found


def remove_store(run_dir):
    """Remove the store of ``run_dir`` (manifest first, so that a half-removed store is no
    store), its checkpoints, old-format chunks and temporary files."""
    run_dir = Path(run_dir)
    for path in store_files(run_dir):
        if path.is_dir():
            shutil.rmtree(path)
        else:
            path.unlink(missing_ok=True)
    for path in run_dir.glob("*"):
        if (path.is_file() and path.name.startswith(("manifest.json", "checkpoint"))
                and is_temporary(path)):
            path.unlink(missing_ok=True)


def is_legacy(run_dir):
    """True when ``run_dir`` holds a store of the old format (``chunk_*.npz``,
    ``checkpoint.npz``) and no manifest."""
    run_dir = Path(run_dir)
    return (not (run_dir / MANIFEST).exists()
            and ((run_dir / LEGACY_CHECKPOINT).exists() or any(run_dir.glob(LEGACY_CHUNKS))))


def describe_run(manifest):
    """A run's manifest in a few words: scene, saved steps, last time, status."""
    last = manifest.get("last") or {}
    text = f"{manifest.get('saved', 0)} saved steps"
    if last.get("t") is not None:
        text += f" up to t = {last['t']:.6g} s"
    scene = (manifest.get("attrs") or {}).get("scene")
    if scene:
        text = f"scene {scene!r}, " + text
    return f"{text}, {manifest.get('status', '?')}"


class RunStore(Observer):
    """Writes the saved steps of a run into the run directory ``path`` as it goes: a
    Zarr store ``results.zarr`` (appended every ``chunk`` saved steps), a checkpoint and
    the manifest, so that an interrupted run keeps every step up to its last commit and
    ``resume(path)`` continues it bit for bit.

    At the end of the run, whatever ended it (an error, Ctrl-C, ``SIGTERM``), the pending
    steps and a checkpoint are committed.  While the run goes, ``SIGTERM`` and ``SIGHUP``
    raise ``io.signals.Terminated`` (a ``KeyboardInterrupt``) in the main thread, and
    signals wait for a commit to complete.  From ``start`` to ``finish`` the store holds
    the lock of its run directory (``io.lock``): a second writer is refused
    (``RunLocked``).  The manifest's ``wall_time`` adds up the sessions of the run.

    Parameters
    ----------
    path : path
        Run directory (created at the start of the run).
    chunk : int
        Saved steps per commit (and per Zarr chunk).
    fields : sequence of str, optional
        The fields of ``result.FIELDS`` to store (``t`` always); default
        ``DEFAULT_FIELDS``, all but the accelerations ``a``.  Fields left out read back as
        NaN (``iterations``: -1); the checkpoint always holds the full state.
    overwrite : bool
        A new run replaces a store already in ``path``; otherwise that is an error
        (``RunExists``).
    source : path, optional
        For a resumed run whose ``path`` holds no store: the run directory the run was
        resumed from, whose store is copied first (so that ``path`` holds the whole run).
    attrs : dict, optional
        Attributes of the store and the manifest (the runner records the scene and its
        parameters).
    handle_signals : bool
        Turn ``SIGTERM``/``SIGHUP`` into ``Terminated`` while the run goes.

    A resumed run (``simulate(resume=...)``) continues the store of ``path`` only when its
    fingerprint (``io.fingerprint``: system and solver settings) matches, the run was
    resumed from its last commit, that commit's last step is the checkpoint's and
    ``t_end`` does not end before it; otherwise ``StoreMismatch``/``StoreError``.

    Examples
    --------
    >>> sc.simulate(system, 10.0, 1e-3, observers=[RunStore("runs/a")])  # doctest: +SKIP
    >>> sc.simulate(system, 10.0, 1e-3, resume=RunStore.resume("runs/a"),  # doctest: +SKIP
    ...             observers=[RunStore("runs/a")])
    """

    def __init__(self, path, chunk=200, fields=None, overwrite=False, source=None,
                 attrs=None, handle_signals=True):
        if int(chunk) != chunk or chunk < 1:
            raise ValueError(f"chunk must be a positive integer, got {chunk!r}")
        self.path = Path(path)
        self.chunk = int(chunk)
        self.fields = check_fields(fields)
        self.overwrite = bool(overwrite)
        self.source = None if source is None else Path(source)
        self.attrs = dict(attrs or {})
        self.handle_signals = handle_signals
        self.pending = []  # [record, checkpoint or None]: the last one has its checkpoint
        self.committed = 0
        self.manifest = None
        self._arrays = None
        self._graceful = False
        self._lock = ExitStack()
        self._clock = (0.0, 0.0)  # (perf_counter at start, wall time of earlier sessions)

    @property
    def root(self):
        """The Zarr store ``path/results.zarr``."""
        return self.path / STORE

    # --- the observer ------------------------------------------------------------------
    def start(self, run):
        self.pending, self._arrays = [], None
        self._clock = (time.perf_counter(), 0.0)
        self._graceful = self.handle_signals and signals.install_graceful()
        try:
            self._lock.enter_context(lock.hold(self.path))
            with signals.deferred():
                self._open(run)
        except BaseException as err:
            self._release()
            if isinstance(err, OSError) and not hasattr(err, "result"):
                _set_result(err, Result(run.system, _empty_records(run.system, 0),
                                        dict(run.stats)))
            raise

    def saved(self, run, step):
        record = step_record(step)
        record["index"] = step.index
        for c in COUNTERS:
            record["stat_" + c] = run.stats.get(c, 0)
        snap = run.integrator.snapshot()
        snap.update(index=step.index, settings=settings_array(run.settings),
                    **{"stat_" + k: v for k, v in run.stats.items()})
        # one append: the record and the checkpoint of its step never part (a Ctrl-C
        # between two statements would otherwise store a step its checkpoint precedes)
        self.pending.append([record, snap])
        if len(self.pending) > 1:
            self.pending[-2][1] = None
        if len(self.pending) >= self.chunk:
            self.flush()

    def finish(self, run, error):
        try:
            with signals.deferred(deliver=error is None):
                if self.pending:
                    self._commit()
                if self.manifest is not None:
                    self._close(run, error)
        except Exception as exc:
            self._on_failure(run, error, exc)
            raise
        finally:
            self._release()
        if error is not None and not hasattr(error, "result"):
            _set_result(error, self._partial_result(run))
        if error is not None:
            _add_note(error, f"run store {self.path}: {describe_run(self.manifest)}")

    # --- commits -----------------------------------------------------------------------
    def flush(self):
        """Commit the pending steps: append them to the arrays, write their checkpoint,
        then the manifest (signals wait until it is done)."""
        if self.pending:
            with signals.deferred():
                self._commit()

    def _commit(self):
        records = [r for r, _ in self.pending]
        snap = self.pending[-1][1]
        start, stop = self.committed, self.committed + len(records)
        blocks = {name: var.block(records) for name, var in self.variables.items()}
        _sync(_append(self.root, self._arrays, start, blocks))
        index, t = int(records[-1]["index"]), float(records[-1]["t"])
        buf = io.BytesIO()
        np.savez_compressed(buf, **snap, n_saved=stop)
        data = buf.getvalue()
        name = checkpoint_name(index)
        write_atomic(self.path / name, data)
        previous = (self.manifest.get("checkpoint") or {}).get("file")
        manifest = dict(self.manifest, saved=stop, commits=self.manifest["commits"] + 1,
                        last={"index": index, "t": t}, status="running", message=None,
                        wall_time=self._wall_time(),
                        checkpoint={"file": name, "index": index, "t": t, "bytes": len(data),
                                    "sha256": hashlib.sha256(data).hexdigest()})
        if start == 0:
            manifest["first"] = {"index": int(records[0]["index"]), "t": float(records[0]["t"])}
        self.manifest = write_manifest(self.path, manifest)
        self.committed = stop
        self.pending = []
        if previous and previous != name:
            (self.path / previous).unlink(missing_ok=True)

    def _close(self, run, error):
        sig = signals.interrupt_signal(error)
        if error is None:
            status, message = ("stopped", run.stop_reason) if run.stop_reason else ("complete",
                                                                                   None)
        elif sig is not None:
            status, message = "interrupted", f"interrupted by {signals.signal_name(sig)}"
        else:
            status, message = "failed", f"{type(error).__name__}: {error}"
        self.manifest = write_manifest(self.path, dict(self.manifest, status=status,
                                                       message=message,
                                                       wall_time=self._wall_time()))

    def _wall_time(self):
        """Wall time of the run so far (s): this session's and the earlier ones'."""
        started, before = self._clock
        return before + time.perf_counter() - started

    def _on_failure(self, run, error, exc):
        """``finish`` could not commit (a full disk): say where the steps are."""
        held = len(self.pending)
        note = (f"run store {self.path}: {describe_run(self.manifest or {})}; the "
                f"{held} saved steps after them could not be written ({exc})"
                + ("; they are in the exception's result" if held else ""))
        target = error if error is not None else exc
        if not hasattr(target, "result"):
            _set_result(target, self._partial_result(run))
        _add_note(target, note)
        remove_temporaries(self.root)
        if self.manifest is not None:  # a checkpoint written before the manifest failed
            self._remove_stale_checkpoints(self.manifest)

    def _partial_result(self, run):
        """The committed steps (read back) and the pending ones (in memory)."""
        try:
            records = (_read_records(self.path, run.system, self.manifest)
                       if self.manifest else _empty_records(run.system, 0))
        except Exception:
            records = _empty_records(run.system, 0)
        if self.pending:
            extra = _fill(run.system, {k: [r[k] for r, _ in self.pending] for k in FIELDS},
                          FIELDS, len(self.pending))
            records = {k: np.concatenate([records[k], extra[k]]) for k in FIELDS}
        return Result(run.system, records, dict(run.stats))

    def _release(self):
        self._lock.close()
        if self._graceful:
            signals.uninstall_graceful()
            self._graceful = False

    # --- opening -----------------------------------------------------------------------
    def _open(self, run):
        self.path.mkdir(parents=True, exist_ok=True)
        self.variables = _variables(run.system, self.fields)
        fp = {"system": system_fingerprint(run.system),
              "settings": settings_fingerprint(run.settings)}
        fp["run"] = hashlib.sha256((fp["system"] + fp["settings"]).encode()).hexdigest()
        settings = jsonable(run.settings)
        if run.resumed:
            manifest = self._existing(run)
            check_fingerprint(self.path, manifest, run.system, run.settings)
            last = manifest.get("checkpoint") or {}
            if last.get("t") != run.integrator.t:
                raise StoreError(
                    f"{self.path} holds a run whose last commit is at t = {last.get('t')} s, "
                    f"but the run was resumed at t = {run.integrator.t} s: resume it from "
                    f"that directory (resume({str(self.path)!r}))")
            check_last_commit(self.path, manifest)
            check_t_end(self.path, manifest, run.settings["t_end"])
            stored = tuple(name for name in manifest["variables"])
            self.variables = {k: v for k, v in _variables(run.system, FIELDS).items()
                              if k in stored}
            self.fields = tuple(_FIELD.get(k, k) for k in stored if _FIELD.get(k, k) in FIELDS)
            remove_temporaries(self.path)
            self._remove_stale_checkpoints(manifest)
            self._arrays = _sync(_open_arrays(self.root, list(self.variables),
                                              manifest["saved"]))
            self.committed = manifest["saved"]
            self._clock = (self._clock[0], manifest.get("wall_time", 0.0))
            self.manifest = write_manifest(self.path, dict(manifest, settings=settings,
                                                           status="running", message=None))
            return
        if store_files(self.path):
            if not self.overwrite:
                old = run_info(self.path)
                what = describe_run(old) if old else "an earlier run's files"
                raise RunExists(f"{self.path} already holds a run ({what}): write the new "
                                "run elsewhere, replace it (overwrite=True, --overwrite) or "
                                "continue it (resume, --resume)")
            remove_store(self.path)
        # the manifest first: from now on the directory holds a run (of no steps yet)
        manifest = {"fingerprint": fp, "system": outline(run.system), "settings": settings,
                    "n_dofs": run.system.n_dofs, "n_constraints": run.system.n_constraints,
                    "fields": list(self.fields), "variables": list(self.variables),
                    "store": STORE, "chunk": self.chunk, "saved": 0, "first": None,
                    "last": None, "checkpoint": None, "status": "running", "message": None,
                    "attrs": jsonable(self.attrs), "commits": 0, "wall_time": 0.0,
                    "created": time.strftime("%Y-%m-%dT%H:%M:%S%z")}
        self.manifest = write_manifest(self.path, manifest)
        attrs = {"title": "skfem_cable run", **jsonable(self.attrs),
                 "settings": settings, "fingerprint": fp, **_layout(run.system)}
        self._arrays = _sync(_create_group(self.root, run.system, self.variables, self.chunk,
                                           attrs))
        self.committed = 0

    def _existing(self, run):
        """The manifest of the store that a resumed run continues (copied from
        ``source`` when ``path`` has none)."""
        manifest = read_manifest(self.path)
        if manifest is not None:
            return manifest
        if is_legacy(self.path):
            raise StoreError(_LEGACY_RESUME.format(path=self.path))
        if self.source is not None and self.source.resolve() != self.path.resolve():
            return copy_store(self.source, self.path)
        raise StoreError(f"{self.path} holds no stored run to continue: continue a run in "
                         "the directory it was stored in, or give the directory it was "
                         "resumed from as source (io.run_observers(path, restart=True, "
                         "source=...)) to copy its steps first")

    def _remove_stale_checkpoints(self, manifest):
        keep = (manifest.get("checkpoint") or {}).get("file")
        for p in self.path.glob("checkpoint_*.npz"):
            if p.name != keep:
                p.unlink(missing_ok=True)

    @staticmethod
    def resume(path):
        """What ``simulate(resume=...)`` needs to continue the run stored in ``path``."""
        return resume(path)


_LEGACY_RESUME = ("{path} is a run directory of the old format (chunk_*.npz, "
                  "checkpoint.npz): Result.load reads it, but this version cannot continue "
                  "it; run it again into a new directory (or with --overwrite)")


def _set_result(error, result):
    try:
        error.result = result
    except (AttributeError, TypeError):
        pass


def _add_note(error, note):
    if hasattr(error, "add_note"):  # Python >= 3.11
        error.add_note(note)


def copy_store(source, path):
    """Copy the committed store of the run directory ``source`` into ``path`` (arrays,
    checkpoint, then the manifest); returns the copied manifest."""
    source, path = Path(source), Path(path)
    manifest = read_manifest(source)
    if manifest is None:
        raise StoreError(f"{source} holds no stored run (no {MANIFEST}) to copy")
    ck = manifest.get("checkpoint")
    if ck is None:
        raise StoreError(f"{source} has no checkpoint yet: nothing to continue")
    data = _checkpoint_bytes(source, manifest)
    path.mkdir(parents=True, exist_ok=True)
    if (path / STORE).exists():
        shutil.rmtree(path / STORE)
    shutil.copytree(source / STORE, path / STORE,
                    ignore=lambda d, names: [n for n in names if ".tmp-" in n
                                             or n.endswith(".partial")])
    write_atomic(path / ck["file"], data)
    return write_manifest(path, dict(manifest, copied_from=str(source)))


def check_fingerprint(path, manifest, system, settings=None):
    """Raise ``StoreMismatch`` unless the store of ``path`` (its ``manifest``) was written
    by ``system`` (and with ``settings``, when given)."""
    fp = manifest.get("fingerprint") or {}
    if fp.get("system") != system_fingerprint(system):
        raise StoreMismatch(
            f"{path} was written by another system: stored {manifest.get('system')}; "
            f"given {outline(system)}"
            + ("" if manifest.get("system") != outline(system) else
               " (same bodies and sizes: sections, masses, constraints or loads differ)")
            + ": load or continue it with the system that wrote it (or write a new run)")
    if settings is not None and fp.get("settings") != settings_fingerprint(settings):
        stored = manifest.get("settings") or {}
        given = jsonable(settings)
        differ = [k for k in sorted(set(stored) | set(given))
                  if k not in ("t_end", "n_steps") and stored.get(k) != given.get(k)]
        details = ", ".join(f"{k}: stored {stored.get(k)!r}, given {given.get(k)!r}"
                            for k in differ) or "they differ"
        raise StoreMismatch(f"{path} was run with other solver settings ({details}): "
                            "continue it with the settings it was started with")


def check_t_end(path, manifest, t_end):
    """Raise ``StoreError`` when the store of ``path`` (its ``manifest``) holds steps after
    ``t_end``: a resumed run only continues, it cannot end before its stored data."""
    last = manifest.get("last") or {}
    if last.get("t") is not None and t_end < last["t"]:
        raise StoreError(f"{path} holds the run up to t = {last['t']:.6g} s "
                         f"({manifest['saved']} saved steps); a continuation cannot end "
                         f"before that (t_end = {t_end:.6g} s): give --t-end {last['t']:.6g} "
                         "or later, or read the steps up to the time wanted from the store "
                         "(Result.load, xarray.open_zarr)")


def check_last_commit(path, manifest):
    """Raise ``StoreCorrupt`` unless the last of the ``saved`` steps the manifest of
    ``path`` commits is the step of its checkpoint, in the arrays themselves: the
    continuation appends after that step, so any other would leave a gap or a repeat in
    the data (a manifest edited or damaged after the run)."""
    ck, n = manifest.get("checkpoint"), manifest["saved"]
    if ck is None:
        return
    path = Path(path)
    file = path / MANIFEST
    try:
        arrays = _sync(_read_last(path / STORE, n))
    except Exception as err:
        raise StoreCorrupt(f"{path / STORE} cannot be read at the last committed step "
                           f"({type(err).__name__}: {err})", path / STORE) from err
    if arrays != (ck["index"], ck["t"]):
        step, t = arrays
        raise StoreCorrupt(
            f"{file} commits {n} saved steps, the last at step {step} (t = {t:.6g} s), but "
            f"its checkpoint {ck['file']} is at step {ck['index']} (t = {ck['t']:.6g} s): "
            "continuing would leave a gap or a repeat in the data.  The manifest was edited "
            "or damaged after the run: restore it (its 'saved' and 'last' must describe the "
            "store); the steps themselves still load", file)


async def _read_last(root, n):
    """``(step, time)`` of the ``n``-th step of the store ``root``."""
    import zarr.api.asynchronous as za

    group = await za.open_group(store=atomic_store(root, read_only=True), mode="r",
                                use_consolidated=False)
    arrays = await _gather([group.getitem("step"), group.getitem("time")])
    held = min(a.shape[0] for a in arrays)
    if not 1 <= n <= held:
        raise ValueError(f"the arrays hold {held} steps, the manifest commits {n}")
    step, t = await _gather([a.getitem(n - 1) for a in arrays])
    return int(step), float(t)


# --- reading ------------------------------------------------------------------------------
@dataclass
class Resume:
    """A stored run to continue: ``snapshot`` (the checkpoint: integrator state,
    ``index``, ``settings``, ``stat_*``), ``records`` (the saved steps, a dict of arrays
    keyed by ``result.FIELDS``; fields the store left out are NaN), the run directory
    ``path`` and its ``manifest``."""

    snapshot: dict
    records: dict
    path: Path | None = None
    manifest: dict = field(default_factory=dict)


def _empty_records(system, n):
    return _fill(system, {}, (), n)


def _fill(system, records, stored, n):
    """``records`` with every field of ``FIELDS``: those not ``stored`` are NaN
    (``iterations``: -1)."""
    shapes = {"q": (system.n_dofs,), "v": (system.n_dofs,), "a": (system.n_dofs,),
              "lam": (system.n_constraints,)}
    out = {}
    for name in FIELDS:
        if name in stored:
            out[name] = np.asarray(records[name])
            if name in shapes:
                out[name] = out[name].reshape(n, *shapes[name])
        elif name == "iterations":
            out[name] = np.full(n, -1, dtype=np.int64)
        else:
            out[name] = np.full((n, *shapes.get(name, ())), np.nan)
    return out


def _chunk_file(root, name, k):
    """The file of the ``k``-th time chunk of the array ``name``."""
    folder = root / name / "c" / str(k)
    return folder / "0" if folder.is_dir() else folder


def _missing_chunk(root, name, chunk, n):
    """``(file, "is missing")`` for the first chunk of the committed steps of ``name``
    that has no file (Zarr would read it as fill values), or None."""
    meta = root / name / "zarr.json"
    if not meta.is_file():
        return meta, "is missing"
    try:
        if 0 in json.loads(meta.read_text())["shape"][1:]:
            return None  # no coordinates (a system without constraints): no chunks
    except (ValueError, KeyError, TypeError) as err:
        return meta, f"is corrupt ({type(err).__name__}: {err})"
    for k in range(-(-n // chunk)):
        file = _chunk_file(root, name, k)
        if not file.is_file():
            return file, "is missing"
    return None


def _undecodable_chunk(root, name, chunk, n):
    """``(file, reason)`` of the first chunk of ``name`` that cannot be decoded, or
    None."""
    import zarr

    try:
        arr = zarr.open_array(root / name, mode="r")
    except Exception as err:
        return root / name / "zarr.json", f"cannot be read ({type(err).__name__}: {err})"
    for k in range(-(-n // chunk)):
        try:
            arr[k * chunk:min((k + 1) * chunk, n)]
        except Exception as err:
            return _chunk_file(root, name, k), f"cannot be decoded ({type(err).__name__}: {err})"
    return None


def _open_dataset(root):
    """The store ``root`` as a lazy ``xarray.Dataset``.  Without its consolidated metadata
    (``zarr.json`` lost its list of the arrays) it is read from the arrays' own metadata,
    and the consolidated metadata is written again (``repair_metadata``)."""
    import xarray as xr

    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message=".*[Cc]onsolidated metadata")
        try:
            return xr.open_zarr(root, consolidated=True, chunks=None)
        except Exception:
            ds = xr.open_zarr(root, consolidated=False, chunks=None)
    repair_metadata(root)
    return ds


def repair_metadata(root):
    """Write the consolidated metadata of the store ``root`` again, from its arrays
    (with a ``RuntimeWarning``), unless a run holds its directory (that run writes it at
    its next commit) or it cannot be written (a read-only directory: readers fall back
    on the arrays' metadata)."""
    import zarr.api.asynchronous as za

    try:
        with lock.hold(Path(root).parent):
            _sync(za.consolidate_metadata(atomic_store(root)))
    except (StoreError, OSError):
        return
    warnings.warn(f"{root}/zarr.json had lost its consolidated metadata (the list of the "
                  "arrays that xarray.open_zarr reads first); the arrays were read without "
                  "it and it was written again", RuntimeWarning, stacklevel=3)


def open_dataset(path):
    """The committed steps of the run directory ``path`` as an ``xarray.Dataset`` (lazy:
    nothing is read until used), with the manifest in ``attrs["manifest"]``.

    ``xarray.open_zarr(path / "results.zarr")`` gives the same Dataset, except after a
    writer was killed in the middle of a commit (then it may show that commit's steps
    too)."""
    path = Path(path)
    manifest = _manifest_or_raise(path)
    n = manifest["saved"]
    try:
        ds = _open_dataset(path / STORE)
    except Exception as err:
        raise _unopenable(path / STORE, err) from err
    ds = ds.isel(time=slice(0, n))
    ds.attrs["manifest"] = manifest
    return ds


def _unopenable(root, err):
    """The ``StoreCorrupt`` of a store ``root`` that does not open, even from its arrays'
    own metadata."""
    return StoreCorrupt(f"{root} cannot be opened, neither from its consolidated metadata "
                        f"nor from its arrays' ({type(err).__name__}: {err}): its metadata "
                        "(zarr.json files) is damaged; restore it from a backup (arrays "
                        "whose zarr.json is intact still open with zarr.open_array), or "
                        "run again (--overwrite) to replace the run", root)


def _manifest_or_raise(path):
    manifest = read_manifest(path)
    if manifest is None:
        if is_legacy(path):
            raise StoreError(f"{path} is a run directory of the old format (chunk_*.npz): "
                             "read it with Result.load(path, system)")
        raise FileNotFoundError(f"no {MANIFEST} in {path}: not a run directory")
    return manifest


def _read_records(path, system, manifest):
    """The committed steps of the store in ``path`` as arrays keyed by ``FIELDS``."""
    path = Path(path)
    n = int(manifest["saved"])
    stored = [_FIELD.get(v, v) for v in manifest["variables"]]
    if n == 0:
        return _empty_records(system, 0)
    root = path / STORE
    try:
        ds = _open_dataset(root)
    except Exception as err:
        raise _unopenable(root, err) from err
    records = {}
    for name in FIELDS:
        if name not in stored:
            continue
        var = _VARIABLE.get(name, name)
        bad = _missing_chunk(root, var, int(manifest["chunk"]), n)
        if bad is None:
            try:
                values = ds[var].isel(time=slice(0, n)).values
                if values.shape[0] != n:
                    raise ValueError(f"{values.shape[0]} steps stored, {n} committed")
            except Exception as err:
                bad = (_undecodable_chunk(root, var, int(manifest["chunk"]), n)
                       or (root / var, f"cannot be read ({type(err).__name__}: {err})"))
        if bad is not None:
            raise StoreCorrupt(f"{bad[0]} {bad[1]}: the saved steps of {path} cannot be read "
                               "completely; run again (--overwrite), or continue the run "
                               "(--resume) if its checkpoint is intact", bad[0])
        records[name] = values
    return _fill(system, records, stored, n)


def _checkpoint_bytes(path, manifest):
    ck = manifest.get("checkpoint")
    if ck is None:
        raise StoreError(f"{path} has no checkpoint yet (the run was stopped before its "
                         "first commit): nothing to continue; run it again (--overwrite)")
    file = Path(path) / ck["file"]
    try:
        data = file.read_bytes()
    except FileNotFoundError:
        raise StoreCorrupt(f"{file} is missing: the run cannot be continued; its saved "
                           "steps still load (Result.load); run again (--overwrite) to "
                           "continue", file) from None
    if hashlib.sha256(data).hexdigest() != ck.get("sha256"):
        raise StoreCorrupt(f"{file} is truncated or corrupt ({len(data)} bytes, "
                           f"{ck.get('bytes')} written; its SHA-256 differs from the "
                           "manifest's): the run cannot be continued from it; its saved "
                           "steps still load (Result.load); run again (--overwrite)", file)
    return data


def read_checkpoint(path, manifest=None):
    """The checkpoint (integrator snapshot with ``index``, ``settings``, ``stat_*``) of
    the run directory ``path``, checked against the manifest's SHA-256."""
    manifest = manifest or _manifest_or_raise(Path(path))
    data = _checkpoint_bytes(path, manifest)
    with np.load(io.BytesIO(data), allow_pickle=False) as ck:
        return {k: ck[k] for k in ck.files}


def _read_legacy(path, system=None):
    """``(records, checkpoint)`` of an old-format run directory."""
    ck_file = path / LEGACY_CHECKPOINT
    if not ck_file.exists():
        raise FileNotFoundError(f"no {MANIFEST} in {path}: not a run directory")
    checkpoint = _load_npz(ck_file)
    parts = {name: [] for name in FIELDS}
    for k in range(int(checkpoint["chunks"])):
        chunk = _load_npz(path / chunk_name(k))
        for name in FIELDS:
            parts[name].append(chunk[name])
    records = {name: np.concatenate(parts[name]) if parts[name] else np.zeros(0)
               for name in FIELDS}
    if system is not None and len(records["q"]) and records["q"].shape[1] != system.n_dofs:
        raise StoreMismatch(f"{path} (old format) holds {records['q'].shape[1]} coordinates; "
                            f"the given system has {system.n_dofs}: load it with the system "
                            "that wrote it")
    return records, checkpoint


def _load_npz(file):
    try:
        with np.load(file, allow_pickle=False) as z:
            return {k: z[k] for k in z.files}
    except FileNotFoundError:
        raise StoreCorrupt(f"{file} is missing: this run directory (old format) is "
                           "incomplete and cannot be read; run the scene again", file) from None
    except Exception as err:
        raise StoreCorrupt(f"{file} is truncated or corrupt ({type(err).__name__}: {err}): "
                           "this run directory (old format) cannot be read; run the scene "
                           "again", file) from err


def read_run(path, system=None):
    """``(records, checkpoint)`` of the run directory ``path``: the committed saved steps
    (arrays keyed by ``result.FIELDS``) and the checkpoint (also of the old format).
    Without ``system``, fields the store left out are omitted from ``records``."""
    path = Path(path)
    manifest = read_manifest(path)
    if manifest is None:
        return _read_legacy(path, system)
    if system is None:
        system = _ShapeOnly(manifest)
    return _read_records(path, system, manifest), read_checkpoint(path, manifest)


class _ShapeOnly:
    """Stands for the system when reading without one (only sizes are needed)."""

    def __init__(self, manifest):
        self.n_dofs = int(manifest.get("n_dofs", 0))
        self.n_constraints = int(manifest.get("n_constraints", 0))


def resume(path, system=None):
    """The ``Resume`` of the run directory ``path`` (for ``simulate(resume=...)``).

    With ``system``, first check that the store was written by it (``StoreMismatch``
    otherwise); a ``RunStore`` observer of the continued run checks it in any case, with
    the solver settings."""
    path = Path(path)
    manifest = read_manifest(path)
    if manifest is None:
        if is_legacy(path):
            raise StoreError(_LEGACY_RESUME.format(path=path))
        raise FileNotFoundError(f"no {MANIFEST} in {path}: not a run directory")
    if system is not None:
        check_fingerprint(path, manifest, system)
    checkpoint = read_checkpoint(path, manifest)
    check_last_commit(path, manifest)
    shape = system if system is not None else _ShapeOnly(manifest)
    records = _read_records(path, shape, manifest)
    return Resume(checkpoint, records, path, manifest)


def load_result(path, system, check=True):
    """The saved steps of the run directory ``path`` as a ``Result``; ``Result.load``
    calls this.

    The store must have been written by ``system`` (its fingerprint, ``io.fingerprint``):
    otherwise ``StoreMismatch`` (``check=False`` skips the test; the sizes must still
    match).  Fields the store left out are NaN (``iterations``: -1).  ``stats``: the
    solver counters at the last saved step, ``status`` and ``stopped``.  Old run
    directories (``chunk_*.npz``) are read too."""
    path = Path(path)
    manifest = read_manifest(path)
    if manifest is None:
        records, checkpoint = _read_legacy(path, system)
        stats = {k[5:]: int(checkpoint[k]) for k in checkpoint if k.startswith("stat_")}
        return Result(system, records, stats)
    if check:
        check_fingerprint(path, manifest, system)
    elif (manifest.get("n_dofs", system.n_dofs) != system.n_dofs
          or manifest.get("n_constraints", system.n_constraints) != system.n_constraints):
        raise StoreMismatch(f"{path} holds {manifest.get('n_dofs')} coordinates and "
                            f"{manifest.get('n_constraints')} multipliers; the given system "
                            f"has {system.n_dofs} and {system.n_constraints}")
    records = _read_records(path, system, manifest)
    stats = {"status": manifest.get("status"),
             "stopped": manifest.get("message") if manifest.get("status") == "stopped"
             else None}
    if manifest["saved"]:
        stats.update(_counters(path, manifest))
    return Result(system, records, stats)


def _counters(path, manifest):
    ds = _open_dataset(Path(path) / STORE)
    n = manifest["saved"]
    return {c: int(ds["stat_" + c].isel(time=n - 1).values) for c in COUNTERS
            if "stat_" + c in ds}


def run_info(path):
    """A summary of the store in ``path`` (for messages): its manifest, or None."""
    try:
        return read_manifest(path)
    except StoreError:
        return None
