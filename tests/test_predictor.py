"""Newton's predictor (``GeneralizedAlpha.predictor``): exact for accelerations linear in
time at any steps, and it follows what the method leaves of the unresolved modes."""

import numpy as np
import pytest
from galpha_modes import amplification

from skfem_cable.scenes import classics
from skfem_cable.solvers.galpha import GeneralizedAlpha


def integrator(rho_inf=0.8):
    scene = classics.pendulum(n_elements=2)
    g = GeneralizedAlpha(scene.system, rho_inf=rho_inf)
    g.initialize(scene.initial.q, scene.initial.v, 0.0)
    return g


@pytest.mark.parametrize("rho_inf", [0.0, 0.5, 0.8, 1.0])
def test_predictor_is_exact_for_linear_accelerations_at_varying_steps(rho_inf):
    """``a(t) = m + b t`` at the times 0, 0.3, 0.5 and 1.2 (steps 0.3, 0.2, 0.7): the
    predicted ``a(1.2)`` from the first three is exact to round-off."""
    g = integrator(rho_inf)
    m, b = np.linspace(1.0, 2.0, g.n), np.linspace(-3.0, 5.0, g.n)
    a = {t: m + b * t for t in (0.0, 0.3, 0.5, 1.2)}
    g.a, g.a_prev, g.da_prev = a[0.5], a[0.3], a[0.3] - a[0.0]
    g.h_prev, g.h_prev2, g.iterations = 0.2, 0.3, 2
    assert g.predicted_acceleration(0.7) == pytest.approx(a[1.2], rel=1e-13, abs=1e-13)


def test_predictor_follows_the_unresolved_modes():
    """A mode at ``omega h = 100`` and ``1e4`` (``rho_inf = 0.8``): the method's
    amplification has three roots within 0.08 of ``-rho_inf`` (its fourth is 0), and of
    its free decay the predictor misses the next acceleration by a fifth of the change of
    the acceleration over the step (measured 0.20 and 0.23), where linear extrapolation
    misses it by twice that change (2.17 and 2.14)."""
    rho = 0.8
    g = integrator(rho)
    for omega_h in (100.0, 1e4):
        A = amplification(omega_h, rho)
        roots = np.linalg.eigvals(A)
        assert np.sort(np.abs(roots + rho))[:3] == pytest.approx(0.0, abs=0.08)  # and 0
        state, a = np.array([1.0, 0.3, -omega_h**2, -0.9 * omega_h**2]), []
        for _ in range(40):
            state = A @ state
            a.append(state[2])
        ours, linear = [], []
        for k in range(3, 39):
            g.a, g.a_prev = np.full(g.n, a[k]), np.full(g.n, a[k - 1])
            g.da_prev, g.h_prev, g.h_prev2, g.iterations = np.full(g.n, a[k - 1] - a[k - 2]), \
                1.0, 1.0, 2
            change = abs(a[k + 1] - a[k])
            ours.append(abs(a[k + 1] - g.predicted_acceleration(1.0)[0]) / change)
            linear.append(abs(a[k + 1] - (2 * a[k] - a[k - 1])) / change)
        assert np.median(ours) < 0.25
        assert np.median(linear) > 2.0


def test_predictor_after_a_start_and_after_hard_steps():
    """After a start the constant acceleration; after one step linear extrapolation; after
    a step of more than ``SMOOTH_ITERATIONS`` iterations the constant acceleration if
    the step factored its tangent (``tangent_age == 0``), the extrapolation if it
    iterated on an older one (whose drift its count measures too)."""
    g = integrator()
    assert g.predictor(0.1) == (0.0, 0.0)
    g.a_prev, g.h_prev, g.iterations = g.a.copy(), 0.2, 2
    assert g.predictor(0.1) == (0.5, 0.0)
    g.da_prev, g.h_prev2 = np.zeros(g.n), 0.2
    g.iterations, g.tangent_age = g.SMOOTH_ITERATIONS + 1, 0
    assert g.predictor(0.1) == (0.0, 0.0)
    g.tangent_age = 1
    kappa = (0.1 + 0.8 * 0.2) / (0.2 + 0.8 * 0.2)
    assert g.predictor(0.1) == pytest.approx((kappa - 0.8, kappa * 0.8), rel=1e-15)
