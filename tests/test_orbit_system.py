"""Systems in orbit: the differential gravity on every body, its tangent, and the
tethered-satellite results of Beletsky & Levin (rigid-dumbbell librations, the massive
tether's gravity-gradient tension and its string modes)."""

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.spatial.transform import Rotation

import skfem_cable as sc
from skfem_cable.loads.orbit_gravity import system_mass_points

ORBIT = sc.Orbit(sc.MU_EARTH, sc.R_EARTH + 400e3)
N = ORBIT.mean_motion
L = 20e3


def dumbbell(n_elements=8, orbit=ORBIT, m=100.0):
    """Two 100 kg end bodies on a stiff, nearly massless 20 km tether along the local
    vertical."""
    cable = sc.Cable.straight([-L / 2, 0, 0], [L / 2, 0, 0], n_elements,
                              sc.Section.circular(1e-3, 1e11, 1.0))
    system = sc.System([cable]).add_point_mass(cable.node(0), m)
    return cable, system.add_point_mass(cable.node(-1), m).add_orbit(orbit)


def massive_tether(n_elements=16):
    cable = sc.Cable.straight([-L / 2, 0, 0], [L / 2, 0, 0], n_elements,
                              sc.Section.circular(1e-3, 1e11, 1000.0))
    return cable, sc.System([cable]).add_orbit(ORBIT)


def librated(system, state, angle, axis):
    """``state`` turned by ``angle`` about ``axis`` (LVLH), at rest in the orbiting frame."""
    q = system.rotate(state.q, Rotation.from_rotvec(angle * np.asarray(axis)).as_matrix())
    v = system.rotation_operator(np.cross([0, 0, N], np.eye(3)).T) @ q
    return sc.State(system, q, state.lam, v=v)


def spinning_modes(build, k):
    cable, system = build()
    state = sc.solve_steady(system, omega=[0, 0, N])
    freqs, shapes = sc.modes(build()[1].add_centrifugal([0, 0, N]), state, k=k, spin=[0, 0, N])
    out_of_plane = np.array([np.sum(np.abs(s[2::3]) ** 2) / np.sum(np.abs(s) ** 2)
                             for s in shapes])
    return cable, state, 2 * np.pi * np.asarray(freqs) / N, out_of_plane > 0.5


def test_mass_points_hold_mass_centre_and_second_moments():
    """Every body's mass points reproduce its mass, centre of mass and second moments."""
    hub = sc.RigidBody.cylinder(radius=1.0, height=2.0, density=884.0,
                                rotation=Rotation.from_rotvec([0.3, -0.2, 0.5]).as_matrix())
    cable = sc.Cable.straight([0, 1, 0], [3, 5, 2], 4, sc.Section.circular(1e-3, 7e10, 2700.0))
    system = sc.System([hub, cable]).add_point_mass(cable.node(-1), 2.5)
    points = system_mass_points(system)
    x, mass = points.positions(system.q0), points.mass
    M = system.mass_matrix()
    ones = system.rigid_motion_velocity(system.q0, (0, 0, 0), velocity=[1, 1, 1])
    assert mass.sum() == pytest.approx(ones @ M @ ones / 3, rel=1e-13)
    np.testing.assert_allclose(mass @ x / mass.sum(), system.centre_of_mass(system.q0),
                               rtol=1e-12)
    for i in range(3):
        u = system.rigid_motion_velocity(system.q0, (0, 0, 0), velocity=np.eye(3)[i])
        assert mass @ x[:, i] == pytest.approx(u @ M @ system.q0, rel=1e-12)
    assert len(points.groups) - 1 == 1 + 4 + 1   # the hub, 4 elements, the point mass
    # second moments of the hub about its centre: its inertia tensor
    hub_points = slice(0, 6)
    rel = x[hub_points] - hub.positions(hub.q0, hub.center_of_mass)
    second = np.einsum("p,pi,pj->ij", mass[hub_points], rel, rel)
    C = hub.rotation(hub.q0)
    inertia = np.trace(second) * np.eye(3) - second
    np.testing.assert_allclose(inertia, C @ hub.inertia @ C.T, rtol=1e-12, atol=1e-9)


@pytest.mark.parametrize("j2", [None, 1.08262668e-3])
def test_tangent_against_central_differences(j2):
    """The differential gravity's tangent on a free cable, a rigid body and a point mass
    in an inclined, eccentric orbit (with and without J2) against central differences
    (``sc.check_tangent``: the term alone; statics, where it is always assembled)."""
    orbit = sc.Orbit(sc.MU_EARTH, 7.2e6, e=0.1, inclination=0.8, raan=0.3, anomaly=1.0)
    hub = sc.RigidBody.cylinder(radius=2.0, height=3.0, density=500.0, position=(5e2, 0, 0))
    cable = sc.Cable.straight([0, 1e3, 0], [3e3, 4e3, 2e3], 3,
                              sc.Section.circular(2e-3, 1e8, 2000.0))
    system = sc.System([hub, cable]).add_point_mass(cable.node(-1), 10.0)
    system.add_orbit(orbit, j2=j2, body_radius=None if j2 is None else sc.R_EARTH)
    q = system.q0 + np.random.default_rng(3).normal(scale=1.0, size=system.n_dofs)
    check = sc.check_tangent(system, q, t=321.0, step=1.0 / system.layout.length_scale)
    gravity, = (p for p in check.parts if p.name == "differential gravity")
    assert gravity.error < 1e-7, str(check)


def test_uniform_gravity_and_an_orbit_exclude_each_other():
    cable, system = dumbbell()
    with pytest.raises(ValueError, match="add_gravity: the system is in orbit"):
        system.add_gravity([0, -9.81, 0])
    other = sc.System([cable]).add_gravity([0, -9.81, 0])
    with pytest.raises(ValueError, match="uniform gravity"):
        other.add_orbit(ORBIT)
    with pytest.raises(ValueError, match="j2 and body_radius together"):
        sc.System([cable]).add_orbit(ORBIT, j2=1e-3)


def test_dumbbell_tension_and_librations():
    """Rigid-dumbbell limit (Beletsky & Levin): tension ``3 n^2 L m1 m2 / (m1 + m2)``
    (3.840 N) at the centre, pitch at ``sqrt(3) n`` and roll at ``2 n``, within 0.5 %."""
    cable, state, freqs, out_of_plane = spinning_modes(dumbbell, 6)
    expected = 3 * N**2 * L * 100.0 * 100.0 / 200.0
    assert expected == pytest.approx(3.840, abs=1e-3)
    assert cable.tension(state.q, L / 2) == pytest.approx(expected, rel=5e-3)
    pitch = freqs[~out_of_plane][np.argmin(np.abs(freqs[~out_of_plane] - np.sqrt(3)))]
    roll = freqs[out_of_plane][np.argmin(np.abs(freqs[out_of_plane] - 2.0))]
    assert pitch == pytest.approx(np.sqrt(3), rel=5e-3)
    assert roll == pytest.approx(2.0, rel=5e-3)


def test_dumbbell_pitch_libration_in_time():
    """A 0.05 rad pitch offset librates at ``sqrt(3) n`` (to the amplitude's own
    correction, ``1 + (2 theta_0)^2 / 16``), on the compiled step."""
    cable, system = dumbbell()
    steady = sc.solve_steady(system, omega=[0, 0, N])
    period = 2 * np.pi / (np.sqrt(3) * N)
    result = sc.simulate(system, t_end=2 * period, dt=period / 200,
                         initial=librated(system, steady, 0.05, [0, 0, 1]))
    assert result.stats["path"] == "compiled"
    ends = np.array([cable.interpolate(q, np.array([0.0, L]))[0] for q in result.q])
    y = ORBIT.to_lvlh(result.t, ends[:, 1] - ends[:, 0])
    pitch = np.arctan2(y[:, 1], y[:, 0])
    sign = np.sign(pitch)
    k = np.nonzero(sign[:-1] * sign[1:] < 0)[0]
    crossings = result.t[k] - pitch[k] * np.diff(result.t)[k] / (pitch[k + 1] - pitch[k])
    measured = 2 * np.mean(np.diff(crossings))
    assert measured / period == pytest.approx(1 + 0.1**2 / 16, abs=5e-4)
    assert np.max(np.abs(pitch)) == pytest.approx(0.05, rel=1e-3)


def test_massive_tether_tension_and_string_modes():
    """A 20 km tether alone: tension ``3/2 rho A n^2 (l^2 - x^2)`` within 1e-3 of its
    maximum; in-plane modes ``n sqrt(1.5 k (k+1))`` and out-of-plane
    ``n sqrt(1 + 1.5 k (k+1))``, k = 1..3, within 1e-3."""
    cable, state, freqs, out_of_plane = spinning_modes(massive_tether, 16)
    s = np.linspace(0, L, 21)
    x = s - L / 2
    rho_a = cable.section.mass_per_length
    exact = 1.5 * rho_a * N**2 * ((L / 2) ** 2 - x**2)
    assert np.max(np.abs(cable.tension(state.q, s) - exact)) < 1e-3 * exact.max()
    for k in (1, 2, 3):
        for plane, target in ((~out_of_plane, np.sqrt(1.5 * k * (k + 1))),
                              (out_of_plane, np.sqrt(1 + 1.5 * k * (k + 1)))):
            nearest = freqs[plane][np.argmin(np.abs(freqs[plane] - target))]
            assert nearest == pytest.approx(target, rel=1e-3)


def test_eccentric_orbit_pitch_follows_the_dumbbell_equation():
    """In an ``e = 0.05`` orbit the pitch follows ``(1 + e cos v) theta'' - 2 e sin v
    (1 + theta') + 3 sin theta cos theta = 0`` (true anomaly ``v``; derived from the
    angular momentum of a rigid dumbbell, integrated with DOP853) to 2 % of its amplitude
    over 3 orbits (measured 0.64 % at 20 s steps, 0.07 % at 5 s)."""
    e, theta0 = 0.05, 0.05
    orbit = sc.Orbit(sc.MU_EARTH, sc.R_EARTH + 400e3, e=e)
    cable, system = dumbbell(orbit=orbit)
    steady = sc.solve_steady(dumbbell()[1], omega=[0, 0, N])   # the circular orbit's shape
    q = system.rotate(steady.q, Rotation.from_rotvec([0, 0, theta0]).as_matrix())
    turning = np.cross(orbit.angular_velocity(0.0), np.eye(3)).T
    initial = sc.State(system, q, steady.lam, v=system.rotation_operator(turning) @ q)
    result = sc.simulate(system, t_end=3 * orbit.period, dt=20.0, initial=initial)
    ends = np.array([cable.interpolate(q, np.array([0.0, L]))[0] for q in result.q])
    y = orbit.to_lvlh(result.t, ends[:, 1] - ends[:, 0])
    pitch = np.unwrap(np.arctan2(y[:, 1], y[:, 0]))
    anomaly = orbit.true_anomaly(result.t)

    def rhs(v, s):
        return [s[1], (2 * e * np.sin(v) * (1 + s[1]) - 3 * np.sin(s[0]) * np.cos(s[0]))
                / (1 + e * np.cos(v))]

    reference = solve_ivp(rhs, (0, anomaly[-1]), [theta0, 0.0], method="DOP853", rtol=1e-12,
                          atol=1e-12, dense_output=True).sol(anomaly)[0]
    assert np.abs(pitch - reference).max() < 0.02 * np.abs(reference).max()


def test_a_body_joins_an_orbit_through_its_mass_points():
    """A user body (the bead of ``test_extending``) without ``mass_points`` is refused by
    name (a hook of ``contract.Body``); with the hook it feels the differential gravity:
    at ``delta`` along the radius, ``2 n^2 delta`` (to first order) outwards."""
    from test_extending import Bead

    class MasslessBead(Bead):
        mass_points = property(lambda self: self.__getattribute__("no_such_hook"))

    with pytest.raises(TypeError, match="Bead.* lacks mass_points"):
        sc.System([MasslessBead(m=2.0, k=0.0, anchor=[0, 0, 0])])
    bead = Bead(m=2.0, k=0.0, anchor=[10.0, 0, 0])
    system = sc.System([bead]).add_orbit(ORBIT)
    r = system.evaluate(bead.q0, None, 0.0, np.zeros(0))[0]
    assert -r[0] == pytest.approx(2 * N**2 * 10.0 * 2.0, rel=1e-5)


def test_precision_at_one_au():
    """A 1 km tether at rest relative to a circular heliocentric orbit for one day: its
    strain stays within 1e-12 of the tidal one and its position in the orbiting frame
    within 1e-6 m (measured 9e-16 and 3e-10 m at 60 s steps and ``tol = 1e-14``).  The
    same states in absolute coordinates (1.5e11 m) carry strain noise of about 1e-7."""
    orbit = sc.Orbit(sc.MU_SUN, sc.AU, anomaly=0.9)
    n = orbit.mean_motion
    cable = sc.Cable.straight([-500, 0, 0], [500, 0, 0], 8,
                              sc.Section.circular(0.5e-3, 7e10, 2700.0))
    system = sc.System([cable]).add_orbit(orbit)
    radial = orbit.lvlh(0.0)
    steady = sc.solve_steady(system, omega=[0, 0, n],
                             initial=sc.State(system, system.rotate(system.q0, radial.T)))
    v = system.rotation_operator(np.cross([0, 0, n], np.eye(3)).T) @ steady.q
    result = sc.simulate(system, t_end=86400.0, dt=60.0, every=60, tol=1e-14,
                         initial=sc.State(system, steady.q, steady.lam, v=v))
    s = np.linspace(0, 1000, 17)
    strain0 = cable.strain(steady.q, s)
    spurious = max(np.abs(cable.strain(q, s) - strain0).max() for q in result.q)
    assert spurious < 1e-12
    positions = np.array([cable.interpolate(q, s)[0] for q in result.q])
    lvlh = orbit.to_lvlh(result.t, positions)
    assert np.abs(lvlh - lvlh[0]).max() < 1e-6
    absolute = steady.q.copy()
    absolute[cable.position_mask] += np.tile(orbit.position(0.0), cable.n_nodes)
    assert np.abs(cable.strain(absolute, s) - strain0).max() > 1e-9   # what is lost


def test_orbital_energy_is_conserved_to_the_integrators_order():
    """The dumbbell librating (0.1 rad) in a circular orbit, 2 pitch periods, no
    numerical damping: the orbital energy (kinetic plus potential in the central field,
    relative to the reference point's) plus the elastic energy is conserved to the
    integrator's order: its largest change, 0.22 and 0.051 of the libration energy at 50
    and 100 steps per pitch period (the error of the trapezoidal rule on the dumbbell's
    rotation at ``n``, whose kinetic energy is 33 times the libration's), falls as
    ``h^2``."""
    from skfem_cable.loads.orbit_gravity import orbital_energy

    drifts = []
    for steps in (50, 100):
        cable, system = dumbbell()
        steady = sc.solve_steady(system, omega=[0, 0, N])
        initial = librated(system, steady, 0.1, [0, 0, 1])
        period = 2 * np.pi / (np.sqrt(3) * N)
        result = sc.simulate(system, t_end=2 * period, dt=period / steps, initial=initial,
                             rho_inf=1.0)
        total = np.array([orbital_energy(system, q, v, t) for q, v, t in
                          zip(result.q, result.v, result.t)])
        total += result.energy["axial"] + result.energy["bending"]
        libration = 1.5 * N**2 * 0.1**2 * 2 * 100.0 * (L / 2) ** 2
        drifts.append(np.abs(total - total[0]).max() / libration)
    assert drifts[1] < 0.06
    assert drifts[1] < drifts[0] / 3.5
