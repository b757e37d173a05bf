"""The rod's compiled step made cheaper (issue 48, item 7, ``docs/rods.md``): the mismatch
angle of two nodal frames in closed form against its definition, and a point moment on a
rod's node: the space-fixed moment, with its exact tangent (the slope force of its part
about the tangent through the node's reference frame, ``PointMoment.reference_force``).
The rod kernel's forces and tangent against central differences are ``tests/test_rods.py``'s."""

import numpy as np
import pytest

import skfem_cable as sc
from skfem_cable.kernels import rod as kernel


def unit(v):
    return v / np.linalg.norm(v)


def frames(rng, spread):
    """A random unit tangent and a unit director normal to it, and a second pair near."""
    ai = unit(rng.standard_normal(3))
    aj = unit(ai + spread * rng.standard_normal(3))
    di, dj = (unit(np.cross(a, rng.standard_normal(3))) for a in (ai, aj))
    return ai, di, aj, dj


def test_mismatch_closed_form_is_the_angle_of_the_carried_directors():
    """``kernels.rod.mismatch``, ``alpha_0 + 2 atan2(N, D)`` (the holonomy of the smallest
    rotations around the spherical triangle ``a_i, t, a_j``), is the angle about ``t``
    from ``R(a_i -> t) d_i`` to ``R(a_j -> t) d_j`` to round-off (1e-13, modulo 2 pi),
    for tangents up to about a radian apart; its gradient and Hessian in ``A`` against
    central differences (step 1e-6): 1e-7 and 1e-8 relative (measured 4e-9, 4e-10)."""
    rng = np.random.default_rng(7)
    step = 1e-6
    for _ in range(20):
        ai, di, aj, dj = frames(rng, 0.7)
        A = 1.3 * unit(aj + 0.5 * rng.standard_normal(3))
        t = unit(A)
        u, w = kernel.smallest_rotation(ai, t, di), kernel.smallest_rotation(aj, t, dj)
        expected = np.arctan2(np.cross(u, w) @ t, u @ w)
        g, H = np.zeros(3), np.zeros((3, 3))
        alpha = kernel.mismatch(A, ai, di, aj, dj, g, H, True)
        assert abs(np.angle(np.exp(1j * (alpha - expected)))) < 1e-13
        fd_g, fd_H = np.zeros(3), np.zeros((3, 3))
        for k in range(3):
            dA = np.zeros(3)
            dA[k] = step
            gp, gm = np.zeros(3), np.zeros(3)
            plus = kernel.mismatch(A + dA, ai, di, aj, dj, gp, H.copy(), False)
            minus = kernel.mismatch(A - dA, ai, di, aj, dj, gm, H.copy(), False)
            fd_g[k], fd_H[:, k] = (plus - minus) / (2 * step), (gp - gm) / (2 * step)
        assert np.abs(g - fd_g).max() < 1e-7 * np.abs(g).max()
        assert np.abs(H - fd_H).max() < 1e-8 * np.abs(H).max()


@pytest.fixture(scope="module")
def moment():
    """A bent, stretched and twisted rod of 3 elements clamped at one end, a moment with a
    large part about the tangent at the other, its frames (the initial ones) away from
    the tangents: the rod, the system, its state and the moment."""
    section = sc.Section(E=1e3, A=1e-4, I=1e-6, rho=1e3, G=2e3, J=3e-6, I_edge=4e-6)
    rod = sc.Rod.straight([0, 0, 0], [1, 0, 0], 3, section, normal=[0, 0.3, 1])
    M = np.array([0.5, 0.1, -0.3])
    system = sc.System([rod]).clamp(rod.node(0)).add_point_moment(rod.node(-1), M)
    q = system.q0 + 0.1 * np.random.default_rng(4).standard_normal(system.n_dofs)
    return rod, system, q, M


def test_point_moment_on_a_rod_is_the_space_fixed_moment(moment):
    """The generalized force of ``add_point_moment`` on a rod's node does the virtual work
    ``M . dtheta`` of the fixed moment on the rotation ``dtheta`` of the node's material
    frame (``Rod.frame`` with the system's frames, central differences, step 1e-6), for
    random virtual displacements: 1e-8 relative (measured 4e-11; 8e-3 without the slope
    force ``PointMoment.reference_force``)."""
    rod, system, q, M = moment
    _, info = system.evaluate(q, None, 0.0, np.zeros(system.n_constraints))
    f = info["f_nc"]
    reference = rod.reference_frames(system)
    ref = (reference.t0.copy(), reference.d0.copy())
    assert np.abs(ref[0] - unit(q[3:6])).max() > 0.05          # frames away from tangents
    rng, step = np.random.default_rng(5), 1e-6
    for _ in range(5):
        dq = rng.standard_normal(system.n_dofs)
        D = [rod.frame(q + sign * step * dq, 1.0, frames=ref) for sign in (1, -1)]
        here = rod.frame(q, 1.0, frames=ref)
        dtheta = 0.5 * sum(np.cross(here[k], (D[0][k] - D[1][k]) / (2 * step)) for k in range(3))
        assert abs(f @ dq - M @ dtheta) < 1e-8 * np.linalg.norm(M) * np.linalg.norm(dtheta)


def test_point_moment_on_a_rod_has_its_exact_tangent(moment):
    """``sc.check_tangent`` of the system with the moment, frames away from the tangents:
    every part within 1e-6 (measured 1.5e-10)."""
    _, system, q, _ = moment
    check = sc.check_tangent(system, q)
    assert check.error < 1e-6, str(check)


def test_energy_parts_read_the_systems_frames():
    """``System.energy_parts`` evaluates a rod with the reference frames of its term in
    the system (a run's, transported), not its initial ones: a bent, twisted state turned
    rigidly by 3 rad with its frames keeps its bending and twist energy to 1e-12
    (measured 1e-16; a system with the initial frames reports 76 times the energy)."""
    section = sc.Section(E=1e3, A=1e-4, I=1e-6, rho=1e3, G=2e3, J=3e-6, I_edge=4e-6)
    rod = sc.Rod.straight([0, 0, 0], [1, 0, 0], 3, section, normal=[0, 0.3, 1])
    system = sc.System([rod])
    q = rod.q0 + 0.1 * np.random.default_rng(6).standard_normal(rod.n_dofs)
    assert system.layout is not None                       # binds the rod
    frames = rod.reference_frames(system)
    frames.t0[:], frames.d0[:] = rod.frames_at(q)
    (before,) = system.energy_parts(q, None).values()
    turn = np.array([[np.cos(3.0), -np.sin(3.0), 0.0], [np.sin(3.0), np.cos(3.0), 0.0],
                     [0.0, 0.0, 1.0]])
    turned = q.copy()
    turned[:rod.n_centreline] = (q[:rod.n_centreline].reshape(-1, 3) @ turn.T).ravel()
    frames.t0[:], frames.d0[:] = frames.t0 @ turn.T, frames.d0 @ turn.T
    (after,) = system.energy_parts(turned, None).values()
    (fresh,) = sc.System([rod]).energy_parts(turned, None).values()
    energy = before["bending and twist"]
    assert energy > 0
    assert abs(after["bending and twist"] - energy) < 1e-12 * energy
    assert abs(fresh["bending and twist"] - energy) > 1e-6 * energy
