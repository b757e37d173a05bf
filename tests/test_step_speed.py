"""The E-sail step's cuts of issue 47 ("back and beyond") keep its numbers.

The solar wind's distance scaling ``(d0 / rho)^p`` is taken at each Gauss point from its
series about the origin's distance from the Sun (``kernels.coulomb.expansion``), one power
per time step instead of one per point: the series against the power over the range where
the kernel takes it and beyond (where it takes the power), its truncation in 50-digit
arithmetic, the force of a tether against the force computed with the power, and the
series refreshed with a moving Sun.  One tether of three elements, the kernel of
``tests/test_step_overhead.py``'s scene (compiled once per machine for both files).
"""

import mpmath
import numpy as np
import pytest
from numba import njit

import skfem_cable as sc
from skfem_cable.kernels import coulomb as kernel
from skfem_cable.loads.coulomb import AU, THRUST_EXPONENT, SolarWindForce, SunAtFocus

SECTION = sc.Section.circular(1e-5, 7e10, 2700.0)


@njit(cache=True)
def scales(scaling, rho):
    """The kernel's ``s(rho)`` at each distance of ``rho``."""
    out = np.empty_like(rho)
    for i in range(rho.size):
        out[i] = kernel._scale(scaling, rho[i])
    return out


@pytest.mark.parametrize("power", [THRUST_EXPONENT, 0.5, 2.0, 1e-300])
def test_the_series_of_the_scaling_is_the_power_to_rounding(power):
    """Over ``|q| <= 2 q_max`` and far away (``q = rho / R - 1`` up to 3: the power taken
    there) the kernel's scaling equals ``(d0 / rho)^p`` within ``(1 + p)`` units of
    rounding (2.2e-16) relative, the Sun 1 AU from the origin: each of the two is within
    ``p`` units of the exact value of its ``rho`` (``1 / R`` and ``d0 / rho`` rounded, then
    raised to ``p``; 50-digit arithmetic, p = 0.5 to 5: 1 to 4 units)."""
    scaling = np.array(kernel.expansion(AU, power, np.array([-AU, 0.0, 0.0])))
    q_max = scaling[6]
    q = np.concatenate([np.linspace(-2 * q_max, 2 * q_max, 4001), [1e-3, -0.5, 3.0]])
    rho = AU * (1.0 + q)
    exact = (AU / rho) ** power
    np.testing.assert_allclose(scales(scaling, rho), exact, rtol=(1 + power) * 2.3e-16,
                               atol=0)


def test_the_series_truncation_is_below_a_hundredth_of_rounding():
    """At ``|q| = q_max`` the series ``1 + c1 q + c2 q^2`` misses ``(1 + q)^(-p)`` by at
    most ``TRUNCATION`` = 1e-18 relative (50 digits); a sail of tethers of 20 km, ``|q|
    <= 1.4e-7`` at 1 AU, is within ``q_max`` (9.1e-7) of the paper's ``p = 7/6``."""
    mpmath.mp.dps = 50
    for power in (THRUST_EXPONENT, 0.5, 2.0, 5.0):
        d0, p, _, _, c1, c2, q_max = kernel.expansion(AU, power, (AU, 0.0, 0.0))
        for q in (-q_max, q_max):
            q = mpmath.mpf(q)
            exact = (1 + q) ** (-mpmath.mpf(p))
            series = 1 + mpmath.mpf(c1) * q + mpmath.mpf(c2) * q * q
            assert abs(series / exact - 1) <= 1.0001 * kernel.TRUNCATION
    assert kernel.expansion(AU, THRUST_EXPONENT, (AU, 0.0, 0.0))[6] > 20e3 / AU * 6


@pytest.fixture(scope="module")
def tether():
    """A tether of 3 elements pinned at its root (``test_step_overhead.py``'s scene) and
    a deformed state."""
    cable = sc.Cable.straight([0, 0, 0], [3.0, 30.0, -4.0], 3, SECTION, name="tether")
    system = sc.System([cable]).pin(cable.node(0))
    q = system.q0 + 0.2 * np.random.default_rng(3).standard_normal(system.n_dofs)
    return cable, system, q


def test_the_wind_at_one_au_is_the_force_with_the_power(tether):
    """The Sun at ``-AU`` (every Gauss point on the series): the kernel's generalized
    force equals ``sum w S_A c (d / rho)^p u_perp`` with the power at each point, within
    4e-16 of its largest entry."""
    cable, system, q = tether
    load = SolarWindForce([cable], 20e3, sun_position=np.array([-AU, 0.0, 0.0]))
    qe = q[cable.element_dofs].reshape(-1, 4, 3)
    r = np.einsum("egA,eAi->egi", cable.S, qe)
    a = np.einsum("egA,eAi->egi", cable.Sx, qe)
    f = load.line_force(r, a, np.full(r.shape[:2], load.coefficients(0.0)[0]), 0.0)
    hand = np.zeros(system.n_dofs)
    np.add.at(hand, cable.element_dofs,
              np.einsum("eg,egA,egi->eAi", cable.weights, cable.S, f).reshape(qe.shape[0], -1))
    force = np.zeros(system.n_dofs)
    load.add_force(system, q, 0.0, force)
    np.testing.assert_allclose(force, hand, rtol=0, atol=4e-16 * np.abs(hand).max())


def test_a_moving_sun_refreshes_the_series(tether):
    """With the Sun at the focus of an eccentric orbit (``SunAtFocus``), each step's
    ``prepare`` sets the series about the origin's distance at that time: ``1 / R`` and
    ``s(R) = (AU / R)^p``."""
    cable, system, _ = tether
    orbit = sc.Orbit(sc.MU_SUN, 1.3 * AU, e=0.2)
    load = SolarWindForce([cable], 20e3, sun_position=SunAtFocus(orbit))
    term = load.bind(system)
    sun, scaling = term.kernels[0][1][5]
    for t in (0.0, 3e6, 1e7):
        term.prepare(t)
        R = np.linalg.norm(orbit.position(t))
        np.testing.assert_allclose(sun, -orbit.position(t), rtol=0, atol=0)
        np.testing.assert_allclose(scaling[2:4], [1 / R, (AU / R) ** THRUST_EXPONENT],
                                   rtol=1e-15)
