"""Crash-safe files: every file of a run store is written to a temporary name in its final
folder, flushed to the disk (``fsync``) and renamed over its final name, so that a reader
sees either the old or the new content, never a part of it, whatever stops the writer
(``SIGKILL``, a full disk, a power cut after the rename).

``replacing`` gives the temporary file to write and renames it; ``write_atomic`` writes
one file of bytes with it (``io.zarr_store.atomic_store`` is the Zarr store whose every
object, chunk or metadata, is written by ``write_atomic``); ``remove_temporaries`` removes
what a killed writer left behind.  All bytes pass through ``_write``: the tests make it
raise ``OSError(ENOSPC)`` to play a full disk.

``SKFEM_CABLE_FSYNC=0`` leaves out the ``fsync`` calls (``durable``): the rename still
publishes whole files to every reader and survives a killed writer (the page cache keeps
what it wrote), not a power cut.  The test suite sets it (``tests/conftest.py``): its
faults are killed processes, and ``tests/test_faults.py`` alone made 11,067 ``fsync``
calls.

A leaf of the package (the standard library only): the compiled kernels' cache
(``kernels.generated``), the exports and the run store all write through it.
"""

import os
import uuid
from contextlib import contextmanager
from pathlib import Path

#: Part of the name of every temporary file (``NAME.tmp-<random>``).
TMP_MARK = ".tmp-"

#: What Zarr's own ``LocalStore`` names its temporary files (``NAME.<hex>.partial``).
ZARR_PARTIAL = ".partial"


def _write(f, data):
    """Write ``data`` to the open binary file ``f``: the only place bytes of a run store
    reach a file (a test replaces it to simulate a full disk)."""
    f.write(data)


def durable():
    """Whether writes are flushed to the disk before their rename: unless the environment
    sets ``SKFEM_CABLE_FSYNC=0`` (read at each write)."""
    return os.environ.get("SKFEM_CABLE_FSYNC") != "0"


def _fsync_dir(path):
    if not durable():
        return
    try:
        fd = os.open(path, os.O_RDONLY)
    except OSError:  # not possible on some systems (Windows): the rename is enough there
        return
    try:
        os.fsync(fd)
    except OSError:
        pass
    finally:
        os.close(fd)


def _temporary(path):
    """The name ``NAME.tmp-<random>`` of a temporary file beside ``path``, one no other
    writer uses (48 random bits; ``replacing`` creates it with ``O_EXCL``)."""
    return path.with_name(f"{path.name}{TMP_MARK}{uuid.uuid4().hex[:12]}")


@contextmanager
def replacing(path):
    """A temporary file beside ``path``, unique (``_temporary``, created with the
    permissions ``open`` gives a new file), to write inside the block; renamed over
    ``path`` when the block succeeds.  Whatever interrupts the block or its start (an
    exception, ``KeyboardInterrupt`` or a signal turned into one, even between the
    file's creation and the block), the temporary file is removed and ``path`` keeps its
    old content."""
    path = Path(path)
    tmp = _temporary(path)
    creating = True
    try:
        os.close(os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666))
        creating = False
        yield tmp
        os.replace(tmp, path)
    except BaseException as err:
        if not (creating and isinstance(err, FileExistsError)):  # not another writer's
            try:
                tmp.unlink(missing_ok=True)
            except OSError:
                pass
        raise


def write_atomic(path, data, exclusive=False):
    """Write ``data`` (bytes-like) into ``path`` atomically and durably: a temporary file
    in the same folder (``replacing``), ``fsync``, rename, ``fsync`` of the folder.
    ``exclusive``: leave an existing ``path`` alone."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    if exclusive and path.exists():
        return
    with replacing(path) as tmp, open(tmp, "wb") as f:
        _write(f, data)
        f.flush()
        if durable():
            os.fsync(f.fileno())
    _fsync_dir(path.parent)


def is_temporary(path):
    """True for a temporary file of ``write_atomic`` or of Zarr's ``LocalStore``."""
    name = Path(path).name
    return TMP_MARK in name or name.endswith(ZARR_PARTIAL)


def remove_temporaries(folder):
    """Remove the temporary files that a killed writer left in ``folder`` (recursively);
    returns their number."""
    folder = Path(folder)
    if not folder.is_dir():
        return 0
    count = 0
    for p in folder.rglob("*"):
        if p.is_file() and is_temporary(p):
            p.unlink(missing_ok=True)
            count += 1
    return count
