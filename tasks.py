"""Single entry point for a fresh machine: ``python3 tasks.py demo|test|docs|bench|lint``.

Extra arguments go to the task's command; a leading ``--`` is dropped, so that
``python3 tasks.py bench -- --quick kernel_cost`` runs ``skfem-cable bench --quick
kernel_cost`` (its tables stream as they are computed), and ``python3 tasks.py bench
--against [REF]`` times the tracked cases of ``benchmarks/commit_compare.py`` here and at
the commit ``REF`` (default: its fixed reference), printing each ratio and flagging those
above 1.05: run it before every speed-relevant commit.

Each task creates (or reuses) the local virtual environment ``.venv``, installs the
package with its test and docs extras when ``pyproject.toml`` changed since the last
install, and runs the task inside it.  ``demo`` and ``test`` first run
``scripts/install_system_deps.sh`` (the EGL/Mesa libraries off-screen rendering needs; it
installs them when run as root on Debian/Ubuntu and is a no-op otherwise).  Only Python 3
(with ``venv``) and network access to PyPI are required.  ``test`` runs the suite on
every core (pytest-xdist), the tests of one file on one worker, so that a file's module
fixtures (the E-sail baseline run) are computed once.
"""

import hashlib
import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent
VENV = ROOT / ".venv"
PY = VENV / ("Scripts/python.exe" if os.name == "nt" else "bin/python")
STAMP = VENV / ".skfem_cable-installed"
SYSTEM_DEPS = ROOT / "scripts" / "install_system_deps.sh"

TASKS = {
    "demo": [["demos/esail_baseline.py"]],
    # zarr's pytest plugin (the base class of zarr's own store tests, no fixture the suite
    # uses) would import zarr into every pytest process, xdist's controller too (0.45 CPU s).
    # A worker that dies (a segfault) ends the run, its test named as failed: restarted
    # under ``--dist loadfile``, the suite waited without end (pytest-xdist 3).
    "test": [["-m", "pytest", "-q", "-p", "no:zarr", "-n", "auto", "--dist", "loadfile",
              "--max-worker-restart", "0"]],
    "docs": [["-m", "mkdocs", "build", "--strict", "--quiet"]],
    "bench": [["-u", "-m", "skfem_cable.cli", "bench"]],
    "lint": [["-m", "ruff", "check", "."]],
}
NEEDS_RENDERING = ("demo", "test")
#: ``PYTHONDONTWRITEBYTECODE`` is dropped from every task's environment: the virtual
#: environment is installed without byte-compiling its 10,800 modules (``--no-compile``:
#: 22.6 s instead of 44.3 s from pip's cache on the 2-core machine), and a task's first
#: run writes the bytecode of the 700 or so modules it imports, which every later process
#: reads.  Without it every process would compile them again: 8-9 s against 2.4-2.9 s to
#: import the package and its libraries; every pytest-xdist worker would rewrite the
#: asserts of every test module at its collection (10.3 -> 5.8 CPU s per worker).


def ensure_venv():
    """Create ``.venv`` and install ``.[test,docs]`` when missing or out of date."""
    if not PY.exists():
        subprocess.run([sys.executable, "-m", "venv", str(VENV)], check=True)
    digest = hashlib.sha256((ROOT / "pyproject.toml").read_bytes()).hexdigest()
    if STAMP.exists() and STAMP.read_text() == digest:
        return
    pip = [str(PY), "-m", "pip", "install", "--disable-pip-version-check", "-q"]
    subprocess.run(pip + ["--upgrade", "pip"], check=True)
    subprocess.run(pip + ["--no-compile", "-e", f"{ROOT}[test,docs]"], check=True)
    STAMP.write_text(digest)


def task_arguments(argv):
    """``(task, extra arguments)`` of the command line ``argv`` (without the program name),
    with a leading ``--`` of the extra arguments dropped."""
    task, extra = argv[0], argv[1:]
    return task, extra[1:] if extra[:1] == ["--"] else extra


def task_environment(environ=os.environ):
    """The environment of the tasks' commands: ``environ`` without
    ``PYTHONDONTWRITEBYTECODE`` (the comment above ``ensure_venv``)."""
    return {k: v for k, v in environ.items() if k != "PYTHONDONTWRITEBYTECODE"}


def main(argv):
    if len(argv) < 1 or argv[0] not in TASKS:
        print(f"usage: python3 tasks.py {{{'|'.join(TASKS)}}} [[--] extra args]",
              file=sys.stderr)
        return 2
    ensure_venv()
    task, extra = task_arguments(argv)
    if task in NEEDS_RENDERING and SYSTEM_DEPS.exists() and os.name != "nt":
        subprocess.run(["bash", str(SYSTEM_DEPS)], cwd=ROOT)
    for cmd in TASKS[task]:
        rc = subprocess.run([str(PY), *cmd, *extra], cwd=ROOT,
                            env=task_environment()).returncode
        if task == "test" and rc == 5:
            print("pytest collected no tests: treated as a failure", file=sys.stderr)
            return 1
        if rc != 0:
            return rc
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
