"""The cable cases of the peers' own test suites, built with ``skfem_cable``
(``docs/peers.md``; ``tests/test_peer_suites.py`` checks them against the peers' stored
numbers, ``benchmarks/peer_suites.py`` runs the peers side by side when they import).

Each case takes the peer's law and settings by default and ours on request, so that the
difference between the two is measured, not argued:

* ``exudyn_cantilever``: Exudyn ``TestModels/MiniExamples/ObjectANCFCable2D.py``, a
  cantilever bending under its own weight (static);
* ``exudyn_free_beam``: Exudyn ``TestModels/computeODE2EigenvaluesTest.py``, the first
  bending frequency of a free-free beam;
* ``exudyn_tip_load``: the cable part of Exudyn ``TestModels/ANCFCableBeamDampingTest.py``,
  a clamped cable under a suddenly applied tip load (dynamic, zero initial
  accelerations);
* ``exudyn_softening``: Exudyn ``TestModels/ANCFcable2DuserFunction.py``, a cantilever
  swinging down with an axial stiffness that softens in time and a bending moment that
  saturates (user functions, here a law with a time-dependent parameter);
* ``moordyn_pendulum``: MoorDyn ``tests/pendulum.cpp`` with ``tests/Mooring/pendulum.txt``,
  a 1e5 kg mass swinging on a 100.5 m line.

Exudyn's 2-D cable is our 3-D cable moving in its plane (the out-of-plane coordinates
stay zero): the same energy, with the curvature ``(a x b)_z / |a|^2`` a vector's length.
"""

import numpy as np

from ..bodies.cable import Cable
from ..bodies.section import Section
from ..laws import atan, cable_law, curvature_vector, dot, log, norm, rate, sqrt
from ..loads.drag import Buoyancy
from ..model.system import System
from ..results.timeseries import period
from ..solvers.modal import modes
from ..solvers.simulate import simulate
from ..solvers.static import solve_static

#: Exudyn's Gauss rules of its cable (``useReducedOrderIntegration=0``): 5 points for the
#: axial part (order 9), 3 for the bending part (order 5); reduced (``=1``): 4 and 2.
EXUDYN_RULES = {"axial": 5, "bending": 3}
EXUDYN_REDUCED_RULES = {"axial": 4, "bending": 2}

#: Exudyn's default spectral radius of its generalized-alpha method.
EXUDYN_RHO_INF = 0.9

#: The first root of ``cosh(beta) cos(beta) = 1`` (free-free beam), as Exudyn's test
#: gives it.
BETA_1 = 4.730040744862704


def exudyn_cantilever(n_elements=32, law="exudyn", quadrature=EXUDYN_RULES, EA=1e6):
    """The tip's x-displacement (m) of a 2 m cantilever (rho A = 78 kg/m, EA = 1e6 N,
    EI = 833.33 N m^2, 32 elements) bending under gravity 9.81 m/s^2, its root pinned with
    the slope's direction fixed (Exudyn's ``[1, 1, 0, 1]``: the root may stretch); static.

    Exudyn stores -0.5013058140308901 (``runTestSuiteRefSol.py``).  ``EA`` changes the
    axial stiffness (the difference between the laws scales with the axial strain)."""
    section = Section(E=EA, A=1.0, I=833.3333333333333 / EA, rho=78.0)
    cable = Cable.straight([0, 0, 0], [2, 0, 0], n_elements, section, law=law,
                           quadrature=quadrature)
    system = System([cable]).clamp(cable.node(0))
    system.add_gravity([0.0, -9.81, 0.0])
    state = solve_static(system, tol=1e-13)
    return float(state.position(cable, cable.length)[0] - cable.length)


def exudyn_free_beam(n_elements=32, law="exudyn", quadrature=EXUDYN_REDUCED_RULES):
    """``u = omega_analytic - omega_1`` (rad/s): the Euler-Bernoulli first bending
    frequency of a free-free steel bar (2 m, 1 cm x 1 cm, E = 2.07e11 Pa, rho = 7800
    kg/m^3, the axial stiffness taken a tenth of E A), less the discrete one of 32
    elements, and the discrete one's mode shape.

    Exudyn stores ``1e-6 u = -2.749026293713541e-11`` (``runTestSuiteRefSol.py``).  About
    the straight, unstretched bar every law of the gallery has the same stiffness (the
    Hessians of the Green and the engineering strain, and of both curvatures, agree
    there), and the Gauss rules integrate it exactly: the laws give the same number."""
    E, rho, side, L = 2.07e11, 7800.0, 0.01, 2.0
    A, I = side**2, side**4 / 12
    section = Section(E=0.1 * E, A=A, I=10 * I, rho=rho)  # EA / 10, EI
    cable = Cable.straight([0, 0, 0], [L, 0, 0], n_elements, section, law=law,
                           quadrature=quadrature)
    # five zero modes (three translations, two rotations), then the bending pair
    freqs, shapes = modes(System([cable]), k=7)
    omega = (BETA_1 / L) ** 2 * np.sqrt(E * I / (rho * A))
    return float(omega - 2 * np.pi * freqs[5]), cable, shapes[5]


def exudyn_tip_load(case, law="exudyn", quadrature=EXUDYN_RULES, dt=None,
                    initial_acceleration="zero", n_elements=4):
    """The tip displacement ``(u_x, u_y)`` (m) at t = 0.1 s of a 0.5 m cable (diameter
    2 cm, E = 1e8 Pa, 2 kg/m, 4 elements, no damping) clamped with its whole slope
    (Exudyn's ``[1, 1, 1, 1]``) under a tip force applied at t = 0: ``case`` 0 is
    ``(0, -5, 0)`` N with steps of 4 ms, case 1 ``(-100, 0, 0)`` N with 0.5 ms;
    generalized-alpha with Exudyn's spectral radius 0.9, started from zero accelerations
    as Exudyn's test does (``initial_acceleration="consistent"`` for the true start)."""
    force, step = (([0.0, -5.0, 0.0], 4e-3), ([-100.0, 0.0, 0.0], 0.5e-3))[case]
    radius = 0.01
    section = Section.circular(radius, 1e8, 2.0 / (np.pi * radius**2))
    cable = Cable.straight([0, 0, 0], [0.5, 0, 0], n_elements, section, law=law,
                           quadrature=quadrature)
    system = System([cable]).clamp(cable.node(0), slope="full")
    system.add_point_load(cable.node(-1), force)
    result = simulate(system, 0.1, step if dt is None else dt, rho_inf=EXUDYN_RHO_INF,
                      tol=1e-13, initial_acceleration=initial_acceleration)
    return result.position(cable, cable.length)[-1, :2] - [0.5, 0.0]


# --8<-- [start:saturating]
def _softening_damping(a, b, ad, bd, c_axial, c_bending):
    """Exudyn's cable damping with absolute coefficients: ``D = c_x eps_dot^2 / 2 +
    c_b |k_dot|^2 / 2``."""
    k = curvature_vector(a, b)
    return (c_axial * (dot(a, ad) / norm(a)) ** 2 / 2
            + c_bending * sum(rate(k[i], a, b, ad, bd) ** 2 for i in range(3)) / 2)


@cable_law(dissipation=_softening_damping, name="exudyn-user-functions")
def saturating(a, b, EA, EI):
    """The law of Exudyn's ``ANCFcable2DuserFunction.py``: engineering strain ``eps = |a| -
    1`` and a bending moment that saturates, ``M = EI atan(10 kappa) / 10``, i.e. ``W = EA
    eps^2 / 2 + EI (kappa atan(10 kappa) - ln(1 + 100 kappa^2) / 20) / 10`` with Exudyn's
    curvature ``kappa = |a x b| / |a|^2`` (``curvature_vector``).  ``kappa`` is taken as
    ``sqrt(|k|^2 + 1e-60)``: the density is even in ``kappa``, and the tiny offset keeps
    its derivatives free of ``0/0`` at zero curvature (their values there are exact)."""
    k2 = dot(curvature_vector(a, b), curvature_vector(a, b))
    kappa = sqrt(k2 + 1e-60)
    return EA * (norm(a) - 1) ** 2 / 2 + EI * (kappa * atan(10 * kappa)
                                               - log(1 + 100 * k2) / 20) / 10


def softening_stiffness(t, EA=1e5):
    """Exudyn's ``axialForceUserFunction``: the axial stiffness ``EA max(0.02, 2 - sqrt(t))``
    (N)."""
    return EA * max(0.02, 2.0 - np.sqrt(max(t, 0.0)))


#: The case's law: stiffness softening in time, Exudyn's damping coefficients.
SOFTENING = saturating.with_parameters(EA=softening_stiffness, EI=2000.0,
                                       c_axial=0.05 * 1e5, c_bending=0.1 * 2000.0)
# --8<-- [end:saturating]


def exudyn_softening(pseudo_acceleration="initial", dt=5e-3, n_elements=16):
    """The sum of the tip's coordinates (m) at t = 0.5 s of a 2 m cantilever (rho A = 78
    kg/m, EA = 1e5 N, EI = 2000 N m^2, axial and bending damping 0.05 EA and 0.1 EI, 16
    elements, root as in ``exudyn_cantilever``) released straight under gravity: the
    ``SOFTENING`` law (``saturating``, axial stiffness ``softening_stiffness(t)``), 5 ms steps,
    Exudyn's spectral radius 0.9 and consistent initial accelerations with, as Exudyn
    starts, ``abar_0 = a_0``.

    Exudyn stores 0.6015588367721232 (``runTestSuiteRefSol.py``)."""
    section = Section(E=1e5, A=1.0, I=2000.0 / 1e5, rho=78.0)  # the mass: 78 kg/m
    cable = Cable.straight([0, 0, 0], [2, 0, 0], n_elements, section, law=SOFTENING,
                           quadrature=EXUDYN_RULES)
    system = System([cable]).clamp(cable.node(0))
    system.add_gravity([0.0, -9.81, 0.0])
    result = simulate(system, 0.5, dt, rho_inf=EXUDYN_RHO_INF, tol=1e-13,
                      pseudo_acceleration=pseudo_acceleration)
    return float(result.position(cable, cable.length)[-1].sum()), result


@cable_law(name="hooke-truss")
def hooke_truss(a, b, EA):
    """MoorDyn's line: tension ``EA (|a| - 1)`` (engineering strain), no bending."""
    return EA * (norm(a) - 1) ** 2 / 2


def moordyn_pendulum(law=hooke_truss, element="linear", dt=0.05, t_end=45.0,
                     rho_inf=0.9):
    """The period (s) of MoorDyn's pendulum: a line of 100.5 m (20 segments, EA = 1e9 N,
    7.85398 kg/m, diameter 0.1 m: neutrally buoyant in water of 1000 kg/m^3) from a fixed
    point to a free 1e5 kg point mass starting at rest at (10, 0, -100) m, 100.499 m away
    (the line slack by 1.2 mm: ``Cable.between`` hangs it), gravity 9.80665 m/s^2; the
    mean period from the zero crossings of the mass's x over ``t_end``.

    MoorDyn 2.7.2 gives 20.1630254 s (``benchmarks/peer_suites.py``)."""
    g = np.array([0.0, 0.0, -9.80665])
    diameter, mu, EA = 0.1, 7.85398, 1e9
    A = np.pi * diameter**2 / 4
    section = Section(E=EA / A, A=A, I=1e-12, rho=mu / A)  # no bending: I unused
    line = Cable.between([0, 0, 0], [10, 0, -100], 100.5, 20, section, sag=g, law=law,
                         element=element)
    system = System([line]).pin(line.node(0))
    system.add_point_mass(line.node(-1), 1e5)
    system.add_gravity(g)
    system.add_load(Buoyancy(line, 1000.0, diameter, g))
    result = simulate(system, t_end, dt, rho_inf=rho_inf)
    tip = line.length
    return period(result.t, result.position(line, tip)[:, 0], result.velocity(line, tip)[:, 0])
