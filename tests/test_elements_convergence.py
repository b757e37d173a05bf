"""Convergence orders of the element types (``Cable(..., element=...)``) on small meshes,
so that a regression of an element's order fails here: the linear element's catenary, the
quintic against the cubic on the elastica, the quintic's spinning-tether frequency.  The
full study, with more meshes and the measured numbers, is ``benchmarks/elements.py``
(``docs/elements.md``)."""

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq
from skfem import MeshLine

import skfem_cable as sc
from skfem_cable.analysis.analytic import elastic_catenary, rotating_string
from skfem_cable.bodies.catenary import green_stretch
from skfem_cable.scenes import classics

G = 9.81
#: The catenary of ``benchmarks/elements.py``: pins at (0, 0, 0) and (10, 0, 2) m, 12 m
#: of cable, ``EA = 1e4 N``, 0.98 N/m, the truss law.
SPAN, HEIGHT, LENGTH = 10.0, 2.0, 12.0
CATENARY_SECTION = sc.Section(E=1e8, A=1e-4, I=1e-12, rho=1e3)


def order(coarse, fine, ratio=2.0):
    """Observed order between two meshes whose sizes differ by ``ratio``."""
    return float(np.log(coarse / fine) / np.log(ratio))


def catenary_exact(s):
    """Exact positions and slopes ``r_x`` of the catenary at unstretched arc lengths."""
    sec = CATENARY_SECTION
    w = sec.mass_per_length * G
    xz, T, H, VA = elastic_catenary(s, SPAN, HEIGHT, LENGTH, w, sec.EA)
    t = np.column_stack([H + 0 * s, w * s - VA]) * ((1 + green_stretch(T, sec.EA)) / T)[:, None]
    zero = np.zeros_like(s)
    return (np.column_stack([xz[:, 0], zero, xz[:, 1]]),
            np.column_stack([t[:, 0], zero, t[:, 1]]))


def catenary_position_error(n, element):
    """Largest position error over the catenary of ``n`` elements (started from the exact
    nodal values and solved), relative to the span."""
    nodes = np.linspace(0.0, LENGTH, n + 1)
    positions, slopes = catenary_exact(nodes)
    cable = sc.Cable(MeshLine(nodes), CATENARY_SECTION, positions, slopes, law="truss",
                     element=element)
    system = sc.System([cable]).pin(cable.node(0))
    system.pin(cable.node(-1), [SPAN, 0.0, HEIGHT]).add_gravity([0.0, 0.0, -G])
    state = sc.solve_static(system)
    s = np.linspace(0.0, LENGTH, 2001)
    return np.abs(state.position(cable, s) - catenary_exact(s)[0]).max() / SPAN


def test_linear_element_is_second_order_on_the_catenary():
    """The linear element's position error on the elastic catenary falls by about 4 per
    halving: order 2 +- 0.3 between 16 and 32 elements (measured 2.00: 8.8e-4 and 2.2e-4
    of the span), against the exact Green-law catenary."""
    coarse, fine = (catenary_position_error(n, "linear") for n in (16, 32))
    assert fine < 1e-3
    assert order(coarse, fine) == pytest.approx(2.0, abs=0.3)


def elastica_tip(n, element):
    """Tip ``(x, y)`` of the elastica (``k = 5``, ``classics.ELASTICA_SECTION``, 1 m,
    dead tip load along -y, cable law, 10 load steps) of ``n`` elements."""
    section = classics.ELASTICA_SECTION
    cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], n, section, element=element)
    system = sc.System([cable]).clamp(cable.node(0))
    system.add_point_load(cable.node(-1), [0.0, -5.0 * section.EI, 0.0])
    return sc.solve_static(system, load_steps=10).position(cable, 1.0)[:2]


def test_quintic_beats_the_cubic_on_the_elastica():
    """Against the converged model (32 quintic elements, 2.4e-13 from 64): the quintic's
    tip error is below the cubic's at 4 and at 8 elements (measured 5.0e-6 against 4.1e-4,
    3.6e-8 against 2.8e-5), and falls at order above 5 from 4 to 8 elements (measured
    7.1; the cubic's is 3.9)."""
    converged = elastica_tip(32, "hermite5")
    error = {(element, n): np.abs(elastica_tip(n, element) - converged).max()
             for element in ("hermite3", "hermite5") for n in (4, 8)}
    for n in (4, 8):
        assert error["hermite5", n] < error["hermite3", n]
    assert order(error["hermite5", 4], error["hermite5", 8]) > 5.0


def tether_string_frequency():
    """First out-of-plane string frequency (Hz) of ``classics.spinning_tether`` (truss,
    tip mass 0.5 kg, 2 rad/s about z), in the rotating frame: ``p' = -mu w^2 w``,
    ``w' = lambda p / T`` on the steady state of ``analytic.rotating_string``, ``w(0) =
    0``, ``p(L) = m w^2 w(L)`` (derived in ``benchmarks/elements.py``,
    ``tether_reference``), by shooting; bracketed about the taut-string estimate."""
    cable = classics.spinning_tether(n_elements=1, kind="truss").cable
    L, EA, mu, m, spin = cable.length, cable.section.EA, cable.section.mass_per_length, 0.5, 2.0
    T0 = float(rotating_string([0.0], L, EA, mu, m, spin)[1][0])

    def mismatch(omega):
        def rhs(_, y):
            lam = 1.0 + green_stretch(max(y[1], 0.0), EA)
            return [lam, -mu * spin**2 * y[0], lam * y[3] / y[1], -mu * omega**2 * y[2]]

        y = solve_ivp(rhs, (0.0, L), [0.0, T0, 0.0, 1.0], method="DOP853", rtol=1e-12,
                      atol=1e-16).y[:, -1]
        return y[3] - m * omega**2 * y[2]

    string = np.pi / L * np.sqrt(m * spin**2 * L / mu)  # taut string, tension m spin^2 L
    return brentq(mismatch, 0.8 * string, 1.2 * string, xtol=1e-13) / (2 * np.pi)


def tether_frequencies(n):
    """Out-of-plane frequencies (Hz) of the spinning tether of ``n`` quintic elements:
    ``solve_steady`` and ``modes(..., spin=)`` in the rotating frame."""
    base = classics.spinning_tether(n_elements=1, kind="truss").cable
    cable = sc.Cable.straight([0, 0, 0], [base.length, 0, 0], n, base.section, law="truss",
                              element="hermite5")
    system = sc.System([cable]).pin(cable.node(0)).add_point_mass(cable.node(-1), 0.5)
    state = sc.solve_steady(system, [0, 0, 2.0])
    system.add_centrifugal([0, 0, 2.0])
    freqs, shapes = sc.modes(system, state, k=12, spin=[0, 0, 2.0])
    along = np.array([np.sum(np.abs(v[2::3]) ** 2) / np.sum(np.abs(v) ** 2) for v in shapes])
    return freqs[along > 0.5]


def test_spinning_tether_frequency_converges_on_the_quintic():
    """The first out-of-plane mode is the tilt at the spin frequency (to 1e-9; measured
    2e-13), and the next, the first string mode (4.908 Hz), converges on the quintic
    element: relative error below 1e-4 with one element (measured 6.8e-6), below 1e-7 with
    two (6.3e-9), an observed order above 6 between them (10.1)."""
    reference = tether_string_frequency()
    assert reference == pytest.approx(4.9081, rel=1e-4)
    errors = []
    for n in (1, 2):
        f = tether_frequencies(n)
        assert f[0] == pytest.approx(2.0 / (2 * np.pi), rel=1e-9)
        errors.append(abs(f[1] / reference - 1.0))
    assert errors[0] < 1e-4 and errors[1] < 1e-7
    assert order(*errors) > 6.0
