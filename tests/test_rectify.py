"""Encke's rectification (``solvers.rectify``): a thrusting system in orbit re-bases its
reference on the osculating orbit of its centre of mass, keeps small offsets, follows the
same absolute motion as without, closes its energy books, and continues bit for bit.
Before: the reference stayed the given Keplerian orbit and the offsets grew as ``a t^2 /
2`` (15 km here in 25 minutes)."""

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import skfem_cable as sc
from skfem_cable import io
from skfem_cable.loads.orbit_gravity import system_mass_points
from skfem_cable.model.fingerprint import system_fingerprint

L, M = 1e3, 100.0
THRUST = np.array([0.0, 1.0, 0.3])  # N on each end mass: 0.01 m/s^2 along-track and up
T, DT = 1500.0, 1.0


def thrusting(pinned=False):
    """A 1 km tether with two 100 kg end masses in a 400 km circular orbit, each end
    mass pushed by ``THRUST``; ``pinned``: one end held at the reference point."""
    orbit = sc.Orbit(sc.MU_EARTH, sc.R_EARTH + 400e3)
    cable = sc.Cable.straight([-L / 2, 0, 0], [L / 2, 0, 0], 4,
                              sc.Section.circular(1e-3, 1e11, 1.0))
    system = sc.System([cable])
    for end in (cable.node(0), cable.node(-1)):
        system.add_point_mass(end, M).add_load(sc.PointLoad(end, THRUST))
    if pinned:
        system.pin(cable.node(0))
    return system.add_orbit(orbit), orbit


def point_mass(orbit, t, mass):
    """The centre of mass as a point mass under the central gravity and the thrust,
    propagated independently (DOP853, rtol 1e-13)."""
    def rhs(_, y):
        r = y[:3]
        return np.concatenate([y[3:], -sc.MU_EARTH * r / np.linalg.norm(r) ** 3
                               + 2 * THRUST / mass])

    y0 = np.concatenate([orbit.position(0.0), orbit.velocity(0.0)])
    sol = solve_ivp(rhs, (0.0, t[-1]), y0, method="DOP853", rtol=1e-13, atol=1e-6,
                    dense_output=True)
    return sol.sol(t)[:3].T


def absolute_centre(system, orbit, result):
    return result.reference.position(result.t) + system.centre_of_mass(result.q)


def test_rectified_run_keeps_small_offsets_and_the_absolute_motion():
    runs = {}
    for rectify in (1e-4, None):
        system, orbit = thrusting()
        result = sc.simulate(system, T, DT, every=10, rectify=rectify)
        runs[rectify] = (system, orbit, result)
    system, orbit, result = runs[1e-4]
    assert result.stats["rectification"] == "on" and result.stats["rectifications"] >= 10
    assert runs[None][2].stats["rectification"] == "none"
    offsets = np.linalg.norm(system.centre_of_mass(result.q), axis=1)
    R = np.linalg.norm(result.reference.position(result.t), axis=1)
    assert offsets.max() < 1e-4 * R.min()  # 26 m; without: 15 km
    free = runs[None]
    assert np.linalg.norm(free[0].centre_of_mass(free[2].q), axis=1).max() > 1.4e4
    # the same absolute motion (each saved step read against the arc it was computed
    # in), which a point mass follows to the integrator's error
    reference = point_mass(orbit, result.t, system_mass_points(system).mass.sum())
    departure = np.linalg.norm(reference - sc.Orbit(sc.MU_EARTH, orbit.a).position(result.t),
                               axis=1).max()
    rectified = absolute_centre(system, orbit, result)
    plain = absolute_centre(*free)
    assert np.linalg.norm(rectified - plain, axis=1).max() < 2e-6 * departure
    assert np.linalg.norm(rectified - reference, axis=1).max() < 2e-5 * departure
    # the frame's jumps are booked as external work: the balance stays closed
    E = result.energy
    assert np.abs(E["balance"]).max() < 1e-5 * np.abs(E["external_work"]).max()


def test_rectified_run_continues_bit_for_bit(tmp_path):
    """Over 300 s (the frame re-bases every 74 s): interrupted at 220 s, after two
    re-bases, and resumed from there through two more."""
    class Interrupt(sc.Observer):
        def saved(self, run, step):
            if step.t >= 215.0:
                raise KeyboardInterrupt

    system, orbit = thrusting()
    full = sc.simulate(system, 300.0, DT, every=10)
    rebases = full.reference.rebases
    system, orbit = thrusting()
    with pytest.raises(KeyboardInterrupt):
        sc.simulate(system, 300.0, DT, every=10,
                    observers=[io.RunStore(tmp_path, chunk=7), Interrupt()])
    assert 0 < len(sc.Result.load(tmp_path, system).reference.rebases) < len(rebases)
    system, orbit = thrusting()
    resumed = sc.simulate(system, 300.0, DT, every=10, resume=io.resume(tmp_path),
                          observers=[io.RunStore(tmp_path, chunk=7)])
    for name in ("q", "v", "lam", "external_work"):  # a: not stored by default
        np.testing.assert_array_equal(getattr(resumed, name), getattr(full, name))
    np.testing.assert_array_equal(resumed.reference.rebases, rebases)
    # a loaded run brings its arcs along, so its offsets read against them
    system, orbit = thrusting()
    loaded = sc.Result.load(tmp_path, system)
    np.testing.assert_array_equal(loaded.reference.rebases, rebases)
    np.testing.assert_array_equal(loaded.reference.position(loaded.t),
                                  thrusting_reference(rebases, loaded.t))


def thrusting_reference(rebases, t):
    """The reference positions at ``t`` of an orbit given the ``rebases``, evaluated
    arc by arc with plain Keplerian orbits."""
    given = thrusting()[1]
    out = given.position(t)
    for row in rebases:
        arc = sc.Orbit.from_state(sc.MU_EARTH, row[1:4], row[4:], row[0])
        later = t >= row[0]
        out[later] = arc.position(t[later])
    return out


def test_a_second_run_starts_on_the_given_orbit():
    system, orbit = thrusting()
    first = sc.simulate(system, 300.0, DT, every=10)
    assert len(first.reference.rebases) > 0
    again = sc.simulate(system, 300.0, DT, every=10)
    np.testing.assert_array_equal(again.q, first.q)


def test_a_pin_to_the_reference_point_turns_it_off():
    system, orbit = thrusting(pinned=True)
    result = sc.simulate(system, 100.0, DT, every=10)
    assert result.stats["rectification"].startswith("off: constraint pin Node(cable, 0)")
    assert "ties the system to the reference point" in result.stats["rectification"]
    assert result.stats["rectifications"] == 0 and len(result.reference.rebases) == 0


def test_orbit_arcs():
    given = sc.Orbit(sc.MU_EARTH, 7e6, e=0.01)
    orbit = sc.Reference(given)
    before = system_fingerprint(thrusting()[0])
    r, v = orbit.position(100.0) + [10.0, 0, 0], orbit.velocity(100.0) + [0, 1.0, 0]
    orbit.rebase(r, v, 100.0)
    arc = sc.Orbit.from_state(sc.MU_EARTH, r, v, 100.0)
    t = np.array([0.0, 99.0, 100.0, 500.0])
    np.testing.assert_array_equal(orbit.position(t)[:2], sc.Orbit(sc.MU_EARTH, 7e6,
                                                                   e=0.01).position(t[:2]))
    np.testing.assert_array_equal(orbit.position(t)[2:], arc.position(t[2:]))
    for k, tk in enumerate(t):  # the scalar path agrees with the arrays
        np.testing.assert_allclose(orbit.position(float(tk)), orbit.position(t)[k], rtol=1e-15)
        np.testing.assert_allclose(orbit.lvlh(float(tk)), orbit.lvlh(t)[k], atol=1e-15)
    assert given.a == 7e6 and orbit.arc(150.0).a == arc.a  # the orbit is as given
    np.testing.assert_array_equal(given.position(t), sc.Orbit(sc.MU_EARTH, 7e6,
                                                              e=0.01).position(t))
    with pytest.raises(ValueError, match="not after the last rebase"):
        orbit.rebase(r, v, 100.0)
    copy = sc.Reference(sc.Orbit(sc.MU_EARTH, 7e6, e=0.01))
    copy.restore(orbit.rebases)
    np.testing.assert_array_equal(copy.velocity(t), orbit.velocity(t))
    system, gone = thrusting()
    sc.Reference(gone).rebase(r, v, 100.0)  # a run's state: not in the fingerprint
    assert system_fingerprint(system) == before
