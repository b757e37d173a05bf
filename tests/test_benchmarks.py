"""The benchmark scripts run (at tiny sizes) and report sane numbers: benchmarks are not
timed tests, but they must not rot."""

import importlib.util
from pathlib import Path

import numpy as np
import pytest

BENCH = Path(__file__).parents[1] / "benchmarks"


def load(name):
    spec = importlib.util.spec_from_file_location(name, BENCH / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_kernel_cost(capsys):
    rows = load("kernel_cost").main(sizes=(10, 20, 40))
    assert [r[0] for r in rows] == [10, 20, 40] and all(r[1] > 0 and r[2] > 0 for r in rows)
    assert "growth exponent" in capsys.readouterr().out


def test_step_cost(capsys):
    """Both paths are timed, the exponent is fitted (here: of tiny sizes) and the
    peak memory is read."""
    rows = load("step_cost").main(sizes=(4, 8, 16), steps=3, repeats=1)
    assert all(r[1] > 0 and r[2] > 0 and r[3] >= 1 and r[4] > 10 for r in rows)
    assert "growth exponent per step, compiled" in capsys.readouterr().out


def test_cantilever_convergence(capsys):
    errors = load("cantilever_convergence").main(ks=(1, 2, 5), elements=(8, 16))
    assert errors[16][2] < errors[8][2] < 1e-2


def test_pendulum_speed_error(capsys):
    ref, rows = load("pendulum_speed_error").main(elements=(4,), steps=(4e-3,),
                                                  reference=(4, 2e-3), tolerances=(1e-4,))
    assert np.isfinite(ref).all() and 0 < rows[0][2] < 1e-3
    assert rows[1][1] == -1e-4 and 0 < rows[1][2] < 1e-3  # the adaptive row


@pytest.mark.slow
def test_esail_report_speed_table(capsys):
    load("esail_report").speed(steps=5)
    assert "ms/step" in capsys.readouterr().out


def test_rodchain_speed(capsys):
    bench = load("rodchain_speed")
    bench.solve_table([10, 20, 40])
    bench.rk4_table([10, 30, 60])
    out = capsys.readouterr().out
    assert "10" in out and "30" in out


@pytest.mark.slow
def test_commit_compare(capsys):
    """Against HEAD itself (a git worktree): both columns are timed, the ratio is printed."""
    rows = load("commit_compare").main(["--base", "HEAD", "--repeats", "1",
                                        "--steps-scale", "0.01"])
    assert set(rows) == {"esail", "pendulum"}
    assert all(ours["ms_per_step"] > 0 and theirs["ms_per_step"] > 0
               for ours, theirs in rows.values())
    assert "ratio" in capsys.readouterr().out


@pytest.mark.slow
def test_peers_pendulum_against_exudyn(capsys):
    """Runs where the ``peers`` extra is installed: both codes reach the same tip."""
    pytest.importorskip("exudyn")
    rows = load("peers").pendulum(quick=True, repeats=1)
    ours = rows[0]
    matched = next(r for r in rows if r["code"] == "exudyn" and "matched" in r["setting"])
    assert abs(ours["error"] - matched["error"]) < 1e-6 and ours["error"] < 1e-4
