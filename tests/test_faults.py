"""Faults: whatever stops, fills, damages or mismatches a run must not lose or mix its data.

Each test reproduces one fault and asserts what the user is left with.  Sections:

* store faults (issue 12): signals, a full disk, truncated and corrupt files, mismatched
  systems, existing run directories;
* (numerical faults are appended below the store section).
"""

import errno
import json
import os
import re
import shlex
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

import skfem_cable as sc
from skfem_cable.cli import command as cli
from skfem_cable.core.records import ENERGIES, FIELDS, SETTINGS
from skfem_cable.io import (
    RunExists,
    RunStore,
    StoreCorrupt,
    StoreError,
    StoreMismatch,
    export,
    resume,
    run_observers,
)
from skfem_cable.io.legacy import LEGACY_CHECKPOINT, chunk_name
from skfem_cable.io.schema import DEFAULT_FIELDS, STORE
from skfem_cable.loads.coulomb import SolarWindForce
from skfem_cable.scenes import classics
from skfem_cable.util import atomic

# ===========================================================================================
# Store faults (issue 12): the run store never loses or mixes data
# ===========================================================================================

#: The fields a default store keeps (all but the accelerations).
STORED = [f for f in FIELDS if f in DEFAULT_FIELDS]

#: A small run: 3-element pendulum, every step saved, commits of 4 steps.
RUN = dict(dt=1e-3, every=1, rho_inf=0.8)


def pendulum(n=3):
    return classics.pendulum(n_elements=n).system


def reference(t_end, system=None, **kw):
    return sc.simulate(system or pendulum(), t_end=t_end, **{**RUN, **kw})


def assert_same(result, ref, n=None, fields=STORED):
    """The first ``n`` saved steps of ``result`` are bit for bit those of ``ref``."""
    n = len(result) if n is None else n
    assert len(result) >= n
    assert np.all(np.diff(result.t) > 0), "saved times are not increasing"
    for name in fields:
        assert np.array_equal(getattr(result, name)[:n], getattr(ref, name)[:n]), name


def temporaries(folder):
    return [p for p in Path(folder).rglob("*") if atomic.is_temporary(p)]


def manifest(run):
    return json.loads((Path(run) / "manifest.json").read_text())


# --- SIGKILL at any moment ----------------------------------------------------------------
def _fork(child):
    """Run ``child()`` in a forked process; returns the signal that ended it (0 if none)."""
    pid = os.fork()
    if pid == 0:  # pragma: no cover (child)
        code = 0
        try:
            child()
        except BaseException:
            code = 3
        finally:
            os._exit(code)
    _, status = os.waitpid(pid, 0)
    return os.WTERMSIG(status) if os.WIFSIGNALED(status) else 0


def _killed_at(run, pattern, k, t_end=0.011):
    """A child that stores a run in ``run`` and SIGKILLs itself in the middle of the
    ``k``-th write of a file whose name contains ``pattern`` (half of it written)."""

    def child():
        real, count = atomic._write, [0]

        def write(f, data):
            if pattern in f.name:
                count[0] += 1
                if count[0] == k:
                    raw = memoryview(data).cast("B")
                    real(f, raw[: len(raw) // 2])
                    f.flush()
                    os.kill(os.getpid(), signal.SIGKILL)
                    time.sleep(60)
            real(f, data)

        atomic._write = write
        sc.simulate(pendulum(), t_end=t_end, observers=[RunStore(run, chunk=4)], **RUN)

    return _fork(child)


@pytest.mark.skipif(not hasattr(os, "fork"), reason="needs fork")
@pytest.mark.parametrize("pattern, k, kept", [
    ("results.zarr/q/zarr.json", 1, 0),   # creating the store
    ("results.zarr/q/zarr.json", 3, 4),   # 2nd commit: resizing the arrays
    ("results.zarr/q/c/1/0", 1, 4),       # 2nd commit: writing a chunk
    ("results.zarr/zarr.", 4, 4),         # 2nd commit: consolidated metadata
    ("checkpoint_", 2, 4),                # 2nd commit: its checkpoint
    ("manifest.json", 3, 4),              # 2nd commit: its manifest
    ("manifest.json", 4, 8),              # 3rd commit, right after the 2nd
])
def test_sigkill_at_any_moment_leaves_a_loadable_store_that_continues(tmp_path, pattern, k,
                                                                        kept):
    """Before: a killed ``np.savez`` could leave a torn chunk and a checkpoint ahead of the
    chunks.  Now the directory loads with every step of the last complete commit, the
    half-written file is a temporary that is cleaned up, and the run continues bit for
    bit."""
    run = tmp_path / "run"
    assert _killed_at(run, pattern, k) == signal.SIGKILL
    assert temporaries(run), "the child was not killed in the middle of a write"
    ref = reference(0.011)
    loaded = sc.Result.load(run, pendulum())
    assert len(loaded) == kept
    assert_same(loaded, ref)
    if kept == 0:  # killed before the first commit: nothing to continue, but no mix-up
        with pytest.raises(StoreError, match="no checkpoint yet"):
            resume(run)
        return
    resumed = sc.simulate(pendulum(), t_end=0.011, resume=resume(run),
                          observers=[RunStore(run, chunk=4)], **RUN)
    assert_same(resumed, ref, len(ref))
    assert_same(sc.Result.load(run, pendulum()), ref, len(ref))
    assert not temporaries(run)
    assert len(list(run.glob("checkpoint_*.npz"))) == 1


# --- SIGTERM and SIGINT to a running `skfem-cable run` --------------------------------------
def _default_sigint():  # pragma: no cover (child)
    # a shell may start background jobs with SIGINT ignored; Python then never raises
    # KeyboardInterrupt.  The child gets the default, as in a terminal.
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def _cli(*args, cwd):
    return subprocess.Popen([sys.executable, "-m", "skfem_cable.cli", *args], cwd=cwd,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            preexec_fn=_default_sigint)


@pytest.mark.skipif(os.name != "posix", reason="POSIX signals")
@pytest.mark.parametrize("signum, status", [(signal.SIGTERM, 143), (signal.SIGINT, 130)])
def test_signal_stores_every_saved_step_and_resume_continues(tmp_path, signum, status):
    """Before: SIGTERM killed the run and lost the steps since the last 200-step chunk;
    SIGINT kept them but a restart could duplicate a step.  Now both store every saved
    step and a checkpoint, exit with the shell's status and say how to continue, and
    ``--resume`` continues bit for bit."""
    out = tmp_path / "run"
    args = ["run", "pendulum", "--elements", "4", "--t-end", "60", "--no-progress",
            "--no-plots", "--out", str(out)]
    proc = _cli(*args, cwd=tmp_path)
    try:
        deadline = time.monotonic() + 120
        while not (out / "vtu" / "series_000025.vtu").exists():  # none committed yet
            assert proc.poll() is None, proc.communicate()
            assert time.monotonic() < deadline, "the run did not start"
            time.sleep(0.05)
        proc.send_signal(signum)
        _, err = proc.communicate(timeout=60)
    finally:
        proc.kill()
    assert proc.returncode == status, err
    assert f"interrupted by {signal.Signals(signum).name}" in err
    assert "continue the run with: skfem-cable run pendulum" in err and "--resume" in err
    m = manifest(out)
    assert m["status"] == "interrupted" and not temporaries(out)
    series = [t for t, _ in export.read_pvd(out / "series.pvd")]
    # every saved step (the series may lag by the step the signal interrupted: the .vtu
    # the test waits for is written before the .pvd lists it, and the signal may come
    # between the two)
    assert 25 <= len(series) <= m["saved"] <= len(series) + 1
    stored = sc.Result.load(out, classics.pendulum(n_elements=4).system)
    assert list(stored.t[: len(series)]) == series
    # continue with the printed command line, a little further than the signal
    t_end = (m["last"]["index"] + 35) * 1e-3
    line = err.split("continue the run with: skfem-cable ")[1].splitlines()[0]
    argv = shlex.split(line)
    argv[argv.index("--t-end") + 1] = repr(t_end)
    assert cli.main(argv) == 0
    system = classics.pendulum(n_elements=4)
    ref = sc.simulate(system.system, t_end=t_end, dt=1e-3, every=10, rho_inf=0.8,
                      initial=system.initial)
    stored = sc.Result.load(out, system.system)
    assert_same(stored, ref, len(ref))
    assert manifest(out)["status"] == "complete"


def test_ctrl_c_between_a_step_and_its_checkpoint_duplicates_no_step(tmp_path, monkeypatch):
    """Before: Ctrl-C inside the store's ``saved`` (after the step was queued, before its
    checkpoint was taken) stored the step with the previous checkpoint, and the restart
    saved it twice (time not monotonic).  Now a step and its checkpoint are queued
    together."""
    from skfem_cable.solvers.galpha import GeneralizedAlpha

    calls, real = [0], GeneralizedAlpha.snapshot

    def snapshot(self):
        calls[0] += 1
        if calls[0] == 7:
            raise KeyboardInterrupt
        return real(self)

    monkeypatch.setattr(GeneralizedAlpha, "snapshot", snapshot)
    with pytest.raises(KeyboardInterrupt) as info:
        sc.simulate(pendulum(), t_end=0.011, observers=[RunStore(tmp_path, chunk=4)], **RUN)
    monkeypatch.setattr(GeneralizedAlpha, "snapshot", real)
    assert len(info.value.result) >= 6  # the store had steps 0-5, the recorder 0-6
    assert manifest(tmp_path)["saved"] == 6 and manifest(tmp_path)["last"]["index"] == 5
    resumed = sc.simulate(pendulum(), t_end=0.011, resume=resume(tmp_path),
                          observers=[RunStore(tmp_path, chunk=4)], **RUN)
    ref = reference(0.011)
    assert_same(resumed, ref, len(ref))
    assert_same(sc.Result.load(tmp_path, pendulum()), ref, len(ref))


@pytest.fixture
def python_sigint():
    """SIGINT raising ``KeyboardInterrupt`` during the test, as in a terminal."""
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, previous)


def test_signal_during_a_commit_waits_for_it(tmp_path, monkeypatch, python_sigint):
    """A Ctrl-C that arrives while a commit writes its files is held until the commit is
    complete, then ends the run; no file is torn and nothing is lost.  (SIGINT gets
    Python's handler here: a shell starts background jobs with it ignored, and then the
    held signal is rightly dropped.)"""
    real, sent = atomic._write, []

    def write(f, data):
        if "q/c/1/" in f.name and not sent:
            sent.append(True)
            os.kill(os.getpid(), signal.SIGINT)
            time.sleep(0.05)  # the signal arrives while the commit goes on
        real(f, data)

    monkeypatch.setattr(atomic, "_write", write)
    with pytest.raises(KeyboardInterrupt):
        sc.simulate(pendulum(), t_end=0.03, observers=[RunStore(tmp_path, chunk=4)], **RUN)
    m = manifest(tmp_path)
    assert sent and m["commits"] == 2 and m["saved"] == 8 and m["status"] == "interrupted"
    assert_same(sc.Result.load(tmp_path, pendulum()), reference(0.03), 8)
    assert not temporaries(tmp_path)


# --- a full disk ------------------------------------------------------------------------------
def _bytes_written(monkeypatch, budget=None):
    """Count the bytes the store writes; past ``budget`` raise ``OSError(ENOSPC)`` (a
    tiny full file system)."""
    real, total = atomic._write, [0]

    def write(f, data):
        size = memoryview(data).nbytes
        if budget is not None and total[0] + size > budget:
            raw = memoryview(data).cast("B")
            real(f, raw[: max(budget - total[0], 0)])  # what fits, then the error
            total[0] = budget
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), f.name)
        total[0] += size
        real(f, data)

    monkeypatch.setattr(atomic, "_write", write)
    return total


@pytest.fixture(scope="module")
def full_run(tmp_path_factory):
    """The reference of the full-disk runs and the bytes their store writes."""
    with pytest.MonkeyPatch.context() as monkeypatch:
        total = _bytes_written(monkeypatch)
        ref = sc.simulate(pendulum(), t_end=0.02, **RUN,
                          observers=[RunStore(tmp_path_factory.mktemp("full"), chunk=4)])
    return ref, total[0]


@pytest.mark.parametrize("fraction", [0.0, 0.05, 0.3, 0.55, 0.8, 0.995])
def test_full_disk_keeps_every_step_and_cleans_up(tmp_path, monkeypatch, fraction, full_run):
    """Before: a full disk lost the steps held in memory, left ``*.tmp.npz`` files and the
    exception had no ``result``.  Now the directory holds every complete commit and no
    temporary file, the exception carries all saved steps (``.result``) and says where
    they are, and once there is room again the run continues bit for bit."""
    ref, total = full_run
    _bytes_written(monkeypatch, budget=int(fraction * total))
    run = tmp_path / "run"
    with pytest.raises(OSError) as info:
        sc.simulate(pendulum(), t_end=0.02, observers=[RunStore(run, chunk=4)], **RUN)
    err = info.value
    assert err.errno == errno.ENOSPC
    assert not temporaries(run)
    if (run / "manifest.json").exists():  # no checkpoint but the committed one
        committed = manifest(run)["checkpoint"]
        assert [p.name for p in run.glob("checkpoint_*")] == ([committed["file"]]
                                                               if committed else [])
    partial = err.result  # every saved step: those on disk and those held in memory
    assert_same(partial, ref)
    monkeypatch.undo()  # room again
    if not (run / "manifest.json").exists():  # not even the first file fitted
        assert fraction == 0.0 and len(partial) == 0
        return
    assert any("run store" in note for note in getattr(err, "__notes__", ["run store"]))
    m = manifest(run)
    on_disk = sc.Result.load(run, pendulum())
    assert len(on_disk) == m["saved"] <= len(partial)
    assert_same(on_disk, ref)
    if m["checkpoint"] is None:
        with pytest.raises(StoreError, match="no checkpoint yet"):
            resume(run)
        return
    resumed = sc.simulate(pendulum(), t_end=0.02, resume=resume(run),
                          observers=[RunStore(run, chunk=4)], **RUN)
    assert_same(resumed, ref, len(ref))
    assert_same(sc.Result.load(run, pendulum()), ref, len(ref))


# --- truncated and corrupt files ------------------------------------------------------------
@pytest.fixture
def stored(tmp_path):
    """A finished run of 21 saved steps in commits of 4."""
    run = tmp_path / "run"
    sc.simulate(pendulum(), t_end=0.02, observers=[RunStore(run, chunk=4)], **RUN)
    return run


def _truncate(path):
    data = path.read_bytes()
    path.write_bytes(data[: len(data) // 2])


def _flip(path):
    data = bytearray(path.read_bytes())
    data[len(data) // 2] ^= 0xFF
    path.write_bytes(bytes(data))


@pytest.mark.parametrize("damage", [_truncate, _flip, Path.unlink])
def test_damaged_chunk_is_named(stored, damage):
    """Before: a truncated chunk raised a bare ``BadZipFile``.  Now the error names the
    file and says what to do (restore it or run again into a new directory: not
    ``--overwrite``, which would delete the steps that still read); a flipped byte is
    caught by the checksum and a missing chunk is not read as NaN."""
    chunk = stored / STORE / "v" / "c" / "2" / "0"
    damage(chunk)
    with pytest.raises(StoreCorrupt) as info:
        sc.Result.load(stored, pendulum())
    assert info.value.path == chunk and str(chunk) in str(info.value)
    assert "new directory (--out)" in str(info.value) and "--overwrite" not in str(info.value)


def test_truncated_checkpoint_is_named_and_the_steps_still_load(stored):
    ck = stored / manifest(stored)["checkpoint"]["file"]
    _truncate(ck)
    with pytest.raises(StoreCorrupt, match="truncated or corrupt") as info:
        resume(stored)
    assert info.value.path == ck and "Result.load" in str(info.value)
    assert len(sc.Result.load(stored, pendulum())) == 21


def test_corrupt_manifest_is_named(stored):
    _truncate(stored / "manifest.json")
    with pytest.raises(StoreCorrupt, match="manifest.json is corrupt"):
        sc.Result.load(stored, pendulum())


def _legacy_run(folder, system, n_chunks=2, per_chunk=3):
    """A run directory of the old format (``chunk_NNNNN.npz`` + ``checkpoint.npz``)."""
    result = sc.simulate(system, t_end=n_chunks * per_chunk * 1e-3 - 1e-3, **RUN)
    folder.mkdir()
    for k in range(n_chunks):
        part = slice(k * per_chunk, (k + 1) * per_chunk)
        np.savez_compressed(folder / chunk_name(k),
                            **{f: getattr(result, f)[part] for f in FIELDS})
    np.savez_compressed(folder / LEGACY_CHECKPOINT, chunks=n_chunks, index=5,
                        settings=np.zeros(len(SETTINGS)), stat_steps=5)
    return result


def test_old_run_directories_load_or_say_why_not(tmp_path):
    old = tmp_path / "old"
    result = _legacy_run(old, pendulum())
    back = sc.Result.load(old, pendulum())
    assert_same(back, result, len(result), fields=FIELDS)
    with pytest.raises(StoreMismatch, match="old format"):
        sc.Result.load(old, pendulum(4))
    with pytest.raises(StoreError, match="old format.*cannot continue"):
        resume(old)
    _truncate(old / chunk_name(1))
    with pytest.raises(StoreCorrupt, match="chunk_00001.npz is truncated or corrupt"):
        sc.Result.load(old, pendulum())


# --- mismatched systems -----------------------------------------------------------------------
def test_load_or_resume_with_another_system_raises(stored):
    """Before: ``Result.load(dir, other_system)`` returned arrays of the wrong shape or,
    worse, of the right shape and the wrong meaning.  Now the fingerprint must match."""
    with pytest.raises(StoreMismatch, match="another system"):
        sc.Result.load(stored, pendulum(4))  # other size
    stiffer = classics.pendulum(n_elements=3, E=8e10).system  # same sizes, other physics
    with pytest.raises(StoreMismatch, match="same bodies and sizes"):
        sc.Result.load(stored, stiffer)
    with pytest.raises(StoreMismatch):
        resume(stored, stiffer)
    with pytest.raises(StoreMismatch):  # the store of the continued run checks too
        sc.simulate(stiffer, t_end=0.03, resume=resume(stored), observers=[RunStore(stored)],
                    **RUN)
    with pytest.raises(StoreMismatch, match="newton: stored 'modified', given 'full'"):
        sc.simulate(pendulum(), t_end=0.03, resume=resume(stored), newton="full",
                    observers=[RunStore(stored)], **RUN)
    assert len(sc.Result.load(stored, stiffer, check=False)) == 21
    assert manifest(stored)["saved"] == 21  # nothing was written by the refused runs


def test_resume_into_another_directory_copies_or_refuses(tmp_path):
    """Resuming the run of A with output B: B must hold the whole run (copied), or the
    run is refused; B's store never mixes two runs."""
    a, b, c = tmp_path / "a", tmp_path / "b", tmp_path / "c"
    ref = reference(0.02)
    with pytest.raises(KeyboardInterrupt):
        sc.simulate(pendulum(), t_end=0.02, observers=[RunStore(a, chunk=4), _StopAt(9)],
                    **RUN)
    with pytest.raises(StoreError, match="holds no stored run to continue"):
        sc.simulate(pendulum(), t_end=0.02, resume=resume(a), observers=[RunStore(b)], **RUN)
    result = sc.simulate(pendulum(), t_end=0.02, resume=resume(a),
                         observers=run_observers(b, progress=False, source=a), **RUN)
    assert_same(result, ref, len(ref))
    assert_same(sc.Result.load(b, pendulum()), ref, len(ref))
    assert len(sc.Result.load(a, pendulum())) == 10  # A is left as it was
    # B now holds the finished run: continuing A's interrupted state into it is refused
    with pytest.raises(StoreError, match="resumed at t = 0.009"):
        sc.simulate(pendulum(), t_end=0.02, resume=resume(a), observers=[RunStore(b)],
                    **RUN)
    # and a new run does not silently replace it
    with pytest.raises(RunExists, match="already holds a run"):
        sc.simulate(pendulum(), t_end=0.02, observers=[RunStore(b)], **RUN)
    sc.simulate(pendulum(), t_end=0.005, observers=[RunStore(c), RunStore(b, overwrite=True)],
                **RUN)
    assert len(sc.Result.load(b, pendulum())) == 6


class _StopAt(sc.Observer):
    """Ctrl-C right after saved step ``index``."""

    def __init__(self, index):
        self.index = index

    def saved(self, run, step):
        if step.index == self.index:
            raise KeyboardInterrupt


# --- existing run directories (the command line) -------------------------------------------
def _run(out, *extra):
    return cli.main(["run", "pendulum", "--elements", "3", "--no-progress", "--no-plots",
                     "--out", str(out), *extra])


def test_existing_run_directory_is_refused_replaced_or_continued(tmp_path, capsys):
    """Before: ``--out DIR`` silently overwrote a previous run and left its orphaned
    files, which ``Result.load`` and a restart could mix with the new ones.  Now another
    run is refused (exit 2, naming it); ``--overwrite`` removes only the files the
    package wrote; ``--resume`` continues only the same scene."""
    out = tmp_path / "run"
    assert _run(out, "--t-end", "0.05") == 0
    (out / "notes.txt").write_text("mine")
    before = (out / "manifest.json").read_bytes()
    capsys.readouterr()
    assert _run(out, "--t-end", "0.02") == 2
    err = capsys.readouterr().err
    assert str(out) in err and "already holds a run" in err and "scene 'pendulum'" in err
    assert "--overwrite" in err and "--resume" in err
    assert (out / "manifest.json").read_bytes() == before
    # a stray file of the old format is an earlier run's too
    (out / "chunk_00000.npz").write_bytes(b"old")
    assert _run(out, "--t-end", "0.02", "--overwrite") == 0
    assert not (out / "chunk_00000.npz").exists() and (out / "notes.txt").read_text() == "mine"
    assert len(sc.Result.load(out, pendulum())) == 3
    assert len(list((out / "vtu").glob("*.vtu"))) == 3  # the 6 of the first run are gone
    summary = json.loads((out / "summary.json").read_text())
    assert summary["files"]["store"] == STORE and summary["store"]["saved_steps"] == 3
    # --resume continues (a finished run to a later end), only with the same scene
    assert _run(out, "--t-end", "0.04", "--resume") == 0
    assert len(sc.Result.load(out, pendulum())) == 5
    capsys.readouterr()
    assert cli.main(["run", "pendulum", "--elements", "4", "--no-progress", "--no-plots",
                     "--t-end", "0.06", "--out", str(out), "--resume"]) == 2
    assert "another system" in capsys.readouterr().err
    assert _run(tmp_path / "empty", "--resume") == 2
    assert "no run store to continue" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        _run(out, "--resume", "--overwrite")


def test_default_fields_leave_out_the_accelerations(tmp_path):
    """The ``fields`` option: the default store has no ``a`` (it reads back as NaN), the
    full state for a restart is in the checkpoint, and ``fields=FIELDS`` keeps it."""
    sc.simulate(pendulum(), t_end=0.005, observers=[RunStore(tmp_path / "d")], **RUN)
    sc.simulate(pendulum(), t_end=0.005, observers=[RunStore(tmp_path / "f", fields=FIELDS)],
                **RUN)
    ref = reference(0.005)
    default = sc.Result.load(tmp_path / "d", pendulum())
    assert np.isnan(default.a).all() and "a" not in manifest(tmp_path / "d")["fields"]
    assert_same(default, ref, fields=STORED)
    assert_same(sc.Result.load(tmp_path / "f", pendulum()), ref, fields=FIELDS)
    with pytest.raises(ValueError, match="unknown field 'acc'"):
        RunStore(tmp_path / "x", fields=["q", "acc"])
    assert set(ENERGIES) <= set(DEFAULT_FIELDS)


# ===========================================================================================
# Numerical faults (issue 12): the instability guard and clear errors for bad numbers
# ===========================================================================================
def spinning(dt=0.45, t_end=2.25, **kwargs):
    scene = classics.spinning_tether(n_elements=10, spin=2.0, tip_mass=0.5)
    return sc.simulate(scene.system, t_end=t_end, dt=dt, initial=scene.initial,
                       rho_inf=0.95, **kwargs)


def test_blow_up_without_the_guard_is_what_it_prevents():
    """The fault: the spinning tether at dt = 0.45 s, nearly undamped (``rho_inf =
    0.95``), gains 697x its energy and returns normally when the guard is off
    (``energy_tol=None``).  The scene is chaotic in the step and the method: which steps
    blow up moves with every change of Newton's choices (it blew up at dt = 0.75 s
    before steps of long-step stretches started from a fresh tangent,
    ``GeneralizedAlpha._choose_newton``, and at rho_inf = 0.8 before those stretches)."""
    r = spinning(energy_tol=None)
    assert r.energy["total"].max() > 100 * r.energy["total"][0]


def test_guard_retries_smaller_and_keeps_energy_bounded():
    """With the guard (default) the same run rejects the growing steps, retries them
    smaller and ends with its energy balance never above the start."""
    r = spinning()
    assert r.stats["rejected"] > 0
    E = r.energy
    assert E["balance"].max() <= 0.05 * np.abs(E["total"]).max()
    assert E["total"].max() <= E["total"][0] * (1 + 1e-9)


def test_guard_stops_with_a_diagnostic_and_the_results():
    """With two halvings allowed the guard stops at the growing step: the message names the
    time, the step, the energy history and the body; the result holds the steps done."""
    with pytest.raises(sc.SimulationError) as info:
        spinning(max_halvings=2)
    msg = str(info.value)
    for part in ("t=0.5625", "h=0.113", "energy balance grew", "cable gained",
                 "last accepted steps", "t=0.45:"):
        assert part in msg, part
    assert len(info.value.result) >= 1 and info.value.result.t[0] == 0.0


def test_guard_sees_no_growth_in_round_off():
    """A large cable at rest: round-off energies (1e-16 J) are no instability."""
    cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], 2000, sc.Section.circular(1e-3, 2e11, 7850))
    r = sc.simulate(sc.System([cable]).pin(cable.node(0)), 3e-3, 1e-3)
    assert r.stats["rejected"] == 0


def test_guard_keeps_driven_work_in_the_balance():
    """A pivot that drives a pendulum does work on it (booked as external work): the
    guard sees no growth, the balance closes within the numerical dissipation."""
    w, a = 2 * np.pi * 10, 0.06
    section = sc.Section.circular(radius=0.02, E=2e11, rho=7850.0)
    pivot = np.array([0, a, 0.0])
    rod = sc.Cable.straight(pivot, pivot + [np.sin(0.1), np.cos(0.1), 0], 3, section)
    system = sc.System([rod]).pin(rod.node(0), lambda t: np.array([0, a * np.cos(w * t), 0]))
    system.add_gravity([0, -9.81, 0])
    r = sc.simulate(system, 1.0, 2 * np.pi / w / 50)
    E = r.energy
    assert r.stats["rejected"] == 0
    assert np.abs(E["external_work"]).max() > 10.0
    assert np.abs(E["balance"]).max() < 0.01 * np.abs(E["external_work"]).max()


@pytest.mark.parametrize("kwargs, match", [
    ({"max_halvings": float("nan")}, "max_halvings must be an integer in"),
    ({"max_halvings": 52}, "max_halvings must be an integer in"),
    ({"dt": 1e-300}, "steps"),
    ({"dt": 1e-3, "t_start": 1e13, "t_end": 1e13 + 1.0}, "does not advance the time"),
    ({"energy_tol": -1.0}, "energy_tol must be"),
])
def test_bad_step_settings_are_refused_at_once(kwargs, match):
    cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], 2, sc.Section.circular(1e-3, 2e11, 7850))
    settings = {"t_end": 1.0, "dt": 1e-3, **kwargs}
    with pytest.raises(ValueError, match=match):
        sc.simulate(sc.System([cable]), **settings)


def test_bad_voltage_names_the_tether():
    cable = sc.Cable.straight([0, 0, 0], [0, 100, 0], 2, sc.Section.circular(1e-3, 2e11, 7850),
                              name="tether 3")
    with pytest.raises(ValueError, match="voltage of tether 'tether 3' at t = 0.0 is nan"):
        SolarWindForce([cable], lambda t: float("nan"))
    load = SolarWindForce([cable], lambda t: 20e3 if t < 1 else -5.0)
    with pytest.raises(ValueError, match=r"at t = 2.0 is -5.0: it must be finite and >= 0"):
        load.coefficients(2.0)


def test_a_cable_too_large_for_memory_is_refused_with_the_estimate():
    with pytest.raises(ValueError, match=r"n_elements = 10000000000: .* needs about 2\.5e\+05"):
        sc.Cable.straight([0, 0, 0], [1, 0, 0], 10**10, sc.Section.circular(1e-3, 2e11, 7850))


def test_scene_file_cable_far_from_the_origin():
    """A 5 m cable 1000 km from the origin is a cable (an absolute tolerance used to call
    its ends equal); equal ends are still refused, naming the key."""
    from skfem_cable import scene_file

    text = """
[solver]
analysis = "dynamic"
t_end = 0.01
dt = 1e-3

[sections.wire]
E = 2e11
rho = 7850.0
radius = 5e-4

[[cables]]
name = "far"
section = "wire"
start = [1e6, 0, 0]
end = [{end}, 0, 0]
elements = 2
"""
    spec = scene_file.loads_text(text.format(end="1000005.0"))
    assert spec.system.bodies[0].length == pytest.approx(5.0, rel=1e-12)
    with pytest.raises(scene_file.SceneFileError, match="end"):
        scene_file.loads_text(text.format(end="1e6"))


def test_heavy_numerical_dissipation_is_reported(capsys):
    """The guard stops growth, not numerical dissipation: a run that lost about half its
    energy to a coarse step says so on stderr (54.6 % measured; 47.9 and 48.0 % while the
    integrator started from ``abar_0 = a_0``: the run halves most of its steps, and where
    Newton refreshes its tangent moves the figure a little)."""
    rc = cli.main(["run", "spinning-tether", "--dt", "0.5", "--t-end", "2", "--no-plots"])
    assert rc == 0
    drift = re.search(r"the energy balance drifted by ([\d.]+) %", capsys.readouterr().err)
    assert drift and 52 <= float(drift.group(1)) <= 57


def test_singular_matrix_names_the_unknown_with_either_solver():
    """An unconstrained cable under a load: the banded and the sparse factorization both
    name the coordinate where the matrix loses rank (the sparse one used to say '?')."""
    messages = {}
    for method in ("banded", "sparse"):
        cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], 3, sc.Section(E=1e9, A=1e-4, I=1e-10,
                                                                      rho=1e3))
        system = sc.System([cable])
        system.add_point_load(cable.node(-1), [1.0, 0, 0])
        with pytest.raises(sc.StaticConvergenceError) as err:
            sc.solve_static(system, method=method, max_bisections=0)
        messages[method] = str(err.value)
    for message in messages.values():
        assert "singular matrix at cable coordinate" in message and "?" not in message
    assert messages["banded"] == messages["sparse"]
