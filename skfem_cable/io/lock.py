"""One writer per run directory: ``hold(run_dir)`` keeps an OS lock on the file
``run_dir/.skfem-cable.lock`` for as long as its block runs.

The lock is ``fcntl.flock`` (exclusive) on an open file descriptor: the kernel drops it
when the descriptor is closed or its process ends, however it ends (``SIGKILL``, a power
cut), so a lock never outlives its holder and nothing stale blocks a later run.  The file
stays; while held, it records the holder's PID, host and start time, which a refused
process names.  The runner holds the lock from its first look at the directory (before
``--overwrite`` removes anything, before a new run checks that the directory is free) to
the last file of the run; ``RunStore`` holds it while it writes, so that a run of the
Python API is protected too.  Holds nested in one thread share the lock; another thread or
process is refused (``RunLocked``) or, with ``wait=True``, waits.  Without ``fcntl``
(Windows) there is no lock.
"""

import json
import os
import socket
import threading
import time
from contextlib import contextmanager
from pathlib import Path

from .manifest import StoreError

try:
    import fcntl
except ImportError:  # pragma: no cover (Windows)
    fcntl = None

#: The lock file of a run directory.
LOCK = ".skfem-cable.lock"


class RunLocked(StoreError):
    """Another process (or thread) holds the lock of the run directory."""


_held = {}  # lock file -> the thread holding it
_guard = threading.Lock()


@contextmanager
def hold(run_dir, wait=False):
    """Hold the lock of ``run_dir`` (created if missing) inside the block.

    Parameters
    ----------
    run_dir : path
    wait : bool
        Wait while another holds it; otherwise raise ``RunLocked`` naming the holder.

    Raises
    ------
    RunLocked
        Another process or thread holds the lock (``wait=False``).
    StoreError
        The directory or its lock file cannot be written (read-only, no permission).
    """
    run_dir = Path(run_dir)
    key = os.path.realpath(run_dir / LOCK)
    with _guard:
        nested = _held.get(key) == threading.get_ident()
    if nested:  # this thread holds it already (the runner, then its store)
        yield
        return
    fd = _open(run_dir)
    _lock(fd, run_dir, wait)
    with _guard:
        _held[key] = threading.get_ident()
    try:
        yield
    finally:
        with _guard:
            del _held[key]
        _release(fd)


def _open(run_dir):
    """A descriptor of the lock file of ``run_dir``; ``StoreError`` when it cannot be
    written."""
    try:
        run_dir.mkdir(parents=True, exist_ok=True)
        return os.open(run_dir / LOCK, os.O_RDWR | os.O_CREAT | os.O_CLOEXEC, 0o644)
    except OSError as err:
        raise StoreError(f"{run_dir} cannot be written ({err.strerror}: {err.filename}): "
                         "a run needs a directory it may write into; choose another "
                         "directory (--out) or make it writable") from None


def _lock(fd, run_dir, wait):
    """Lock ``fd`` and record this process in it; ``RunLocked`` when another holds it."""
    if fcntl is None:  # pragma: no cover (Windows)
        return
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | (0 if wait else fcntl.LOCK_NB))
    except BlockingIOError:
        holder = _holder(fd)
        os.close(fd)
        raise RunLocked(f"{run_dir} is in use by another run: {holder} holds its lock "
                        f"({LOCK}); wait until that run ends, or write this one into "
                        "another directory") from None
    except BaseException:
        os.close(fd)
        raise
    me = {"pid": os.getpid(), "host": socket.gethostname(),
          "since": time.strftime("%Y-%m-%dT%H:%M:%S%z")}
    os.ftruncate(fd, 0)
    os.pwrite(fd, (json.dumps(me) + "\n").encode(), 0)


def _release(fd):
    """Forget the holder recorded in ``fd`` (a waiting process names its own), close it:
    the lock is released."""
    try:
        os.ftruncate(fd, 0)
    finally:
        os.close(fd)


def _holder(fd):
    """The holder recorded in the lock file ``fd``, as text."""
    try:
        who = json.loads(os.pread(fd, 4096, 0))
        return f"process {who['pid']} on host {who['host']!r} (since {who['since']})"
    except (OSError, ValueError, KeyError, TypeError):
        return "a process that has not recorded itself yet"
