"""The space loads on a line body that is not a ``Cable`` (``tests/line_body.py``'s
Lagrange-quadratic string, positions only): ``SolarWindForce`` and ``ElectrodynamicForce``
reach it through the line-body hook alone (``lines.line_points``), with forces against
independent checks, exact tangents and a run on the compiled step; on the E-sail's
tethers both equal what they gave before the hook (issue 46)."""

import numpy as np
import pytest
from line_body import QuadraticString

import skfem_cable as sc
from skfem_cable.core.contract import Evaluation
from skfem_cable.core.lines import line_points
from skfem_cable.loads.coulomb import AU, THRUST_EXPONENT, SolarWind, SolarWindForce
from skfem_cable.loads.electrodynamic import MU0_OVER_4PI, OMEGA_EARTH
from skfem_cable.scenes import esail

EA, RHO_A = 1.0e3, 1.0e-4


def string(start, end, n=4, name="string"):
    return QuadraticString(start, end, n, EA, RHO_A, name=name)


def curved(system, seed, size=0.02):
    """A curved state: the initial coordinates plus ``size`` times the coordinates' scale
    times normal noise."""
    scale = system.current_layout().coordinate_scale
    return system.q0 + size * scale * np.random.default_rng(seed).standard_normal(
        system.n_dofs)


def term_of(system, name):
    (term, index), = [(t, i) for t, i in system.current_layout().load_terms
                      if t.name == name]
    return term, index


def force_and_tangent(system, name, q, v, t):
    """The term ``name``'s external force (n,) and its tangent's matrix values at
    ``(q, v, t)``, with ``cK = 0.7``, ``cC = 0.3``."""
    term, index = term_of(system, name)
    lay = system.current_layout()
    data = np.zeros(lay.nnz)
    ev = Evaluation(system, t, q, v, np.zeros(lay.n_c), 0.7, 0.3, data)
    term.evaluate(ev, index)
    return ev.f_ext, data


def fingerprint(f, data):
    """Four numbers of a force and a tangent: their dot products with fixed random
    vectors and their norms."""
    rng = np.random.default_rng(11)
    return [f @ rng.standard_normal(f.size), np.linalg.norm(f),
            data @ rng.standard_normal(data.size), np.linalg.norm(data)]


# --- the solar wind ---------------------------------------------------------------------


def test_solar_wind_on_straight_strings_across_the_wind():
    """Two straight strings across the wind (along y and z, 20 and 10 kV), the Sun at
    0.5 AU along -x: the resultant is ``sum c L (AU / (0.5 AU))^(7/6)`` along +x (to
    1e-12), each string's nodal forces add up to its share (the quadratic functions sum
    to one), and a string of zero voltage gets nothing."""
    a = string([0, 0, 0], [0, 120.0, 0], name="a")
    b = string([0, 0, 0], [0, 0, -80.0], n=3, name="b")
    off = string([5.0, 0, 0], [5.0, 50.0, 0], name="off")
    load = SolarWindForce([a, b, off], [20e3, 10e3, 0.0], sun_position=(-0.5 * AU, 0, 0))
    system = sc.System([a, b, off]).add_load(load)
    f = np.zeros(system.n_dofs)
    resultant = load.add_force(system, system.q0, 0.0, f)
    wind = SolarWind()
    scaling = 2.0 ** THRUST_EXPONENT
    shares = {"a": wind.force_per_length(20e3) * 120.0 * scaling,
              "b": wind.force_per_length(10e3) * 80.0 * scaling, "off": 0.0}
    expected = np.array([shares["a"] + shares["b"], 0.0, 0.0])
    np.testing.assert_allclose(resultant, expected, rtol=1e-12, atol=1e-12 * expected[0])
    for body in (a, b, off):
        nodal = f[system.dofs(body)].reshape(-1, 3).sum(axis=0)
        np.testing.assert_allclose(nodal, [shares[body.name], 0, 0], rtol=1e-12,
                                   atol=1e-12 * expected[0])


def test_solar_wind_tangent_on_a_curved_string_against_differences():
    """A Sun 50 m away (the distance scaling's and ``i_R``'s derivatives of the force's
    order), a curved string: the tangent matches central differences to 1e-7."""
    body = string([0, 0, 0], [3.0, 30.0, -4.0], n=3)
    system = sc.System([body]).add_load(
        SolarWindForce([body], 20e3, sun_position=(-40.0, -25.0, 10.0)))
    q = curved(system, 7, 0.01)
    check = sc.check_tangent(system, q, step=1e-6 / system.layout.length_scale)
    wind, = (p for p in check.parts if p.name == "solar wind")
    assert wind.error < 1e-7, str(check)


def test_a_body_without_the_hook_is_refused_by_name():
    class Rod:
        name = "rod"

    with pytest.raises(TypeError, match="must be a line body.*line_points"):
        line_points(Rod(), None)


def test_strings_of_different_elements_in_one_wind_are_refused():
    """One load runs one loop: its line bodies share the points and functions per
    element (ValueError naming them otherwise)."""
    body = string([0, 0, 0], [0, 10.0, 0])
    cable = sc.Cable.straight([1, 0, 0], [1, 10.0, 0], 2, sc.Section.circular(1e-4, 7e10, 2700))
    system = sc.System([body, cable]).add_load(SolarWindForce([body, cable], 20e3))
    with pytest.raises(ValueError, match="same points and functions per element"):
        system.current_layout()


# --- the electrodynamic force -----------------------------------------------------------


def dipole_field(x, moment, t):
    """Jackson Eq. 5.56 at positions ``x`` (..., 3), for ``sc.MagneticDipole``'s
    moment ``moment`` (its axis at time ``t``)."""
    m = MU0_OVER_4PI * moment.moment * moment.axis(t)
    r = np.linalg.norm(x, axis=-1, keepdims=True)
    return 3 * (x @ m)[..., None] * x / r**5 - m / r**3


def orbiting_string(current, resistance=None):
    orbit = sc.Orbit(sc.MU_EARTH, sc.R_EARTH + 400e3, inclination=0.4)
    body = string([-2.5e3, 0, 0], [2.5e3, 300.0, 100.0], n=4)
    field = sc.MagneticDipole(tilt=0.3, azimuth=0.5, rotation_rate=OMEGA_EARTH)
    load = sc.ElectrodynamicForce(body, current, field, resistance=resistance,
                                  plasma_rotation=[0, 0, OMEGA_EARTH])
    system = sc.System([body]).add_orbit(orbit).add_load(load)
    return body, system, load, orbit, field


def test_electrodynamic_short_circuit_against_numpy():
    """A curved string moving along an inclined orbit, short-circuited through 200 ohm in a
    tilted, turning dipole: the EMF, the current, the resultant and the generalized force
    equal a numpy computation over the hook's points (``LinePoints.at``) to 1e-12."""
    body, system, load, orbit, field = orbiting_string("short-circuit", 200.0)
    q = curved(system, 4)
    v = np.random.default_rng(5).standard_normal(system.n_dofs)
    t = 600.0
    points = line_points(body, system)
    X, A, V = points.at(q, v)
    X, V = X + orbit.position(t), V + orbit.velocity(t)
    B = dipole_field(X, field, t)
    u = V - np.cross([0, 0, OMEGA_EARTH], X)
    emf = np.einsum("eg,egi->", points.w, np.cross(u, B) * A)
    current = emf / 200.0
    f = current * np.cross(A, B)
    generalized = np.zeros(system.n_dofs)
    np.add.at(generalized, points.edofs,
              np.einsum("eg,egA,egi->eAi", points.w, points.S, f).reshape(points.edofs.shape))

    out = load.evaluate(system, q, v, t)
    assert out["emf"] == pytest.approx(emf, rel=1e-12)
    assert out["current"] == pytest.approx(current, rel=1e-12)
    np.testing.assert_allclose(out["force"], np.einsum("eg,egi->i", points.w, f),
                               rtol=1e-12, atol=1e-12 * np.abs(f).max())
    f_ext, _ = force_and_tangent(system, "electrodynamic force string", q, v, t)
    np.testing.assert_allclose(f_ext, generalized, rtol=1e-12,
                               atol=1e-12 * np.abs(generalized).max())


def test_electrodynamic_tangent_on_a_curved_string_against_differences():
    """A prescribed current (the tangent is exact at fixed current) in the dipole of an
    orbit: the tangent matches central differences (steps of 5 cm on a 5 km string) to
    1e-9 (measured 6.5e-12)."""
    body, system, load, orbit, field = orbiting_string(2.0)
    q = curved(system, 8)
    check = sc.check_tangent(system, q, t=100.0, step=1e-5)
    ed, = (p for p in check.parts if p.name == "electrodynamic force string")
    assert ed.error < 1e-9, str(check)


# --- on the compiled step ---------------------------------------------------------------


def test_both_loads_on_a_pinned_string_run_on_the_compiled_step():
    """A string pinned at one end, in a modulated solar wind (along +x) and carrying a
    current across a uniform field along z (force along +x too): 40 steps on the
    compiled Newton step; the free end moves downwind."""
    body = string([0, 0, 0], [0, 20.0, 0], n=4)
    wind = SolarWindForce([body], lambda t: 20e3 * (1 + 0.5 * np.sin(t)),
                          sun_position=(-AU, 0, 0))
    lorentz = sc.ElectrodynamicForce(body, 1e-3, [0, 0, 1e-4])
    system = sc.System([body]).pin(body.node(0)).add_load(wind).add_load(lorentz)
    result = sc.simulate(system, t_end=4.0, dt=0.1)
    assert result.stats["path"] == "compiled"
    tip = result.q[:, system.dofs(body)[-3:]]
    assert np.all(np.isfinite(result.q)) and tip[-1, 0] > 1e-3
    np.testing.assert_allclose(tip[-1, 1:], [20.0, 0.0], atol=0.5)


# --- the E-sail's tethers: as before the hook -------------------------------------------

#: ``fingerprint`` of the solar wind's force and tangent on the E-sail rig and of the
#: electrodynamic force's on an orbiting tether, computed at 35fde8e (before the hook).
BEFORE = {"wind": [1.4146483331211295, 0.8191648325538641, 0.2773466553973186,
                   0.3012218141866374],
          "electrodynamic": [-33.379039869495585, 22.91455754969391, -3.0919043401108643,
                             9.405336375918354]}


def test_the_esail_rig_wind_is_as_before():
    """The solar wind on the 12 x 5 rig at a curved, moving state: force and tangent as
    before the hook, to 1e-13."""
    scene = esail.build(esail.BaselineConfig(), 10.0, 5)
    system = scene.system
    lay = system.current_layout()
    rng = np.random.default_rng(3)
    q = scene.initial.q + 0.02 * lay.coordinate_scale * rng.standard_normal(system.n_dofs)
    v = scene.initial.v + 0.01 * lay.coordinate_scale * rng.standard_normal(system.n_dofs)
    got = fingerprint(*force_and_tangent(system, "solar wind", q, v, 3.0))
    np.testing.assert_allclose(got, BEFORE["wind"], rtol=1e-13)


def test_the_electrodynamic_tether_is_as_before():
    """A short-circuited tether in a tilted dipole on a 400 km orbit, at a curved, moving
    state: force and tangent as before the hook, to 1e-13."""
    orbit = sc.Orbit(sc.MU_EARTH, sc.R_EARTH + 400e3)
    tether = sc.Cable.straight([-2.5e3, 0, 0], [2.5e3, 300.0, 100.0], 4,
                               sc.Section.circular(1e-3, 7e10, 2700.0))
    system = sc.System([tether]).add_orbit(orbit)
    system.add_load(sc.ElectrodynamicForce(tether, "short-circuit",
                                           sc.MagneticDipole(tilt=0.3, azimuth=0.5),
                                           resistance=200.0))
    lay = system.current_layout()
    rng = np.random.default_rng(4)
    q = system.q0 + 0.02 * lay.coordinate_scale * rng.standard_normal(system.n_dofs)
    v = rng.standard_normal(system.n_dofs)
    got = fingerprint(*force_and_tangent(system, "electrodynamic force cable", q, v, 5.0))
    np.testing.assert_allclose(got, BEFORE["electrodynamic"], rtol=1e-13)
