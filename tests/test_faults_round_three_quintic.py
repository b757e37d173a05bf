"""Issue 45, item 4: the quintic element's default formulation is free of membrane locking.

Its default is the assumed strain of ``kernels.assumed_strain.Rule``, written once for
every element type: on the quintic, the C1 piecewise quintic with the raw strain's nodal
values and slopes and its element means and first moments.
Before, the quintic had the paper's formulation only, which locks on slender cables at
coarse meshes (``docs/locking.md``, ``docs/elements.md``).
"""

import functools

import numpy as np
import pytest

import skfem_cable as sc
from skfem_cable.analysis.analytic import elastica_tip_load


@functools.cache
def elastica_tip_error(n, slenderness, formulation=None, k=5.0):
    """Tip error (relative to the length) of the cantilever elastica of ``n`` quintic
    elements (tip load ``k EI / L^2``, ``L = 1``, ``EA L^2 / EI = slenderness``) against
    the exact inextensible elastica; each case solved once in the module (4 elements at
    1e11 serve two tests)."""
    section = sc.Section(E=1e9, A=1e-4, I=1e-4 / slenderness, rho=7850.0)
    cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], n, section, element="hermite5",
                              formulation=formulation)
    system = sc.System([cable]).clamp(cable.node(0))
    system.add_point_load(cable.node(-1), [0, -k * section.EI, 0])
    q = sc.solve_static(system, load_steps=max(10, int(2 * k))).q[:cable.n_dofs]
    tip = cable.interpolate(q, 1.0)[0]
    u, w = elastica_tip_load(k)
    return max(abs(1 - tip[0] - u), abs(-tip[1] - w))


def test_quintic_elastica_does_not_lock_on_slender_cables():
    """4 quintic elements, k = 5: tip error 1.3e-6 at EA L^2/EI = 1e7 and 1.6e-6 at 1e11
    (before: 4.3e-6 and 1.3e-3, the paper's formulation, which stays available)."""
    stocky, slender = (elastica_tip_error(4, r) for r in (1e7, 1e11))
    assert slender <= 2 * stocky
    assert slender < 3e-6
    assert elastica_tip_error(4, 1e11, formulation="paper") > 100 * slender


def test_quintic_elastica_keeps_its_order():
    """At EA L^2/EI = 1e11 (the extensible model within 1e-10 of the exact elastica) the
    tip error falls at order 5.0 and 5.2 from 2 to 4 and 4 to 8 elements (5.4e-5,
    1.6e-6, 4.4e-8), against the cubic element's 4."""
    errors = [elastica_tip_error(n, 1e11) for n in (2, 4, 8)]
    orders = np.log2(np.divide(errors[:-1], errors[1:]))
    assert np.all(orders > 4.8), errors


def test_assumed_strain_rule_keeps_the_nodal_derivatives_and_moments():
    """The quintic's rule: the raw strain (degree 8) is fixed by its 9 samples; a quintic
    raw strain is its own assumed strain, and the assumed strain keeps the nodal values
    and slopes, the mean and the first moment of any raw strain of degree 8.  The cubic's
    rule is the quadratic with the strain's nodal values and its mean (the map the cubic
    element always had)."""
    from numpy.polynomial import polynomial as P

    from skfem_cable.kernels.assumed_strain import GAUSS_W, GAUSS_XI, rule

    quintic = rule((0, 1, 2))
    assert quintic.samples.size == 9 and quintic.map.shape == (6, 9)
    rng = np.random.default_rng(4)
    own = rng.standard_normal(6)
    assumed = quintic.map @ P.polyval(quintic.samples, own)
    assert np.allclose(assumed, P.polyval(quintic.gauss[0], own), rtol=0, atol=1e-14)
    octic = rng.standard_normal(9)
    raw = P.polyval(quintic.samples, octic)
    xi = np.array([0.0, 1.0])
    ends = quintic.assumed_map(xi) @ raw
    assert np.allclose(ends, P.polyval(xi, octic), rtol=0, atol=1e-13)
    slope = (quintic.assumed_map(xi + 1e-6) - quintic.assumed_map(xi - 1e-6)) @ raw / 2e-6
    assert np.allclose(slope, P.polyval(xi, P.polyder(octic)), rtol=0, atol=1e-8)
    x, w = np.polynomial.legendre.leggauss(8)
    at, w = 0.5 + 0.5 * x, 0.5 * w
    for weight in (np.ones_like(at), 2 * at - 1):
        kept = w @ (weight * (quintic.assumed_map(at) @ raw))
        assert kept == pytest.approx(w @ (weight * P.polyval(at, octic)), abs=1e-14)
    bubble = 6 * GAUSS_XI * (1 - GAUSS_XI)
    quadratic = np.column_stack([1 - GAUSS_XI - bubble / 2, GAUSS_XI - bubble / 2,
                                 bubble[:, None] * GAUSS_W[None, :]])
    assert np.allclose(rule((0, 1)).map, quadratic, rtol=0, atol=1e-15)


@pytest.mark.parametrize("law", ["cable", "truss"])
def test_quintic_assumed_strain_tangent_is_exact(law):
    """``check_tangent`` of a damped quintic cable in the assumed strain, pinned, bent and
    moving: the elastic and damping tangents against central differences."""
    section = sc.Section(E=7e10, A=3e-6, I=1e-12, rho=2700.0, gamma_axial=0.3,
                         gamma_bending=0.7)
    cable = sc.Cable.straight([0, 0, 0], [2, 0, 0], 3, section, law=law, element="hermite5",
                              formulation="assumed-strain")
    system = sc.System([cable]).pin(cable.node(0))
    rng = np.random.default_rng(7)
    q = system.q0 + 0.05 * rng.standard_normal(system.n_dofs)
    v = rng.standard_normal(system.n_dofs)
    check = sc.check_tangent(system, q, v)
    assert {p.wrt for p in check.parts} >= {"q", "v"}
    assert check.error < 1e-7, str(check)
