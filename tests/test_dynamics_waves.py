"""Wave and vibration references for the dynamics: axial bar period, taut-string
frequency, and the modal damping of the internal (Kelvin-Voigt) damping."""

import numpy as np
import pytest

import skfem_cable as sc
from skfem_cable.analysis.analytic import string_frequency
from skfem_cable.results.timeseries import decay_rate, period
from skfem_cable.scenes import classics

YOUNG, RHO, L = 2e11, 7800.0, 1.0
C_BAR = np.sqrt(YOUNG / RHO)


def test_axial_wave_period_of_fixed_free_bar():
    """Released from a uniform pre-stretch, the tip moves as a triangle wave of period
    4 L / c; 32 elements, 400 steps per period: within 2e-3 (measured 1.3e-4)."""
    scene = classics.stretched_bar(n_elements=32, E=YOUNG, rho=RHO)
    T = 4 * L / C_BAR
    r = sc.simulate(scene.system, t_end=2.2 * T, dt=T / 400, rho_inf=0.8, initial=scene.initial)
    u = r.position(scene.cable, L)[:, 0] - L
    v = r.velocity(scene.cable, L)[:, 0]
    assert period(r.t, u, v) == pytest.approx(T, rel=2e-3)


@pytest.mark.parametrize("kind", ["truss", "cable"])
def test_taut_string_frequency(kind):
    """First transverse mode of a pinned, pre-stretched string: f = 1/(2L') sqrt(T/mu')
    in the stretched configuration; the cable adds the bending correction
    sqrt(1 + EI (pi/L')^2 / T) (here 1.2e-3).  Tolerance 2e-4 (measured 1.2e-5)."""
    strain = 1e-3
    scene = classics.taut_string(n_elements=16, strain=strain, kind=kind)
    sec = scene.cable.section
    stretch = 1 + strain
    tension = sec.EA * 0.5 * (stretch**2 - 1) * stretch
    EI = sec.EI if kind == "cable" else 0.0
    f = string_frequency(L * stretch, tension, sec.mass_per_length / stretch, EI)
    r = sc.simulate(scene.system, t_end=2.2 / f, dt=1 / (400 * f), rho_inf=0.9,
                    initial=scene.initial)
    y = r.position(scene.cable, L / 2)[:, 1]
    vy = r.velocity(scene.cable, L / 2)[:, 1]
    assert 1 / period(r.t, y, vy) == pytest.approx(f, rel=2e-4)


def test_axial_damping_matches_modal_damping_ratio():
    """Kelvin-Voigt law N = EA (eps + gamma eps_dot): each mode obeys
    m u'' + gamma k u' + k u = 0, i.e. zeta_n = gamma omega_n / 2 and a decay rate
    sigma_n = gamma omega_n^2 / 2.  First axial mode of a clamped-free bar,
    omega_1 = pi c / (2 L), zeta = 2 %: decay rate within 2 % (measured 0.02 %)."""
    omega1 = np.pi * C_BAR / (2 * L)
    gamma = 2 * 0.02 / omega1
    scene = classics.stretched_bar(n_elements=16, E=YOUNG, rho=RHO, mode=1, gamma_axial=gamma)
    T = 2 * np.pi / omega1
    r = sc.simulate(scene.system, t_end=10 * T, dt=T / 200, rho_inf=1.0, initial=scene.initial)
    u = r.position(scene.cable, L)[:, 0] - L
    assert decay_rate(r.t, u) == pytest.approx(gamma * omega1**2 / 2, rel=0.02)
    E = r.energy
    assert E["dissipated"][-1] > 0.5 * E["total"][0]
    assert np.abs(E["balance"]).max() < 1e-6 * E["total"][0]
