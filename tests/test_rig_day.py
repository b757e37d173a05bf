"""A day of the full rig (issue 51, item 6): the auxiliary tethers' law ``"tension-only"``
with its damping coming on continuously over ``onset_strain`` (``laws.builtin.
slack_kelvin_voigt``): the axial force continuous through the switch, the tangent that of
the force, and the truss's section beyond the onset; on one bar of the ring's section
(``esail.FULL_RIG.auxiliary``: EA = 95 N, gamma_axial = 1 s), which the ring's tests
compile too."""

import numpy as np
import pytest

import skfem_cable as sc
from skfem_cable.laws.builtin import tension_only
from skfem_cable.scenes import esail

SECTION = esail.FULL_RIG.auxiliary
ONSET = tension_only.values["onset_strain"]
#: A strain rate of the ring's libration (its strain swings by about 1e-4 over 20 s).
RATE = 1e-4


@pytest.fixture(scope="module")
def bar():
    """One linear element of unit length along x, its first node held by nothing (the
    force is read at the second node's x coordinate, index 3)."""
    cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], 1, SECTION, element="linear",
                              law="tension-only")
    return cable, sc.System([cable])


def state(eps, rate):
    """Coordinates and velocities of the bar at Green strain ``eps`` and its rate."""
    stretch = np.sqrt(1 + 2 * eps)
    q = np.array([0, 0, 0, stretch, 0, 0], dtype=float)
    v = np.array([0, 0, 0, rate / stretch, 0, 0], dtype=float)
    return q, v


def force(system, eps, rate):
    """The axial force on the second node (N)."""
    q, v = state(eps, rate)
    return system.assemble(q, v)[0][3]


def test_the_force_is_continuous_where_the_tether_goes_taut(bar):
    """Switched on at zero strain, the damping force jumped by ``gamma EA eps_dot``
    (9.5 mN here, the design tension's 4.4 times); now the force near the switch is
    of the order of the strain, from either side and either direction of the rate."""
    _, system = bar
    jump = SECTION.gamma_axial * SECTION.EA * RATE
    for rate in (RATE, -RATE):
        for delta in (1e-10, 1e-9):
            assert force(system, -delta, rate) == 0.0
            stretched = force(system, delta, rate)
            bound = SECTION.EA * delta * (1 + SECTION.gamma_axial * RATE / ONSET) * 1.01
            assert abs(stretched) <= bound < 1e-3 * jump


def test_beyond_the_onset_the_section_is_the_truss(bar):
    """At and beyond ``onset_strain`` the force is ``(EA eps + gamma EA eps_dot) |r_x|``,
    and within it the damping is the share ``eps / onset_strain`` of that."""
    _, system = bar
    for eps in (ONSET, 3 * ONSET, 0.5 * ONSET):
        share = min(eps / ONSET, 1.0)
        stretch = np.sqrt(1 + 2 * eps)
        want = SECTION.EA * (eps + share * SECTION.gamma_axial * RATE) * stretch
        assert force(system, eps, RATE) == pytest.approx(want, rel=1e-12)


@pytest.mark.parametrize("eps", [-2e-5, 0.4 * ONSET, 2.5 * ONSET])
def test_the_tangent_is_that_of_the_force(bar, eps):
    """The stiffness ``df/dq`` and damping ``df/dv`` the Newton step factors, against
    central differences of the force, away from the kinks at 0 and ``onset_strain``."""
    cable, system = bar
    q, v = state(eps, RATE)
    h = 1e-9
    for which, (cK, cC) in (("q", (1.0, 0.0)), ("v", (0.0, 1.0))):
        K = system.assemble(q, v, cK=cK, cC=cC)[1].toarray()
        fd = np.empty_like(K)
        for j in range(len(q)):
            dq = np.zeros_like(q)
            dq[j] = h
            plus = system.assemble(*((q + dq, v) if which == "q" else (q, v + dq)))[0]
            minus = system.assemble(*((q - dq, v) if which == "q" else (q, v - dq)))[0]
            fd[:, j] = (plus - minus) / (2 * h)
        scale = np.abs(K).max() + SECTION.EA * abs(eps)
        np.testing.assert_allclose(K, fd, atol=1e-6 * scale)
