"""``benchmarks/newton_count.py``, the Newton count of the released pendulum step by step
(issue 47, item 4): what it logs is what the integrator did.

The benchmark found where the count's growth with the size comes from (``docs/
benchmarks.md``, "Why the Newton count grows with the size"): the ringing of the elements
next to the pin after the release, longer on finer meshes.  These checks run it on a small
mesh for a few steps."""

import numpy as np
import pytest
from test_benchmarks import BENCH, load

newton_count = load(BENCH / "newton_count.py")

STEPS = 12


@pytest.fixture(scope="module")
def logged():
    return newton_count.steps_of(100, steps=STEPS)


def test_the_log_has_a_row_per_step_with_the_runs_counts(logged):
    _, rows, result = logged
    assert len(rows) == STEPS + 1 == result.stats["steps"]
    assert sum(r["corrections"] for r in rows) == result.stats["newton"]
    # the run's start factors once more, before its first step
    assert 0 < sum(r["factorizations"] for r in rows) <= result.stats["factorizations"]


def test_the_rows_carry_the_predictor_and_the_residual_before_each_correction(logged):
    system, rows, _ = logged
    assert not rows[0]["extrapolated"]  # a start: the constant acceleration
    assert any(r["extrapolated"] for r in rows[1:])
    for r in rows:
        assert 0 < r["history"].size <= r["corrections"]
        assert np.all(np.isfinite(r["history"])) and np.all(r["history"] > 0)
        assert 0 <= r["largest"] < system.n_dofs
    assert newton_count.pattern(rows).split()[0].startswith("c")


def test_the_report_prints_each_size(capsys):
    per_step = newton_count.report((30,), steps=4, shown=(3,))
    out = capsys.readouterr().out
    assert "30 elements:" in out and "step 3:" in out and "steps 1-80: c" in out
    assert per_step[30] >= 1
