"""Continuing a stored run: ``resume(path)`` gives the ``Resume`` that
``simulate(resume=...)`` starts from (the checkpoint and the saved steps), after the checks
that make the continuation bit for bit: the system that wrote the store
(``io.fingerprint.check_fingerprint``), the last commit's step equal to its checkpoint's
(``check_last_commit``) and, for the ``RunStore`` that appends to it, ``t_end`` not before
the stored steps (``check_t_end``).  ``copy_store`` copies a store to continue it
elsewhere.
"""

import shutil
from dataclasses import dataclass, field
from pathlib import Path

from ..core.protocols import SystemView
from ..util.atomic import write_atomic
from .legacy import LEGACY_RESUME, is_legacy
from .manifest import MANIFEST, StoreCorrupt, StoreError, read_manifest, write_manifest
from .matching import check_fingerprint
from .reader import ShapeOnly, check_chunks, checkpoint_bytes, read_checkpoint, read_records
from .schema import STORE
from .zarr_store import atomic_store, gather, sync


@dataclass
class Resume:
    """A stored run to continue: ``snapshot`` (the checkpoint: integrator state,
    ``index``, ``settings``, ``stat_*``), ``records`` (the saved steps, a dict of arrays
    keyed by ``records.FIELDS``; fields the store left out are NaN), the run directory
    ``path`` and its ``manifest``."""

    snapshot: dict
    records: dict
    path: Path | None = None
    manifest: dict = field(default_factory=dict)


def resume(path, system: SystemView | None = None):
    """The ``Resume`` of the run directory ``path`` (for ``simulate(resume=...)``).

    With ``system``, first check that the store was written by it (``StoreMismatch``
    otherwise); a ``RunStore`` observer of the continued run checks it in any case, with
    the solver settings."""
    path = Path(path)
    manifest = read_manifest(path)
    if manifest is None:
        if is_legacy(path):
            raise StoreError(LEGACY_RESUME.format(path=path))
        raise FileNotFoundError(f"no {MANIFEST} in {path}: not a run directory")
    if system is not None:
        check_fingerprint(path, manifest, system)
    check_chunks(path, manifest)  # before reading the last step: a missing chunk reads 0
    checkpoint = read_checkpoint(path, manifest)
    check_last_commit(path, manifest)
    shape = system if system is not None else ShapeOnly(manifest)
    records = read_records(path, shape, manifest)
    return Resume(checkpoint, records, path, manifest)


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
    data = checkpoint_bytes(source, manifest)
    path.mkdir(parents=True, exist_ok=True)
    if (path / STORE).exists():
        shutil.rmtree(path / STORE)
    shutil.copytree(source / STORE, path / STORE,
                    ignore=lambda d, names: [n for n in names if ".tmp-" in n
                                             or n.endswith(".partial")])
    write_atomic(path / ck["file"], data)
    return write_manifest(path, dict(manifest, copied_from=str(source)))


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
        arrays = sync(_read_last(path / STORE, n))
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
    arrays = await gather([group.getitem("step"), group.getitem("time")])
    held = min(a.shape[0] for a in arrays)
    if not 1 <= n <= held:
        raise ValueError(f"the arrays hold {held} steps, the manifest commits {n}")
    step, t = await gather([a.getitem(n - 1) for a in arrays])
    return int(step), float(t)
