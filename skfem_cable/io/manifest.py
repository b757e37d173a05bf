"""The manifest of a run directory, ``manifest.json``: what the store holds, written
(atomically) after the data it describes, so that it is the commit record of the store.

Keys: ``format`` and ``version``; ``fingerprint`` (``system``, ``settings``, ``run``,
``version``: see ``io.fingerprint``); ``system`` (a readable outline); ``settings``
(``run.settings`` of the last session); ``fields`` (the stored variables); ``saved``
(number of committed saved steps), ``first``/``last`` (index and time of the first and
last of them); ``checkpoint`` (``file``, ``index``, ``t``, ``sha256``, ``bytes``, or None
before the first commit);
``status`` (``running``, ``complete``, ``stopped``, ``interrupted``, ``failed``) with a
``message``; ``attrs`` (scene parameters); ``commits`` and ``updated``.

A reader trusts the store up to ``saved`` steps only: whatever a writer killed in the
middle of a commit added beyond is ignored (and overwritten when the run continues).
"""

import json
import time
from pathlib import Path

from ..util.atomic import write_atomic

#: File name of the manifest in a run directory.
MANIFEST = "manifest.json"

FORMAT = "skfem_cable run store"
VERSION = 1


class StoreError(ValueError):
    """A run directory cannot be used as asked (its message says why and what to do)."""


class StoreCorrupt(StoreError):
    """A file of a run directory is truncated or corrupt; ``path`` names it."""

    def __init__(self, message, path=None):
        super().__init__(message)
        self.path = None if path is None else Path(path)


class StoreMismatch(StoreError):
    """A run directory was written by another system or with other solver settings."""


class RunExists(StoreError):
    """The output directory already holds another run."""


def manifest_path(run_dir):
    return Path(run_dir) / MANIFEST


#: What a reader of the store needs from the manifest: key -> (check, what is accepted).
REQUIRED = {
    "saved": (lambda v: _integer(v) and v >= 0, "an integer >= 0"),
    "chunk": (lambda v: _integer(v) and v >= 1, "an integer >= 1"),
    "variables": (lambda v: isinstance(v, list) and bool(v)
                  and all(isinstance(x, str) for x in v), "a list of variable names"),
    "fingerprint": (lambda v: isinstance(v, dict), "a table of fingerprints"),
    "checkpoint": (lambda v: v is None or (isinstance(v, dict) and all(
        k in v for k in ("file", "index", "t", "sha256"))),
        "null or a table with file, index, t, sha256"),
}

#: What is left of a run whose manifest cannot be used.
_KEPT = "the steps in results.zarr still open with xarray.open_zarr"

#: The end of every message about a damaged manifest: what is left and what to do.
_RESTORE = ("it is written atomically, so it was damaged after the run: restore it from a "
            f"backup; {_KEPT}")


def _integer(v):
    return isinstance(v, int) and not isinstance(v, bool)


def read_manifest(run_dir):
    """The manifest of ``run_dir`` (a dict), or None when there is none; ``StoreCorrupt``
    naming the damage when it cannot be read or lacks a key of ``REQUIRED``."""
    path = manifest_path(run_dir)
    try:
        text = path.read_text()
    except FileNotFoundError:
        return None
    except OSError as err:
        raise StoreCorrupt(f"{path} cannot be read ({err}); {_KEPT}", path) from err
    except UnicodeDecodeError as err:
        raise StoreCorrupt(f"{path} is corrupt: not text ({err}); {_RESTORE}", path) from err
    try:
        manifest = json.loads(text)
    except json.JSONDecodeError as err:
        end = len(text.rstrip())  # the text ends before the JSON does: truncated
        damage = ("empty" if not text.strip() else
                  f"truncated (its {len(text)} characters end inside the JSON)"
                  if err.pos >= end or not text.rstrip().endswith("}") else "not valid JSON")
        raise StoreCorrupt(f"{path} is corrupt: {damage} ({err}); {_RESTORE}", path) from err
    if not isinstance(manifest, dict) or manifest.get("format") != FORMAT:
        raise StoreCorrupt(f"{path} is not the manifest of a skfem_cable run store", path)
    if manifest.get("version", 0) > VERSION:
        raise StoreError(f"{path} has store version {manifest['version']}; this "
                         f"skfem_cable reads version {VERSION}: update skfem_cable")
    for key, (check, accepted) in REQUIRED.items():
        if key not in manifest:
            raise StoreCorrupt(f"{path} is corrupt: it has no {key!r} ({accepted}); "
                               f"{_RESTORE}", path)
        if not check(manifest[key]):
            raise StoreCorrupt(f"{path} is corrupt: {key!r} is {manifest[key]!r}, not "
                               f"{accepted}; {_RESTORE}", path)
    return manifest


def write_manifest(run_dir, manifest):
    """Write ``manifest`` (a dict) as ``run_dir/manifest.json``, atomically and durably."""
    manifest = dict(manifest, format=FORMAT, version=VERSION,
                    updated=time.strftime("%Y-%m-%dT%H:%M:%S%z"))
    text = json.dumps(manifest, indent=1, sort_keys=True, allow_nan=False) + "\n"
    write_atomic(manifest_path(run_dir), text.encode())
    return manifest
