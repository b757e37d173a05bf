"""The cubic-Hermite ANCF element on scikit-fem: accuracy, scikit-fem integration."""

import numpy as np
import pytest
from skfem import Basis, BilinearForm, ElementLineHermite, ElementVector, Functional, MeshLine, asm
from skfem.helpers import dot

from skfem_cable import ElementLineCableHermite, Section


def cubic(x):
    return 2.0 - x + 3.0 * x**2 - 0.7 * x**3, -1.0 + 6.0 * x - 2.1 * x**2, 6.0 - 4.2 * x


def interpolation_errors(element, n_elements):
    """Max relative errors of value, first and second derivative of the interpolant of a
    cubic (reproduced exactly by the element) at the Gauss points."""
    mesh = MeshLine(np.linspace(0.0, 1.0, n_elements + 1))
    basis = Basis(mesh, element, intorder=4)
    x = mesh.p[0]
    f, fx, _ = cubic(x)
    u = np.empty(basis.N)
    u[basis.nodal_dofs[0]] = f
    u[basis.nodal_dofs[1]] = fx
    field = basis.interpolate(u)
    xq = np.asarray(basis.global_coordinates())[0]
    exact = cubic(xq)
    got = (np.asarray(field), field.grad[0], field.hess[0, 0])
    return [np.max(np.abs(g - e)) / np.max(np.abs(e)) for g, e in zip(got, exact)]


@pytest.mark.parametrize("n_elements", [1, 60, 600, 6000])
def test_cubic_reproduced_to_machine_precision(n_elements):
    value, grad, hess = interpolation_errors(ElementLineCableHermite(), n_elements)
    eps = np.finfo(float).eps
    assert value < 4 * eps
    # derivatives are differences of nodal data over h and h^2: their round-off is
    # eps * n and eps * n^2 relative, whatever the element; nothing is lost beyond that
    assert grad < 16 * eps * n_elements + 4 * eps
    assert hess < 16 * eps * n_elements**2 + 4 * eps


def test_far_more_accurate_than_skfem_hermite_when_refined():
    ours = interpolation_errors(ElementLineCableHermite(), 600)[0]
    theirs = interpolation_errors(ElementLineHermite(), 600)[0]
    assert theirs > 1e-11
    assert ours < 1e-4 * theirs


def test_vector_element_with_skfem_basis_asm_and_get_dofs():
    sec = Section(E=1e9, A=2e-4, I=1e-9, rho=1000.0)
    L, n = 3.0, 7
    mesh = MeshLine(np.linspace(0.0, L, n + 1))
    basis = Basis(mesh, ElementVector(ElementLineCableHermite(), dim=3), intorder=6)
    assert basis.N == 6 * (n + 1)
    M = asm(BilinearForm(lambda u, v, w: sec.rho * sec.A * dot(u, v)), basis)
    ones = np.zeros(basis.N)
    ones[basis.nodal_dofs[1]] = 1.0  # rigid translation along y: r^2 = 1, slopes 0
    assert ones @ M @ ones == pytest.approx(sec.rho * sec.A * L, rel=1e-13)
    length = asm(Functional(lambda w: 1.0 + 0.0 * w.x[0]), basis)
    assert length == pytest.approx(L, rel=1e-14)
    dofs = basis.get_dofs(lambda x: np.isclose(x[0], 0.0))
    assert sorted(dofs.nodal) == ["u^1", "u^2", "u^3", "u_x^1", "u_x^2", "u_x^3"]
    assert list(dofs.nodal["u_x^2"]) == [4]


def test_gbasis_rejects_bad_index():
    mesh = MeshLine(np.linspace(0.0, 1.0, 3))
    basis = Basis(mesh, ElementLineCableHermite())
    with pytest.raises(ValueError):
        ElementLineCableHermite().gbasis(basis.mapping, basis.X, 4)
