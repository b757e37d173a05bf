"""What keeps the test command's run time short (issue 47, item 5): ``python3 tasks.py
test`` keeps Python's bytecode caches where the environment switches them off (each
pytest-xdist worker would otherwise rewrite every test module's asserts at its collection,
and each process the suite starts would compile the package again)."""

import os
from pathlib import Path
from types import SimpleNamespace

from test_bench_guard import load

ROOT = Path(__file__).parents[1]


def test_the_test_task_writes_bytecode_and_the_others_keep_the_environment(monkeypatch):
    """Under ``PYTHONDONTWRITEBYTECODE=1``: the test command's environment is the caller's
    without it; the lint command's is the caller's."""
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
    assert test[-2:] == ["loadfile", "-x"] and lint[-2:] == ["check", "."]
    assert "PYTHONDONTWRITEBYTECODE" not in test_env
    assert test_env == {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    assert lint_env == dict(os.environ)
