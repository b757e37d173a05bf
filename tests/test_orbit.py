"""Keplerian reference orbits and the cancellation-free differential gravity."""

import mpmath
import numpy as np
import pytest
from scipy.integrate import solve_ivp

import skfem_cable as sc
from skfem_cable.space.kepler import eccentric_anomaly
from skfem_cable.space.tidal import battin_f, differential_gravity, gravity_gradient

LEO = sc.R_EARTH + 400e3
ELEMENTS = [  # e, inclination, raan, argp, anomaly
    (0.0, 0.0, 0.0, 0.0, 0.0),
    (0.05, 0.9, 0.3, 1.1, 2.0),
    (0.7, 2.5, -1.2, 4.0, -0.5),
    (0.3, np.pi, 0.0, 0.7, 3.0),     # retrograde equatorial
    (0.0, 0.4, 1.0, 0.0, 5.0),       # circular inclined
]


def test_constants_and_period():
    """The constants named by the issue; a 400 km orbit lasts 92.56 min."""
    assert (sc.MU_EARTH, sc.MU_SUN, sc.R_EARTH, sc.AU) == (
        3.986004418e14, 1.32712440018e20, 6378.137e3, 1.495978707e11)
    orbit = sc.Orbit(sc.MU_EARTH, LEO)
    assert orbit.period == pytest.approx(2 * np.pi * np.sqrt(LEO**3 / sc.MU_EARTH), rel=1e-15)
    assert orbit.period / 60 == pytest.approx(92.56, abs=5e-3)


def test_default_frame_at_epoch():
    """Defaults: at t = t0 radial is +x, along-track +y, normal +z."""
    orbit = sc.Orbit(sc.MU_EARTH, LEO, e=0.1, t0=5.0)
    np.testing.assert_allclose(orbit.lvlh(5.0), np.eye(3), atol=1e-15)
    np.testing.assert_allclose(orbit.position(5.0), [LEO * 0.9, 0, 0], rtol=1e-15)


@pytest.mark.parametrize("e", [0.0, 0.3, 0.9, 0.999999])
def test_kepler_to_round_off(e):
    m = np.linspace(-20.0, 20.0, 4001)
    ecc = eccentric_anomaly(m, e)
    assert np.max(np.abs(ecc - e * np.sin(ecc) - m)) < 1e-14 * 20


@pytest.mark.parametrize("elements", ELEMENTS)
def test_state_matches_an_independent_propagation(elements):
    """Position and velocity follow Newton's two-body equations (DOP853, rtol 1e-13)
    over 1.5 periods, and ``from_state`` recovers the orbit from any of its states."""
    orbit = sc.Orbit(sc.MU_EARTH, 2 * LEO, *elements, t0=100.0)
    t = orbit.t0 + np.linspace(0.0, 1.5 * orbit.period, 7)
    mu = orbit.mu

    def rhs(_, y):
        return np.concatenate([y[3:], -mu * y[:3] / np.linalg.norm(y[:3]) ** 3])

    y0 = np.concatenate([orbit.position(t[0]), orbit.velocity(t[0])])
    sol = solve_ivp(rhs, (t[0], t[-1]), y0, method="DOP853", t_eval=t, rtol=1e-13,
                    atol=1e-6)
    np.testing.assert_allclose(orbit.position(t), sol.y[:3].T, rtol=0, atol=2e-8 * orbit.a)
    again = sc.Orbit.from_state(mu, orbit.position(t[3]), orbit.velocity(t[3]), t0=t[3])
    np.testing.assert_allclose(again.position(t), orbit.position(t), rtol=0,
                               atol=1e-12 * orbit.a)
    np.testing.assert_allclose(again.velocity(t), orbit.velocity(t), rtol=0,
                               atol=1e-12 * np.sqrt(mu / orbit.a))
    assert again.e == pytest.approx(orbit.e, abs=1e-13)


@pytest.mark.parametrize("elements", ELEMENTS[1:3])
def test_frame_is_orthonormal_and_turns_at_its_rate(elements):
    orbit = sc.Orbit(sc.MU_EARTH, LEO, *elements)
    t = np.linspace(0.0, orbit.period, 5)
    frame = orbit.lvlh(t)
    np.testing.assert_allclose(frame @ frame.transpose(0, 2, 1), np.broadcast_to(
        np.eye(3), frame.shape), atol=1e-14)
    np.testing.assert_allclose(np.linalg.det(frame), 1.0, atol=1e-14)
    np.testing.assert_allclose(frame[:, 0] * np.linalg.norm(orbit.position(t), axis=1)[:, None],
                               orbit.position(t), rtol=1e-14, atol=1e-6)
    h = 1e-3
    rate = (orbit.lvlh(t + h) - orbit.lvlh(t - h)) / (2 * h)
    w = orbit.angular_velocity(t)
    np.testing.assert_allclose(rate[:, 0], np.cross(w, frame[:, 0]), rtol=0, atol=1e-12)
    x = np.random.default_rng(1).normal(size=(5, 4, 3))
    np.testing.assert_allclose(orbit.from_lvlh(t, orbit.to_lvlh(t, x)), x, atol=1e-14)
    np.testing.assert_allclose(orbit.to_lvlh(t[2], x[2]), x[2] @ frame[2].T, atol=1e-15)


@pytest.mark.parametrize("kwargs, name", [
    ({"a": -1.0}, "a"), ({"e": 1.0}, "e"), ({"e": -0.1}, "e"), ({"mu": 0.0}, "mu"),
    ({"inclination": np.nan}, "inclination"), ({"a": np.inf}, "a"), ({"t0": np.nan}, "t0"),
])
def test_bad_elements_are_refused_by_name(kwargs, name):
    args = {"mu": sc.MU_EARTH, "a": LEO} | kwargs
    with pytest.raises(ValueError, match=f"Orbit: {name} must"):
        sc.Orbit(**args)


def test_unbound_state_is_refused():
    r = np.array([LEO, 0, 0])
    with pytest.raises(ValueError, match="not bound"):
        sc.Orbit.from_state(sc.MU_EARTH, r, [0, 1.5 * np.sqrt(2 * sc.MU_EARTH / LEO), 0])


def _exact_difference(mu, big, small):
    with mpmath.workdps(50):
        rr = [mpmath.mpf(float(b)) + mpmath.mpf(float(s)) for b, s in zip(big, small)]
        RR = [mpmath.mpf(float(b)) for b in big]
        nr = mpmath.sqrt(sum(x * x for x in rr)) ** 3
        nR = mpmath.sqrt(sum(x * x for x in RR)) ** 3
        return np.array([float(-mu * (x / nr - y / nR)) for x, y in zip(rr, RR)])


def test_differential_gravity_is_free_of_cancellation():
    """At 1 AU a metre's differential gravity is exact to 1e-14 relative (50-digit
    reference); the naive difference ``g(R + d) - g(R)`` loses 1e-5 to 6e-5 of it (1e-9
    of a kilometre's)."""
    reference = sc.AU * np.array([0.6, 0.8, 0.0])
    deltas = np.array([[1.0, 0, 0], [0, 1.0, 0], [0.3, -0.2, 0.9], [1e3, 2e3, -5e2]])
    ours = differential_gravity(sc.MU_SUN, reference, deltas)
    naive = []
    for d in deltas:
        r = reference + d
        naive.append(-sc.MU_SUN * (r / np.linalg.norm(r) ** 3
                                   - reference / np.linalg.norm(reference) ** 3))
    for d, mine, plain in zip(deltas, ours, naive):
        exact = _exact_difference(sc.MU_SUN, reference, d)
        scale = np.linalg.norm(exact)
        assert np.linalg.norm(mine - exact) < 1e-14 * scale
        if np.linalg.norm(d) < 2:
            assert np.linalg.norm(plain - exact) > 1e-6 * scale   # what subtraction loses


def test_battin_f_matches_its_definition():
    """``f(q) = (1 + q)^(3/2) - 1`` to 2e-16 relative, also where forming it by
    subtraction would lose every digit."""
    q = np.array([-0.5, -1e-3, 1e-9, 0.2, 3.0, 1e-20])
    with mpmath.workdps(40):
        exact = np.array([float((1 + mpmath.mpf(x)) ** 1.5 - 1) for x in q])
    np.testing.assert_allclose(battin_f(q), exact, rtol=2e-16)


def test_gravity_gradient_against_central_differences():
    reference = np.array([LEO, 2e5, -1e5])
    delta = np.array([[300.0, -200.0, 50.0], [-5e3, 1e4, 2e3]])
    tangent = gravity_gradient(sc.MU_EARTH, reference + delta)
    h = 1.0
    for k in range(3):
        e = np.zeros(3)
        e[k] = h
        column = (differential_gravity(sc.MU_EARTH, reference, delta + e)
                  - differential_gravity(sc.MU_EARTH, reference, delta - e)) / (2 * h)
        np.testing.assert_allclose(tangent[:, :, k], column, rtol=1e-8,
                                   atol=1e-9 * np.abs(tangent).max())


def test_j2_acceleration_is_minus_the_gradient_of_its_potential():
    """``a_J2 = -grad(mu J2 R_e^2 (3 z^2 - r^2) / (2 r^5))`` (central differences,
    mpmath); at the pole it points away from the centre with ``3 mu J2 R_e^2 / r^4``
    (an oblate body attracts less over its poles)."""
    from skfem_cable.kernels.central import j2_acceleration

    j2, k = 1.08262668e-3, 1.5 * sc.MU_EARTH * 1.08262668e-3 * sc.R_EARTH**2
    r = np.array([4.1e6, -3.3e6, 4.4e6])
    out = np.empty(3)
    j2_acceleration(k, r, out)
    with mpmath.workdps(40):
        x = [mpmath.mpf(float(c)) for c in r]

        def potential(*p):
            rr = mpmath.sqrt(sum(c * c for c in p))
            return sc.MU_EARTH * j2 * sc.R_EARTH**2 * (3 * p[2] ** 2 - rr**2) / (2 * rr**5)

        grad = [mpmath.diff(potential, x, tuple(int(i == j) for j in range(3)))
                for i in range(3)]
    np.testing.assert_allclose(out, [-float(g) for g in grad], rtol=1e-12)
    j2_acceleration(k, np.array([0.0, 0.0, 7e6]), out)
    np.testing.assert_allclose(out, [0, 0, 2 * k / 7e6**4], rtol=1e-14)
