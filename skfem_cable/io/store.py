"""Raw results of a run on disk, written as it goes: the observer ``RunStore``.

A run directory holds ``chunk_NNNNN.npz`` files (compressed, each a block of saved steps
with the arrays of ``result.FIELDS``, written atomically) and ``checkpoint.npz`` (the
integrator's ``snapshot()`` at the last stored step, with ``index``, ``settings``,
``stat_*`` and the number of ``chunks``, written atomically after each chunk).  An
interrupted run therefore keeps everything up to its last chunk (and, when Python could
still run the observers' ``finish``, up to its last saved step), and ``resume(path)``
continues it bit for bit.
"""

import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..contract import Observer
from ..result import FIELDS, Result, settings_array, step_record

CHECKPOINT = "checkpoint.npz"


def _atomic_savez(path, **arrays):
    tmp = Path(str(path) + ".tmp.npz")
    np.savez_compressed(tmp, **arrays)
    os.replace(tmp, path)


def chunk_name(k):
    """File name of the ``k``-th chunk."""
    return f"chunk_{k:05d}.npz"


class RunStore(Observer):
    """Writes the saved steps of a run into the directory ``path`` in chunks of ``chunk``
    steps, each followed by the checkpoint; the pending steps are written at the end of
    the run, also when it failed or was interrupted.

    A resumed run (``simulate(resume=...)``) continues the chunks of ``path`` (from the
    chunk count of its checkpoint; a directory without one gets only the continuation).

    Parameters
    ----------
    path : path
        Run directory (created at the start of the run).
    chunk : int
        Saved steps per chunk file.

    Examples
    --------
    >>> sc.simulate(system, 10.0, 1e-3, observers=[RunStore("runs/a")])  # doctest: +SKIP
    >>> sc.simulate(system, 10.0, 1e-3, resume=RunStore.resume("runs/a"),  # doctest: +SKIP
    ...             observers=[RunStore("runs/a")])
    """

    def __init__(self, path, chunk=200):
        if int(chunk) != chunk or chunk < 1:
            raise ValueError(f"chunk must be a positive integer, got {chunk!r}")
        self.path = Path(path)
        self.chunk = int(chunk)
        self.pending = []
        self.chunks = 0
        self.checkpoint = None

    def start(self, run):
        self.path.mkdir(parents=True, exist_ok=True)
        self.pending, self.chunks, self.checkpoint = [], 0, None
        self.settings = settings_array(run.settings)
        ck_file = self.path / CHECKPOINT
        if run.resumed and ck_file.exists():
            with np.load(ck_file, allow_pickle=False) as ck:
                self.chunks = int(ck["chunks"])

    def saved(self, run, step):
        self.pending.append(step_record(step))
        # the checkpoint of this step: the integrator may move on before the next flush
        snap = run.integrator.snapshot()
        snap.update(index=step.index, settings=self.settings,
                    **{"stat_" + k: v for k, v in run.stats.items()})
        self.checkpoint = snap
        if len(self.pending) >= self.chunk:
            self.flush()

    def finish(self, run, error):
        # whatever ended the run (an error, Ctrl-C), the saved steps reach the disk
        if self.checkpoint is not None and (self.pending or error is None):
            self.flush()

    def flush(self):
        """Write the pending steps as a new chunk, then the checkpoint (both atomically)."""
        if self.pending:
            block = {name: np.asarray([r[name] for r in self.pending]) for name in FIELDS}
            _atomic_savez(self.path / chunk_name(self.chunks), **block)
            self.chunks += 1
            self.pending = []
        _atomic_savez(self.path / CHECKPOINT, chunks=self.chunks, **self.checkpoint)

    @staticmethod
    def resume(path):
        """What ``simulate(resume=...)`` needs to continue the run stored in ``path``."""
        return resume(path)


@dataclass
class Resume:
    """A stored run to continue: ``snapshot`` (the checkpoint: integrator state,
    ``index``, ``settings``, ``stat_*``, ``chunks``) and ``records`` (the saved steps,
    a dict of arrays keyed by ``result.FIELDS``)."""

    snapshot: dict
    records: dict


def read_run(path):
    """Concatenate the chunks of a run directory; returns ``(records, checkpoint)``."""
    path = Path(path)
    ck_file = path / CHECKPOINT
    if not ck_file.exists():
        raise FileNotFoundError(f"no {CHECKPOINT} in {path}: not a run directory")
    with np.load(ck_file, allow_pickle=False) as ck:
        checkpoint = {k: ck[k] for k in ck.files}
    n_chunks = int(checkpoint["chunks"])
    parts = {name: [] for name in FIELDS}
    for k in range(n_chunks):
        with np.load(path / chunk_name(k), allow_pickle=False) as chunk:
            for name in FIELDS:
                parts[name].append(chunk[name])
    records = {name: np.concatenate(parts[name]) if parts[name] else np.zeros(0)
               for name in FIELDS}
    return records, checkpoint


def resume(path):
    """The ``Resume`` of the run directory ``path`` (for ``simulate(resume=...)``)."""
    records, checkpoint = read_run(path)
    return Resume(checkpoint, records)


def load_result(path, system):
    """The saved steps of the run directory ``path`` as a ``Result`` (``stats``: the
    checkpoint's entries); ``Result.load`` calls this."""
    records, checkpoint = read_run(path)
    return Result(system, records, checkpoint)
