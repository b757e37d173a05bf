"""Reading a run store (``io.schema``) back: ``open_dataset`` (the committed steps as a
lazy ``xarray.Dataset``), ``read_run`` (records and checkpoint), ``read_result`` (what
``Result.load`` is made of), ``read_checkpoint``, ``run_info`` and ``describe_run`` (the
manifest, for messages).

A reader uses the first ``saved`` steps of the arrays (the manifest's commit) and ignores
whatever a broken commit appended after them; a chunk that is missing (``check_chunks``,
by listing the folders: Zarr would read it as its fill value) or cannot be decoded raises
``StoreCorrupt`` naming its file.  Old run directories (``chunk_*.npz``) are read by
``io.legacy``.
"""

import hashlib
import io
import itertools
import json
import os
import warnings
from pathlib import Path

import numpy as np

from ..core.protocols import SystemView
from ..core.records import FIELDS, INPUT, OUTPUT
from ..space.reference import Reference
from . import lock
from .legacy import is_legacy, read_legacy
from .manifest import MANIFEST, StoreCorrupt, StoreError, StoreMismatch, read_manifest
from .matching import check_fingerprint
from .schema import COUNTERS, FIELD, STORE, VARIABLE
from .zarr_store import atomic_store, gather, settled, sync

#: The end of a message about a damaged store: what can still be read.
_READABLE = "the rest of the store still opens with xarray.open_zarr"

#: The end of a message about a checkpoint that cannot be continued from: the saved
#: steps are intact, so nothing advises deleting them.
_KEEP = ("its saved steps still load (Result.load): restore the file from a backup, or "
         "run the scene again into a new directory (--out) to go further")


def empty_records(system, n):
    """``n`` saved steps of no stored field (``fill_records``: all NaN, ``iterations``
    -1)."""
    return fill_records(system, {}, (), n)


def fill_records(system, records, stored, n):
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


def missing_chunks(root, saved, variables):
    """The chunk files of the store ``root`` that are missing although its manifest
    commits them: of the ``variables`` (time first) those of the first ``saved`` steps,
    of the other arrays (the labels, written once) all; before the first commit
    (``saved`` 0) none.  Zarr reads a missing chunk as its fill value (NaN, 0, -1), so a
    missing file would pass for data.  Found by listing the arrays' folders (no data is
    read); an array of ``variables`` without its ``zarr.json`` counts as missing.

    Returns
    -------
    list of Path
        The missing files (chunk files or ``zarr.json``), in order of the arrays' names.
    """
    if not saved:
        return []
    root = Path(root)
    metas = {p.parent.name: p for p in root.glob("*/zarr.json")}
    missing = [root / name / "zarr.json" for name in variables if name not in metas]
    for name in sorted(metas):
        missing += _missing_in(metas[name], saved if name in variables else None)
    return missing


def _missing_in(meta, saved):
    """The missing chunk files of the array whose metadata is ``meta``: those of its
    first ``saved`` steps, or with ``saved`` None all its chunks."""
    try:
        info = json.loads(meta.read_text())
        shape = list(info["shape"])
        chunks = info["chunk_grid"]["configuration"]["chunk_shape"]
        separator = info["chunk_key_encoding"]["configuration"]["separator"]
    except (ValueError, KeyError, TypeError) as err:
        raise StoreCorrupt(f"{meta} is corrupt ({type(err).__name__}: {err}): restore it "
                           "from a backup", meta) from err
    if saved is not None:
        shape[0] = saved
    folder = meta.parent
    present = {Path(d, f).relative_to(folder).as_posix()
               for d, _, files in os.walk(folder) for f in files}
    grid = itertools.product(*(range(-(-s // max(c, 1))) for s, c in zip(shape, chunks)))
    keys = (separator.join(["c", *map(str, index)]) for index in grid)
    return [folder / key for key in keys if key not in present]


def check_chunks(path, manifest):
    """Raise ``StoreCorrupt`` naming the missing chunk files (``missing_chunks``) of the
    store of the run directory ``path`` that its ``manifest`` commits."""
    missing = missing_chunks(Path(path) / STORE, manifest["saved"], manifest["variables"])
    if missing:
        listed = ", ".join(map(str, missing[:4])) + (
            f" and {len(missing) - 4} more" if len(missing) > 4 else "")
        files, are, them = (("files", "are", "them") if len(missing) > 1 else
                            ("file", "is", "it"))
        raise StoreCorrupt(
            f"{path} is damaged: {len(missing)} {files} that its manifest commits (its "
            f"{manifest['saved']} saved steps and their labels) {are} missing ({listed}); "
            f"Zarr would read {them} as fill values (NaN, 0, -1), not as data.  Restore "
            f"{them} from a backup, or run the scene again into a new directory (--out); "
            f"{_READABLE}", missing[0])


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
            sync(za.consolidate_metadata(atomic_store(root)))
    except (StoreError, OSError):
        return
    warnings.warn(f"{root}/zarr.json had lost its consolidated metadata (the list of the "
                  "arrays that xarray.open_zarr reads first); the arrays were read without "
                  "it and it was written again", RuntimeWarning, stacklevel=3)


def open_dataset(path):
    """The committed steps of the run directory ``path`` as an ``xarray.Dataset`` (lazy:
    nothing is read until used), with the manifest in ``attrs["manifest"]``; a chunk file
    the manifest commits that is missing raises ``StoreCorrupt`` (``check_chunks``).

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
    check_chunks(path, manifest)
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
                        "run the scene again into a new directory (--out)", root)


def _manifest_or_raise(path):
    manifest = read_manifest(path)
    if manifest is None:
        if is_legacy(path):
            raise StoreError(f"{path} is a run directory of the old format (chunk_*.npz): "
                             "read it with Result.load(path, system)")
        raise FileNotFoundError(f"no {MANIFEST} in {path}: not a run directory")
    return manifest


def read_records(path, system, manifest):
    """The committed steps of the store in ``path`` as arrays keyed by ``FIELDS``, the
    inputs' values by ``input_<name>`` and the loads' outputs by ``output_<name>``."""
    return _records(system, manifest, _read(path, manifest, _record_variables(manifest)))


def _record_variables(manifest):
    """The stored variables that make the records (``read_records``): the fields of
    ``FIELDS`` in their order, then the inputs' and the loads' outputs."""
    stored = [FIELD.get(v, v) for v in manifest["variables"]]
    names = [name for name in FIELDS if name in stored]
    names += [v for v in stored if v.startswith((INPUT, OUTPUT))]
    return [VARIABLE.get(name, name) for name in names]


def _records(system, manifest, values):
    """The records (``read_records``) of the stored ``values`` (``{variable: array}``)."""
    n = int(manifest["saved"])
    stored = [FIELD.get(v, v) for v in manifest["variables"]]
    if n == 0:
        return empty_records(system, 0)
    records = {FIELD.get(v, v): a for v, a in values.items()}
    inputs = {k: v for k, v in records.items() if k.startswith((INPUT, OUTPUT))}
    return {**fill_records(system, records, stored, n), **inputs}


def _read(path, manifest, names):
    """``{name: values}`` of the first ``saved`` steps of the variables ``names`` of the
    store in ``path``, read at once with zarr (the arrays of the consolidated metadata,
    read around and repaired when it is lost, as ``open_dataset``); a missing chunk, an
    array that cannot be read or has fewer steps raise ``StoreCorrupt`` naming the file
    (the first of ``names`` that fails)."""
    path = Path(path)
    n = int(manifest["saved"])
    if n == 0:
        return {}
    check_chunks(path, manifest)
    root = path / STORE
    try:
        arrays = _open_arrays(root, names)
    except Exception as err:
        raise _unopenable(root, err) from err
    values = sync(settled(a.getitem(slice(0, n)) for a in arrays))
    for name, value in zip(names, values):
        if not isinstance(value, Exception) and value.shape[0] != n:
            value = ValueError(f"{value.shape[0]} steps stored, {n} committed")
        if isinstance(value, Exception):
            bad = (_undecodable_chunk(root, name, int(manifest["chunk"]), n)
                   or (root / name, f"cannot be read ({type(value).__name__}: {value})"))
            raise StoreCorrupt(f"{bad[0]} {bad[1]}: the saved steps of {path} cannot be read "
                               "completely; restore the file from a backup, or run the scene "
                               f"again into a new directory (--out); {_READABLE}",
                               bad[0]) from value
    return dict(zip(names, values))


def _open_arrays(root, names):
    """The arrays ``names`` of the store ``root`` (``AsyncArray``), from its consolidated
    metadata; without it from their own, and the consolidated metadata is written again
    (``repair_metadata``)."""
    try:
        return sync(_arrays(root, names, consolidated=True))
    except Exception:
        arrays = sync(_arrays(root, names, consolidated=False))
    repair_metadata(root)
    return arrays


async def _arrays(root, names, consolidated):
    import zarr.api.asynchronous as za

    group = await za.open_group(store=atomic_store(root, read_only=True), mode="r",
                                use_consolidated=consolidated)
    return await gather([group.getitem(name) for name in names])


def checkpoint_bytes(path, manifest):
    """The bytes of the checkpoint of the run directory ``path`` that its ``manifest``
    commits, checked against the manifest's SHA-256."""
    ck = manifest.get("checkpoint")
    if ck is None:
        raise StoreError(f"{path} has no checkpoint yet (the run was stopped before its "
                         "first commit): nothing to continue; run it again (--overwrite)")
    file = Path(path) / ck["file"]
    try:
        data = file.read_bytes()
    except FileNotFoundError:
        raise StoreCorrupt(f"{file} is missing: the run cannot be continued; {_KEEP}",
                           file) from None
    if hashlib.sha256(data).hexdigest() != ck.get("sha256"):
        raise StoreCorrupt(f"{file} is truncated or corrupt ({len(data)} bytes, "
                           f"{ck.get('bytes')} written; its SHA-256 differs from the "
                           f"manifest's): the run cannot be continued from it; {_KEEP}",
                           file)
    return data


def read_checkpoint(path, manifest=None):
    """The checkpoint (integrator snapshot with ``index``, ``settings``, ``stat_*``) of
    the run directory ``path``, checked against the manifest's SHA-256."""
    manifest = manifest or _manifest_or_raise(Path(path))
    data = checkpoint_bytes(path, manifest)
    with np.load(io.BytesIO(data), allow_pickle=False) as ck:
        return {k: ck[k] for k in ck.files}


def read_run(path, system: SystemView | None = None):
    """``(records, checkpoint)`` of the run directory ``path``: the committed saved steps
    (arrays keyed by ``records.FIELDS``) and the checkpoint (also of the old format).
    Without ``system``, fields the store left out are omitted from ``records``."""
    path = Path(path)
    manifest = read_manifest(path)
    if manifest is None:
        return read_legacy(path, system)
    if system is None:
        system = ShapeOnly(manifest)
    return read_records(path, system, manifest), read_checkpoint(path, manifest)


class ShapeOnly:
    """Stands for the system when reading without one (only sizes are needed)."""

    def __init__(self, manifest):
        self.n_dofs = int(manifest.get("n_dofs", 0))
        self.n_constraints = int(manifest.get("n_constraints", 0))


def read_result(path, system: SystemView, check=True):
    """``(records, stats, reference)`` of the saved steps of the run directory ``path``:
    what ``Result.load`` makes its ``Result`` of.

    The store must have been written by ``system`` (its fingerprint, ``io.fingerprint``):
    otherwise ``StoreMismatch`` (``check=False`` skips the test; the sizes must still
    match).  Fields the store left out are NaN (``iterations``: -1).  ``stats``: the
    solver counters at the last saved step, ``status`` and ``stopped``.  Old run
    directories (``chunk_*.npz``) are read too.  In orbit, ``reference`` is the run's
    (``orbit.Reference``): ``system.orbit`` and the rebases of Encke's rectification
    (``solvers.rectify``) from the checkpoint, so that its functions of time are those
    the saved offsets were computed against; ``system`` is not changed (None out of
    orbit)."""
    path = Path(path)
    manifest = read_manifest(path)
    if manifest is None:
        records, checkpoint = read_legacy(path, system)
        stats = {k[5:]: int(checkpoint[k]) for k in checkpoint if k.startswith("stat_")}
        return records, stats, _reference(system, checkpoint)
    if check:
        check_fingerprint(path, manifest, system)
    elif (manifest.get("n_dofs", system.n_dofs) != system.n_dofs
          or manifest.get("n_constraints", system.n_constraints) != system.n_constraints):
        raise StoreMismatch(f"{path} holds {manifest.get('n_dofs')} coordinates and "
                            f"{manifest.get('n_constraints')} multipliers; the given system "
                            f"has {system.n_dofs} and {system.n_constraints}")
    counters = [name for name in ("stat_" + c for c in COUNTERS)
                if name in manifest["variables"]]
    values = _read(path, manifest, _record_variables(manifest) + counters)
    records = _records(system, manifest, values)
    in_orbit = system.orbit is not None
    reference = _reference(system, read_checkpoint(path, manifest)
                           if in_orbit and manifest.get("checkpoint") else {})
    stats = {"status": manifest.get("status"),
             "stopped": manifest.get("message") if manifest.get("status") == "stopped"
             else None}
    if manifest["saved"]:
        stats.update({name[5:]: int(values[name][-1]) for name in counters})
    return records, stats, reference


def _reference(system, checkpoint):
    """The run's reference of ``system`` (in orbit; else None) with the rebases of
    ``checkpoint`` (a mapping; none without ``orbit_rebases``)."""
    orbit = system.orbit
    return None if orbit is None else Reference(orbit, checkpoint.get("orbit_rebases"))


def run_info(path):
    """A summary of the store in ``path`` (for messages): its manifest, or None."""
    try:
        return read_manifest(path)
    except StoreError:
        return None


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
