"""Electrodynamic tethers: the dipole field, the Lorentz force ``I r_x x B`` and its
tangent, the short-circuit current, and the orbit decay of Gauss's equation."""

import numpy as np
import pytest

import skfem_cable as sc
from skfem_cable.core.contract import Evaluation
from skfem_cable.loads.electrodynamic import MU0_OVER_4PI, OMEGA_EARTH
from skfem_cable.loads.orbit_gravity import system_mass_points

ORBIT = sc.Orbit(sc.MU_EARTH, sc.R_EARTH + 400e3)
TETHER = sc.Section.circular(1e-3, 7e10, 2700.0)


def force_and_tangent(load, system, q, v=None, t=0.0):
    """The load's generalized force and ``dF/dq`` (dense) as its term gives them."""
    term = load.bind(system)
    rows, cols = np.broadcast_arrays(term.rows, term.cols)
    index = np.arange(rows.size).reshape(rows.shape)
    ev = Evaluation(system, t, q, v, np.zeros(system.n_constraints), data=np.zeros(rows.size))
    term.evaluate(ev, index)
    K = np.zeros((system.n_dofs,) * 2)
    np.add.at(K, (rows.ravel(), cols.ravel()), -ev.data)
    return ev.f_ext, K


def central_differences(fn, q, mask):
    """Central differences of ``fn`` in every coordinate: steps of 1 m for positions,
    1e-3 for slopes (the force is linear in the slopes; a slope step moves the element's
    points by about a quarter of its length times the step)."""
    n = q.size
    out = np.empty((fn(q).size, n))
    for j in range(n):
        e = np.zeros(n)
        e[j] = 1.0 if mask[j] else 1e-3
        out[:, j] = (fn(q + e) - fn(q - e)) / (2 * e[j])
    return out


def test_dipole_field_is_minus_the_gradient_of_its_potential():
    """``B = -grad psi``, ``psi = mu_0 / (4 pi) m . x / |x|^3`` (central differences,
    relative 1e-8); ``dB/dx`` against central differences of ``B`` (1e-8); on the equator
    ``mu_0 M / (4 pi r^3)`` northwards, over the north pole twice that, downwards."""
    dipole = sc.MagneticDipole(moment=8.0e22, tilt=0.3, azimuth=1.1, rotation_rate=OMEGA_EARTH)
    t = 5000.0
    m = MU0_OVER_4PI * 8.0e22 * dipole.axis(t)

    def psi(x):
        return m @ x / np.linalg.norm(x) ** 3

    x = np.array([4.1e6, -3.3e6, 2.9e6])
    B, dB = dipole.field(x, t)
    h = 1.0
    grad = np.array([(psi(x + h * e) - psi(x - h * e)) / (2 * h) for e in np.eye(3)])
    assert np.abs(B + grad).max() < 1e-8 * np.abs(B).max()
    fd = np.column_stack([(dipole.field(x + h * e, t)[0] - dipole.field(x - h * e, t)[0])
                          / (2 * h) for e in np.eye(3)])
    assert np.abs(dB - fd).max() < 1e-8 * np.abs(dB).max()
    earth, r = sc.MagneticDipole(), sc.R_EARTH + 400e3
    equator = earth.field([0.0, r, 0.0])[0]
    pole = earth.field([0.0, 0.0, r])[0]
    np.testing.assert_allclose(equator, [0, 0, 1e-7 * 8.0e22 / r**3], rtol=1e-14)
    np.testing.assert_allclose(pole, [0, 0, -2e-7 * 8.0e22 / r**3], rtol=1e-14)
    # the tilted north axis turns about z at rotation_rate
    axis = dipole.axis(t)
    assert -axis[2] == pytest.approx(np.cos(0.3), rel=1e-14)
    assert np.arctan2(-axis[1], -axis[0]) == pytest.approx(1.1 + OMEGA_EARTH * t, rel=1e-14)


def test_straight_tether_in_a_uniform_field_feels_I_L_cross_B():
    """A straight tether in a uniform field: the generalized force is the consistent load
    of ``I t x B`` (scikit-fem's assembly, relative 1e-13) and its sum ``I L x B`` to
    round-off; a tether of any shape feels ``I (r(L) - r(0)) x B`` (the integral of
    ``r_x``)."""
    start, end = np.array([1.0, -2.0, 0.5]), np.array([301.0, 398.0, -99.5])
    cable = sc.Cable.straight(start, end, 5, TETHER)
    system = sc.System([cable])
    B, current = np.array([2e-5, -1e-5, 3e-5]), 2.5
    load = sc.ElectrodynamicForce(cable, current, B)
    F, _ = force_and_tangent(load, system, cable.q0)
    L = end - start
    expected = cable.line_load(current * np.cross(L / np.linalg.norm(L), B))
    assert np.abs(F - expected).max() < 1e-13 * np.abs(expected).max()
    total = load.evaluate(system, cable.q0)["force"]
    exact = current * np.cross(L, B)
    assert np.abs(total - exact).max() < 1e-14 * np.abs(exact).max()
    bent = cable.q0 + np.random.default_rng(1).normal(scale=20.0, size=cable.n_dofs)
    ends = cable.interpolate(bent, np.array([0.0, cable.length]))[0]
    total = load.evaluate(system, bent)["force"]
    exact = current * np.cross(ends[1] - ends[0], B)
    assert np.abs(total - exact).max() < 1e-13 * np.abs(exact).max()


def _inclined_tether():
    orbit = sc.Orbit(sc.MU_EARTH, 7.2e6, e=0.1, inclination=0.8, raan=0.3, anomaly=1.0)
    cable = sc.Cable.straight([0, 1e3, 0], [3e3, 4e3, 2e3], 3, TETHER)
    system = sc.System([cable]).add_orbit(orbit)
    q = system.q0 + np.random.default_rng(3).normal(scale=1.0, size=system.n_dofs)
    return cable, system, q


TILTED = sc.MagneticDipole(tilt=0.2, azimuth=1.0, rotation_rate=OMEGA_EARTH)


@pytest.mark.parametrize("field, tol", [
    (TILTED, 1e-10),                                    # compiled dipole
    ([1e-5, -3e-5, 2e-5], 1e-12),                       # compiled uniform field
    (lambda x, t: TILTED.field(x, t)[0], 1e-10),        # Python path, differenced gradient
], ids=["dipole", "uniform", "callable"])
def test_tangent_against_central_differences(field, tol):
    """``dF/dq`` of a current changing in time on a tether in an inclined, eccentric orbit
    against central differences (measured 1.6e-12 of the largest entry for the dipole,
    7e-13 for the uniform field, 1.6e-12 for the callable field, whose gradient is itself
    a central difference)."""
    cable, system, q = _inclined_tether()
    load = sc.ElectrodynamicForce(cable, lambda t: 2.0 + np.sin(t), field)
    t = 321.0
    K = force_and_tangent(load, system, q, t=t)[1]
    fd = central_differences(lambda x: force_and_tangent(load, system, x, t=t)[0], q,
                             cable.position_mask)
    assert np.abs(K - fd).max() < tol * np.abs(fd).max()


def test_short_circuit_tangent_leaves_out_only_the_rank_one_coupling():
    """With the short-circuit current the tangent is the one at fixed ``I``: central
    differences of the force minus the tangent are ``(F / I) (dI/dq)^T`` (relative 1e-10,
    measured 1.7e-12), the coupling that would fill the cable's block (8 % of the largest
    entry here)."""
    cable, system, q = _inclined_tether()
    load = sc.ElectrodynamicForce(cable, "short-circuit", TILTED, resistance=50.0,
                                  plasma_rotation=[0, 0, OMEGA_EARTH])
    v = np.random.default_rng(4).normal(scale=3.0, size=system.n_dofs)
    t = 321.0
    F, K = force_and_tangent(load, system, q, v, t)
    mask = cable.position_mask
    fd = central_differences(lambda x: force_and_tangent(load, system, x, v, t)[0], q, mask)
    current = load.evaluate(system, q, v, t)["current"]
    dI = central_differences(lambda x: np.array([load.evaluate(system, x, v, t)["current"]]),
                             q, mask)[0]
    coupling = np.outer(F / current, dI)
    assert np.abs(fd - K - coupling).max() < 1e-10 * np.abs(fd).max()
    assert np.abs(coupling).max() > 1e-3 * np.abs(fd).max()   # not a vacuous check


def test_short_circuit_current_is_the_emf_over_the_resistance():
    """A radial tether in an equatorial orbit, at rest relative to the reference point:
    ``E = int_(R-l)^(R+l) (V - Omega r) k M / r^3 dr`` in closed form (relative 1e-12),
    ``I = E / R_c`` and the force that of the fixed current ``E / R_c`` (round-off)."""
    l, R = 2.5e3, ORBIT.a
    cable = sc.Cable.straight([-l, 0, 0], [l, 0, 0], 4, TETHER)
    system = sc.System([cable]).add_orbit(ORBIT)
    load = sc.ElectrodynamicForce(cable, "short-circuit", sc.MagneticDipole(),
                                  resistance=1000.0, plasma_rotation=[0, 0, OMEGA_EARTH])
    out = load.evaluate(system, cable.q0)
    kM, V = 1e-7 * 8.0e22, np.linalg.norm(ORBIT.velocity(0.0))
    emf = kM * (V / 2 * (1 / (R - l) ** 2 - 1 / (R + l) ** 2)
                - OMEGA_EARTH * (1 / (R - l) - 1 / (R + l)))
    assert out["emf"] == pytest.approx(emf, rel=1e-12)
    assert out["current"] == out["emf"] / 1000.0
    fixed = sc.ElectrodynamicForce(cable, out["current"], sc.MagneticDipole())
    np.testing.assert_allclose(out["force"], fixed.evaluate(system, cable.q0)["force"],
                               rtol=1e-15, atol=0)
    assert out["force"][1] < 0   # a brake: against the orbital motion (+y)


def test_short_circuit_run_converges_to_the_current_of_its_state():
    """On the compiled step, a short-circuited tether librating in orbit: at every saved
    step the equations of motion ``M a + f_int - f_ext = 0`` hold with the force of the
    fixed current ``E(q, v) / R_c`` of the converged state to the Newton tolerance, a
    hundred times better than with a current 1e-5 off (measured: 1.7e-3 of it at worst);
    the omitted coupling costs under 5 % more Newton iterations than the prescribed
    current (measured 508 against 500)."""
    cable, system = dumbbell(load=lambda c: sc.ElectrodynamicForce(
        c, "short-circuit", sc.MagneticDipole(), resistance=1000.0))
    start = librated(system, 0.1)
    result = sc.simulate(system, t_end=600.0, dt=20.0, initial=start)
    assert result.stats["path"] == "compiled"
    M, n, load = system.mass_matrix(), system.n_dofs, system.loads[-1]
    currents = []
    for q, v, a, lam, t in zip(result.q, result.v, result.a, result.lam, result.t):
        current = load.evaluate(system, q, v, t)["current"]

        def residual(i, q=q, v=v, a=a, lam=lam, t=t):
            fixed = dumbbell(load=lambda c: sc.ElectrodynamicForce(c, i, sc.MagneticDipole()))
            return np.abs(fixed[1].evaluate(q, v, t, lam)[0][:n] + M @ a).max()

        assert residual(current) < 1e-2 * residual(current * (1 + 1e-5))
        currents.append(current)
    assert 0.5 < np.mean(currents) < 1.5
    _, prescribed = dumbbell(load=lambda c: sc.ElectrodynamicForce(c, np.mean(currents),
                                                                   sc.MagneticDipole()))
    other = sc.simulate(prescribed, t_end=600.0, dt=20.0, initial=start)
    assert result.stats["newton"] <= 1.05 * other.stats["newton"]


def dumbbell(load=None, m=500.0, n_elements=4, length=5e3):
    """A tether of ``length`` along the local vertical between two end masses ``m`` in the
    400 km equatorial orbit, with the load ``load(cable)`` (or none)."""
    cable = sc.Cable.straight([-length / 2, 0, 0], [length / 2, 0, 0], n_elements, TETHER)
    system = (sc.System([cable]).add_point_mass(cable.node(0), m)
              .add_point_mass(cable.node(-1), m).add_orbit(ORBIT))
    if load is not None:
        system.add_load(load(cable))
    return cable, system


def librated(system, angle=0.0):
    """The gravity-gradient steady state of the dumbbell without load, turned by ``angle``
    in pitch, at rest in the orbiting frame, as an initial state of ``system``."""
    n = ORBIT.mean_motion
    steady = sc.solve_steady(dumbbell()[1], omega=[0, 0, n])
    c, s = np.cos(angle), np.sin(angle)
    q = system.rotate(steady.q, np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]]))
    v = system.rotation_operator(np.cross([0, 0, n], np.eye(3)).T) @ q
    return sc.State(system, q, steady.lam, v=v)


def centre_of_mass(system, q, v):
    """Offset and velocity of the centre of mass and the mass."""
    return system.centre_of_mass(q), system.centre_of_mass(v), \
        system_mass_points(system).mass.sum()


def test_orbit_decays_at_the_rate_of_gauss_equation():
    """A 5 km tether carrying 1 A upwards between two 500 kg end masses, gravity-gradient
    stabilised in the 400 km equatorial orbit of a non-tilted dipole: the osculating
    semi-major axis of the centre of mass (from its absolute state) falls at

        da/dt = 2 F_t / (m n)

    within 2 % over three orbits (measured -0.65 % at ``dt = P / 400``; the error is the
    integrator's, second order in ``dt``: -2.5 % at ``P / 200``).  Gauss's equation for a
    tangential force on a near-circular orbit: the specific energy ``-mu / (2 a)`` changes
    at ``v . F / m``, so ``da/dt = 2 a^2 v F_t / (mu m)``, and ``v = n a``,
    ``mu = n^2 a^3`` give ``2 F_t / (m n)``; ``F_t`` is the along-track component of the
    total Lorentz force (about ``-I L B = -0.128 N``), ``m`` the total mass."""
    cable, system = dumbbell(load=lambda c: sc.ElectrodynamicForce(c, 1.0, sc.MagneticDipole()))
    period = ORBIT.period
    result = sc.simulate(system, t_end=3 * period, dt=period / 400, initial=librated(system),
                         every=20)
    load = system.loads[-1]
    a, rate = [], []
    for q, v, t in zip(result.q, result.v, result.t):
        x, u, m = centre_of_mass(system, q, v)
        reference = result.reference  # the run's: the orbit and its rebases
        r, w = reference.position(t) + x, reference.velocity(t) + u
        osculating = sc.Orbit.from_state(sc.MU_EARTH, r, w)
        along = load.evaluate(system, q, v, t, reference)["force"] @ w / np.linalg.norm(w)
        a.append(osculating.a)
        rate.append(2 * along / (m * osculating.mean_motion))
    measured = np.polyfit(result.t, a, 1)[0]
    assert np.mean(rate) == pytest.approx(-0.2179, rel=1e-3)
    assert measured == pytest.approx(np.mean(rate), rel=0.02)


def test_inputs_are_checked_with_clear_errors():
    cable = sc.Cable.straight([0, 0, 0], [1e3, 0, 0], 2, TETHER)
    B = [0, 0, 1e-5]
    with pytest.raises(ValueError, match="current must be a number .* or 'short-circuit'"):
        sc.ElectrodynamicForce(cable, "open", B)
    with pytest.raises(ValueError, match="needs the circuit's resistance"):
        sc.ElectrodynamicForce(cable, "short-circuit", B)
    with pytest.raises(ValueError, match="resistance must be finite and > 0"):
        sc.ElectrodynamicForce(cable, "short-circuit", B, resistance=-1.0)
    with pytest.raises(ValueError, match="resistance is used only with"):
        sc.ElectrodynamicForce(cable, 1.0, B, resistance=10.0)
    with pytest.raises(ValueError, match="current must be finite"):
        sc.ElectrodynamicForce(cable, np.nan, B)
    with pytest.raises(ValueError, match=r"current\(0.0\) must be finite"):
        sc.ElectrodynamicForce(cable, lambda t: np.inf, B)
    with pytest.raises(ValueError, match="field must be a finite 3-vector"):
        sc.ElectrodynamicForce(cable, 1.0, [0, 1e-5])
    with pytest.raises(ValueError, match="plasma_rotation must be a finite 3-vector"):
        sc.ElectrodynamicForce(cable, 1.0, B, plasma_rotation=1.0)
    with pytest.raises(ValueError, match="moment must be finite and > 0"):
        sc.MagneticDipole(moment=0.0)
    with pytest.raises(ValueError, match=r"tilt must lie in \[0, pi\]"):
        sc.MagneticDipole(tilt=4.0)
    bad = sc.ElectrodynamicForce(cable, 1.0, lambda x, t: np.zeros(3))
    with pytest.raises(ValueError, match=r"field\(x, t\) must return a finite array of shape"):
        bad.evaluate(sc.System([cable]), cable.q0)
