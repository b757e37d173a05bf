"""The locking-free cable (axial part of the law on the 3-point Gauss-Lobatto rule):
elastica accuracy at 16 elements, recovered tension, and no spurious zero-energy mode."""

import numpy as np
import pytest

import skfem_cable as sc
from skfem_cable.analytic import elastica_tip_load, elastica_tip_load_angle
from skfem_cable.scenes.classics import ELASTICA_SECTION as SEC


def cantilever(k, n=16, locking_free=True):
    """The tip-loaded elastica (``P = k EI / L^2``, L = 1), solved statically."""
    cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], n, SEC, locking_free=locking_free)
    system = sc.System([cable]).clamp(cable.node(0))
    system.add_point_load(cable.node(-1), [0, -k * SEC.EI, 0])
    state = sc.solve_static(system, load_steps=max(10, int(2 * k)))
    return cable, state.q[:cable.n_dofs]


def tip_error(k, **options):
    cable, q = cantilever(k, **options)
    tip = cable.interpolate(q, 1.0)[0]
    u, w = elastica_tip_load(k)
    return max(abs(1 - tip[0] - u), abs(-tip[1] - w))


@pytest.mark.parametrize("k", [1.0, 2.0, 5.0, 10.0])
def test_elastica_tip_within_exudyn_reduced_integration(k):
    """16 elements: tip error <= 2.6e-5 (Exudyn's reduced integration reaches 2.6e-5 at
    k = 10; measured here 5e-8 .. 7.8e-6), against 5.8e-5 .. 5.6e-4 for the paper's
    formulation."""
    assert tip_error(k) <= 2.6e-5
    assert tip_error(k, locking_free=False) > 5 * tip_error(k)


@pytest.mark.parametrize("k", [15.0, 20.0])
def test_elastica_tip_large_loads(k):
    assert tip_error(k) <= 1e-3  # measured 1.5e-5, 2.3e-5


def test_exact_angle_is_the_elliptic_elastica():
    """The reference angle is consistent: zero moment (theta' = 0) at the tip and the tip
    position of the elliptic solution."""
    k = 5.0
    s = np.linspace(0, 1, 4001)
    theta = elastica_tip_load_angle(k, s)
    x, y = np.trapezoid(np.cos(theta), s), np.trapezoid(np.sin(theta), s)
    u, w = elastica_tip_load(k)
    assert 1 - x == pytest.approx(u, abs=1e-7) and y == pytest.approx(w, abs=1e-7)
    assert (theta[-1] - theta[-2]) / (s[1] - s[0]) == pytest.approx(0.0, abs=2e-3)


@pytest.mark.parametrize("k", [5.0, 10.0])
def test_recovered_tension_is_the_exact_axial_force(k):
    """N(s) = P sin(theta(s)) within 1 % of P everywhere, root included (the paper's
    formulation, sampled anywhere, is off by tens of P: membrane locking)."""
    P = k * SEC.EI
    s = np.linspace(0, 1, 321)
    exact = P * np.sin(elastica_tip_load_angle(k, s))
    cable, q = cantilever(k)
    assert np.abs(cable.tension(q, s) - exact).max() < 0.01 * P
    paper, q = cantilever(k, locking_free=False)
    assert np.abs(paper.tension(q, s) - exact).max() > P


@pytest.mark.parametrize("n", [1, 2, 12])
@pytest.mark.parametrize("law", ["cable", "truss"])
def test_free_straight_cable_has_exactly_the_rigid_zero_modes(n, law):
    """Stiffness spectrum of a free straight cable: five zero modes (three translations,
    two rotations; the spin about its own axis moves no coordinate) for the cable, and for
    the truss, stiff only along its axis, exactly its 2 n + 1 axial strain values; nothing
    else (the paper's formulation has the same count)."""
    section = sc.Section(E=1e9, A=1e-4, I=1e-10, rho=7850.0)
    cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], n, section, law=law, locking_free=True)
    eig = np.abs(np.linalg.eigvalsh(cable.assemble(cable.q0)[1].toarray()))
    zero = int(np.sum(eig < 1e-9 * eig.max()))
    if law == "cable":
        assert zero == 5
    else:  # a truss only resists stretching: one stiff axial direction per sampled value
        assert cable.n_dofs - zero == 2 * n + 1
    paper = sc.Cable.straight([0, 0, 0], [1, 0, 0], n, section, law=law, locking_free=False)
    eig = np.abs(np.linalg.eigvalsh(paper.assemble(paper.q0)[1].toarray()))
    assert int(np.sum(eig < 1e-9 * eig.max())) == zero


def test_locking_free_must_be_a_bool_and_has_no_single_form():
    with pytest.raises(TypeError, match="locking_free"):
        sc.Cable.straight([0, 0, 0], [1, 0, 0], 2, SEC, locking_free="yes")
    cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], 2, SEC, locking_free=True)
    with pytest.raises(NotImplementedError, match="locking-free"):
        sc.forms.internal(cable)


@pytest.mark.parametrize("law", ["cable", "truss"])
def test_locking_free_tangents_match_finite_differences(law):
    """f = dU/dq and K = df/dq of the two-rule kernel against central differences."""
    cable = sc.Cable.straight([0, 0, 0], [2, 0, 0], 3, SEC, law=law, locking_free=True)
    rng = np.random.default_rng(5)
    q = cable.q0 * 1.01 + 0.02 * rng.standard_normal(cable.n_dofs)
    system = sc.System([cable])

    def energy(q):
        return system.evaluate(q, None, 0.0, np.zeros(0))[1]["energy"].sum()

    f, K = cable.assemble(q)
    h = 1e-6
    E = np.eye(cable.n_dofs)
    fd_f = np.array([(energy(q + h * e) - energy(q - h * e)) / (2 * h) for e in E])
    fd_K = np.array([(cable.assemble(q + h * e)[0] - cable.assemble(q - h * e)[0]) / (2 * h)
                     for e in E]).T
    assert np.abs(fd_f - f).max() < 1e-6 * np.abs(f).max()
    assert np.abs(fd_K - K.toarray()).max() < 1e-6 * np.abs(K.toarray()).max()


def test_cli_scene_and_scene_file_take_the_option(tmp_path):
    """`skfem-cable run cantilever` (locking-free by default) reports a root tension of ~0
    (exact: 0; with --paper-formulation: 6.4 N, 64 P), and a scene file selects the option
    per cable."""
    from skfem_cable import scene_file
    from skfem_cable.runner import RunOptions
    from skfem_cable.scenes.catalog import run_scene

    summary = run_scene("cantilever", RunOptions(plots=False, progress=False))
    assert summary["parameters"]["locking_free"] is True  # the scene's default
    P = 10.0 * SEC.EI
    assert abs(summary["outputs"]["cables"]["cable"]["root_tension"]) < 0.01 * P
    paper = run_scene("cantilever", RunOptions(locking_free=False, plots=False,
                                               progress=False))
    assert paper["outputs"]["cables"]["cable"]["root_tension"] > 10 * P
    path = tmp_path / "bar.toml"
    path.write_text('[sections.s]\nE = 1e9\nA = 1e-4\nI = 1e-10\nrho = 7850.0\n\n'
                    '[[cables]]\nname = "bar"\nsection = "s"\nstart = [0, 0, 0]\n'
                    'end = [1, 0, 0]\nelements = 4\nlocking_free = true\n\n'
                    '[solver]\nt_end = 0.01\ndt = 0.001\n')
    spec = scene_file.load(path)
    assert spec.system.bodies[0].locking_free is True
    with pytest.raises(ValueError, match="locking-free"):
        scene_file.run(path, RunOptions(locking_free=True))
