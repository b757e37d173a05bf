"""Run-time cuts of session 10 (helper c): results bit for bit those of the per-step
code they replace."""

import numpy as np
import pytest

import skfem_cable as sc


@pytest.fixture(scope="module")
def wind():
    sec = sc.Section.circular(1e-5, 7e10, 2700.0)
    a = sc.Cable.straight([0, 0, 0], [0, 100, 0], 2, sec, name="a")
    b = sc.Cable.straight([0, 0, 0], [0, -100, 0], 2, sec, name="b")
    return sc.SolarWindForce([a, b], [20e3, lambda t: 20e3 + 10.0 * t])


def test_line_forces_over_steps_equal_line_force_at_each(wind):
    """``SolarWindForce.line_forces`` over the points of many saved steps at once, with
    each step's coefficients, Sun and scaling, gives each step's ``line_force``."""
    rng = np.random.default_rng(3)
    times = np.array([0.0, 1.5, 40.0, 300.0])
    r = rng.normal(scale=100.0, size=(len(times), 7, 3))
    a = rng.normal(size=(len(times), 7, 3))
    owner = np.array([0, 0, 0, 1, 1, 1, 1])
    coef = np.array([wind.coefficients(t)[owner] for t in times])
    sun = np.array([wind.sun_at(t) for t in times])
    scaling = np.array([wind.scaling(t) for t in times])
    together = wind.line_forces(r, a, coef, sun[:, None], scaling[:, None])
    for k, t in enumerate(times):
        one = wind.line_force(r[k], a[k], coef[k], t)
        assert np.abs(one).max() > 0
        np.testing.assert_array_equal(together[k], one)
