"""The Atwood machine with a massive rope over a frictionless drum (issue 49, item 2),
shared by ``test_contact.py`` (EA = 1e5 N) and ``test_contact_surfaces.py`` (a rope ten
times stiffer): masses m1 = 1.1 kg and m2 = 1 kg on legs of 1 m, g = 9.81.  The descent
``x`` of m1 follows ``x = a0 / w^2 (cosh w t - 1)``, ``a0 = g (m1 - m2) / M``, ``w^2 = 2
rho A g / M``, ``M = m1 + m2 + rho A L`` (``test_contact.test_atwood_machine_with_a_massive_rope``
derives it)."""

import numpy as np
import pytest

import skfem_cable as sc
from skfem_cable.scenes.capstan import DRUM, R, wrapped

G, M1, M2 = 9.81, 1.1, 1.0


def atwood(E):
    """``(system, cable)``: the rope (radius 5 mm, Young's modulus ``E``, damped by
    ``gamma_axial = 5e-3`` s) wrapped on the drum, the two masses at its ends, gravity
    and the default contact."""
    rope = sc.Section.circular(5e-3, E, 1273.0, gamma_axial=5e-3)   # damps the bounce
    cable = wrapped(R + 5e-3 + 1e-5, 1.0, 24, 8, section=rope)
    system = (sc.System([cable]).add_gravity([0, -G, 0])
              .add_point_mass(cable.node(0), M1).add_point_mass(cable.node(-1), M2)
              .contact(cable, DRUM))
    return system, cable


def assert_follows_the_closed_form(system, cable, result):
    """m1's descent within 1 % of the closed form over 0.2 .. 1 s, counted from 0.1 s
    (after the rope's first elastic stretch), and its speed at the end within 1 %."""
    rho_a = cable.section.mass_per_length
    M = M1 + M2 + rho_a * cable.length
    a0, w = G * (M1 - M2) / M, np.sqrt(2 * rho_a * G / M)
    t = result.t
    y = result.q[:, system.dofs(cable.node(0))[1]]
    exact = a0 / w**2 * (np.cosh(w * t) - 1)
    start, late = np.searchsorted(t, 0.1 - 1e-9), t >= 0.2 - 1e-9
    assert (y[start] - y[late]) == pytest.approx(exact[late] - exact[start], rel=1e-2)
    speed = -result.v[-1, system.dofs(cable.node(0))[1]]
    assert speed == pytest.approx(a0 / w * np.sinh(w * t[-1]), rel=1e-2)
