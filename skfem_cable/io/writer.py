"""Raw results of a run on disk, written as it goes: the observer ``RunStore``, which
writes the run store of a run directory (its format: ``io.schema``).

**Crash consistency.** A commit (every ``chunk`` saved steps, and at the end of the run
whatever ended it) appends the steps to the Zarr arrays, then writes the checkpoint, then
the manifest; every file is written to a temporary name, flushed to disk and renamed
(``atomic``).  The manifest is written last, so a writer stopped at any moment (signal,
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

import hashlib
import io
import shutil
import time
from contextlib import ExitStack
from pathlib import Path

import numpy as np

from ..core.protocols import Observer
from ..core.records import FIELDS, settings_array, step_record
from ..model.fingerprint import VERSION, settings_fingerprint, system_fingerprint
from ..util.atomic import is_temporary, remove_temporaries, write_atomic
from ..util.jsonable import jsonable
from . import lock, signals
from .legacy import LEGACY_CHECKPOINT, LEGACY_CHUNKS, LEGACY_RESUME, is_legacy
from .manifest import MANIFEST, RunExists, StoreCorrupt, StoreError, read_manifest, write_manifest
from .matching import check_fingerprint, outline, parts
from .reader import describe_run, empty_records, fill_records, read_records, run_info
from .resume import check_last_commit, check_t_end, copy_store, resume
from .schema import (
    ATTRS,
    COUNTERS,
    FIELD,
    STORE,
    check_fields,
    checkpoint_name,
    coordinate_names,
    coordinates,
    layout,
    variables,
)
from .zarr_store import atomic_store, consolidate, gather, sync


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
        The fields of ``records.FIELDS`` to store (``t`` always); default
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
        self._zarr = None  # (the group, its arrays by name) while the run goes
        self._graceful = False
        self._lock = ExitStack()
        self._clock = (0.0, 0.0)  # (perf_counter at start, wall time of earlier sessions)

    @property
    def root(self):
        """The Zarr store ``path/results.zarr``."""
        return self.path / STORE

    # --- the observer ------------------------------------------------------------------
    def start(self, run):
        self.pending, self._zarr = [], None
        self._clock = (time.perf_counter(), 0.0)
        self._graceful = self.handle_signals and signals.install_graceful()
        try:
            self._lock.enter_context(lock.hold(self.path))
            with signals.deferred():
                self._open(run)
        except BaseException as err:
            self._release()
            if isinstance(err, OSError) and not hasattr(err, "result"):
                _set_result(err, run.make_result(empty_records(run.system, 0),
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
        sync(_append(*self._zarr, start, blocks))
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
            records = (read_records(self.path, run.system, self.manifest)
                       if self.manifest else empty_records(run.system, 0))
        except Exception:
            records = empty_records(run.system, 0)
        if self.pending:
            extra = fill_records(run.system,
                                 {k: [r[k] for r, _ in self.pending] for k in FIELDS},
                                 FIELDS, len(self.pending))
            records = {k: np.concatenate([records[k], extra[k]]) for k in FIELDS}
        return run.make_result(records, dict(run.stats))

    def _release(self):
        self._lock.close()
        if self._graceful:
            signals.uninstall_graceful()
            self._graceful = False

    # --- opening -----------------------------------------------------------------------
    def _open(self, run):
        self.path.mkdir(parents=True, exist_ok=True)
        self.variables = variables(run.system, self.fields)
        fp = {"system": system_fingerprint(run.system),
              "settings": settings_fingerprint(run.settings), "version": VERSION}
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
            self.variables = {k: v for k, v in variables(run.system, FIELDS).items()
                              if k in stored}
            self.fields = tuple(FIELD.get(k, k) for k in stored if FIELD.get(k, k) in FIELDS)
            remove_temporaries(self.path)
            self._remove_stale_checkpoints(manifest)
            self._zarr = sync(_open_arrays(self.root, list(self.variables), manifest["saved"]))
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
        manifest = {"fingerprint": fp, "system": outline(run.system), "parts": parts(run.system),
                    "settings": settings,
                    "n_dofs": run.system.n_dofs, "n_constraints": run.system.n_constraints,
                    "fields": list(self.fields), "variables": list(self.variables),
                    "store": STORE, "chunk": self.chunk, "saved": 0, "first": None,
                    "last": None, "checkpoint": None, "status": "running", "message": None,
                    "attrs": jsonable(self.attrs), "commits": 0, "wall_time": 0.0,
                    "created": time.strftime("%Y-%m-%dT%H:%M:%S%z")}
        self.manifest = write_manifest(self.path, manifest)
        attrs = {"title": "skfem_cable run", **jsonable(self.attrs),
                 "settings": settings, "fingerprint": fp, **layout(run.system)}
        self._zarr = sync(_create_group(self.root, run.system, self.variables, self.chunk,
                                        attrs))
        self.committed = 0

    def _existing(self, run):
        """The manifest of the store that a resumed run continues (copied from
        ``source`` when ``path`` has none)."""
        manifest = read_manifest(self.path)
        if manifest is not None:
            return manifest
        if is_legacy(self.path):
            raise StoreError(LEGACY_RESUME.format(path=self.path))
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


def _set_result(error, result):
    try:
        error.result = result
    except (AttributeError, TypeError):
        pass


def _add_note(error, note):
    if hasattr(error, "add_note"):  # Python >= 3.11
        error.add_note(note)


def _codecs(ndim, level=5):
    """``(filters, compressors)`` of an array of ``ndim`` dimensions, time first."""
    from zarr.codecs import BloscCodec, Crc32cCodec, TransposeCodec

    if ndim >= 2:  # each coordinate's history together: ~1.3x better than row order
        return ([TransposeCodec(order=(*range(1, ndim), 0))],
                [BloscCodec(cname="zstd", clevel=level, shuffle="bitshuffle"), Crc32cCodec()])
    return [], [BloscCodec(cname="zstd", clevel=level, shuffle="shuffle"), Crc32cCodec()]


#: Write every chunk, also one that holds only the fill value (zarr skips those by
#: default): a committed step always has its chunk file, so a missing file is damage.
_WRITE_ALL = {"write_empty_chunks": True}


async def _create_group(root, system, variables, chunk, attrs):
    """The new group of the run store at ``root`` and its arrays by name: the
    ``variables`` (empty) and the labels (``schema.coordinates``, filled)."""
    import zarr.api.asynchronous as za

    store = atomic_store(root)
    group = await za.open_group(store=store, mode="w", zarr_format=3, attributes=attrs)
    arrays = {}
    for name, var in variables.items():
        filters, compressors = _codecs(len(var.dims), var.level)
        fill = np.nan if var.dtype == "float64" else 0
        attributes = dict(ATTRS.get(name, {}))
        if coordinate_names(var.dims):
            attributes["coordinates"] = coordinate_names(var.dims)
        arrays[name] = await group.create_array(
            name, shape=(0, *var.tail), chunks=(chunk, *(max(s, 1) for s in var.tail)),
            dtype=var.dtype, fill_value=fill, dimension_names=var.dims, filters=filters,
            compressors=compressors, attributes=attributes)
        arrays[name] = arrays[name].with_config(_WRITE_ALL)
    labels = coordinates(system, variables)
    arrays.update(zip(labels, await gather([_write_coordinate(group, name, dims, values)
                                            for name, (dims, values) in labels.items()])))
    await consolidate(group, arrays)
    return group, arrays


async def _write_coordinate(group, name, dims, values):
    """Create and fill the array ``name`` of the labels ``values`` (written once); returns
    it."""
    strings = values.dtype.kind in "UT"
    fill = "" if strings else np.nan if values.dtype.kind == "f" else -1
    arr = await group.create_array(
        name, shape=values.shape, chunks=tuple(max(s, 1) for s in values.shape),
        dtype=str if strings else values.dtype, fill_value=fill, dimension_names=dims,
        attributes=ATTRS.get(name, {}))
    if values.size:
        await arr.with_config(_WRITE_ALL).setitem(..., values)
    return arr


async def _open_arrays(root, names, saved):
    """The group of the store at ``root`` and its arrays by name, those of ``names``
    truncated to ``saved`` steps (what a broken commit appended is dropped)."""
    import zarr.api.asynchronous as za

    group = await za.open_group(store=atomic_store(root), mode="r+", use_consolidated=False)
    arrays = {name: arr async for name, arr in group.members()}
    for name in names:
        arr = arrays[name]
        if arr.shape[0] < saved:
            raise StoreCorrupt(f"{root / name} has {arr.shape[0]} steps but the manifest "
                               f"committed {saved}: the store was damaged after the run",
                               root / name)
        if arr.shape[0] != saved:
            await arr.resize((saved, *arr.shape[1:]))
        arrays[name] = arr.with_config(_WRITE_ALL)
    await consolidate(group, arrays)
    return group, arrays


async def _append(group, arrays, start, blocks):
    """Append ``blocks`` (``{name: values}``) at the step ``start`` of the ``arrays`` of
    ``group``, then write its consolidated metadata."""

    async def one(arr, block):
        stop = start + len(block)
        await arr.resize((stop, *arr.shape[1:]))
        await arr.setitem(slice(start, stop), block)

    await gather([one(arrays[name], block) for name, block in blocks.items()])
    await consolidate(group, arrays)
