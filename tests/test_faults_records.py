"""Faults, round two: never a silent wrong answer.  A continued run is the stored one or
is refused with the reason; the record (manifest, summary) describes the data; one process
writes a run directory at a time; a message names the file, key or parameter and never
advises ``--overwrite`` for data that can be read.  ``test_faults.py`` holds round one.

Sections: resuming (what may and may not change), run directories shared between
processes (the lock), advice and messages (damaged stores, tracebacks, unclear errors).
"""

import json
import os
import shutil
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

import skfem_cable as sc
from skfem_cable.cli import command as cli
from skfem_cable.io import RunLocked, RunStore, StoreCorrupt, export, lock
from skfem_cable.io.progress import Progress
from skfem_cable.scenes import catalog, classics
from skfem_cable.scenes.catalog import pendulum_scene
from skfem_cable.study import run_point
from skfem_cable.util import atomic

#: Options of every small command-line run.
QUIET = ["--no-progress", "--no-plots"]


def _run(out, *extra, scene="pendulum"):
    """``skfem-cable run`` of a 3-element pendulum (by default) into ``out``."""
    args = ["run", scene, *QUIET, *(["--elements", "3"] if scene == "pendulum" else [])]
    return cli.main([*args, "--out", str(out), *extra])


def _manifest(run):
    return json.loads((Path(run) / "manifest.json").read_text())


def _edit_manifest(run, edit):
    manifest = _manifest(run)
    edit(manifest)
    (Path(run) / "manifest.json").write_text(json.dumps(manifest))


@pytest.fixture(scope="module")
def finished(tmp_path_factory):
    """A finished command-line run (pendulum, t = 0 .. 0.05 s, 6 saved steps)."""
    out = tmp_path_factory.mktemp("finished") / "run"
    assert _run(out, "--t-end", "0.05") == 0
    return out


@pytest.fixture
def run_dir(finished, tmp_path):
    """A copy of ``finished`` to damage."""
    return Path(shutil.copytree(finished, tmp_path / "run"))


def _spawn(*args, cwd):
    """``skfem-cable`` in a process of its own (Ctrl-C at its default, as in a terminal)."""
    return subprocess.Popen([sys.executable, "-m", "skfem_cable.cli", *args], cwd=cwd,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))


def _wait_for(path, proc, timeout=120):
    deadline = time.monotonic() + timeout
    while not path.exists():
        assert proc.poll() is None, proc.communicate()
        assert time.monotonic() < deadline, f"{path} did not appear"
        time.sleep(0.05)


# ===========================================================================================
# Resuming: the stored run, exactly, or a refusal with the reason
# ===========================================================================================
def test_resume_to_an_earlier_t_end_is_refused(run_dir, capsys):
    """Before: ``--resume --t-end 0.02`` on a run stored up to 0.05 s ended with exit 0 and
    status ``complete``, and the manifest and summary said ``t_end 0.02`` over data up to
    0.05 s.  Now it is refused, naming the stored end, and nothing changes."""
    before = {f: (run_dir / f).read_bytes() for f in ("manifest.json", "summary.json")}
    capsys.readouterr()
    assert _run(run_dir, "--t-end", "0.02", "--resume") == 2
    err = capsys.readouterr().err
    assert "holds the run up to t = 0.05 s" in err and "--t-end 0.05 or later" in err
    assert {f: (run_dir / f).read_bytes() for f in before} == before
    assert _run(run_dir, "--t-end", "0.05", "--resume") == 0  # the same end: nothing to do
    assert _manifest(run_dir)["last"]["t"] == 0.05


SCENE = """
title = "wire"
[solver]
t_end = 0.004
dt = 1e-3
every = 1
[sections.wire]
E = 2e11
rho = 7850.0
radius = {radius}
[[cables]]
name = "w"
section = "wire"
start = [0, 0, 0]
end = [1, 0, 0]
elements = 2
[[constraints]]
type = "pin"
node = {{ cable = "w", index = 0 }}
[loads]
gravity = [0, -9.81, 0]
[initial]
velocity = [0, {velocity}, 0]
"""


def test_resume_after_editing_initial_is_refused(tmp_path, capsys):
    """Before: a run continued after ``[initial]`` was edited (edits of material, mesh,
    step or saving were refused).  Now the ``[initial]`` table is a parameter of the run:
    an edit is refused naming it; the same file at another path continues."""
    scene, out = tmp_path / "wire.toml", tmp_path / "run"
    scene.write_text(SCENE.format(radius=1e-3, velocity=0.0))
    assert cli.main(["run", str(scene), *QUIET, "--out", str(out)]) == 0
    scene.write_text(SCENE.format(radius=1e-3, velocity=0.5))
    capsys.readouterr()
    assert cli.main(["run", str(scene), *QUIET, "--out", str(out), "--t-end", "0.006",
                     "--resume"]) == 2
    err = capsys.readouterr().err
    assert "other scene parameters (initial: stored {'velocity': [0, 0.0, 0]}" in err
    moved = tmp_path / "moved.toml"
    moved.write_text(SCENE.format(radius=1e-3, velocity=0.0))
    assert cli.main(["run", str(moved), *QUIET, "--out", str(out), "--t-end", "0.006",
                     "--resume"]) == 0
    assert _manifest(out)["saved"] == 7


def test_hand_edited_saved_count_is_refused_before_the_store_is_cut(run_dir, capsys):
    """Before: a manifest whose ``saved`` was lowered by hand continued from the
    checkpoint after the shortened data: a hole in the stored times.  Now the last
    committed step is checked against the checkpoint first, and the arrays stay whole."""
    _edit_manifest(run_dir, lambda m: m.update(saved=3))
    capsys.readouterr()
    assert _run(run_dir, "--t-end", "0.08", "--resume") == 2
    err = capsys.readouterr().err
    assert "manifest.json commits 3 saved steps, the last at step 20" in err
    assert "checkpoint_00000050.npz is at step 50" in err and "--overwrite" not in err
    assert xr.open_zarr(run_dir / "results.zarr").sizes["time"] == 6


def test_resume_names_the_scene_parameter_that_differs(tmp_path, capsys):
    """Before: ``--resume --alpha 20`` said "written by another system" and named no
    option, although the manifest records the scene's parameters.  Now it names them."""
    out = tmp_path / "esail"
    assert _run(out, "--elements", "2", "--t-end", "0.2", scene="esail") == 0
    capsys.readouterr()
    assert _run(out, "--elements", "2", "--t-end", "0.4", "--alpha", "20", "--resume",
                scene="esail") == 2
    assert "alpha_deg: stored 10.0, given 20.0" in capsys.readouterr().err


def test_wall_time_adds_up_the_sessions(run_dir):
    """Before: after a resume, ``wall_time`` counted the last session only.  Now the
    manifest adds up the sessions, and the summary gives both."""
    first = _manifest(run_dir)["wall_time"]
    assert first > 0
    assert _run(run_dir, "--t-end", "0.08", "--resume") == 0
    summary = json.loads((run_dir / "summary.json").read_text())
    assert summary["wall_time"] == pytest.approx(first + summary["session_wall_time"])
    assert _manifest(run_dir)["wall_time"] > first


# ===========================================================================================
# Run directories shared between processes: one writer, held by an OS lock
# ===========================================================================================
@pytest.mark.skipif(os.name != "posix", reason="fcntl locks")
def test_a_run_directory_is_held_by_one_process(tmp_path, capsys):
    """Before: ``--overwrite`` while another process wrote the same directory deleted its
    store (the first run died with a misleading error, orphan frames and a stale
    checkpoint stayed), two ``--resume`` both started, and two fresh runs were refused by
    luck of timing.  Now the writer holds a lock: the others are refused naming its PID
    and host, and once it is killed (-9) nothing blocks a ``--resume``."""
    out = tmp_path / "run"
    proc = _spawn("run", "pendulum", "--elements", "3", *QUIET, "--t-end", "600", "--out",
                  str(out), cwd=tmp_path)
    try:
        _wait_for(out / "vtu" / "series_000201.vtu", proc)  # after the first commit
        proc.send_signal(signal.SIGSTOP)  # a stopped writer holds its lock, idle
        holder = f"in use by another run: process {proc.pid} on host"
        for extra in (["--overwrite", "--elements", "5"], ["--resume"]):
            capsys.readouterr()
            assert _run(out, "--t-end", "0.05", *extra) == 2
            assert holder in capsys.readouterr().err
        with pytest.raises(RunLocked, match=holder):  # the Python API too
            sc.simulate(classics.pendulum(n_elements=3).system, 0.01, 1e-3,
                        observers=[RunStore(out, overwrite=True)])
    finally:
        proc.kill()
        proc.communicate()
    t_end = round(_manifest(out)["last"]["t"] + 0.03, 3)
    assert _run(out, "--t-end", repr(t_end), "--resume") == 0
    times = xr.open_zarr(out / "results.zarr").time.values
    assert times[-1] == t_end and (abs(times[1:] - times[:-1] - 0.01) < 1e-9).all()
    assert len(list(out.glob("checkpoint_*.npz"))) == 1
    assert not [p for p in out.rglob("*") if atomic.is_temporary(p)]


def test_lock_is_shared_by_nested_holds_and_refuses_other_threads(tmp_path):
    refused = []

    def other():
        try:
            with lock.hold(tmp_path):
                pass
        except RunLocked as err:
            refused.append(str(err))

    with lock.hold(tmp_path), lock.hold(tmp_path):  # the runner, then its store
        thread = threading.Thread(target=other)
        thread.start()
        thread.join()
    assert refused and f"process {os.getpid()} on host" in refused[0]
    with lock.hold(tmp_path):  # released
        pass


def test_temporary_file_names_are_unique(tmp_path, monkeypatch):
    """Before: every frame and the series were written through one fixed temporary name
    (``series.pvd.tmp``), so two writers clashed on it.  Now each write has its own."""
    used, write = [], export.meshio.write

    def recording(path, *args, **kwargs):
        used.append(Path(path))
        write(path, *args, **kwargs)

    monkeypatch.setattr(export.meshio, "write", recording)
    system = classics.pendulum(n_elements=2).system
    for _ in range(2):
        export.write_vtu(tmp_path / "a.vtu", system, sc.State(system, system.q0))
    assert used[0] != used[1] and all(atomic.is_temporary(p) for p in used)
    assert [p.name for p in tmp_path.iterdir()] == ["a.vtu"]


# ===========================================================================================
# Advice and messages: damaged stores, tracebacks, unclear errors
# ===========================================================================================
def test_lost_consolidated_metadata_is_read_around_and_repaired(run_dir):
    """Before: without the consolidated metadata in ``results.zarr/zarr.json`` loading
    said "the store is damaged; run again (--overwrite)" although every step was intact.
    Now the arrays are read from their own metadata and the consolidated one rewritten."""
    root = run_dir / "results.zarr"
    meta = json.loads((root / "zarr.json").read_text())
    del meta["consolidated_metadata"]
    (root / "zarr.json").write_text(json.dumps(meta))
    with pytest.warns(RuntimeWarning, match="written again"):
        result = sc.Result.load(run_dir, classics.pendulum(n_elements=3).system)
    assert len(result) == 6
    assert xr.open_zarr(root, consolidated=True).sizes["time"] == 6


def test_truncated_manifest_is_named_on_resume(run_dir, capsys):
    """Before: ``--resume`` said "no run store to continue (no manifest.json)" and advised
    ``--overwrite``.  Now it names the file and the damage, and advises no deletion."""
    text = (run_dir / "manifest.json").read_text()
    (run_dir / "manifest.json").write_text(text[: len(text) // 2])
    capsys.readouterr()
    assert _run(run_dir, "--t-end", "0.08", "--resume") == 2
    err = capsys.readouterr().err
    assert "manifest.json is corrupt: truncated" in err and "--overwrite" not in err


@pytest.mark.parametrize("edit, named", [
    (lambda m: m.pop("variables"), "it has no 'variables' (a list of variable names)"),
    (lambda m: m.pop("chunk"), "it has no 'chunk' (an integer >= 1)"),
    (lambda m: m.update(chunk=0), "'chunk' is 0, not an integer >= 1"),
])
def test_manifest_without_a_key_is_named(run_dir, capsys, edit, named):
    """Before: ``KeyError`` and ``ZeroDivisionError`` tracebacks.  Now the key and what it
    accepts are named, on ``--resume`` and on loading."""
    _edit_manifest(run_dir, edit)
    capsys.readouterr()
    assert _run(run_dir, "--t-end", "0.08", "--resume") == 2
    assert named in capsys.readouterr().err
    with pytest.raises(StoreCorrupt, match=named.replace("(", r"\(").replace(")", r"\)")):
        sc.Result.load(run_dir, classics.pendulum(n_elements=3).system)


@pytest.fixture
def read_only(monkeypatch):
    """Make folders read-only (mode 0o555); for root, whom modes do not stop,
    ``os.access`` answers as for any other user."""
    folders, access = [], os.access

    def user_access(path, mode, **kwargs):
        if os.geteuid() == 0 and mode & os.W_OK and Path(path).resolve() in folders:
            return False
        return access(path, mode, **kwargs)

    monkeypatch.setattr(os, "access", user_access)

    def make(path):
        path.chmod(0o555)
        folders.append(path.resolve())
        return path

    yield make
    for folder in folders:
        folder.chmod(0o755)


def test_read_only_directories_are_refused_before_any_work(tmp_path, run_dir, read_only,
                                                           monkeypatch, capsys):
    """Before: a read-only parent of ``--out`` raised a ``PermissionError`` traceback from
    ``mkdir`` after the scene was built; ``--resume``/``--overwrite`` on a read-only run
    directory a traceback too.  Now each is refused at once, naming the directory."""
    (tmp_path / "parent").mkdir()
    parent = read_only(tmp_path / "parent")
    monkeypatch.setattr(catalog, "run_scene", lambda *a: pytest.fail("the scene was built"))
    for out, extra, said in ((parent / "run", [], f"{parent} is read-only"),
                             (read_only(run_dir), ["--resume"], "is read-only"),
                             (run_dir, ["--overwrite"], "is read-only")):
        capsys.readouterr()
        assert _run(out, "--t-end", "0.08", *extra) == 2
        assert said in capsys.readouterr().err


@pytest.mark.parametrize("content, message", [
    ("x = " + "[" * 5000 + "]" * 5000 + "\n", "nested deeper than the TOML reader goes"),
    (b'title = "caf\xe9"\n', "not a UTF-8 text file (byte 0xe9 at offset 12)"),
    (bytes(range(256)), "not a UTF-8 text file (byte 0x80 at offset 128)"),
    (SCENE.format(radius=1e-200, velocity=0), "sections.wire.radius is out of range"),
])
def test_scene_file_errors_name_the_file_and_key(tmp_path, capsys, content, message):
    """Before: a ``RecursionError`` traceback, ``'utf-8' codec can't decode ...`` without
    the file, ``A must be finite and > 0, got 0.0`` without the key."""
    scene = tmp_path / "bad.toml"
    if isinstance(content, str):
        scene.write_text(content)
    else:
        scene.write_bytes(content)
    assert cli.main(["run", str(scene), *QUIET]) == 2
    err = capsys.readouterr().err
    assert f"{scene}: " in err and message in err


def test_empty_out_is_refused(tmp_path, monkeypatch, capsys):
    """Before: ``--out ""`` (an unset variable) wrote the run into the current directory."""
    monkeypatch.chdir(tmp_path)
    with pytest.raises(SystemExit) as info:
        _run("", "--t-end", "0.01")
    assert info.value.code == 2 and "argument --out: is empty" in capsys.readouterr().err
    assert not list(tmp_path.iterdir())


def test_truncated_summary_of_a_sweep_point_is_regenerated(tmp_path):
    """Before: a point whose ``summary.json`` was truncated was marked failed with a bare
    ``JSONDecodeError``, its complete store unused.  Now the summary is written again
    from the store."""
    params, out = {"elements": 2, "t_end": 0.05}, tmp_path / "point"
    assert run_point(pendulum_scene, params, out)["status"] == "complete"
    summary = out / "summary.json"
    text = summary.read_text()
    summary.write_text(text[: len(text) // 2])
    record = run_point(pendulum_scene, params, out)
    assert record["status"] == "complete" and record["error"] == ""
    assert json.loads(summary.read_text())["sweep"]["parameters"] == params
    assert _manifest(out)["saved"] == 6


def test_ctrl_c_on_a_sweep_writes_the_finished_points(tmp_path, monkeypatch, capsys):
    """Before: a ``KeyboardInterrupt`` traceback, the scheduler's noise and no
    ``study.zarr`` of the points finished.  Now the study holds them (the others
    ``interrupted``), the command exits with 130 and says how to continue."""
    def interrupt(self, *args):
        raise KeyboardInterrupt

    monkeypatch.setattr(Progress, "update", interrupt)  # Ctrl-C as the first run is in
    out = tmp_path / "study"
    assert cli.main(["sweep", "pendulum", "--param", "elements=2,3", "--t-end", "0.02",
                     "--workers", "1", "--no-progress", "--out", str(out)]) == 130
    err = capsys.readouterr().err
    assert "interrupted by SIGINT" in err and "holds the 1 of 2 runs finished" in err
    assert "continue the study with: skfem-cable sweep pendulum" in err
    assert "Traceback" not in err
    study = xr.open_zarr(out / "study.zarr")
    assert sorted(study.status.values) == ["complete", "interrupted"]


@pytest.mark.skipif(os.name != "posix", reason="POSIX signals")
def test_sigterm_ends_a_rod_chain_run_saying_what_it_left(tmp_path):
    """Before: ``hanging-chain`` ended silently on SIGTERM, and said "nothing was stored"
    on SIGINT while hundreds of frames existed; then it named the frames kept but could
    not be continued.  Now its run store commits the steps so far and the run continues
    from them with the command it prints."""
    out = tmp_path / "chain"
    proc = _spawn("run", "hanging-chain", *QUIET, "--t-end", "20", "--out", str(out),
                  cwd=tmp_path)
    try:
        _wait_for(out / "vtu" / "series_000005.vtu", proc)
        proc.send_signal(signal.SIGTERM)
        _, err = proc.communicate(timeout=60)
    finally:
        proc.kill()
    assert proc.returncode == 143, err
    manifest = json.loads((out / "manifest.json").read_text())
    last = manifest["last"]["t"]
    assert manifest["status"] == "interrupted" and manifest["saved"] > 50
    assert (f"interrupted by SIGTERM; {out} holds {manifest['saved']} saved steps up to "
            f"t = {last:.6g} s" in err)
    assert "--resume" in err.splitlines()[-1]
    t_end = f"{last + 0.01:.4f}"
    assert cli.main(["run", "hanging-chain", *QUIET, "--t-end", t_end, "--out", str(out),
                     "--resume"]) == 0
    times = xr.open_zarr(out / "results.zarr")["time"].values
    assert times[-1] == pytest.approx(float(t_end)) and len(times) == manifest["saved"] + 100
    np.testing.assert_allclose(np.diff(times), 1e-4, rtol=1e-9)  # no gap, no repeat


def test_zero_clamp_direction_names_the_key(tmp_path, capsys):
    """Before: a zero clamp ``direction`` in a scene file was refused without the key."""
    scene = tmp_path / "clamp.toml"
    scene.write_text(SCENE.format(radius=1e-3, velocity=0).replace(
        'type = "pin"', 'type = "clamp"\ndirection = [0, 0, 0]'))
    assert cli.main(["run", str(scene), *QUIET]) == 2
    assert (f"{scene}: constraints[0].direction must be a non-zero list of 3 numbers"
            in capsys.readouterr().err)


def test_simulate_refuses_times_and_every_of_the_wrong_type():
    """Before: ``simulate(dt="0.001")`` failed in numpy with a ``TypeError`` naming no
    parameter, and ``every=True`` was taken as 1."""
    scene = classics.pendulum(n_elements=2)
    with pytest.raises(TypeError, match=r"dt must be a number \(s\), got '0.001'"):
        sc.simulate(scene.system, 0.01, "0.001")
    with pytest.raises(ValueError, match="every must be an integer >= 1, got True"):
        sc.simulate(scene.system, 0.01, 0.001, every=True)
