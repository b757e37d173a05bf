"""A cable node clamped to a rigid body (``System.clamp(node, position=body.point(x))``):
the bilinear slope constraint ``constraints.BodySlope`` against finite differences, tethers
turning rigidly with a spinning hub, the moment the exit guide transmits, and the errors.

The spinning runs share one system layout (a hub with two clamped tethers), so that they
share one compiled Newton step."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import skfem_cable as sc
from skfem_cable.constraints.joints import BodySlope

#: Body to inertial rotation of the hub: its axis (body x) along the global z axis, body y
#: along global x.
HUB_ROTATION = np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]])
SPIN = 2.0  # rad/s about the global z axis


def spinning_hub(tilt=0.0, E=7e10, radius=2e-3, length=1.0, joint="clamp"):
    """A hub (axis z) with two tethers at the opposite rim points ``+-x``, leaving at
    ``tilt`` (rad) from the radial direction in the spin plane (a pinwheel), clamped to the
    hub (or pinned, ``joint="pin"``).  Returns the system, the hub, the tethers and the
    guides' body-frame directions."""
    hub = sc.RigidBody.cylinder(radius=1.0, height=0.5, density=100.0,
                                rotation=HUB_ROTATION)
    section = sc.Section.circular(radius, E, 2700.0)
    tethers, guides = [], []
    for k, side in enumerate((1.0, -1.0)):
        exit_direction = side * np.array([np.cos(tilt), np.sin(tilt), 0.0])
        root = np.array([side, 0.0, 0.0])
        tethers.append(sc.Cable.straight(root, root + length * exit_direction, 3, section,
                                         name=f"tether{k}"))
        guides.append(HUB_ROTATION.T @ exit_direction)
    system = sc.System([hub, *tethers])
    for tether, side in zip(tethers, (1.0, -1.0)):
        anchor = hub.point([0.0, side, 0.0])
        if joint == "clamp":
            system.clamp(tether.node(0), position=anchor)
        else:
            system.pin(tether.node(0), anchor)
    return system, hub, tethers, guides


def root_slopes_in_hub_frame(system, hub, tether, q):
    """Unit slope of ``tether`` at node 0 in the hub's frame, for the rows of ``q``."""
    slope = q[:, system.dofs(tether.node(0))[3:]]
    slope /= np.linalg.norm(slope, axis=1, keepdims=True)
    return np.einsum("tji,tj->ti", hub.rotation(q[:, system.dofs(hub)]), slope)


def rigid_rotation(system):
    """The initial configuration turning rigidly at ``SPIN`` about the z axis."""
    return sc.State(system, system.q0, v=system.rigid_motion_velocity(system.q0, [0, 0, SPIN]))


def turn(angle):
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def test_body_slope_derivatives_match_finite_differences():
    """Jacobian, Hessian term and ``(C_q v)_q v`` of the bilinear constraint against
    central differences at a random point off the rigid manifold, and its value zero at
    any rigid motion of the joined pair."""
    rng = np.random.default_rng(3)
    Q = Rotation.random(random_state=rng).as_matrix()
    hub = sc.RigidBody.cylinder(radius=1.0, height=0.5, density=100.0, rotation=Q)
    tether = sc.Cable.straight([0, 0, 0], [1, 0, 0], 2, sc.Section.circular(1e-3, 7e10, 2700.0))
    guide = BodySlope(tether.node(0), hub, [0.2, 0.9, -0.4])
    assert np.allclose(guide.N @ hub.q0 @ (Q @ guide.direction), 0.0, atol=1e-15)

    q = np.concatenate([Q @ guide.direction, hub.q0]) + 0.1 * rng.standard_normal(15)
    v, lam = rng.standard_normal(15), rng.standard_normal(2)
    h = 1e-6
    steps = h * np.eye(15)
    J_fd = np.array([(guide.value(q + e) - guide.value(q - e)) / (2 * h) for e in steps]).T
    J = guide.jacobian(q)
    assert np.abs(J - J_fd).max() < 1e-7 * np.abs(J).max()
    H_fd = np.array([(guide.jacobian(q + e) - guide.jacobian(q - e)).T @ lam / (2 * h)
                     for e in steps]).T
    H = guide.hessian(q, lam)
    assert np.allclose(H, H.T) and np.abs(H - H_fd).max() < 1e-7 * np.abs(H).max()

    h = 1e-3
    accel_fd = (guide.value(q + h * v) - 2 * guide.value(q) + guide.value(q - h * v)) / h**2
    accel = guide.accel_term(q, v)
    assert np.abs(accel - accel_fd).max() < 1e-7 * np.abs(accel).max()
    assert np.array_equal(guide.velocity_term(q), np.zeros(2))


def test_compiled_hook_matches_the_python_methods():
    """The compiled ``kernel`` writes ``scale C``, adds ``C_q^T lam`` and fills
    ``scale C_q``, ``scale C_q^T`` and ``cK`` times the Hessian term (``contract``) as the
    Python methods give them."""
    rng = np.random.default_rng(4)
    hub = sc.RigidBody.cylinder(radius=1.0, height=0.5, density=100.0)
    tether = sc.Cable.straight([0, 1, 0], [0, 2, 0], 2, sc.Section.circular(1e-3, 7e10, 2700.0))
    guide = BodySlope(tether.node(0), hub, [0.0, 1.0, 0.3])
    q, lam = rng.standard_normal(15), rng.standard_normal(2)
    cK, scale = 0.7, 3.0
    positions = np.arange(30 + 30 + 225)
    index = (np.arange(15), np.arange(2), positions[:30], positions[30:60], positions[60:])
    r_c, f_con, data = np.zeros(2), np.zeros(15), np.zeros(positions.size)
    function, pack = guide.kernel
    function(pack, index, (q, lam, np.array([0.0, cK, scale]), r_c, f_con, data))
    J = guide.jacobian(q)
    assert np.allclose(r_c, scale * guide.value(q), rtol=1e-14, atol=0)
    assert np.allclose(f_con, J.T @ lam, rtol=1e-14, atol=1e-15)
    expected = np.concatenate([scale * J.ravel(), scale * J.T.ravel(),
                               cK * guide.hessian(q, lam).ravel()])
    assert np.allclose(data, expected, rtol=1e-14, atol=1e-15)


def test_default_direction_is_the_initial_slope_in_the_body_frame():
    system, hub, (tether, _), (guide, _) = spinning_hub(tilt=0.4)
    joint = system.constraints[2]
    assert isinstance(joint, BodySlope) and joint.body is hub
    assert np.allclose(joint.direction, guide, atol=1e-15)
    assert np.abs(system.constraint_values(system.q0)).max() < 1e-15
    assert [c.n_eq for c in system.constraints] == [6, 3, 2, 3, 2]


def test_tethers_turn_rigidly_with_the_spinning_hub():
    """From the steady spin (tethers stretched by the centrifugal force, 0.45 mm), the hub
    and its radially clamped tethers turn rigidly: over 3 rad the tips stay on the hub's
    rotation to 1e-7 m and their phase error against the exact rotation ``w t`` is the
    integrator's, 2.2e-4 m at ``w dt = 0.02``, second order in the step; the root slopes
    stay radial in the hub frame to 1e-9.  The compiled Newton step is taken."""
    system, hub, tethers, guides = spinning_hub(E=2e7)
    steady = sc.solve_steady(system, omega=[0, 0, SPIN], center=[0, 0, 0])
    tip = [system.dofs(t.node(-1))[:3] for t in tethers]
    assert steady.q[tip[0]][0] - 2.0 == pytest.approx(4.5e-4, rel=1e-2)
    phase_errors = []
    for dt in (0.02, 0.01):
        result = sc.simulate(system, t_end=1.5, dt=dt, initial=steady)
        assert result.stats["path"] == "compiled"
        d = system.dofs(hub)
        carried = hub.rotation(result.q[:, d]) @ hub.rotation(steady.q[d]).T
        exact = np.array([turn(SPIN * t) for t in result.t])
        for dofs in tip:
            assert np.abs(result.q[:, dofs] - carried @ steady.q[dofs]).max() < 1e-7
        phase_errors.append(max(np.abs(result.q[:, dofs] - exact @ steady.q[dofs]).max()
                                for dofs in tip))
        for tether, guide in zip(tethers, guides):
            slopes = root_slopes_in_hub_frame(system, hub, tether, result.q)
            assert np.abs(slopes - guide).max() < 1e-9
    assert phase_errors[1] < 3e-4
    assert 3.5 < phase_errors[0] / phase_errors[1] < 4.5


def test_exit_guide_transmits_the_moment_and_conserves_angular_momentum():
    """Guides tilted 30 degrees from radial in the spin plane: the centrifugal force bends
    the tethers about their roots, and the clamp holds their slopes on the guides (to
    1e-9), where pinned tethers swing through about 50 degrees.  Started from the rigid
    rotation, the total angular momentum (157.4 kg m^2/s) drifts by 4.0e-6 relative at
    ``dt = 0.01`` and by a quarter of that at half the step (second order)."""
    tilt = np.radians(30.0)
    system, hub, tethers, guides = spinning_hub(tilt=tilt)
    drifts = []
    for dt in (0.01, 0.005):
        result = sc.simulate(system, t_end=1.0, dt=dt, initial=rigid_rotation(system))
        for tether, guide in zip(tethers, guides):
            slopes = root_slopes_in_hub_frame(system, hub, tether, result.q)
            assert np.abs(slopes - guide).max() < 1e-9
        L = np.array([system.angular_momentum(q, v) for q, v in zip(result.q, result.v)])
        drifts.append(np.abs(L - L[0]).max() / np.linalg.norm(L[0]))
    assert drifts[0] < 6e-6
    assert 3.5 < drifts[0] / drifts[1] < 4.5

    pinned, hub, tethers, guides = spinning_hub(tilt=tilt, joint="pin")
    result = sc.simulate(pinned, t_end=1.0, dt=0.01, initial=rigid_rotation(pinned),
                         compiled=False)
    alignment = root_slopes_in_hub_frame(pinned, hub, tethers[0], result.q) @ guides[0]
    swing = np.arccos(np.minimum(alignment, 1.0))
    assert np.degrees(swing.max()) > 40.0


def test_clamp_to_a_body_point_errors():
    system, hub, (tether, _), _ = spinning_hub()
    anchor = hub.point([0.0, 1.0, 0.0])
    for given in ("velocity", "acceleration"):
        with pytest.raises(ValueError, match=given):
            system.clamp(tether.node(0), position=anchor, **{given: lambda t: np.zeros(3)})
    with pytest.raises(ValueError, match="direction"):
        system.clamp(tether.node(0), direction=[0.0, 0.0, 0.0], position=anchor)
    with pytest.raises(TypeError, match="direction"):
        system.clamp(tether.node(0), direction=lambda t: np.ones(3), position=anchor)
    other = sc.RigidBody.cylinder(radius=1.0, height=0.5, density=100.0, name="other")
    with pytest.raises(ValueError, match="not a body of this system"):  # when added
        sc.System([tether]).clamp(tether.node(0), position=other.point([0.0, 1.0, 0.0]))
