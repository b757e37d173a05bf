"""Slack cables in statics: ``solve_static`` finds the elastic catenary of a cable built
straight between two points closer than its length (the initial state violates a pin),
by a continuation that applies the loads first and then closes the violation, with
pseudo-transient continuation where Newton's method fails; checked against the exact
elastic catenary of the Green-strain law (``analytic.elastic_catenary``)."""


import numpy as np
import pytest
from demo_modules import load_demo

import skfem_cable as sc
from skfem_cable.analysis.analytic import elastic_catenary
from skfem_cable.bodies.catenary import green_stretch

demo = load_demo("slack_catenary")


def test_catenary_reference_closes_and_balances():
    """The reference ends at the support, its support forces carry the weight, and its
    stretch is the Green-strain law's (``T = EA lambda (lambda^2 - 1) / 2``)."""
    w, EA = 0.981, 1e3
    s = np.linspace(0.0, 12.0, 5)
    xz, T, H, VA = elastic_catenary(s, 10.0, 2.0, 12.0, w, EA)
    np.testing.assert_allclose(xz[-1], [10.0, 2.0], atol=1e-13)
    assert T[0] == pytest.approx(np.hypot(H, VA), rel=1e-14)
    assert np.hypot(H, w * 12.0 - VA) == pytest.approx(T[-1], rel=1e-14)
    lam = 1 + green_stretch(T, EA)
    np.testing.assert_allclose(EA * lam * (lam**2 - 1) / 2, T, rtol=1e-13)
    with pytest.raises(ValueError, match="length must exceed the chord"):
        elastic_catenary(s, 10.0, 0.0, 9.0, w, EA)


def test_catenary_from_a_straight_start_to_1e_8():
    """64 cubic Hermite elements of the truss law in the paper's formulation: positions
    within 1e-8 of the span of the exact elastic catenary (measured 8.0e-9), the
    horizontal support force within 1e-8 (4.2e-10).  It starts from its hanging shape
    (``hanging_start``, issue 45), from which Newton's method needs no relaxation.  Its
    tension, from the raw strain, converges more slowly (1.6e-4)."""
    cable, state = demo.hang(64, formulation="paper")
    position, tension, H = demo.errors(cable, state)
    assert position < 1e-8
    assert H < 1e-8
    assert tension < 1e-3
    assert state.stats["converged"]


def test_default_catenary_from_a_straight_start():
    """The same with the default formulation: positions third order (2.2e-7 of the span),
    support force 3.8e-8, and the recovered tension within 1e-6 (4.6e-7)."""
    cable, state = demo.hang(64)
    position, tension, H = demo.errors(cable, state)
    assert position < 3e-7 and H < 1e-7 and tension < 1e-6
    assert state.stats["converged"] and state.stats["relaxed"]


@pytest.mark.parametrize("formulation, order, bound", [("paper", 3.5, 3e-7),
                                                       ("assumed-strain", 2.8, 3e-6)])
def test_catenary_converges(formulation, order, bound):
    """Position errors at 8, 16, 32 elements fall at about the fourth power of h in the
    paper's formulation (4.0, 4.3), the third with the assumed strain (2.9, 3.0: it keeps
    the element means of the strain, not their first moments; 1.7e-6 at 32)."""
    out = demo.main(elements=(8, 16, 32), formulation=formulation)
    assert out["position_error"][-1] < bound
    assert min(out["rates"]) > order


def test_cable_law_with_negligible_bending_hangs_the_same():
    """The paper's cable law with ``EI = 1e-13 N m^2`` (the bending length
    ``sqrt(EI / T)`` is 1e-7 m) reaches the same catenary from the same start (to 3e-6 of
    the span with 32 elements, as the truss: 1.7e-6)."""
    cable, state = demo.hang(32, law="cable")
    assert demo.errors(cable, state)[0] < 3e-6


def test_without_relaxation_the_straight_truss_is_singular():
    """The continuation needs the relaxation: with ``relax=False`` the unstressed straight
    truss has a singular tangent, and the error says so."""
    cable = sc.Cable.straight([0, 0, 0], [12.0, 0, 0], 8, demo.SECTION, law="truss",
                              name="wire")
    system = sc.System([cable]).pin(cable.node(0)).pin(cable.node(-1), [10.0, 0.0, 0.0])
    system.add_gravity([0.0, 0.0, -demo.G])
    with pytest.raises(sc.StaticConvergenceError, match="cable 'wire' has no bending"):
        sc.solve_static(system, relax=False, max_bisections=2)


def test_demo_slack_catenary():
    """The demo at reduced size: 16 elements within 2e-5 of the span (1.4e-5)."""
    out = demo.main(elements=(16,))
    assert out["position_error"][0] < 2e-5
