"""Signals and runs: ``SIGTERM`` (and ``SIGHUP``) end a run the way Ctrl-C does, and no
signal cuts a store's write in half.

* ``graceful()``: while active (a ``RunStore`` holds it from ``start`` to ``finish``),
  ``SIGTERM`` and ``SIGHUP`` raise ``Terminated``, a ``KeyboardInterrupt``, in the main
  thread; ``simulate`` then calls its observers' ``finish`` as after Ctrl-C, so the store
  writes the steps saved so far and a checkpoint before the program ends.
* ``deferred()``: around a store's write, ``SIGINT``, ``SIGTERM`` and ``SIGHUP`` are held
  and delivered when the write is complete.
* ``ignored(SIGINT)``: around the start of helper processes (a study's Dask workers),
  which inherit the ignored signal, so that Ctrl-C in a terminal (sent to every process
  of its group) reaches this process only, which stops them.

Both act in the main thread only (Python delivers signals there); elsewhere they do
nothing.
"""

import os
import signal
import threading
from contextlib import contextmanager

#: The signals that end a run through ``finish`` (``SIGHUP``: the terminal went away).
TERMINATING = tuple(getattr(signal, name) for name in ("SIGTERM", "SIGHUP")
                    if hasattr(signal, name))

#: The signals held during a store's write.
HELD = (signal.SIGINT, *TERMINATING)


class Terminated(KeyboardInterrupt):
    """A run ended by ``SIGTERM`` or ``SIGHUP`` (``signum``): a ``KeyboardInterrupt``, so
    that it ends a run like Ctrl-C and is not caught by ``except Exception``."""

    def __init__(self, signum):
        self.signum = int(signum)
        super().__init__(f"terminated by {signal_name(signum)}")


def signal_name(signum):
    try:
        return signal.Signals(signum).name
    except ValueError:
        return f"signal {signum}"


def interrupt_signal(error):
    """The signal number behind ``error`` (``SIGINT`` for a plain ``KeyboardInterrupt``),
    or None when ``error`` is not an interruption."""
    if isinstance(error, Terminated):
        return error.signum
    if isinstance(error, KeyboardInterrupt):
        return int(signal.SIGINT)
    return None


def _main_thread():
    return threading.current_thread() is threading.main_thread()


def _raise_terminated(signum, frame):
    raise Terminated(signum)


_graceful_depth = 0
_graceful_previous = {}


def install_graceful():
    """Make ``SIGTERM``/``SIGHUP`` raise ``Terminated`` (nested calls are counted); returns
    False where that is not possible (not the main thread)."""
    global _graceful_depth
    if not _main_thread():
        return False
    if _graceful_depth == 0:
        for s in TERMINATING:
            previous = signal.getsignal(s)
            if previous == signal.SIG_IGN:  # e.g. SIGHUP under nohup: keep ignoring it
                continue
            _graceful_previous[s] = previous
            signal.signal(s, _raise_terminated)
    _graceful_depth += 1
    return True


def uninstall_graceful():
    """Undo one ``install_graceful`` (the handlers are restored by the last one)."""
    global _graceful_depth
    if not _main_thread() or _graceful_depth == 0:
        return
    _graceful_depth -= 1
    if _graceful_depth == 0:
        for s, previous in _graceful_previous.items():
            signal.signal(s, signal.SIG_DFL if previous is None else previous)
        _graceful_previous.clear()


@contextmanager
def graceful():
    """``SIGTERM`` and ``SIGHUP`` raise ``Terminated`` inside the block (main thread)."""
    installed = install_graceful()
    try:
        yield
    finally:
        if installed:
            uninstall_graceful()


@contextmanager
def deferred(deliver=True):
    """Hold ``SIGINT``, ``SIGTERM`` and ``SIGHUP`` inside the block; after it, deliver the
    first one caught to the handler that was in place (``deliver=False``: drop it, e.g.
    when the run is already ending).  Nothing is delivered when the block raised."""
    if not _main_thread():
        yield
        return
    caught = []

    def hold(signum, frame):
        caught.append(signum)

    previous = {}
    try:
        for s in HELD:
            previous[s] = signal.getsignal(s)
            signal.signal(s, hold)
        yield
    finally:
        for s, handler in previous.items():
            signal.signal(s, signal.SIG_DFL if handler is None else handler)
    if caught and deliver:
        _deliver(caught[0], previous[caught[0]])


@contextmanager
def ignored(*signums):
    """Ignore ``signums`` inside the block (main thread; elsewhere nothing changes).  A
    process started meanwhile keeps ignoring them (an ignored signal stays ignored
    across ``exec``, and Python then installs no ``KeyboardInterrupt`` handler)."""
    if not _main_thread():
        yield
        return
    previous = {s: signal.signal(s, signal.SIG_IGN) for s in signums}
    try:
        yield
    finally:
        for s, handler in previous.items():
            signal.signal(s, signal.SIG_DFL if handler is None else handler)


def _deliver(signum, handler):
    if handler == signal.SIG_IGN:
        return
    if callable(handler):
        handler(signum, None)
    else:  # the default action (end the process), now that the write is complete
        os.kill(os.getpid(), signum)


def exit_status(signum):
    """The shell's exit status of a program ended by ``signum`` (``128 + signum``)."""
    return 128 + int(signum)
