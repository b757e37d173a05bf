"""Run directories: the files a run writes there and what each one is (``DESCRIPTIONS``,
``register_files``), whether a run may be written there (``check_run_dir``), holding one
for a run (``run_directory``) and removing the run it holds (``remove_run``).

The runner describes its own files here: the summary, the run store, the lock, the VTU
series and its figures (``runner.figures``), whichever of its modules a process imported.
A module that writes files of its own into run directories (a scene) registers them when
it is imported::

    from skfem_cable.runner.directory import register_files

    register_files({"my_scene.npz": "every output of my scene, as numpy arrays",
                    "plots/my_scene.png": "what the scene's own figure shows"})

``summary.json`` then describes them (``described_files``) and ``--overwrite`` removes
them (``run_files``).  A run's summary names its files, so that ``--overwrite`` removes
those of a scene whose module this process did not import too (``recorded_files``).
"""

import json
import os
import shutil
from contextlib import contextmanager
from fnmatch import fnmatch
from pathlib import Path, PurePosixPath

from ..io import RunExists, StoreError, lock
from ..io.manifest import read_manifest
from ..io.reader import describe_run, run_info
from ..io.writer import remove_store, store_files
from ..util.atomic import is_temporary

SUMMARY = "summary.json"

#: Every file a run directory can hold (names and patterns relative to it), with the
#: one-line description ``summary.json`` gives it (``described_files``): the runner's own
#: (its figures' those ``runner.figures`` writes), those of a scene added by its module
#: (``register_files``).
DESCRIPTIONS = {
    SUMMARY: "this summary: scene, parameters, solver statistics, key outputs, files",
    "manifest.json": "the run's manifest: status, saved steps, settings and fingerprints",
    lock.LOCK: "the lock a run holds while it writes this directory (io.lock)",
    "results.zarr": "the results store (xarray.open_zarr): every saved step's fields",
    "checkpoint_*.npz": "integrator checkpoint: a resumed run continues bit for bit",
    "series.pvd": "ParaView collection of the VTU frames (open this one in ParaView)",
    "vtu/series_*.vtu": "ParaView frames: bodies with tension, strain and velocity fields",
    # the figures (``runner.figures``)
    "animation.gif": "animation of the run (3-D renders)",
    "animation.mp4": "animation of the run (3-D renders)",
    "plots/energies.png": "energy terms, balance residual and relative drift against time",
    "plots/cables.png": "tip displacements (in orbit: in the LVLH frame about the centre "
                        "of mass; spinning: in the spinning frame) and root and peak "
                        "tensions of the cables against time",
    "plots/tension_psd.png": "power spectral density of the root tensions",
    "plots/inputs.png": "the inputs controllers set (sc.Input) against time",
    "plots/final.png": "3-D render of the final state",
}

#: Names and patterns of further files written into run directories, without a
#: description of their own (``register_files``' ``patterns``).
UNDESCRIBED = []

#: Entries of ``DESCRIPTIONS`` that are the run store (``io.writer.store_files``) and the
#: lock: not among the ``run_patterns``.
STORE_AND_LOCK = ("manifest.json", "results.zarr", "checkpoint_*.npz", lock.LOCK)


def register_files(descriptions, after=None, patterns=()):
    """Register files that a module writes into run directories.

    Parameters
    ----------
    descriptions : dict
        ``{name or pattern relative to the run directory: one-line description}``, the
        description ``summary.json`` gives the file (``described_files``).  An entry
        registered before keeps its place and takes the new description.
    after : str, optional
        The registered entry after which the new ones are listed (in ``summary.json``);
        default: at the end.
    patterns : sequence of str
        Names or patterns of further files the module writes (or wrote in earlier
        versions) that have no description of their own.

    ``--overwrite`` removes all of them (``run_patterns``).
    """
    if after is not None and after not in DESCRIPTIONS:
        raise ValueError(f"no run file {after!r} is registered to list files after")
    entries = list(DESCRIPTIONS.items())
    at = len(entries) if after is None else list(DESCRIPTIONS).index(after) + 1
    new = [(k, v) for k, v in descriptions.items() if k not in DESCRIPTIONS]
    DESCRIPTIONS.clear()
    DESCRIPTIONS.update(entries[:at] + new + entries[at:])
    DESCRIPTIONS.update(descriptions)
    UNDESCRIBED.extend(p for p in patterns if p not in UNDESCRIBED)


def run_patterns():
    """Names and patterns of the files this package writes into a run directory besides
    the store and the lock (``--overwrite`` removes these and nothing else): the
    registered ones (``register_files``), relative to the directory."""
    return [k for k in DESCRIPTIONS if k not in STORE_AND_LOCK] + UNDESCRIBED


def described_files(out):
    """``{relative path: description}`` of every file of the run in ``out`` (the VTU
    frames as one entry with their count); a file without description is listed as
    such."""
    out = Path(out)
    listed = {}
    for path in [*run_files(out), out / lock.LOCK]:
        name = path.relative_to(out).as_posix()
        if is_temporary(path) or name.endswith(".tmp") or not path.exists():
            continue
        pattern = next((k for k in DESCRIPTIONS if fnmatch(name, k)), None)
        if pattern == "vtu/series_*.vtu":
            if pattern not in listed:  # counted once, not once per frame
                count = len(list(out.glob(pattern)))
                listed[pattern] = f"{DESCRIPTIONS[pattern]} ({count} files)"
        else:
            listed[name] = DESCRIPTIONS.get(pattern, "written by this package")
    return listed


def run_files(out):
    """The files and folders of a run (this package's) present in the directory ``out``:
    the store (``io.writer.store_files``), those of ``run_patterns`` and temporary
    files."""
    out = Path(out)
    if not out.is_dir():
        return []
    found = list(store_files(out))
    for pattern in run_patterns():
        found += sorted(out.glob(pattern))
    for folder in (out, out / "vtu", out / "plots"):
        if folder.is_dir():
            found += [p for p in sorted(folder.iterdir()) if p.is_file() and (
                is_temporary(p) or p.name.endswith((".vtu.tmp", ".pvd.tmp")))]
    return list(dict.fromkeys(found))


def recorded_files(out):
    """The files of the run in ``out`` that its ``summary.json`` describes
    (``files.described``), found on disk: those of a scene whose module (which registers
    them) this process did not import among them.  None without a readable summary;
    never the store, the lock or a path outside ``out``."""
    out = Path(out)
    try:
        described = json.loads((out / SUMMARY).read_text())["files"]["described"]
    except (OSError, ValueError, KeyError, TypeError):
        return []
    found = []
    for name in described if isinstance(described, dict) else ():
        parts = PurePosixPath(name).parts
        if (not parts or PurePosixPath(name).is_absolute() or ".." in parts
                or name in STORE_AND_LOCK):
            continue
        found += [p for p in sorted(out.glob(name)) if p.is_file()]
    return found


def remove_run(out):
    """Remove the run in ``out``: its store first (so that a half-removed run is never
    taken for a complete one), then ``run_files`` and ``recorded_files``; empty ``vtu/``
    and ``plots/`` folders go too.  Files this package did not write stay.  Returns the
    number of entries removed."""
    out = Path(out)
    files = list(dict.fromkeys([*run_files(out), *recorded_files(out)]))
    remove_store(out)
    for path in files:
        if path.is_dir():
            shutil.rmtree(path, ignore_errors=True)
        else:
            path.unlink(missing_ok=True)
    for folder in (out / "vtu", out / "plots"):
        if folder.is_dir() and not any(folder.iterdir()):
            folder.rmdir()
    return len(files)


def _describe(out):
    manifest = run_info(out)
    if manifest is None:
        names = ", ".join(p.name for p in run_files(out)[:4])
        return f"files of an earlier run: {names}"
    return describe_run(manifest)


def check_run_dir(out, overwrite=False, resume=False):
    """Raise unless a run may be written into ``out`` as asked: ``RunExists`` when it
    holds another run and neither ``overwrite`` nor ``resume`` is given, ``StoreError``
    when ``resume`` finds nothing to continue (``StoreCorrupt`` naming a damaged
    manifest) or when ``out`` cannot be written.  Changes nothing."""
    if overwrite and resume:
        raise ValueError("--overwrite and --resume exclude each other")
    if out is None:
        if resume:
            raise ValueError("--resume needs the run directory (--out DIR)")
        return
    out = Path(out)
    if out.exists() and not out.is_dir():
        raise ValueError(f"--out {out} is a file, not a directory")
    _check_writable(out, resume or overwrite)
    present = run_files(out)
    if resume:
        if read_manifest(out) is None:
            what = "a run of the old format that cannot be continued" if any(
                p.name == "checkpoint.npz" for p in present) else "no run store to continue"
            raise StoreError(f"{out} holds {what} (no manifest.json): run the scene "
                             "without --resume" + (", into another --out to keep its files"
                                                   if present else ""))
        return
    if present and not overwrite:
        raise RunExists(f"{out} already holds a run ({_describe(out)}): choose another "
                        "--out, replace it with --overwrite, or continue it with --resume")


def _check_writable(out, existing):
    """Raise ``StoreError`` unless ``out``, or the folder it would be created in, may be
    written by this user; ``existing``: the run in ``out`` is continued or replaced."""
    folder = next(p for p in (out, *out.parents) if p.exists())
    if not folder.is_dir():
        raise ValueError(f"--out {out}: {folder} is a file, not a directory")
    if os.access(folder, os.W_OK | os.X_OK):
        return
    if folder != out:
        raise StoreError(f"--out {out} cannot be created: {folder} is read-only for this "
                         "user; choose another --out, or make it writable")
    raise StoreError(f"--out {out} is read-only for this user: "
                     + ("its run cannot be continued or replaced there; make it writable, "
                        "or copy it and continue the copy" if existing else
                        "choose another --out, or make it writable"))


@contextmanager
def run_directory(options, can_resume=True):
    """Hold the run directory ``options.out`` for a run (``io.lock``; yields it as a
    ``Path``, or None without one): created if missing, checked (``check_run_dir``)
    once the lock is held, and with ``options.overwrite`` emptied of the run it held.
    The lock is held until the block ends: no other process writes the directory
    meanwhile."""
    if options.resume and not can_resume:
        raise ValueError("--resume continues time integrations only; this scene has none")
    check_run_dir(options.out, options.overwrite, options.resume)  # before creating it
    if options.out is None:
        yield None
        return
    out = Path(options.out)
    with lock.hold(out):
        check_run_dir(out, options.overwrite, options.resume)  # nobody changes it now
        if options.overwrite:
            remove_run(out)
        yield out
