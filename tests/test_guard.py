"""Never a silent wrong answer: the instability guard and clear errors for bad numbers
(issue 12, numerical faults)."""

import numpy as np
import pytest

import skfem_cable as sc
from skfem_cable.coulomb import SolarWindForce
from skfem_cable.scenes import classics


def spinning(dt=0.5, t_end=1.5, **kwargs):
    scene = classics.spinning_tether(n_elements=10, spin=2.0, tip_mass=0.5)
    return sc.simulate(scene.system, t_end=t_end, dt=dt, initial=scene.initial, **kwargs)


def test_blow_up_without_the_guard_is_what_it_prevents():
    """The fault: the spinning tether at dt = 0.5 s gains 690x its energy and returns
    normally when the guard is off (``energy_tol=None``)."""
    r = spinning(energy_tol=None)
    assert r.energy["total"].max() > 100 * r.energy["total"][0]


def test_guard_retries_smaller_and_keeps_energy_bounded():
    """With the guard (default) the same run rejects the growing steps, retries them
    smaller and ends with its energy balance never above the start."""
    r = spinning()
    assert r.stats["rejected"] > 0
    E = r.energy
    assert E["balance"].max() <= 0.05 * np.abs(E["total"]).max()
    assert E["total"].max() <= E["total"][0] * (1 + 1e-9)


def test_guard_stops_with_a_diagnostic_and_the_results():
    """With one halving allowed the guard stops at the growing step: the message names the
    time, the step, the energy history and the body; the result holds the steps done."""
    with pytest.raises(sc.SimulationError) as info:
        spinning(max_halvings=1)
    msg = str(info.value)
    for part in ("t=0.75", "h=0.25", "energy balance grew", "cable gained",
                 "last accepted steps", "t=0:"):
        assert part in msg, part
    assert len(info.value.result) >= 1 and info.value.result.t[0] == 0.0


def test_guard_sees_no_growth_in_round_off():
    """A large cable at rest: round-off energies (1e-16 J) are no instability."""
    cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], 2000, sc.Section.circular(1e-3, 2e11, 7850))
    r = sc.simulate(sc.System([cable]).pin(cable.node(0)), 3e-3, 1e-3)
    assert r.stats["rejected"] == 0


def test_guard_keeps_driven_work_in_the_balance():
    """A pivot that drives a pendulum does work on it (booked as external work): the
    guard sees no growth, the balance closes within the numerical dissipation."""
    w, a = 2 * np.pi * 10, 0.06
    section = sc.Section.circular(radius=0.02, E=2e11, rho=7850.0)
    pivot = np.array([0, a, 0.0])
    rod = sc.Cable.straight(pivot, pivot + [np.sin(0.1), np.cos(0.1), 0], 3, section)
    system = sc.System([rod]).pin(rod.node(0), lambda t: np.array([0, a * np.cos(w * t), 0]))
    system.add_gravity([0, -9.81, 0])
    r = sc.simulate(system, 1.0, 2 * np.pi / w / 50)
    E = r.energy
    assert r.stats["rejected"] == 0
    assert np.abs(E["external_work"]).max() > 10.0
    assert np.abs(E["balance"]).max() < 0.01 * np.abs(E["external_work"]).max()


@pytest.mark.parametrize("kwargs, match", [
    ({"max_halvings": float("nan")}, "max_halvings must be an integer in"),
    ({"max_halvings": 52}, "max_halvings must be an integer in"),
    ({"dt": 1e-300}, "steps"),
    ({"dt": 1e-3, "t_start": 1e13, "t_end": 1e13 + 1.0}, "does not advance the time"),
    ({"energy_tol": -1.0}, "energy_tol must be"),
])
def test_bad_step_settings_are_refused_at_once(kwargs, match):
    cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], 2, sc.Section.circular(1e-3, 2e11, 7850))
    settings = {"t_end": 1.0, "dt": 1e-3, **kwargs}
    with pytest.raises(ValueError, match=match):
        sc.simulate(sc.System([cable]), **settings)


def test_bad_voltage_names_the_tether():
    cable = sc.Cable.straight([0, 0, 0], [0, 100, 0], 2, sc.Section.circular(1e-3, 2e11, 7850),
                              name="tether 3")
    with pytest.raises(ValueError, match="voltage of tether 'tether 3' at t = 0.0 is nan"):
        SolarWindForce([cable], lambda t: float("nan"))
    load = SolarWindForce([cable], lambda t: 20e3 if t < 1 else -5.0)
    with pytest.raises(ValueError, match=r"at t = 2.0 is -5.0: it must be finite and >= 0"):
        load.coefficients(2.0)


def test_a_cable_too_large_for_memory_is_refused_with_the_estimate():
    with pytest.raises(ValueError, match=r"n_elements = 10000000000: .* needs about 2\.5e\+05"):
        sc.Cable.straight([0, 0, 0], [1, 0, 0], 10**10, sc.Section.circular(1e-3, 2e11, 7850))
