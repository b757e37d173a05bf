"""Modified Newton's choice of tangent from step to step (``solvers.newton_choice``): a
step whose stale tangent served slowly has the next one refactor, unless the step itself
replaced an old tangent (its contraction is then measured across two matrices)."""

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


def test_the_released_pendulum_keeps_the_tangent_it_replaced_at_step_119():
    """At 10,000 elements the tangent of step 34 contracts too slowly at step 119, which
    refactors; step 120 iterates on that factor (it refactored again before: two
    factorizations of the window's six, ``benchmarks/newton_count.py``)."""
    _, rows, _ = newton_count.steps_of(10000, steps=120)
    assert [r["factorizations"] for r in rows[33:120]] == [1] + [0] * 84 + [1, 0]
    assert rows[119]["corrections"] == 2
