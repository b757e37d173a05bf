"""The element types (``skfem_cable.elements``): their functions, and everything that
accepts a cable accepting the quintic and the linear element, with exact tangents."""

from dataclasses import replace

import numpy as np
import pytest
from skfem import Basis, MeshLine

import skfem_cable as sc
from skfem_cable.elements import ELEMENTS

SEC = sc.Section(E=2e9, A=1e-4, I=2e-10, rho=1500.0)


@pytest.mark.parametrize("name", list(ELEMENTS))
def test_functions_interpolate_their_nodal_derivatives(name):
    """Each function has the nodal derivative of its degree of freedom (scaled by
    ``h^k``) and no other; the element reproduces polynomials of its degree through
    scikit-fem's ``Basis.interpolate``."""
    element = ELEMENTS[name]
    ends = [element.shape(np.array(end), 0.37) for end in (0.0, 1.0)]
    # row (end, order k): the k-th x-derivatives of the functions at that end
    D = np.array([ends[end][k] for end in (0, 1) for k in element.orders])
    assert D == pytest.approx(np.eye(element.n_functions), abs=1e-13)
    mesh = MeshLine(np.linspace(0.0, 2.0, 6))
    basis = Basis(mesh, element, intorder=2 * element.maxdeg)
    p = np.polynomial.Polynomial(np.arange(1.0, element.maxdeg + 2) / 3)
    x = mesh.p[0]
    u = np.empty(basis.N)
    for k, order in enumerate(element.orders):
        u[basis.nodal_dofs[k]] = p.deriv(order)(x)
    field = basis.interpolate(u)
    xq = np.asarray(basis.global_coordinates())[0]
    assert np.abs(np.asarray(field) - p(xq)).max() < 1e-13 * np.abs(p(xq)).max()
    assert np.abs(field.grad[0] - p.deriv()(xq)).max() < 1e-12 * np.abs(p.deriv()(xq)).max()


def test_quintic_node_carries_second_derivatives_from_the_cubic_interpolant():
    """A quarter circle given by positions and slopes: the quintic cable's nodal ``r_xx``
    default to the cubic interpolant's (mean of its one-sided values), close to the
    circle's ``-r / R^2``; a straight cable's are zero."""
    R, n = 2.0, 12
    s = np.linspace(0.0, np.pi * R / 2, n + 1)
    pos = R * np.column_stack([np.cos(s / R), np.sin(s / R), 0 * s])
    slopes = np.column_stack([-np.sin(s / R), np.cos(s / R), 0 * s])
    cable = sc.Cable(MeshLine(s), SEC, pos, slopes, element="hermite5")
    r_xx = cable.q0.reshape(-1, 3, 3)[:, 2]
    assert np.abs(r_xx - (-pos / R**2)).max() < 2e-2 / R
    straight = sc.Cable.straight([0, 0, 0], [1, 2, 0], 3, SEC, element="hermite5")
    assert np.all(straight.q0.reshape(-1, 3, 3)[:, 2] == 0.0)
    assert straight.describe_dof(8) == "node 0 r_xx[2]"


def test_linear_element_refuses_bending_and_clamps_clearly():
    with pytest.raises(ValueError, match="law 'cable' has bending.*'linear'.*law='truss'"):
        sc.Cable.straight([0, 0, 0], [1, 0, 0], 2, SEC, law="cable", element="linear")
    cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], 2, SEC, element="linear")
    assert cable.law.name == "truss" and cable.n_dofs == 9
    with pytest.raises(ValueError, match="Node\\(cable, 0\\) has no slope.*positions only"):
        sc.System([cable]).clamp(cable.node(0))
    with pytest.raises(ValueError, match="'lobatto' is not available on the element "
                                         "'hermite5'"):
        sc.Cable.straight([0, 0, 0], [1, 0, 0], 2, SEC, element="hermite5",
                          formulation="lobatto")
    with pytest.raises(ValueError, match="element must be one of"):
        sc.Cable.straight([0, 0, 0], [1, 0, 0], 2, SEC, element="hermite7")


@pytest.mark.parametrize("name", list(ELEMENTS))
def test_mass_is_exact(name):
    """The mass from the mass matrix (a translation's) and from the mass points, and the
    centre of mass, are the continuum's; the linear element's matrix is the consistent
    ``rho A h / 6 [[2, 1], [1, 2]]``."""
    cable = sc.Cable.straight([1, 0, 0], [1, 3, 4], 5, SEC, element=name)
    M = cable.mass_matrix()
    mass = SEC.mass_per_length * 5.0
    one = np.zeros(cable.n_dofs)
    one[cable.position_mask] = np.tile([1.0, 0.0, 0.0], cable.n_nodes)  # translation along x
    assert one @ M @ one == pytest.approx(mass, rel=1e-13)
    vectors, coefficients, point_mass = cable.mass_points()
    q = cable.q0
    points = np.einsum("pA,pAi->pi", coefficients, q[vectors[..., None] + np.arange(3)])
    assert point_mass.sum() == pytest.approx(mass, rel=1e-13)
    assert point_mass @ points / mass == pytest.approx([1.0, 1.5, 2.0], rel=1e-13)
    if name == "linear":
        # the first node's row: one element's [2, 1]; an interior node's diagonal: two
        assert M[0, [0, 3]].toarray().ravel() == pytest.approx(
            SEC.mass_per_length * 1.0 / 6 * np.array([2, 1]), rel=1e-13)
        assert M[3, 3] == pytest.approx(SEC.mass_per_length * 4 / 6, rel=1e-13)


def _scene(name):
    """A hanging, spinning, dragged, wind-blown cable of the element ``name``, pinned at
    its root, with a point mass at its tip, and its coordinates and velocities at a
    deformed state."""
    damped = replace(SEC, gamma_axial=0.01, gamma_bending=0.01 if name != "linear" else 0.0)
    cable = sc.Cable.straight([0, 0, 0], [3, 0, 0], 4, damped, element=name, name="c")
    system = sc.System([cable]).pin(cable.node(0))
    system.add_gravity([0, 0, -9.81]).add_point_mass(cable.node(-1), 0.2)
    system.add_load(sc.MorisonDrag(cable, 1000.0, 0.011, 1.2, 0.01, current=[0.3, 0.1, 0.0]))
    system.add_centrifugal([0, 0, 1.5])
    rng = np.random.default_rng(3)
    q = system.q0 + 0.05 * rng.standard_normal(system.n_dofs)
    v = 0.3 * rng.standard_normal(system.n_dofs)
    return system, q, v


@pytest.mark.parametrize("name", list(ELEMENTS))
def test_tangents_exact_on_every_element(name):
    """``sc.check_tangent`` on the elastic and damping forces, gravity, drag, centrifugal
    load and the pin of each element: every term's tangent against central differences."""
    system, q, v = _scene(name)
    report = sc.check_tangent(system, q, v)
    assert report.error < 1e-6, report


@pytest.mark.parametrize("name", ["hermite5", "linear"])
def test_orbit_and_solar_wind_tangents(name):
    """Differential gravity of an orbit and the E-sail's solar wind on the new elements."""
    cable = sc.Cable.straight([0, 0, 0], [0, 500, 0], 3, SEC, element=name, name="t")
    system = sc.System([cable]).add_orbit(sc.Orbit(sc.MU_EARTH, 7e6))
    system.add_load(sc.SolarWindForce([cable], voltage=2e4))
    rng = np.random.default_rng(5)
    q = system.q0 + 0.5 * rng.standard_normal(system.n_dofs)
    report = sc.check_tangent(system, q)
    assert report.error < 1e-6, report


@pytest.mark.parametrize("name", ["hermite5", "linear"])
def test_export_and_summary(name, tmp_path):
    """A scene file naming the element runs; ParaView output and the summary's tension."""
    from skfem_cable import scene_file
    from skfem_cable.runner import RunOptions

    path = tmp_path / "hang.toml"
    path.write_text(f"""
[sections.rope]
E = 2e9
rho = 1500.0
radius = 0.005

[[cables]]
name = "rope"
section = "rope"
start = [0, 0, 0]
end = [0, 0, -4]
elements = 4
element = "{name}"

[[constraints]]
type = "pin"
node = {{ cable = "rope", index = 0 }}

[loads]
gravity = [0, 0, -9.81]

[solver]
analysis = "static"
""")
    summary = scene_file.run(path, RunOptions(plots=False, progress=False,
                                              out=tmp_path / "run"))
    weight = 1500.0 * np.pi * 0.005**2 * 4 * 9.81
    assert summary["outputs"]["cables"]["rope"]["root_tension"] == pytest.approx(weight,
                                                                                 rel=1e-6)
    assert list((tmp_path / "run").glob("*.vtu")) or list((tmp_path / "run").rglob("*.vtu"))


def test_builtin_scenes_and_sweeps_take_the_element(tmp_path):
    """``skfem-cable run pendulum --element hermite5`` and the sweep builders' ``element``
    parameter; a scene whose cables are fixed refuses ``--element``."""
    from skfem_cable.runner import RunOptions
    from skfem_cable.scenes import catalog

    summary = catalog.run_scene("pendulum", RunOptions(element="hermite5", t_end=0.02,
                                                       progress=False, plots=False))
    assert summary["parameters"]["element"] == "hermite5"
    scene = catalog.SCENES["spinning-tether"].builder()(elements=8, element="linear",
                                                        t_end=0.05)
    assert scene.system.cables()[0].element.name == "linear"
    result = scene.run(RunOptions(progress=False, plots=False))
    assert result["outputs"]["cables"]["cable"]["elements"] == 8
    with pytest.raises(ValueError, match="scene 'esail' does not take --element"):
        catalog.run_scene("esail", RunOptions(element="linear"))


@pytest.mark.parametrize("name", ["hermite5", "linear"])
def test_electrodynamic_force_on_the_new_elements(name):
    """The electrodynamic force in Earth's dipole on the new elements: its tangent against
    central differences (``sc.check_tangent``; the deployment's is checked on every
    element in ``tests/test_deploy.py``)."""
    undamped = sc.Section(E=2e9, A=1e-4, I=2e-10, rho=1500.0)
    cable = sc.Cable.straight([0, 0, 0], [0, 0, -2000.0], 3, undamped, element=name)
    orbiting = sc.System([cable]).add_orbit(sc.Orbit(sc.MU_EARTH, sc.R_EARTH + 400e3,
                                                     inclination=0.5))
    orbiting.add_load(sc.ElectrodynamicForce(cable, 1.5, sc.MagneticDipole(tilt=0.2)))
    q = orbiting.q0 + 1.0 * np.random.default_rng(2).normal(size=orbiting.n_dofs)
    check = sc.check_tangent(orbiting, q, t=300.0)
    assert check.error < 1e-6, str(check)
