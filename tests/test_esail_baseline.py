"""The paper's baseline sail (Sect. 4.3): 12 tethers x 5 cable elements in the paper's
formulation, rho_inf = 0.25, run at steps of 0.5 s (the paper's are 0.1 s: every
quantity checked here is the same at both, the spectrum's peaks in the same bins, the
thrust ratio's error 1.1774e-5 against 1.1772e-5, the thrust turn's error 0.05232 deg,
the rigid coning's 0.10067 against 0.10066 of the amplitude, the coned projection's
9.274e-5; the energy errors grow, the balance's to 3.7e-8 (5.8e-10) and the voltage-free
departure to 5.7e-9 (5.6e-11), 27 and 58 times inside their bounds).  The tilted sail
runs the paper's three spin periods (9,425 steps: its spectrum needs their frequency
bins); the sun-facing sail and the sail without voltage one period (3,142 steps), which
holds all their checks see: the sun-facing thrust's mean is the same over one, two and
three periods to 3e-8, its largest departure from the coned projection (9.3e-5) and its
largest balance error (3.7e-8 of the energy, 8.2e-8 over three) fall in the first; the
tolerances of checks on a quantity that drifts in time are the three periods' ones
scaled to one."""

import numpy as np
import pytest

import skfem_cable as sc
from skfem_cable.loads.coulomb import SolarWind
from skfem_cable.scenes import esail

pytestmark = pytest.mark.slow


def run(alpha, periods, voltage=20e3):
    cfg = esail.BaselineConfig(voltage=voltage)
    scene = esail.build(cfg, alpha_deg=alpha, n_elements=5, kind="cable", formulation="paper")
    result = sc.simulate(scene.system, t_end=periods * cfg.spin_period, dt=0.5,
                         rho_inf=0.25, initial=scene.initial, every=2)
    return cfg, scene, result, esail.outputs(scene, result)


@pytest.fixture(scope="module")
def sun_facing():
    return run(0.0, periods=1)


@pytest.fixture(scope="module")
def tilted():
    return run(10.0, periods=3)


def test_runs_complete_without_step_failures(sun_facing, tilted):
    for (cfg, _, result, _), periods, steps in ((sun_facing, 1, 3142), (tilted, 3, 9425)):
        assert result.t[-1] == pytest.approx(periods * cfg.spin_period)
        assert result.stats["steps"] == steps and result.stats["rejected"] == 0


def test_sun_facing_thrust_is_the_coning_projected_force(sun_facing):
    """|F_c| = 12 x 10 km x 4.494e-7 N/m x <cos^2 gamma> within 1 % (measured 3e-5): the
    perpendicular wind component on a tether coned by gamma is cos(gamma)."""
    cfg, _, _, out = sun_facing
    F0 = cfg.n_tethers * cfg.tether_length * SolarWind().force_per_length(20e3)
    projected = F0 * np.mean(np.cos(out["coning"]) ** 2, axis=1)
    assert np.abs(np.linalg.norm(out["thrust"], axis=1) / projected - 1).max() < 1e-2
    assert np.rad2deg(out["thrust_angle"]).max() < 1e-6


def test_tilted_thrust_drops_and_turns_by_about_half_alpha(sun_facing, tilted):
    _, _, _, out0 = sun_facing
    _, _, _, out10 = tilted
    F0 = np.linalg.norm(out0["thrust"], axis=1).mean()
    F10 = np.linalg.norm(out10["thrust"], axis=1).mean()
    assert F10 < F0
    assert F10 / F0 == pytest.approx(0.5 * np.hypot(1 + np.cos(np.deg2rad(10)) ** 2,
                                                    np.sin(np.deg2rad(20)) / 2), rel=2e-3)
    angle = np.rad2deg(out10["thrust_angle"])
    assert np.abs(angle - 5.0).max() < 0.1  # measured 4.95 ... 4.97 deg


def test_energy_balance_with_the_sail_on(sun_facing):
    """The wind's work is booked: kinetic + elastic + dissipated - work stays constant to
    1e-6 of the energy while the total energy grows by the thrust work (which grows as
    t^2, the sail accelerating from rest: over three periods more than 1 J, measured 6.5;
    over the one run here more than 1/9 J, measured 0.743).  Wind work left out of the
    books would show as 4.8e-5 of the energy."""
    _, _, _, out = sun_facing
    assert out["external_work"][-1] > 1.0 / 9
    assert np.abs(out["balance"]).max() < 1e-6 * out["total"][0]


def test_energy_constant_with_the_sail_off():
    """V0 = 0: the paper shows no visible drift over 3 T_s.  Both the energy's departure
    and the coning of round-off grow linearly (measured 5.7e-9, 1.1e-8, 1.7e-8 of the
    energy and 3.9e-14, 8.8e-14, 1.4e-13 rad after one, two, three T_s; at the paper's
    0.1 s steps 5.6e-11 and 6.9e-13 rad after one): one T_s is run, against the bounds of
    three (1e-6 and 1e-8) divided by three."""
    _, _, _, out = run(10.0, periods=1, voltage=0.0)
    assert np.abs(out["total"] / out["total"][0] - 1).max() < 1e-6 / 3
    assert np.abs(out["coning"]).max() < 1e-8 / 3


def test_psd_peaks_are_modes_of_the_spinning_sail(tilted):
    """Every main PSD peak of the tether-1 angles and length is a natural frequency of the
    whole sail about its steady spin (``esail.spinning_modes``, rotating frame) within two
    frequency bins: the coning angle at the spin frequency 6.37e-4 Hz (Table 2), the
    lagging angle at the first in-plane bending mode 4.47e-3 Hz (Table 2 gives 7.34e-3 Hz,
    which is no mode of this sail).  The first axial mode is 2.18e-2 Hz (Table 2: 2.17e-2)."""
    cfg, _, _, out = tilted
    t = out["t"]
    df = 1 / (t[-1] - t[0])
    freqs = esail.spinning_modes(cfg, 10.0)

    def peaks(x, n=3):
        f, P = esail.psd(t, x, segments=1)
        i = [k for k in range(1, len(P) - 1) if P[k] > P[k - 1] and P[k] >= P[k + 1]]
        return f[sorted(i, key=lambda k: -P[k])[:n]]

    for name in ("coning", "lagging", "length_ratio", "root_coning", "root_lagging"):
        for f in peaks(out[name][:, 0]):
            assert np.min(np.abs(freqs - f)) <= 2 * df, (name, f)
    assert abs(peaks(out["coning"][:, 0])[0] - 6.366e-4) <= df
    assert np.min(np.abs(peaks(out["lagging"][:, 0]) - 4.468e-3)) <= df
    assert np.min(np.abs(freqs - 2.176e-2)) < 2e-5


def test_rigid_pendulum_coning_equation_tracks_tether_one(tilted):
    """Eq. 83 driven by the simulated spin and Coulomb moment follows the coning of
    tether 1 to within 15 % of its amplitude (measured 10 %: the flexible tether bends)."""
    cfg, _, _, out = tilted
    rigid = esail.rigid_coning(cfg, out, tether=0)
    amplitude = np.abs(out["coning"][:, 0]).max()
    assert np.abs(rigid - out["coning"][:, 0]).max() < 0.15 * amplitude
