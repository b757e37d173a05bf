"""Reading a run store (``io.schema``) back: ``open_dataset`` (the committed steps as a
lazy ``xarray.Dataset``), ``read_run`` (records and checkpoint), ``read_result`` (what
``Result.load`` is made of), ``read_checkpoint``, ``run_info`` and ``describe_run`` (the
manifest, for messages).

A reader uses the first ``saved`` steps of the arrays (the manifest's commit) and ignores
whatever a broken commit appended after them; a chunk that is missing or cannot be decoded
raises ``StoreCorrupt`` naming its file.  Old run directories (``chunk_*.npz``) are read by
``io.legacy``.
"""

import hashlib
import io
import json
import warnings
from pathlib import Path

import numpy as np

from ..records import FIELDS, INPUT
from . import lock
from .fingerprint import check_fingerprint
from .legacy import is_legacy, read_legacy
from .manifest import MANIFEST, StoreCorrupt, StoreError, StoreMismatch, read_manifest
from .schema import COUNTERS, FIELD, STORE, VARIABLE
from .zarr_store import atomic_store, sync


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
            sync(za.consolidate_metadata(atomic_store(root)))
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


def read_records(path, system, manifest):
    """The committed steps of the store in ``path`` as arrays keyed by ``FIELDS`` and
    the inputs' values by ``input_<name>``."""
    path = Path(path)
    n = int(manifest["saved"])
    stored = [FIELD.get(v, v) for v in manifest["variables"]]
    if n == 0:
        return empty_records(system, 0)
    root = path / STORE
    try:
        ds = _open_dataset(root)
    except Exception as err:
        raise _unopenable(root, err) from err
    records = {}
    for name in [*FIELDS, *(v for v in stored if v.startswith(INPUT))]:
        if name not in stored:
            continue
        var = VARIABLE.get(name, name)
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
    inputs = {k: v for k, v in records.items() if k.startswith(INPUT)}
    return {**fill_records(system, records, stored, n), **inputs}


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
    data = checkpoint_bytes(path, manifest)
    with np.load(io.BytesIO(data), allow_pickle=False) as ck:
        return {k: ck[k] for k in ck.files}


def read_run(path, system=None):
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


def read_result(path, system, check=True):
    """``(records, stats)`` of the saved steps of the run directory ``path``: what
    ``Result.load`` (``io.load_result``) makes its ``Result`` of.

    The store must have been written by ``system`` (its fingerprint, ``io.fingerprint``):
    otherwise ``StoreMismatch`` (``check=False`` skips the test; the sizes must still
    match).  Fields the store left out are NaN (``iterations``: -1).  ``stats``: the
    solver counters at the last saved step, ``status`` and ``stopped``.  Old run
    directories (``chunk_*.npz``) are read too.  A system in orbit takes the rebases of
    the run's reference (Encke's rectification, ``solvers.rectify``) from the checkpoint,
    so that its orbit's functions of time are those the saved offsets were computed
    against."""
    path = Path(path)
    manifest = read_manifest(path)
    if manifest is None:
        records, checkpoint = read_legacy(path, system)
        stats = {k[5:]: int(checkpoint[k]) for k in checkpoint if k.startswith("stat_")}
        return records, stats
    if check:
        check_fingerprint(path, manifest, system)
    elif (manifest.get("n_dofs", system.n_dofs) != system.n_dofs
          or manifest.get("n_constraints", system.n_constraints) != system.n_constraints):
        raise StoreMismatch(f"{path} holds {manifest.get('n_dofs')} coordinates and "
                            f"{manifest.get('n_constraints')} multipliers; the given system "
                            f"has {system.n_dofs} and {system.n_constraints}")
    records = read_records(path, system, manifest)
    if system.orbit is not None and manifest.get("checkpoint"):
        system.orbit.restore(read_checkpoint(path, manifest).get("orbit_rebases"))
    stats = {"status": manifest.get("status"),
             "stopped": manifest.get("message") if manifest.get("status") == "stopped"
             else None}
    if manifest["saved"]:
        stats.update(_counters(path, manifest))
    return records, stats


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
