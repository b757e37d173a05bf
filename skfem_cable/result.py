"""Time histories of a simulation and their incremental storage on disk.

A run directory holds ``chunk_NNNNN.npz`` files (compressed, each a block of saved steps,
written atomically) and ``checkpoint.npz`` (the integrator state after the last chunk), so
that an interrupted run keeps everything up to the last chunk and can be continued.
"""

import os
from pathlib import Path

import numpy as np

from .state import State

#: Arrays recorded at every saved step.
FIELDS = ("t", "q", "v", "a", "lam", "iterations", "kinetic", "axial", "bending", "potential",
          "dissipated", "external_work")


class Result:
    """Saved steps of a run: ``t, q, v, a, lam`` (leading axis: time), ``iterations``
    (Newton iterations of each saved step), ``energy`` and ``stats``."""

    def __init__(self, system, records, stats=None):
        self.system = system
        for name in FIELDS:
            setattr(self, name, np.asarray(records[name]))
        self.stats = dict(stats or {})

    @property
    def energy(self):
        """Dict of arrays: ``kinetic``, ``elastic`` (= ``axial`` + ``bending``),
        ``potential`` (constant loads and gravity), ``dissipated`` (internal damping, time
        integral of its power), ``external_work`` (time-dependent loads and moments),
        ``total`` (= kinetic + elastic + potential) and ``balance`` (total + dissipated -
        external_work - total at the first saved step; nonzero only through time
        discretisation and numerical dissipation)."""
        elastic = self.axial + self.bending
        total = self.kinetic + elastic + self.potential
        budget = total + self.dissipated - self.external_work
        return {"kinetic": self.kinetic, "axial": self.axial, "bending": self.bending,
                "elastic": elastic, "potential": self.potential,
                "dissipated": self.dissipated, "external_work": self.external_work,
                "total": total, "balance": budget - budget[0]}

    def _fields(self, cable, coords, s, k):
        return cable.interpolate(coords[:, self.system.dofs(cable)], s)[k]

    def position(self, cable, s):
        """Positions ``(nt,) + s.shape + (3,)`` at reference arc lengths ``s``."""
        return self._fields(cable, self.q, s, 0)

    def velocity(self, cable, s):
        return self._fields(cable, self.v, s, 0)

    def tension(self, cable, s):
        return cable.tension(self.q[:, self.system.dofs(cable)], s)

    def curvature(self, cable, s):
        return cable.curvature(self.q[:, self.system.dofs(cable)], s)

    @property
    def multipliers(self):
        """Multipliers of each constraint by name, ``(nt, n_eq)``."""
        out, k = {}, 0
        for c in self.system.constraints:
            out[c.name] = self.lam[:, k: k + c.n_eq]
            k += c.n_eq
        return out

    def state(self, i):
        """The ``i``-th saved step as a ``State``."""
        return State(self.system, self.q[i], self.lam[i], v=self.v[i])

    def __len__(self):
        return len(self.t)

    @classmethod
    def load(cls, path, system):
        """Read the saved steps of a run directory written by ``simulate(output=...)``."""
        records, stats = read_run(path)
        return cls(system, records, stats)


def _atomic_savez(path, **arrays):
    tmp = Path(str(path) + ".tmp.npz")
    np.savez_compressed(tmp, **arrays)
    os.replace(tmp, path)


class RunWriter:
    """Collects saved steps in memory and flushes them to ``path`` in chunks."""

    def __init__(self, path, chunk_size):
        self.path = None if path is None else Path(path)
        self.chunk_size = chunk_size
        self.records = {name: [] for name in FIELDS}
        self.flushed = 0
        self.chunks = 0
        if self.path is not None:
            self.path.mkdir(parents=True, exist_ok=True)

    def append(self, **values):
        for name in FIELDS:
            self.records[name].append(values[name])

    def __len__(self):
        return len(self.records["t"])

    def due(self):
        return self.path is not None and len(self) - self.flushed >= self.chunk_size

    def flush(self, checkpoint):
        """Write the pending steps as a new chunk, then the checkpoint (both atomically)."""
        if self.path is None:
            return
        if len(self) > self.flushed:
            block = {name: np.asarray(self.records[name][self.flushed:]) for name in FIELDS}
            _atomic_savez(self.path / f"chunk_{self.chunks:05d}.npz", **block)
            self.chunks += 1
            self.flushed = len(self)
        _atomic_savez(self.path / "checkpoint.npz", chunks=self.chunks, **checkpoint)

    def arrays(self):
        return {name: np.asarray(self.records[name]) for name in FIELDS}


def read_run(path):
    """Concatenate the chunks of a run directory; returns ``(records, checkpoint)``."""
    path = Path(path)
    ck_file = path / "checkpoint.npz"
    if not ck_file.exists():
        raise FileNotFoundError(f"no checkpoint.npz in {path}: not a run directory")
    with np.load(ck_file, allow_pickle=False) as ck:
        checkpoint = {k: ck[k] for k in ck.files}
    n_chunks = int(checkpoint["chunks"])
    parts = {name: [] for name in FIELDS}
    for k in range(n_chunks):
        with np.load(path / f"chunk_{k:05d}.npz", allow_pickle=False) as chunk:
            for name in FIELDS:
                parts[name].append(chunk[name])
    records = {name: np.concatenate(parts[name]) if parts[name] else np.zeros(0)
               for name in FIELDS}
    return records, checkpoint
