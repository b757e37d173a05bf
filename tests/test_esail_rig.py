"""The E-sail's full rig (issue 51, item 2): remote units at the tips, the ring of
auxiliary tethers at its design tension in the steady spin under the wind, the main
tethers' angles equal, and the neighbouring remote units' spacing under on-off voltage
modulation, on a small rig (6 tethers of 2 elements; the 100-tether rig is
``benchmarks/esail_rig.py``)."""

from dataclasses import replace

import numpy as np
import pytest
from demo_modules import load_demo

import skfem_cable as sc
from skfem_cable.scenes import esail
from skfem_cable.scenes.esail.modulation import alternating_voltage
from skfem_cable.scenes.esail.rig import steady_facing

SMALL = replace(esail.FULL_SIZE, n_tethers=6)
RIG = replace(esail.FULL_RIG, config=SMALL)


@pytest.fixture(scope="module")
def ringed():
    return RIG.build(30.0, 2)


@pytest.fixture(scope="module")
def steady(ringed):
    return steady_facing(ringed)


def test_remote_unit_refuses_bad_values():
    with pytest.raises(ValueError, match="mass"):
        esail.RemoteUnit(mass=0.0, inertia=0.01, thrust_max=1e-4)
    with pytest.raises(ValueError, match="inertia"):
        esail.RemoteUnit(mass=1.5, inertia=np.diag([1.0, 1.0, -1.0]), thrust_max=1e-4)
    with pytest.raises(ValueError, match="thrust_max"):
        esail.RemoteUnit(mass=1.5, inertia=0.01, thrust_max=-1.0)
    with pytest.raises(ValueError, match="auxiliary_tension"):
        esail.build(SMALL, 30.0, 2, auxiliary=RIG.auxiliary, auxiliary_tension=0.0)
    with pytest.raises(ValueError, match="n_tethers >= 3"):
        esail.build(replace(SMALL, n_tethers=2), 30.0, 2, auxiliary=RIG.auxiliary)


def test_the_rig_carries_the_units_and_the_ring(ringed):
    assert ringed.config.remote_mass == RIG.remote_units.mass
    assert len(ringed.auxiliary) == SMALL.n_tethers
    assert all(c.law.name == "tension-only" for c in ringed.auxiliary)
    # every auxiliary tether joins two neighbouring tips: 2 pins each, besides the roots'
    assert ringed.system.n_constraints == 3 * (3 * SMALL.n_tethers) + 6


def test_tension_only_law_goes_slack():
    section = RIG.auxiliary
    bar = sc.Cable.straight([0, 0, 0], [1, 0, 0], 1, section, element="linear",
                            law="tension-only")
    f, _ = sc.System([bar]).assemble(0.9 * bar.q0)
    assert np.abs(f).max() == 0.0
    f, _ = sc.System([bar]).assemble(1.01 * bar.q0)
    eps = (1.01**2 - 1) / 2
    assert np.isclose(abs(f[3]), section.EA * eps * 1.01, rtol=1e-12)


def test_windless_spin_holds_the_design_tension():
    cfg = replace(SMALL, voltage=0.0)
    scene = replace(RIG, config=cfg).build(30.0, 2)
    tension = esail.auxiliary_tension(scene, scene.initial.q)
    np.testing.assert_allclose(tension, RIG.auxiliary_tension, rtol=1e-9)
    state, R = steady_facing(scene)  # the start is the steady spin
    assert np.abs(state.q - scene.system.rotate(scene.initial.q, R)).max() < 1e-6


def test_sailing_spin_holds_the_design_tension_and_equal_angles(ringed, steady):
    """The design's equivalent sail leaves out the axial inertia of its change of tip
    mass (``rig._ring_design``): 1.1 % on the tension here after one pass, 6.5e-5 after
    the two of ``RING_PASSES`` (8 x 2, measured)."""
    state, R = steady
    tension = esail.auxiliary_tension(ringed, state.q)
    np.testing.assert_allclose(tension, RIG.auxiliary_tension, rtol=1e-3)
    assert np.ptp(tension) < 1e-9 * tension.mean()
    hub = state.q[ringed.system.dofs(ringed.hub)].reshape(4, 3)
    axis = ringed.hub.rotation(state.q[ringed.system.dofs(ringed.hub)])[:, 0]
    tips = esail.tip_positions(ringed, state.q) - 0.5 * (hub[0] + hub[1])
    coning = np.arcsin(tips @ axis / np.linalg.norm(tips, axis=1))
    assert coning.min() > np.deg2rad(1.0)  # the wind cones the sail
    assert np.ptp(coning) < 1e-9
    spacing = esail.tip_spacing(ringed, state.q)
    assert np.ptp(spacing) < 1e-9 * spacing.mean()


def test_alternating_voltage():
    v = alternating_voltage(4, 20e3, 100.0)
    assert v(10.0).tolist() == [20e3, 0.0, 20e3, 0.0]
    assert v(60.0).tolist() == [0.0, 20e3, 0.0, 20e3]


def test_the_ring_keeps_the_units_apart_under_modulation():
    """One spin period of on-off modulation, neighbours in antiphase (``demos/esail_rig.py``
    at 6 x 2): with the ring the units keep >= 50 % of their nominal spacing (measured
    1.00 at 24 x 3); without it they come closer (0.02 at 24 x 3: nearly a collision)."""
    out = load_demo("esail_rig").main(tethers=6, elements=2, per_spin=45, relax=0.25)
    assert out["with_ring"].min() >= 0.5
    assert out["without_ring"].min() < out["with_ring"].min()
