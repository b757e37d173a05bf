"""The rod's coupling of twist and bending (issue 48, docs/rods.md): Greenhill's shaft
under semi-tangential end torques, a tumbling tape storing no energy (a few turns of
``benchmarks/rod_tumbling.py``), the loads of tethers in orbit reaching a rod as a
cable, and a rod clamped to a rigid body transmitting torque (``TwistTie``)."""

import sys
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import brentq

import skfem_cable as sc
from skfem_cable import constraints

#: An isotropic shaft, EI = GJ = 1, nearly inextensible (EA L^2 / EI = 1e8).
SHAFT = sc.Section(E=1.0, A=1e8, I=1.0, rho=1.0, G=1.0, J=1.0)


def semi_tangential_critical(p):
    """The critical ``m = M L / EI`` of a shaft on spherical hinges under the compression
    ``p = P L^2 / EI`` and semi-tangential torques ``M`` at both ends (derived in
    docs/rods.md): ``m^2 (cos(m / 2) - cos(d / 2)) = p d sin(d / 2)``, ``d = sqrt(m^2 +
    4 p)``; at ``p = 0``, ``tan(m / 2) = -m / 6``."""
    if p == 0:
        return 2 * brentq(lambda y: np.tan(y) + y / 3, 2.0, 3.0, xtol=1e-14)

    def characteristic(m):
        d = np.sqrt(m * m + 4 * p)
        return m * m * (np.cos(m / 2) - np.cos(d / 2)) - p * d * np.sin(d / 2)

    return brentq(characteristic, 1e-3, 2 * np.sqrt(np.pi**2 - p), xtol=1e-14)


def lowest_eigenvalue(torque, compression, n_elements=16):
    """The signed square of the lowest frequency of the hinged shaft twisted by
    ``torque`` (a ``TwistTorque`` at the sliding end, the twist held at the other) and
    compressed by ``compression``, about its loaded straight state."""
    rod = sc.Rod.straight([0, 0, 0], [1, 0, 0], n_elements, SHAFT, normal=[0, 0, 1])
    system = sc.System([rod]).pin(rod.node(0))
    system.add_constraint(constraints.hold_twist(rod.node(0)))
    system.pin(rod.node(-1), directions=[[0, 1, 0], [0, 0, 1]])
    system.add_point_load(rod.node(-1), [-compression, 0, 0])
    system.add_load(sc.TwistTorque(rod.node(-1), torque))
    freqs, _ = sc.modes(system, sc.solve_static(system), k=1)
    return freqs[0] * abs(freqs[0])


@pytest.mark.parametrize("p", [0.0, np.pi**2 / 2], ids=["torque", "torque-compression"])
def test_greenhill_shaft_under_semi_tangential_torques(p):
    """A shaft on spherical hinges (one sliding along its axis under the compression P),
    twisted by semi-tangential end torques (``TwistTorque`` and the held twist's
    reaction), buckles where its lowest frequency vanishes: at the critical torque of
    that kind (``semi_tangential_critical``) within 1e-3 at 16 elements (measured 1.0e-5
    at P = 0, 1.1e-5 at P = EI pi^2 / (2 L^2)); Greenhill's axial-torque value
    ``2 EI sqrt(pi^2 / L^2 - P / EI)`` is not this kind's."""
    exact = semi_tangential_critical(p)
    critical = brentq(lambda m: lowest_eigenvalue(m, p), 0.9 * exact, 1.1 * exact, xtol=1e-9)
    assert critical == pytest.approx(exact, rel=1e-3)
    assert abs(critical / (2 * np.sqrt(np.pi**2 - p)) - 1) > 0.2


def test_twist_torque_is_a_constant_force_on_the_twist():
    """``TwistTorque``: the constant generalized force T on the node's twist (its tangent
    is zero, exactly); refused on a cable's node."""
    rod = sc.Rod.straight([0, 0, 0], [1, 0, 0], 3, SHAFT, normal=[0, 0, 1])
    system = sc.System([rod]).add_load(sc.TwistTorque(rod.node(1), 0.7))
    f = system.f_const
    assert f[system.dofs(rod)[rod.node(1).twist_dofs]] == pytest.approx([0.7])
    assert np.count_nonzero(f) == 1
    cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], 3, SHAFT)
    with pytest.raises(ValueError, match="node must be a rod's node"):
        sc.TwistTorque(cable.node(0), 1.0)
    with pytest.raises(ValueError, match="torque must be a finite number"):
        sc.TwistTorque(rod.node(0), np.nan)


def test_tumbling_tape_stores_no_bending_or_twist():
    """A free tape tumbling at 10 rad/s about an oblique axis: over 3 turns (400 steps a
    turn) its bending and twist energy, in the run's books, stays below 1e-10 of its
    kinetic energy (measured 1.1e-13; 100 turns in ``benchmarks/rod_tumbling.py``) and
    its section spins at omega . t to 1e-5."""
    sys.path.insert(0, str(Path(__file__).parents[1] / "benchmarks"))
    import rod_tumbling

    ratio, spin_error, _ = rod_tumbling.run(3, 400)
    assert ratio < 1e-10
    assert spin_error < 1e-5


ORBIT = sc.Orbit(sc.MU_EARTH, 7.2e6, e=0.1, inclination=0.8, raan=0.3, anomaly=1.0)
#: A wire without torsional stiffness to speak of (G = 1e-12 E).
WIRE = sc.Section.circular(1e-3, 7e10, 2700.0, G=7e-2)


def in_orbit(body, load):
    """``body`` (a 100 m tether, its centre at the orbit's reference point) in orbit with
    ``load(body)`` (or none)."""
    system = sc.System([body]).add_orbit(ORBIT)
    return system if load is None else system.add_load(load(body))


LOADS = {
    "differential gravity": None,
    "free-molecular drag": lambda b: sc.FreeMolecularDrag(b, 1e-6, 2e-3,
                                                          velocity=[-7.5e3, 0, 0]),
    "solar wind": lambda b: sc.SolarWindForce([b], 2e4, sun_position=[0, -sc.AU, 0]),
    "electrodynamic": lambda b: sc.ElectrodynamicForce(b, 2.0, [1e-5, -3e-5, 2e-5]),
}


@pytest.mark.parametrize("load", LOADS.values(), ids=LOADS.keys())
def test_orbit_loads_reach_a_rod_as_a_cable(load):
    """A 100 m wire tumbling in an inclined eccentric orbit (differential gravity) under
    free-molecular drag, the solar wind's force or an electrodynamic force (prescribed
    current): as a rod without torsional coupling (G = 1e-12 E) its centreline follows
    the cable's to 1e-8 of its length over 60 s (measured: bit for bit under
    differential gravity, the solar wind and the electrodynamic force, 3.0e-11 under
    free-molecular drag)."""
    start, end = [0, -50, 0], [20, 48, 10]
    rod = sc.Rod.straight(start, end, 4, WIRE, normal=[0, 0, 1])
    cable = sc.Cable.straight(start, end, 4, WIRE)
    n = rod.n_centreline
    v = rod.rigid_velocity([0.02, 0.0, 0.05], [10, -1, 5])
    result = sc.simulate(in_orbit(rod, load), t_end=60.0, dt=0.5, initial=(rod.q0, v))
    reference = sc.simulate(in_orbit(cable, load), t_end=60.0, dt=0.5,
                            initial=(cable.q0, v[:n]))
    assert np.abs(result.q[-1][:n] - result.q[0][:n]).max() > 1.0
    assert np.abs(result.q[:, :n] - reference.q).max() < 1e-8 * rod.length


def test_docstring_examples_run():
    """The examples of ``TwistTorque`` and ``hold_twist``."""
    import doctest

    from skfem_cable.constraints import joints
    from skfem_cable.loads import twist

    for module in (twist, joints):
        result = doctest.testmod(module, optionflags=doctest.ELLIPSIS)
        assert result.attempted > 0 and result.failed == 0


def hub_and_shaft(L=2.0):
    """A rigid hub with a shaft along ``x`` clamped to it (position, slope and twist
    tied to the hub), and the shaft."""
    shaft = sc.Section(E=1e4, A=1e-2, I=1e-4, rho=1e3, G=2e3, J=3e-5)
    rod = sc.Rod.straight([0, 0, 0], [L, 0, 0], 8, shaft, normal=[0, 0, 1])
    hub = sc.RigidBody.cylinder(radius=0.1, height=0.1, density=100.0)
    system = sc.System([hub, rod]).clamp(rod.node(0), position=hub.point([0, 0, 0]))
    return system, hub, rod


def test_twist_tie_jacobian_and_hessian_against_central_differences():
    """The twist tie's Jacobian and Hessian against central differences (step 1e-6) at a
    random state with the node's reference frame away from its tangent: 1e-8 relative
    (measured 5e-12, 1e-10); the Hessian symmetric to round-off; the whole system's
    tangent by ``sc.check_tangent`` (measured 5e-9)."""
    from skfem_cable.constraints.twist_tie import TwistTie

    system, hub, rod = hub_and_shaft()
    (tie,) = [c for c in system.constraints if isinstance(c, TwistTie)]
    system.current_layout()
    dofs = tie.dofs(system)
    t0 = np.array([0.9, 0.2, -0.1]) / np.linalg.norm([0.9, 0.2, -0.1])
    d0 = np.cross(t0, [0.3, 1.0, 0.2])
    tie.frames.t0[0], tie.frames.d0[0] = t0, d0 / np.linalg.norm(d0)
    qc = system.q0[dofs] + 0.1 * np.random.default_rng(3).standard_normal(dofs.size)
    grad, H = tie.jacobian(qc)[0], tie.hessian(qc, np.ones(1))
    step, fd_grad, fd_H = 1e-6, np.zeros_like(grad), np.zeros_like(H)
    for j in range(dofs.size):
        dq = np.zeros_like(qc)
        dq[j] = step
        fd_grad[j] = (tie.value(qc + dq)[0] - tie.value(qc - dq)[0]) / (2 * step)
        fd_H[:, j] = (tie.jacobian(qc + dq)[0] - tie.jacobian(qc - dq)[0]) / (2 * step)
    assert np.abs(grad - fd_grad).max() < 1e-8 * np.abs(grad).max()
    assert np.abs(H - fd_H).max() < 1e-8 * np.abs(H).max()
    assert np.abs(H - H.T).max() < 1e-14 * np.abs(H).max()
    q = system.q0 + 0.05 * np.random.default_rng(1).standard_normal(system.n_dofs)
    assert sc.check_tangent(system, q).error < 1e-6


def test_rod_clamped_to_a_hub_transmits_torque():
    """A shaft clamped to a rigid hub and to the ground at its far end; a couple ``M``
    (two forces at the hub's rim) turns the hub by ``theta`` about the shaft: at
    equilibrium ``M = GJ theta / L`` and the shaft's torque is ``M`` all along (1e-9,
    measured 3.0e-11, 2.6e-11), and the tie's multiplier, the torque the hub receives
    from the shaft, is ``M`` against the couple (1e-9, measured 2.3e-11)."""
    L, r, F = 2.0, 0.1, 0.02
    system, hub, rod = hub_and_shaft(L)
    system.clamp(rod.node(-1))
    system.add_point_load(hub.point([0, r, 0]), [0, 0, F])
    system.add_point_load(hub.point([0, -r, 0]), [0, 0, -F])
    state = sc.solve_static(system, load_steps=4)
    R = hub.rotation(state.q[system.dofs(hub)])
    theta = np.arctan2(R[2, 1], R[1, 1])
    couple = 2 * r * F * np.cos(theta)
    assert theta > 0.1
    assert rod.section.GJ * theta / L == pytest.approx(couple, rel=1e-9)
    torque = rod.torque(state.q[system.dofs(rod)], np.linspace(0, L, 5))
    assert np.abs(-torque / couple - 1).max() < 1e-9
    rows = np.cumsum([0] + [c.n_eq for c in system.constraints])
    names = [c.name for c in system.constraints]
    tie = rows[names.index("twist tie Node(rod, 0)-hub")]
    assert state.lam[tie] == pytest.approx(couple, rel=1e-9)


def test_hub_spinning_about_the_shaft_spins_it_rigidly():
    """A free hub with a shaft clamped to it, spinning at 3 rad/s about the shaft's axis:
    the shaft's section spins with the hub (twist rate 3 rad/s at every node to 1e-4,
    measured 1.5e-5: the Newton tolerance on the twist)
    and stores no twist or bending energy (below 1e-10 of the kinetic energy, measured
    5.2e-12) over 200 steps of a turn."""
    system, hub, rod = hub_and_shaft()
    omega = np.array([3.0, 0.0, 0.0])
    v = np.concatenate([np.cross(omega, hub.q0.reshape(-1, 3)).ravel(),
                        rod.rigid_velocity(omega, [0.0, 0.0, 0.0])])
    period = 2 * np.pi / 3.0
    result = sc.simulate(system, t_end=period, dt=period / 200,
                         initial=(system.q0, v), every=50)
    spin = result.v[:, system.dofs(rod)[rod.n_centreline::2]]
    assert np.abs(spin / 3.0 - 1).max() < 1e-4
    ratio = result.energy["bending"][1:] / result.energy["kinetic"][1:]
    assert ratio.max() < 1e-10
