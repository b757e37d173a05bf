"""What keeps the test command's run time short (issue 47, item 5): ``python3 tasks.py
test`` installs its environment without bytecode and keeps Python's bytecode caches
where the environment switches them off (each pytest-xdist worker would otherwise rewrite
every test module's asserts at its collection, and each process the suite starts would
compile the package and its libraries again) and leaves out zarr's pytest plugin; the
suite's writes skip ``fsync``; a run's summary counts its frames once."""

import os
import subprocess
import sys
from pathlib import Path
from types import SimpleNamespace

from test_bench_guard import load

ROOT = Path(__file__).parents[1]


def test_every_task_writes_bytecode(monkeypatch):
    """Under ``PYTHONDONTWRITEBYTECODE=1``: the test and lint commands' environments are
    the caller's without it (the environment is installed without bytecode: the tasks'
    processes write what they import, once)."""
    tasks = load(ROOT / "tasks.py")
    seen = []

    def run(command, env=None, **_):
        seen.append((command, env))
        return SimpleNamespace(returncode=0)

    monkeypatch.setattr(tasks, "ensure_venv", lambda: None)
    monkeypatch.setattr(tasks, "SYSTEM_DEPS", ROOT / "no such script")
    monkeypatch.setattr(tasks, "subprocess", SimpleNamespace(run=run))
    monkeypatch.setenv("PYTHONDONTWRITEBYTECODE", "1")
    assert tasks.main(["test", "-x"]) == 0 and tasks.main(["lint"]) == 0
    (test, test_env), (lint, lint_env) = seen
    assert test[-4:] == ["loadfile", "--max-worker-restart", "0", "-x"]
    assert lint[-2:] == ["check", "."]
    assert test[test.index("-p") + 1] == "no:zarr"  # zarr's plugin, in no process
    assert "PYTHONDONTWRITEBYTECODE" not in test_env
    assert test_env == lint_env == {k: v for k, v in os.environ.items()
                                    if k != "PYTHONDONTWRITEBYTECODE"}


def test_the_environment_is_installed_without_bytecode(monkeypatch, tmp_path):
    """A missing or stale install runs pip with ``--no-compile`` (22.6 s instead of 44.3 s
    from pip's cache: the tasks compile the 700 of its 10,800 modules they import) and
    stamps the ``pyproject.toml`` it installed."""
    tasks = load(ROOT / "tasks.py")
    seen = []
    python = tmp_path / "python"
    python.touch()
    monkeypatch.setattr(tasks, "PY", python)
    monkeypatch.setattr(tasks, "STAMP", tmp_path / "stamp")
    monkeypatch.setattr(tasks, "subprocess",
                        SimpleNamespace(run=lambda command, **_: seen.append(command)))
    tasks.ensure_venv()
    (upgrade, install) = seen
    assert upgrade[-2:] == ["--upgrade", "pip"]
    assert install[-3:] == ["--no-compile", "-e", f"{ROOT}[test,docs]"]
    assert (tmp_path / "stamp").exists()
    tasks.ensure_venv()
    assert len(seen) == 2  # up to date: nothing installed


#: A test file whose first test kills its process as a segfault does.
CRASH = """import os, signal


def test_crash():
    os.kill(os.getpid(), signal.SIGSEGV)


def test_after():
    pass
"""


def test_a_dead_worker_ends_the_run_naming_its_test(tmp_path):
    """The test command's pytest-xdist options on a file whose test segfaults its worker
    (as ``tests/test_kernel_signatures.py`` did on a stale numba cache): the run fails
    at once, naming the test.  Restarting the worker under ``--dist loadfile`` (the
    default), the run waited without end."""
    (tmp_path / "test_crash.py").write_text(CRASH)
    (tmp_path / "test_other.py").write_text("def test_other():\n    pass\n")
    command = load(ROOT / "tasks.py").TASKS["test"][0]
    done = subprocess.run([sys.executable, *command, "-p", "no:cacheprovider"],
                          cwd=tmp_path, capture_output=True, text=True, timeout=120)
    assert done.returncode == 1
    assert "worker 'gw" in done.stdout and "crashed while running" in done.stdout
    assert "test_crash.py::test_crash" in done.stdout


def test_writes_skip_fsync_only_where_the_environment_says_so(tmp_path, monkeypatch):
    """``SKFEM_CABLE_FSYNC=0`` (the suite's, ``conftest.py``): ``write_atomic`` writes the
    same bytes without ``fsync``; unset or any other value, it flushes the file and its
    folder."""
    from skfem_cable.util import atomic

    assert os.environ["SKFEM_CABLE_FSYNC"] == "0"  # the suite's processes and children
    calls = []
    monkeypatch.setattr(atomic.os, "fsync", lambda fd: calls.append(fd))
    for value, flushed in (("0", 0), (None, 2), ("1", 2)):
        if value is None:
            monkeypatch.delenv("SKFEM_CABLE_FSYNC")
        else:
            monkeypatch.setenv("SKFEM_CABLE_FSYNC", value)
        calls.clear()
        atomic.write_atomic(tmp_path / "f", f"{value}".encode())
        assert len(calls) == flushed and (tmp_path / "f").read_text() == f"{value}"
        assert not [p for p in tmp_path.iterdir() if atomic.is_temporary(p)]


def test_a_store_is_the_same_with_and_without_fsync(tmp_path, monkeypatch):
    """The run store's objects (``io.zarr_store.atomic_store``): without ``fsync``
    (``SKFEM_CABLE_FSYNC=0``) written on zarr's event loop, with it (unset) on threads,
    every one flushed; the two stores hold the same bytes."""
    import asyncio

    from skfem_cable.cli import command as cli
    from skfem_cable.util import atomic

    flushed, threaded = [], []
    monkeypatch.setattr(atomic.os, "fsync", lambda fd: flushed.append(fd))
    to_thread = asyncio.to_thread
    monkeypatch.setattr(asyncio, "to_thread",
                        lambda f, *a, **k: threaded.append(f) or to_thread(f, *a, **k))
    stores = {}
    for value in ("0", None):
        if value is None:
            monkeypatch.delenv("SKFEM_CABLE_FSYNC")
        flushed.clear()
        threaded.clear()
        out = tmp_path / f"fsync-{value}"
        assert cli.main(["run", "pendulum", "--elements", "3", "--t-end", "0.03", "--no-plots",
                         "--no-progress", "--out", str(out)]) == 0
        files = sorted(p for p in (out / "results.zarr").rglob("*") if p.is_file())
        puts = [f for f in threaded if getattr(f, "__name__", "") == "_put"]
        if value == "0":
            assert not puts and not flushed
        else:  # every object at least once (the metadata again at each commit)
            assert len(puts) >= len(files) and len(flushed) >= len(puts)
        stores[value] = {p.relative_to(out): p.read_bytes() for p in files}
    assert stores["0"] == stores[None]


def test_the_frames_of_a_run_are_counted_once(tmp_path, monkeypatch):
    """Before: ``described_files`` counted the VTU frames again for each frame (a glob of
    every frame per frame: 73,712 path matches at 271 frames).  Now once, with the same
    description."""
    from skfem_cable.runner import directory

    (tmp_path / "vtu").mkdir()
    for i in range(40):
        (tmp_path / "vtu" / f"series_{i:06d}.vtu").write_text("")
    globs, glob = [], Path.glob
    monkeypatch.setattr(Path, "glob", lambda self, p: globs.append(p) or glob(self, p))
    listed = directory.described_files(tmp_path)
    assert listed["vtu/series_*.vtu"].endswith("(40 files)")
    assert globs.count("vtu/series_*.vtu") == 2  # run_files' listing, then the count
