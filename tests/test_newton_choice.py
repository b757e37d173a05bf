"""Modified Newton's choice of tangent from step to step (``solvers.newton_choice``): a
step whose stale tangent served slowly has the next one refactor, unless the step itself
replaced an old tangent (its contraction is then measured across two matrices); a slow
step on an old tangent too, at a contraction far below that bound."""

import functools

import pytest
from test_benchmarks import BENCH, load

from skfem_cable.solvers.newton_choice import NewtonChoice

newton_count = load(BENCH / "newton_count.py")


class Choice(NewtonChoice):
    """The state ``_choose_newton`` reads, after a step of ``iterations`` at the
    contraction ``rate`` (``GeneralizedAlpha``'s ``iterations`` and ``newton_rate``)."""

    newton = "modified"

    def __init__(self, age, iterations=4, rate=2.2):
        self.fresh_steps = self.strikes = 0
        self.tangent_age, self.iterations, self.newton_rate = age, iterations, rate


def test_a_slow_stale_tangent_is_replaced_at_the_next_predictor():
    choice = Choice(age=40, iterations=2, rate=0.2)
    choice._choose_newton(fresh=False, factorizations=0)
    assert choice.fresh_tangent and choice.tangent_age == 41


def test_a_fast_stale_tangent_is_kept():
    choice = Choice(age=40, iterations=2, rate=0.01)
    choice._choose_newton(fresh=False, factorizations=0)
    assert not choice.fresh_tangent and choice.tangent_age == 41


@pytest.mark.parametrize("age, iterations, fresh_next", [
    (NewtonChoice.OLD_TANGENT - 1, NewtonChoice.SLOW_STEP, True),
    (NewtonChoice.OLD_TANGENT - 2, NewtonChoice.SLOW_STEP, False),
    (NewtonChoice.OLD_TANGENT + 20, NewtonChoice.SLOW_STEP - 1, False)])
def test_a_slow_step_on_an_old_tangent_refreshes_below_the_stale_rate(age, iterations,
                                                                     fresh_next):
    """``age``: the steps the tangent served before this one (which makes it one older)."""
    choice = Choice(age=age, iterations=iterations, rate=NewtonChoice.STALE_RATE / 5)
    choice._choose_newton(fresh=False, factorizations=0)
    assert choice.fresh_tangent == fresh_next and choice.tangent_age == age + 1


def test_a_slow_step_of_exact_corrections_keeps_its_old_tangent():
    """A linear body's corrections contract by 0: its slow steps are the test's, not the
    tangent's."""
    choice = Choice(age=40, iterations=NewtonChoice.SLOW_STEP, rate=0.0)
    choice._choose_newton(fresh=False, factorizations=0)
    assert not choice.fresh_tangent


def test_the_released_pendulum_replaces_the_release_tangent_once_it_serves_slowly():
    """At 1000 elements the steps after the release take 4 corrections on its tangent
    (contracting by 2e-3 to 4e-2, below ``STALE_RATE``; they did up to step 37): the step
    after the ``OLD_TANGENT``-th refactors, and every step after it takes 2."""
    _, rows, _ = newton_count.steps_of(1000, steps=40)
    first = next(k for k in range(1, len(rows)) if rows[k]["factorizations"])
    assert first == NewtonChoice.OLD_TANGENT + 1
    assert rows[first - 1]["corrections"] >= NewtonChoice.SLOW_STEP
    assert [r["corrections"] for r in rows[first:]] == [2] * (len(rows) - first)


@pytest.mark.parametrize("age, fresh_next", [(0, True), (NewtonChoice.YOUNG_TANGENT, True),
                                             (NewtonChoice.YOUNG_TANGENT + 1, False),
                                             (85, False)])
def test_a_step_that_replaced_its_tangent_refactors_again_only_if_it_was_young(age,
                                                                                fresh_next):
    choice = Choice(age=age)
    choice._choose_newton(fresh=False, factorizations=1)
    assert choice.fresh_tangent == fresh_next and choice.tangent_age == 0


def test_a_fresh_step_that_contracts_slowly_still_refreshes():
    """The rule for a replaced tangent reads a contraction across two matrices; a step
    that factored at its predictor measured its own."""
    choice = Choice(age=85, iterations=3, rate=0.3)
    choice.fresh_steps = 1
    choice._choose_newton(fresh=True, factorizations=1)
    assert choice.fresh_tangent and choice.tangent_age == 0


@functools.cache
def released_10000():
    """The rows of ``newton_count.StepLog`` of the 100 m pendulum at 10,000 elements, the
    release and 150 steps."""
    return newton_count.steps_of(10000, steps=150)[1]


def test_the_released_pendulum_keeps_the_tangent_it_replaced_after_long_service():
    """At 10,000 elements the tangent factored at the end of the release's ringing (step
    52) contracts too slowly at step 147, which refactors; step 148 iterates on that
    factor (it refactored again before: one more factorization in the window,
    ``benchmarks/newton_count.py``)."""
    rows = released_10000()
    factored = [k for k, r in enumerate(rows) if r["factorizations"]]
    late = factored[-1]
    assert late - factored[-2] > 80 and late + 1 < len(rows)
    assert rows[late]["factorizations"] == 1 and rows[late + 1]["factorizations"] == 0


def test_the_ringing_keeps_the_extrapolation_on_a_kept_tangent():
    """At 10,000 elements the ringing's steps on the tangent that replaced the release's
    (step 18) keep the extrapolating predictor and take 3 corrections each, as full
    Newton does there (``GeneralizedAlpha.predictor``): when a step of 4 corrections on
    a kept tangent switched them to the constant acceleration they took 4 (steps 19-31),
    and a third factorization came at step 32."""
    rows = released_10000()
    factored = [k for k, r in enumerate(rows) if r["factorizations"]]
    second, third = factored[1], factored[2]
    ringing = rows[second + 2:third]
    assert len(ringing) >= 12
    assert all(r["extrapolated"] and r["corrections"] <= 3 for r in ringing)
