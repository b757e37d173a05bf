"""Rigid body in natural coordinates: mass matrix, constraints, free rotation, tumbling,
pendulum."""

import numpy as np
import pytest

import skfem_cable as sc
from skfem_cable.analysis.analytic import compound_pendulum_period
from skfem_cable.bodies.rigid import RigidBody
from skfem_cable.constraints.linear import LinearConstraint
from skfem_cable.results.timeseries import zero_crossings


def random_rotation(seed):
    Q, R = np.linalg.qr(np.random.default_rng(seed).standard_normal((3, 3)))
    Q = Q * np.sign(np.diag(R))
    return Q if np.linalg.det(Q) > 0 else -Q


def test_mass_matrix_gives_rigid_kinetic_energy():
    """For any rigid motion, 1/2 v^T M v = 1/2 m |v_c|^2 + 1/2 w^T I_c w (Eq. 52 against
    the classical formula), for the cylinder and a general body with offset centre."""
    R0 = random_rotation(1)
    hub = RigidBody.cylinder(radius=1.0, height=2.0, density=884.0, position=[3, 1, 2],
                             rotation=R0)
    I_c = R0 @ np.diag([hub.mass / 2, hub.mass * 7 / 12, hub.mass * 7 / 12]) @ R0.T
    general = RigidBody(5.0, [0.1, -0.2, 0.3], [[2.0, 0.1, 0.0], [0.1, 3.0, -0.2],
                                                [0.0, -0.2, 4.0]],
                        [[0, 0, 0], [1, 0, 0.1], [0.2, 1, 0], [0, 0.3, 1]], rotation=R0)
    for body, inertia in ((hub, I_c), (general, R0 @ general.inertia @ R0.T)):
        system = sc.System([body])
        w = np.array([0.3, -0.7, 1.1])
        vc = np.array([0.5, 0.2, -0.4])
        c = R0 @ body.center_of_mass + (body.q0[:3] - R0 @ body.base_points[0])
        v = system.rigid_motion_velocity(body.q0, w, center=c, velocity=vc)
        T = 0.5 * v @ (body.mass_matrix() @ v)
        assert T == pytest.approx(0.5 * body.mass * vc @ vc + 0.5 * w @ inertia @ w, rel=1e-12)
        L = system.angular_momentum(body.q0, v, center=c)
        assert np.allclose(L, inertia @ w, rtol=1e-12)


def test_kinematics_rotation_and_angular_velocity():
    R0 = random_rotation(2)
    hub = RigidBody.cylinder(1.0, 2.0, 884.0, position=[1, 2, 3], rotation=R0)
    assert np.allclose(hub.rotation(hub.q0), R0, atol=1e-14)
    w_body = np.array([4e-3, 1e-3, -2e-3])
    v = sc.System([hub]).rigid_motion_velocity(hub.q0, R0 @ w_body, center=[1, 2, 3])
    assert np.allclose(hub.angular_velocity(hub.q0, v), w_body, rtol=1e-12)
    x = np.array([0.3, 0.8, -0.5])
    assert np.allclose(hub.positions(hub.q0[None], x)[0], [1, 2, 3] + R0 @ x)
    with pytest.raises(ValueError, match="coplanar"):
        RigidBody(1.0, [0, 0, 0], np.eye(3), [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]])
    with pytest.raises(ValueError, match="triangle"):
        RigidBody(1.0, [0, 0, 0], np.diag([1, 2, 3]), np.vstack([np.zeros(3), np.eye(3)]))


def test_internal_constraint_jacobian_and_hessian():
    hub = RigidBody.cylinder(1.0, 2.0, 884.0)
    con = hub.internal_constraints()[0]
    rng = np.random.default_rng(0)
    d = hub.q0 + 0.05 * rng.standard_normal(12)
    lam = rng.standard_normal(6)
    h = 1e-6
    E = np.eye(12)
    fd_J = np.array([(con.value(d + h * e) - con.value(d - h * e)) / (2 * h) for e in E]).T
    fd_H = np.array([(con.jacobian(d + h * e).T @ lam - con.jacobian(d - h * e).T @ lam)
                     / (2 * h) for e in E]).T
    assert np.allclose(fd_J, con.jacobian(d), atol=1e-8)
    assert np.allclose(fd_H, con.hessian(d, lam), atol=1e-8)
    v = rng.standard_normal(12)
    fd_g = (con.jacobian(d + h * v) @ v - con.jacobian(d - h * v) @ v) / (2 * h)
    assert np.allclose(fd_g, con.accel_term(d, v), atol=1e-8)
    assert np.abs(con.value(hub.q0)).max() < 1e-15


def spin(omega_body, t_end, dt, rho_inf=1.0):
    """Free spin; full Newton: the conservation checks must see the integrator, not the
    Newton tolerance (a 1e-12 position residual is a velocity error of gamma' 1e-12 per
    step, which modified Newton leaves in place)."""
    hub = RigidBody.cylinder(radius=1.0, height=2.0, density=884.0)
    system = sc.System([hub])
    v = system.rigid_motion_velocity(hub.q0, omega_body)
    r = sc.simulate(system, t_end=t_end, dt=dt, rho_inf=rho_inf,
                    initial=sc.State(system, hub.q0, v=v), tol=1e-12, newton="full")
    return hub, system, r


def test_free_spin_about_principal_axis_conserves_momentum_and_energy():
    hub, system, r = spin([4e-3 * 100, 0, 0], t_end=20.0, dt=1e-2)
    E = r.energy["kinetic"]
    L = np.array([system.angular_momentum(q, v) for q, v in zip(r.q, r.v)])
    # trapezoidal rule with quadratic constraints: O(dt^2) drift (measured 1.3e-9)
    assert np.abs(E / E[0] - 1).max() < 1e-8
    assert np.abs(L - L[0]).max() < 1e-8 * np.linalg.norm(L[0])
    w = hub.angular_velocity(r.q, r.v)
    assert np.allclose(w, [0.4, 0, 0], atol=1e-9)
    lay = system.current_layout()  # held: not described at every row
    C = np.array([system.constraint_values(q, layout=lay) for q in r.q])
    assert np.abs(C).max() < 1e-10


def test_intermediate_axis_tumbles():
    """Dzhanibekov effect: a body spinning about its intermediate principal axis with a
    tiny perturbation flips over (omega about that axis changes sign) while energy and
    angular momentum are kept (rho_inf = 0.9, dt = 5e-3: measured 3.6e-7 and 7.1e-8); about
    the major axis the same perturbation stays small.  (The undamped trapezoidal rule,
    rho_inf = 1, goes unstable here after ~36 s: a known weakness of index-3 integration
    without numerical damping.)"""
    body = RigidBody(10.0, [0, 0, 0], np.diag([2.0, 3.0, 4.0]),
                     [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]])
    system = sc.System([body])

    def run(w0):
        v = system.rigid_motion_velocity(body.q0, w0)
        r = sc.simulate(system, t_end=40.0, dt=5e-3, rho_inf=0.9,
                        initial=sc.State(system, body.q0, v=v), tol=1e-12, every=10,
                        newton="full")
        return body.angular_velocity(r.q, r.v), r

    w, r = run([1e-3, 1.0, 1e-3])
    assert w[:, 1].min() < -0.9  # flipped
    L = np.array([system.angular_momentum(q, v) for q, v in zip(r.q, r.v)])
    assert np.abs(np.linalg.norm(L, axis=1) / np.linalg.norm(L[0]) - 1).max() < 2e-6
    E = r.energy["kinetic"]
    assert np.abs(E / E[0] - 1).max() < 5e-7
    w, _ = run([1e-3, 1e-3, 1.0])
    assert w[:, 2].min() > 0.99


def test_hub_pinned_to_ground_is_a_compound_pendulum():
    """The cylinder (h = 2 m) pinned at the centre of an end face swings, released with its
    axis horizontal, with the exact large-amplitude period of a body with moment of inertia
    I_p = I_c + m (h/2)^2 and centre at distance h/2.  Second order in dt: 1.6e-5, 3.9e-6,
    9.8e-7 at T/1000, T/2000, T/4000."""
    hub = RigidBody.cylinder(radius=0.3, height=2.0, density=884.0)
    system = sc.System([hub])
    # the pivot: a body point fixed to ground, a linear constraint on the coordinates
    G = hub.G([-1.0, 0, 0])
    system.add_constraint(LinearConstraint(lambda s: s.dofs(hub), G, G @ hub.q0, "pivot",
                                           ["Fx", "Fy", "Fz"]))
    system.add_gravity([0, -9.81, 0])
    m, h, R = hub.mass, 2.0, 0.3
    I_p = m * (3 * R**2 + h**2) / 12 + m * (h / 2) ** 2
    L_eq = I_p / (m * h / 2)  # equivalent simple pendulum length
    T = compound_pendulum_period(1.5 * L_eq, np.pi / 2)  # 1.5 L_eq: rod of length L has L_eq = 2L/3
    r = sc.simulate(system, t_end=1.05 * T, dt=T / 2000, rho_inf=1.0, tol=1e-12)
    x = hub.positions(r.q, [1.0, 0, 0])[:, 0]
    vx = hub.positions(r.v, [1.0, 0, 0])[:, 0]
    c = zero_crossings(r.t, x + 1.0, vx)  # pivot at x = -1: free end crosses the vertical
    assert 2 * (c[1] - c[0]) == pytest.approx(T, rel=1e-5)


def test_force_at_a_body_point_gives_force_and_moment():
    """A force F at body point x on a free body: the generalized force G(x)^T F yields
    m a_c = F and I_c dw/dt = (x - c) x F at t = 0 (from rest)."""
    hub = RigidBody.cylinder(radius=1.0, height=2.0, density=884.0)
    system = sc.System([hub])
    x = np.array([0.7, 0.2, -0.9])
    F = np.array([3.0, -1.0, 2.0])
    system.add_point_load(hub.point(x), F)
    from skfem_cable.solvers.galpha import GeneralizedAlpha

    integ = GeneralizedAlpha(system)
    integ.initialize(hub.q0, np.zeros(12), 0.0)
    a_c = hub.positions(integ.a[None], np.zeros(3))[0]
    assert np.allclose(a_c, F / hub.mass, rtol=1e-10)
    I_c = np.diag([hub.mass / 2, hub.mass * 7 / 12, hub.mass * 7 / 12])
    w_dot = hub.angular_velocity(hub.q0, integ.a)  # d omega/dt from rest
    assert np.allclose(I_c @ w_dot, np.cross(x, F), rtol=1e-10)
