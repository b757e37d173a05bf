"""The run directories of the format before the Zarr store: ``checkpoint.npz`` and
``chunk_NNNNN.npz`` files of saved steps, no manifest.  They are still read
(``Result.load``, ``io.read_run``); they cannot be continued.
"""

from pathlib import Path

import numpy as np

from ..core.records import FIELDS
from .manifest import MANIFEST, StoreCorrupt, StoreMismatch

#: The files of the format before the Zarr store (read by ``Result.load``).
LEGACY_CHECKPOINT = "checkpoint.npz"
LEGACY_CHUNKS = "chunk_*.npz"


def chunk_name(k):
    """File name of the ``k``-th chunk of the old format."""
    return f"chunk_{k:05d}.npz"


def is_legacy(run_dir):
    """True when ``run_dir`` holds a store of the old format (``chunk_*.npz``,
    ``checkpoint.npz``) and no manifest."""
    run_dir = Path(run_dir)
    return (not (run_dir / MANIFEST).exists()
            and ((run_dir / LEGACY_CHECKPOINT).exists() or any(run_dir.glob(LEGACY_CHUNKS))))


#: Why a run directory of the old format cannot be continued (``format(path=...)``).
LEGACY_RESUME = ("{path} is a run directory of the old format (chunk_*.npz, "
                 "checkpoint.npz): Result.load reads it, but this version cannot continue "
                 "it; run it again into a new directory (--out)")


def read_legacy(path, system=None):
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
