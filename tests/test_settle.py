"""Dynamic relaxation (``solvers.settle``): a released cable settles to its static
equilibrium, which an undamped run does not reach, and a settled E-sail starts calm."""

from dataclasses import replace

import numpy as np
import pytest
from galpha_modes import amplification

import skfem_cable as sc
from skfem_cable.scenes import esail


def swinging_catenary(sag=(0, -1, 0)):
    """A 10 m polymer rope (5 mm, E = 1 GPa) between pins 8 m apart hung as the catenary
    of its length sagging along ``sag`` (the horizontal by default), under gravity along
    -z: it swings about its equilibrium with ``omega`` of about 2 rad/s."""
    sec = sc.Section.circular(5e-3, 1e9, 1100.0)
    cable = sc.Cable.between([0, 0, 0], [8, 0, 0], 10.0, 8, sec, sag=sag)
    system = sc.System([cable]).pin(cable.node(0)).pin(cable.node(-1))
    system.add_gravity([0, 0, -9.81])
    return system, cable


def test_settle_relaxes_a_swinging_cable_to_its_equilibrium():
    """After 60 steps of 1 s (``omega h`` about 2) the midpoint is within 1e-4 m of the
    static equilibrium and nearly at rest; the same run at ``rho_inf = 0.5`` is still
    swinging (more than 0.1 m off: 0.89 m; at 0.3 0.008 m).  At ``rho_inf = 0.8`` it
    swings more (1.25 m) but its steps of 1 s are halved some 3000 times (1.6 s of CPU
    against 0.3)."""
    hanging, down = swinging_catenary(sag=(0, 0, -1))
    equilibrium = sc.solve_static(hanging).position(down, 5.0)
    system, cable = swinging_catenary()
    state = sc.settle(system, 60.0, 1.0)
    assert state.t == pytest.approx(60.0)
    assert np.linalg.norm(state.position(cable, 5.0) - equilibrium) < 1e-4
    assert np.abs(state.v).max() < 1e-3
    ringing = sc.settle(system, 60.0, 1.0, rho_inf=0.5)
    assert np.linalg.norm(ringing.position(cable, 5.0) - equilibrium) > 0.1


def test_settle_refuses_bad_durations():
    system, _ = swinging_catenary()
    for args, name in (((0.0, 1.0), "duration"), ((10.0, np.nan), "dt"), ((1.0, 2.0), "dt")):
        with pytest.raises(ValueError, match=name):
            sc.settle(system, *args)


def test_settled_esail_starts_calm():
    """A full-size sail of 12 tethers settled under the wind starts at t = 0 from its coned
    equilibrium: over half an hour of adaptive steps at ``MISSION_RTOL`` its mean coning
    stays within 5 % of its start (3.4 %), where from the windless spin of ``build`` it
    swings by more than its mean (7.7 deg about 3.0), and it takes at most 0.6 of the
    steps (75 against 230).  (With four tethers the tilt sets each tether's coning
    swinging by 13 deg: that sail is no disc.)"""
    scene = esail.build(replace(esail.FULL_SIZE, n_tethers=12), 10.0, 2)
    calm = esail.settled(scene)
    assert calm.initial.t == 0.0

    def run(start):
        result = sc.simulate(start.system, 1800.0, 1.0, initial=start.initial, rho_inf=0.25,
                             rtol=esail.MISSION_RTOL, atol=1e-3, every=5)
        coning = np.degrees(esail.outputs(start, result)["coning"]).mean(axis=1)
        return result.stats["steps"], coning

    (steps, coning), (windless_steps, windless) = run(calm), run(scene)
    assert np.ptp(coning) < 0.05 * coning[0] and np.ptp(windless) > windless.mean()
    assert steps <= 0.6 * windless_steps
    with pytest.raises(ValueError, match="spins"):
        esail.settled(scene, spins=0.0)


def spectral_radius(omega_h, rho_inf):
    """The spectral radius of a step of the generalized-alpha method in the form of
    Arnold and Bruls (``a``, ``abar``; ``galpha_parameters``) on ``x'' = -omega^2 x``."""
    return np.abs(np.linalg.eigvals(amplification(omega_h, rho_inf))).max()


def test_the_damping_settle_states():
    """The figures of ``solvers.settle``'s docstring: at ``rho_inf = 0`` a step keeps
    0.99995 of a mode at ``omega h = 0.1``, 0.91 at 1, 0.71 at 2, 0.24 at 10, and tends to
    0; at ``rho_inf = 1`` nothing is damped; and the band ``esail.settled`` damps."""
    for omega_h, kept in ((0.1, 0.99995), (1.0, 0.91), (2.0, 0.71), (10.0, 0.24)):
        assert spectral_radius(omega_h, 0.0) == pytest.approx(kept, abs=0.005)
    assert spectral_radius(1e4, 0.0) < 1e-2
    assert spectral_radius(10.0, 1.0) == pytest.approx(1.0, abs=1e-9)
    assert 0.9066**75 < 1e-3  # "a factor 1e3 in 75 steps"
    # esail.settled: its steps take a factor 1e3 off the modes at omega h > 0.59
    steps = esail.SETTLE_SPINS / esail.SETTLE_STEP
    assert spectral_radius(0.59, 0.0) ** steps < 1e-3 < spectral_radius(0.57, 0.0) ** steps
