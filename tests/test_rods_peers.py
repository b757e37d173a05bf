"""Our side of PyElastica's Timoshenko cantilever (its ``examples/TimoshenkoBeamCase``)
against its closed form; PyElastica's side runs in ``benchmarks/rods.py``."""

import numpy as np
import pytest

import skfem_cable as sc
from skfem_cable.analysis.analytic import elastica_tip_load

#: The case: length, radius, E, density, tip load, shear-stiff G (the example's
#: "unshearable" rod, Poisson's ratio -0.7).
L, R, E, RHO, F = 3.0, 0.25, 1e6, 5000.0, 15.0
G = E / 0.3


def tip_deflection(section, n_elements):
    """Static tip deflection along the load of the clamped rod under its tip load."""
    rod = sc.Rod.straight([0, 0, 0], [0, 0, L], n_elements, section, normal=[0, 1, 0])
    system = sc.System([rod]).clamp(rod.node(0)).add_point_load(rod.node(-1), [-F, 0, 0])
    return -sc.solve_static(system).q[system.dofs(rod)][rod.n_centreline - 6]


@pytest.mark.parametrize("axial_scale, tol", [(1.0, 2e-5), (1e6, 1e-7)],
                         ids=["case", "inextensible"])
def test_timoshenko_cantilever_in_its_shear_stiff_limit(axial_scale, tol):
    """PyElastica's Timoshenko cantilever (L = 3 m, r = 0.25 m, E = 1e6 Pa, 15 N at the
    tip) as a Kirchhoff rod of 8 elements: its tip deflection is the inextensible
    elastica's (Bisshopp & Drucker; ``F L^2 / EI = 0.044``, 2.2e-4 below the linear ``F
    L^3 / 3 EI``) to 2e-5 with the case's ``EA`` (measured 9.4e-6: the tension of the
    bent rod stretches it) and to 1e-7 with a 1e6 times larger ``A`` (measured 7.7e-9)."""
    I = np.pi * R**4 / 4
    section = sc.Section(E, np.pi * R**2 * axial_scale, I, RHO, G=G)
    exact = L * elastica_tip_load(F * L**2 / (E * I))[1]
    assert exact == pytest.approx(F * L**3 / (3 * E * I), rel=3e-4)
    assert tip_deflection(section, 8) == pytest.approx(exact, rel=tol)


def test_axial_stretching_against_the_green_strain_closed_form():
    """PyElastica's axial stretching (L = 1 m, r = 0.025 m, E = 1e4 Pa, 1 N at the tip, a
    strain of 5 %, 19 elements) with our default law (Green strain): the tip moves by
    ``L (lambda - 1)``, ``lambda (lambda^2 - 1) / 2 = F / EA``, to 1e-12 (measured 9e-15;
    PyElastica's own law gives ``F L / (EA - F)``, ``benchmarks/rods.py``)."""
    section = sc.Section.circular(0.025, 1e4, 1000.0, G=1e4 / 1.5)
    rod = sc.Rod.straight([0, 0, 0], [1, 0, 0], 19, section, normal=[0, 1, 0])
    system = sc.System([rod]).clamp(rod.node(0)).add_point_load(rod.node(-1), [1.0, 0, 0])
    tip = sc.solve_static(system).q[system.dofs(rod)][rod.n_centreline - 6] - 1.0
    roots = np.roots([1.0, 0.0, -1.0, -2.0 / section.EA])
    stretch = roots[np.argmin(abs(roots - 1))].real
    assert tip == pytest.approx(stretch - 1, rel=1e-12)
