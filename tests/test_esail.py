"""E-sail scene: Coulomb force and its Jacobian, configuration checks, initial state,
frames and outputs on a short run, rotating-frame modes against Table 2."""

import numpy as np
import pytest

import skfem_cable as sc
from skfem_cable.loads.coulomb import AU, SolarWind, SolarWindForce
from skfem_cable.scenes import esail
from skfem_cable.space.frames import dcm_321, dcm_323, euler_321, euler_323, orbit_frame

TETHER = esail.BaselineConfig().section


def sun_facing_tether(n=5, L=10e3, voltage=20e3):
    """A straight tether along y, the Sun along -x at 1 AU (wind along +x)."""
    cable = sc.Cable.straight([0, 0, 0], [0, L, 0], n, TETHER)
    system = sc.System([cable]).pin(cable.node(0))
    load = SolarWindForce([cable], voltage, sun_position=(-AU, 0, 0))
    system.add_load(load)
    return cable, system, load


def test_force_per_length_by_hand():
    """0.18 * 19000 V * sqrt(8.854e-12 * 1.67e-27 * 7.3e6) * 4e5 = 4.494e-7 N/m (Eq. 29)."""
    hand = 0.18 * 19000 * np.sqrt(8.854e-12 * 1.67e-27 * 7.3e6) * 4e5
    assert hand == pytest.approx(4.494e-7, rel=1e-4)
    assert SolarWind().force_per_length(20e3) == pytest.approx(hand, rel=1e-12)
    assert SolarWind().force_per_length(500.0) == 0.0  # below V1: no force
    cable, system, load = sun_facing_tether()
    f = np.zeros(system.n_dofs)
    resultant = load.add_force(system, system.q0, 0.0, f)
    assert resultant == pytest.approx([hand * 10e3, 0, 0], rel=1e-9, abs=1e-15)
    # consistent nodal forces: the position DOFs carry the resultant
    assert f.reshape(-1, 2, 3)[:, 0].sum(axis=0) == pytest.approx(resultant, rel=1e-12)


def test_coulomb_jacobian_matches_finite_differences():
    cable, system, load = sun_facing_tether(n=3, L=30.0)
    load.sun = np.array([-40.0, -25.0, 10.0])  # close Sun: exercise the i_R dependence
    rng = np.random.default_rng(5)
    q = system.q0 + 0.3 * rng.standard_normal(system.n_dofs)
    check = sc.check_tangent(system, q, step=1e-6 / system.layout.length_scale)
    wind, = (p for p in check.parts if p.name == "solar wind")
    assert wind.error < 1e-6, str(check)


def test_voltage_modulation_and_validation():
    cable = sc.Cable.straight([0, 0, 0], [0, 100, 0], 2, TETHER)
    load = SolarWindForce([cable], lambda t: 20e3 if t < 1 else 0.0)
    assert load.coefficients(0.5)[0] > 0 and load.coefficients(2.0)[0] == 0
    with pytest.raises(ValueError, match="voltage"):
        SolarWindForce([cable], -5.0)
    with pytest.raises(ValueError, match="one value per cable"):
        SolarWindForce([cable], [1.0, 2.0])


def test_config_validation_names_the_field():
    with pytest.raises(ValueError, match="tether_length"):
        esail.build(esail.BaselineConfig(tether_length=-1), 10.0, 5)
    with pytest.raises(ValueError, match="n_tethers"):
        esail.build(esail.BaselineConfig(n_tethers=0), 10.0, 5)
    with pytest.raises(ValueError, match="alpha_deg"):
        esail.build(esail.BaselineConfig(), 120.0, 5)
    with pytest.raises(ValueError, match="n_elements"):
        esail.build(esail.BaselineConfig(), 10.0, 0)
    cfg = esail.BaselineConfig()
    assert cfg.spin_period == pytest.approx(2 * np.pi / 4e-3)


def test_euler_angles_round_trip_and_orbit_frame():
    rng = np.random.default_rng(1)
    for _ in range(20):
        a = rng.uniform(-3, 3, 3)
        a[1] = rng.uniform(-1.5, 1.5)
        assert np.allclose(euler_321(dcm_321(*a)), a)
        b = rng.uniform(-3, 3, 3)
        b[1] = rng.uniform(0.05, 3.0)
        assert np.allclose(euler_323(dcm_323(*b)), b)
    C = orbit_frame([np.sqrt(0.5), np.sqrt(0.5), 0])
    assert np.allclose(C.T @ C, np.eye(3)) and np.linalg.det(C) == pytest.approx(1)
    assert np.allclose(C[:, 2], [np.sqrt(0.5), np.sqrt(0.5), 0])  # Z_O radial
    assert np.allclose(C[:, 1], [0, 0, 1])  # Y_O: ecliptic normal (Sect. 2.1 at this R0)


@pytest.fixture(scope="module")
def short_run():
    cfg = esail.BaselineConfig()
    scene = esail.build(cfg, alpha_deg=10.0, n_elements=2, kind="cable")
    result = sc.simulate(scene.system, t_end=20.0, dt=0.1, rho_inf=0.25,
                         initial=scene.initial)
    return cfg, scene, result, esail.outputs(scene, result)


def test_public_api_and_initial_state(short_run):
    cfg, scene, result, out = short_run
    p = cfg.n_tethers
    assert out["thrust_O"].shape == (len(result.t), 3)
    assert out["coning"].shape == (len(result.t), p)
    for name in ("coning", "lagging", "root_coning", "root_lagging", "length_ratio",
                 "omega_B", "spin_rate", "euler_B", "euler_E", "sailing_angle", "precession_angle",
                 "thrust", "thrust_O", "thrust_angle", "thrust_moment", "reaction_force",
                 "reaction_moment", "reaction_angle", "kinetic", "elastic", "total"):
        assert np.all(np.isfinite(out[name])), name
    assert np.abs(scene.system.constraint_values(scene.initial.q)).max() < 1e-9
    assert out["omega_B"][0] == pytest.approx([4e-3, 0, 0], abs=1e-15)
    # the remote units start in the steady spin of the hub
    assert out["spin_rate"][0] == pytest.approx(4e-3, rel=1e-12)
    assert np.rad2deg(out["sailing_angle"][0]) == pytest.approx(10.0, abs=1e-9)
    assert np.rad2deg(out["euler_B"][0]) == pytest.approx([0, -80, 0], abs=1e-9)
    assert np.abs(out["coning"][0]).max() < 1e-12 and np.abs(out["lagging"][0]).max() < 1e-12
    # stretched by the steady rotating-cable solution: ~8.6e-4 at 4e-3 rad/s
    assert out["length_ratio"][0] == pytest.approx(np.full(p, 1.000861), abs=2e-6)
    assert result.stats["rejected"] == 0


def test_thrust_angle_is_half_the_sailing_angle(short_run):
    """For a flat sail at alpha, each tether at azimuth z feels (I - t t^T) i_R; averaged
    over the spin, the thrust angle is atan(sin a cos a / (1 + cos^2 a)) (= 4.96 deg at
    10 deg: 'close to alpha / 2', as the paper says)."""
    _, _, _, out = short_run
    a = np.deg2rad(10.0)
    expected = np.arctan(np.sin(a) * np.cos(a) / (1 + np.cos(a) ** 2))
    assert out["thrust_angle"][0] == pytest.approx(expected, rel=1e-3)
    F = 12 * 10e3 * SolarWind().force_per_length(20e3)
    # magnitude of the spin average: F/2 sqrt((1 + cos^2 a)^2 + (sin a cos a)^2)
    mag = F / 2 * np.hypot(1 + np.cos(a) ** 2, np.sin(a) * np.cos(a))
    assert np.linalg.norm(out["thrust"][0]) == pytest.approx(mag, rel=2e-3)


def test_modes_of_the_spinning_tether_against_table2():
    """A tether pinned at the hub rim with its remote unit, spinning at 4e-3 rad/s, in the
    rotating frame: the steady state from solve_static with centrifugal loads coincides with
    the analytic stretch used by ``esail.build`` (to 3e-8 m, 3e-12 of the 10 km tether;
    measured 1.3e-8 m with 5 elements), and ``modes(spin=...)`` gives
    the coning (spin) mode 6.37e-4 Hz and the first axial mode 2.17e-2 Hz of Table 2.
    Its first bending pair is at 4.47e-3/4.51e-3 Hz, not Table 2's 7.34e-3 Hz: a taut
    string with T ~ m Omega^2 L = 0.24 N has c / 2L = 4.28e-3 Hz (docs/esail.md)."""
    cfg = esail.BaselineConfig()
    Om = cfg.spin_rate
    system = esail.spinning_tether(cfg, n_elements=5)
    state = sc.solve_static(system)
    assert np.abs(state.q - system.q0).max() < 3e-8
    f, _ = sc.modes(system, state, k=12, spin=[Om, 0, 0])
    assert f[1] == pytest.approx(6.37e-4, rel=1e-3)
    axial = f[np.argmin(np.abs(f - 2.17e-2))]
    assert axial == pytest.approx(2.17e-2, rel=5e-3)
    assert f[2] == pytest.approx(4.468e-3, rel=1e-3) and f[3] == pytest.approx(4.513e-3, rel=1e-3)


def test_spinning_modes_are_those_of_the_constrained_pencil():
    """``modes(spin=)`` (the constraints eliminated, a standard eigenproblem) against the
    QZ algorithm on the first-order KKT pencil ``A z = lambda B z``, ``z = (x, lambda x,
    mu)``, of the spinning tether: the 12 lowest frequencies to 1e-9 relative (measured
    1e-11), but the lowest, the in-plane swing about the hub's rim (6.5e-6 Hz, about
    ``Omega sqrt(R / L) / 2 pi`` = 6.4e-6 Hz), to 1e-6 (measured 2e-8: a root far below the
    pencil's largest carries more of its round-off), and each shape a null vector of
    ``lambda^2 M + lambda G + K`` on the constrained motions, mass-normalised.  With
    ``shapes=False`` (eigenvalues alone) the same frequencies to the same bounds."""
    from scipy.linalg import eigvals, null_space

    from skfem_cable.loads.gravity import spin_matrix
    cfg = esail.BaselineConfig()
    spin = np.array([cfg.spin_rate, 0, 0])
    system = esail.spinning_tether(cfg, n_elements=5)
    state = sc.solve_static(system)
    f, shapes = sc.modes(system, state, k=12, spin=spin)
    lay, n = system.layout, system.n_dofs
    data = lay.linear_data.copy()
    system.evaluate(state.q, None, 0.0, state.lam, data=data, layout=lay)
    K = lay.matrix(data).toarray()
    M = system.mass_matrix().toarray()
    G = 2.0 * spin_matrix(system, system.mass_matrix(), spin, 1).toarray()
    m = K.shape[0] - n
    O, eye = np.zeros, np.eye
    A = np.block([[O((n, n)), eye(n), O((n, m))], [-K[:n, :n], -G, -K[:n, n:]],
                  [K[n:, :n], O((m, n)), O((m, m))]])
    B = np.block([[eye(n), O((n, n + m))], [O((n, n)), M, O((n, m))], [O((m, 2 * n + m))]])
    lam = eigvals(A, B)
    lam = lam[np.isfinite(lam) & (lam.imag >= 0)]
    reference = np.sort(np.abs(lam))[:12] / (2 * np.pi)
    print(f"swing {f[0]:.3e} Hz within {abs(f[0] / reference[0] - 1):.1e}, the others "
          f"within {np.abs(f[1:] / reference[1:] - 1).max():.1e}")
    assert f[0] == pytest.approx(reference[0], rel=1e-6)
    np.testing.assert_allclose(f[1:], reference[1:], rtol=1e-9)
    Z = null_space(K[n:, :n])
    for freq, x in zip(f, shapes):
        lam = 2j * np.pi * freq
        residual = Z.T @ ((lam ** 2 * M + lam * G + K[:n, :n]) @ x)
        assert np.abs(residual).max() < 1e-8 * np.abs(K[:n, :n] @ x).max()
        assert np.conj(x) @ M @ x == pytest.approx(1.0, rel=1e-12)
    alone, none = sc.modes(system, state, k=12, spin=spin, shapes=False)
    assert none is None and alone[0] == pytest.approx(reference[0], rel=1e-6)
    np.testing.assert_allclose(alone[1:], reference[1:], rtol=1e-9)


def test_esail_scene_of_the_command_line_fills_a_run_directory(tmp_path):
    """``skfem-cable run esail`` (reduced): series, outputs, the paper's figures, summary."""
    import json

    from skfem_cable.runner import RunOptions
    from skfem_cable.scenes import catalog

    summary = catalog.run_scene("esail", RunOptions(out=tmp_path, t_end=30.0, elements=2,
                                                    alpha=10.0, every=10, progress=False))
    outputs = summary["outputs"]
    assert outputs["thrust_angle_mean_deg"] == pytest.approx(4.96, abs=0.02)
    saved = np.load(tmp_path / "esail_outputs.npz")
    assert saved["thrust_O"].shape == (len(saved["t"]), 3)
    for name in ("esail_tether", "esail_hub", "esail_forces", "esail_psd"):
        assert (tmp_path / "plots" / f"{name}.png").stat().st_size > 10_000
    written = json.loads((tmp_path / "summary.json").read_text())
    assert written["scene"] == "esail"
    pngs = {p.relative_to(tmp_path).as_posix() for p in (tmp_path / "plots").glob("*.png")}
    assert pngs <= set(written["files"]["plots"]) and len(pngs) >= 7
    assert (tmp_path / "series.pvd").exists()
