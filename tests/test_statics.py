"""Statics: the large-deflection cantilever against the exact elastica, the pure-moment
semicircle, the E-sail stiffness ratio, slack cables and solver diagnostics."""

import numpy as np
import pytest

import skfem_cable as sc
from skfem_cable.analysis.analytic import elastica_tip_load
from skfem_cable.scenes import classics

#: EA L^2 / EI = 1e7: inextensible within 1e-7 of the tip load
SEC = classics.ELASTICA_SECTION


def tip_load_cantilever(k, n_elements):
    scene = classics.cantilever(n_elements, k)
    state = sc.solve_static(scene.system, load_steps=20)
    tip = state.position(scene.cable, 1.0)
    return 1.0 - tip[0], -tip[1], state


def test_public_api_script():
    sec = sc.Section(E=2.1e11, A=1e-4, I=1e-10, rho=7850.0)
    cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], n_elements=16, section=sec)
    system = sc.System([cable])
    system.clamp(cable.node(0))
    P = 5 * sec.E * sec.I / 1.0**2
    system.add_point_load(cable.node(-1), [0, -P, 0])
    state = sc.solve_static(system, load_steps=20)
    tip = state.position(cable, 1.0)
    assert tip.shape == (3,)
    assert state.position(cable, np.linspace(0, 1, 7)).shape == (7, 3)
    assert state.tension(cable, [0.2, 0.4]).shape == (2,)
    assert state.curvature(cable, 0.5).shape == ()
    freqs, shapes = sc.modes(sc.System([cable]).clamp(cable.node(0)), k=3)
    assert freqs.shape == (3,) and shapes.shape == (3, cable.n_dofs)
    u, w = elastica_tip_load(5.0)
    assert abs(1 - tip[0] - u) < 1e-3 * u and abs(-tip[1] - w) < 1e-3 * w


@pytest.mark.parametrize("k, u_ref, w_ref", [(1, 0.05643, 0.30172), (2, 0.16064, 0.49346),
                                             (5, 0.38763, 0.71379), (10, 0.55500, 0.81061)])
def test_elastica_reference_matches_published_table(k, u_ref, w_ref):
    u, w = elastica_tip_load(k)
    assert u == pytest.approx(u_ref, abs=6e-6) and w == pytest.approx(w_ref, abs=6e-6)


@pytest.mark.parametrize("k", [1, 2, 5, 10])
def test_elastica_16_elements(k):
    u_ref, w_ref = elastica_tip_load(k)
    u, w, _ = tip_load_cantilever(k, 16)
    assert abs(u - u_ref) / u_ref < 1e-3
    assert abs(w - w_ref) / w_ref < 1e-3


def test_elastica_converges_with_refinement():
    """Cubic Hermite elements without membrane locking (the default formulation): the tip
    converges at fourth order to the converged model (128 elements; measured 3.90, 3.98,
    4.00), which is the exact inextensible elastica to its extensibility ``k EI / EA``
    (the paper's formulation locks: orders 2.3 to 3.6, docs/locking.md)."""
    u_ref, w_ref = elastica_tip_load(5.0)
    converged = np.array(tip_load_cantilever(5.0, 128)[:2])
    errors = []
    for n in (4, 8, 16, 32):
        u, w, _ = tip_load_cantilever(5.0, n)
        errors.append(np.linalg.norm([u, w] - converged))
    rates = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    assert np.all(rates > 3.7), rates
    assert np.hypot(*(converged - [u_ref, w_ref])) < 1e-6


def test_pure_moment_rolls_cantilever_into_semicircle():
    cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], 16, SEC)
    system = sc.System([cable]).clamp(cable.node(0))
    system.add_point_moment(cable.node(-1), [0, 0, np.pi * SEC.EI])
    state = sc.solve_static(system, load_steps=10)
    tip = state.position(cable, 1.0)
    assert np.linalg.norm(tip - [0, 2 / np.pi, 0]) < 1e-4
    kappa = state.curvature(cable, np.linspace(0.05, 0.95, 7))
    assert np.allclose(kappa, np.pi, rtol=5e-3)


def test_esail_stiffness_ratio_keeps_tension_accurate():
    """E-sail tether: EA l^2/EI ~ 1e16 with 2 km elements; the tension under a tip pull is
    exact to round-off, also after a lateral load has rotated the tether."""
    sec = sc.Section(E=70e9, A=4.28e-9, I=1.47e-18, rho=7653.0)
    L = 10e3
    cable = sc.Cable.straight([0, 0, 0], [L, 0, 0], 5, sec)
    assert sec.EA * (L / 5) ** 2 / sec.EI > 1e16
    system = sc.System([cable]).pin(cable.node(0))
    system.add_point_load(cable.node(-1), [0.05, 0, 0])
    state = sc.solve_static(system)
    s = np.linspace(0, L, 11)
    assert np.allclose(state.tension(cable, s), 0.05, rtol=1e-10)
    system.add_point_load(cable.node(-1), [0, 1e-3, 0])
    state = sc.solve_static(system, initial=state)
    P = np.hypot(0.05, 1e-3)
    assert np.allclose(state.tension(cable, s), P, rtol=1e-9)
    direction = np.array([0.05, 1e-3, 0]) / P
    stretch = 1 + P / sec.EA  # Green law: EA eps |r_x| = P, to first order |r_x| - 1 = P/EA
    assert np.allclose(state.position(cable, L), L * stretch * direction, rtol=1e-6)
    reaction = -state.multipliers[system.constraints[0].name]
    assert np.allclose(reaction, [-0.05, -1e-3, 0], rtol=1e-9, atol=1e-15)


def test_slack_cable_is_finite_or_raises_clearly():
    """Both ends pinned closer than the cable length: the straight start is compressed and
    buckling is the only way out."""
    cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], 8, SEC)
    system = sc.System([cable]).pin(cable.node(0)).pin(cable.node(-1), [0.9, 0, 0])
    system.add_line_load(cable, [0, -1e-4, 0])
    try:
        state = sc.solve_static(system, load_steps=5)
    except sc.StaticConvergenceError as err:
        assert "did not converge" in str(err) and "load factor" in str(err)
        assert np.all(np.isfinite(err.last_converged.q))
    else:
        assert np.all(np.isfinite(state.q)) and np.all(np.isfinite(state.lam))


def test_failure_reports_load_step_and_can_return_last_converged():
    cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], 4, SEC)
    system = sc.System([cable]).clamp(cable.node(0))
    system.add_point_load(cable.node(-1), [0, -100 * SEC.EI, 0])
    with pytest.raises(sc.StaticConvergenceError, match=r"load factor .* residual history"):
        sc.solve_static(system, load_steps=1, max_iter=2, max_bisections=1, line_search=False)
    state = sc.solve_static(system, load_steps=4, max_iter=2, max_bisections=0,
                            return_last_converged=True)
    assert state.stats["converged"] is False and "did not converge" in state.stats["message"]
    assert np.all(np.isfinite(state.q))


def test_bad_arguments_are_named():
    cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], 4, SEC)
    system = sc.System([cable]).clamp(cable.node(0))
    with pytest.raises(ValueError, match="load_steps"):
        sc.solve_static(system, load_steps=0)
    with pytest.raises(ValueError, match="tol"):
        sc.solve_static(system, tol=2.0)
    with pytest.raises(ValueError, match="force must be a finite 3-vector"):
        system.add_point_load(cable.node(-1), [0, np.nan, 0])
    with pytest.raises(ValueError, match="k must be"):
        sc.modes(system, k=0)
    with pytest.raises(IndexError):
        cable.node(5)


def test_slack_truss_failure_says_why_and_what_to_do():
    """A truss (no bending) pinned straight and unstretched at both ends has no
    stiffness across itself under gravity: without the relaxation that rescues it
    (``relax=False``) the solve fails and says so, naming the cable, its strain and the
    remedies."""
    sec = sc.Section.circular(1e-3, 2e11, 7850)
    cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], 8, sec, law="truss", name="wire")
    system = sc.System([cable]).pin(cable.node(0)).pin(cable.node(-1))
    system.add_gravity([0, -9.81, 0])
    with pytest.raises(sc.StaticConvergenceError) as info:
        sc.solve_static(system, max_bisections=2, relax=False)
    text = str(info.value)
    for part in ("cable 'wire' has no bending stiffness (law 'truss')",
                 "compressed or slack (strain ", "start from a stretched state",
                 "law 'cable'"):
        assert part in text, part
