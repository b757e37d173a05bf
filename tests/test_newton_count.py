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


def test_the_report_prints_each_size_in_modified_and_full_newton(capsys):
    per_step = newton_count.report((20, 30), steps=4, shown=(3,))
    out = capsys.readouterr().out
    assert "30 elements:" in out and "step 3:" in out and "steps 1-80: c" in out
    assert "30 elements, full Newton:" in out and "exponent of the corrections" in out
    for newton in ("modified", "full"):
        assert set(per_step[newton]) == {20, 30}
        assert all(c >= 1 for c in per_step[newton].values())


def test_full_newton_counts_what_its_log_counts():
    """Full Newton's window count is its run's corrections less the release's (a tangent
    refactored at every iterate: as many factorizations as corrections, and more)."""
    _, rows, result = newton_count.steps_of(30, steps=4, newton="full")
    assert newton_count.window_count(rows, 4) * 4 == (result.stats["newton"]
                                                      - rows[0]["corrections"])
    assert result.stats["factorizations"] >= result.stats["newton"]
