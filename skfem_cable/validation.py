"""Fast validation cases against closed-form references (``skfem-cable validate``).

Each case is a reduced version of a test of the suite (``tests/test_validation_statics.py``,
``tests/test_dynamics*.py``) that runs in about a second and returns the reference value and
ours; the table lists the relative error against the case's tolerance.
"""

import time
from dataclasses import dataclass

import numpy as np

from .analytic import compound_pendulum_period, elastica_tip_load, string_frequency
from .cable import Cable
from .scenes import classics
from .section import Section
from .solvers.modal import modes
from .solvers.simulate import simulate
from .solvers.static import solve_static
from .system import System
from .timeseries import decay_rate, period, zero_crossings

#: The beam of the static and modal cases (EA L^2 / EI = 1e6).
STEEL = Section(E=2.1e11, A=1e-4, I=1e-10, rho=7850.0)


@dataclass
class Case:
    """A validation case: ``compute() -> (reference, ours)``, passing when the relative
    error is at most ``tol``."""

    name: str
    reference: str
    compute: object
    tol: float


def elastica():
    """Tip deflection ``w/L`` of a cantilever under a dead tip load ``P L^2/EI = 5``
    (Bisshopp & Drucker), 16 elements, EA L^2/EI = 1e7."""
    scene = classics.cantilever(16, 5.0)
    state = solve_static(scene.system, load_steps=20)
    return elastica_tip_load(5.0)[1], -state.position(scene.cable, 1.0)[1]


def cantilever_frequency():
    """First bending frequency of a clamped-free beam, 8 elements:
    ``(beta L)^2 / (2 pi L^2) sqrt(EI / rho A)`` with ``beta L = 1.8751040687``."""
    cable = Cable.straight([0, 0, 0], [1, 0, 0], 8, STEEL)
    freqs, _ = modes(System([cable]).clamp(cable.node(0)), k=1)
    reference = 1.875104068712**2 / (2 * np.pi) * np.sqrt(STEEL.EI / STEEL.mass_per_length)
    return reference, freqs[0]


def spinning_tension():
    """Root tension of a tether with a tip mass spinning at 2 rad/s, steady state in the
    rotating frame (``add_centrifugal``, root clamped along the radius): the rigid value
    ``m W^2 L + rho A W^2 L^2 / 2`` (the strain, 4e-4, bounds the difference)."""
    scene = classics.spinning_tether(n_elements=10, spin=2.0, tip_mass=0.5)
    cable = scene.cable
    system = System([cable]).clamp(cable.node(0)).add_point_mass(cable.node(-1), 0.5)
    system.add_centrifugal([0, 0, 2.0])
    state = solve_static(system, load_steps=2)
    L, mu = cable.length, cable.section.mass_per_length
    return 0.5 * 4.0 * L + mu * 4.0 * L**2 / 2, state.tension(cable, 0.0)


def pendulum_period():
    """Period of a stiff 0.2 m bar (4 elements) released from horizontal (twice the time
    between its two passages through the vertical): the exact large-amplitude compound
    pendulum ``4 K(sin^2(pi/4)) / sqrt(3 g / 2 L)``."""
    L = 0.2
    scene = classics.pendulum(n_elements=4, length=L, radius=0.01, E=2e11, rho=7800.0)
    T = compound_pendulum_period(L, np.pi / 2)
    r = simulate(scene.system, t_end=1.05 * T, dt=T / 400, rho_inf=1.0, tol=1e-11)
    c = zero_crossings(r.t, r.position(scene.cable, L)[:, 0], r.velocity(scene.cable, L)[:, 0])
    return T, 2 * (c[1] - c[0])


def axial_wave():
    """Period ``4 L / c`` of the axial wave in a clamped-free bar released from a uniform
    stretch, 32 elements, 400 steps per period."""
    scene = classics.stretched_bar(n_elements=32)
    T = 4.0 / np.sqrt(2e11 / 7800.0)
    r = simulate(scene.system, t_end=2.2 * T, dt=T / 400, rho_inf=0.8, initial=scene.initial)
    u = r.position(scene.cable, 1.0)[:, 0] - 1.0
    return T, period(r.t, u, r.velocity(scene.cable, 1.0)[:, 0])


def string():
    """First frequency of a pinned taut string (truss, strain 1e-3), 16 elements:
    ``1/(2L) sqrt(T/mu)`` in the stretched configuration."""
    strain = 1e-3
    scene = classics.taut_string(n_elements=16, strain=strain)
    sec = scene.cable.section
    stretch = 1 + strain
    f = string_frequency(stretch, sec.EA * 0.5 * (stretch**2 - 1) * stretch,
                         sec.mass_per_length / stretch)
    r = simulate(scene.system, t_end=2.2 / f, dt=1 / (200 * f), rho_inf=0.9,
                 initial=scene.initial)
    y = r.position(scene.cable, 0.5)[:, 1]
    return f, 1.0 / period(r.t, y, r.velocity(scene.cable, 0.5)[:, 1])


def damping():
    """Decay rate ``gamma omega^2 / 2`` of the first axial mode of a clamped-free bar with
    Kelvin-Voigt damping (damping ratio 2 %), 16 elements, 6 periods."""
    omega = np.pi * np.sqrt(2e11 / 7800.0) / 2
    gamma = 2 * 0.02 / omega
    scene = classics.stretched_bar(n_elements=16, mode=1, gamma_axial=gamma)
    T = 2 * np.pi / omega
    r = simulate(scene.system, t_end=6 * T, dt=T / 100, rho_inf=1.0, initial=scene.initial)
    return gamma * omega**2 / 2, decay_rate(r.t, r.position(scene.cable, 1.0)[:, 0] - 1.0)


CASES = [
    Case("elastica", "tip deflection w/L, P L^2/EI = 5", elastica, 1e-3),
    Case("cantilever-frequency", "1st bending frequency (Hz)", cantilever_frequency, 1e-5),
    Case("spinning-tension", "root tension of a spinning tether (N)", spinning_tension, 1e-3),
    Case("pendulum-period", "compound pendulum period (s)", pendulum_period, 5e-4),
    Case("axial-wave", "axial wave period 4L/c (s)", axial_wave, 5e-4),
    Case("string-frequency", "taut string frequency (Hz)", string, 5e-4),
    Case("damping-rate", "Kelvin-Voigt modal decay rate (1/s)", damping, 5e-3),
]


def run(names=None):
    """Run the cases ``names`` (default: all); returns one dict per case with ``name``,
    ``quantity``, ``reference``, ``ours``, ``error`` (relative), ``tol``, ``passed`` and
    ``seconds``."""
    known = {c.name: c for c in CASES}
    unknown = [n for n in (names or []) if n not in known]
    if unknown:
        raise ValueError(f"unknown validation case {unknown[0]!r}: use one of "
                         f"{', '.join(known)}")
    rows = []
    for case in [known[n] for n in names] if names else CASES:
        start = time.perf_counter()
        reference, ours = (float(x) for x in case.compute())
        error = abs(ours - reference) / abs(reference)
        rows.append({"name": case.name, "quantity": case.reference, "reference": reference,
                     "ours": ours, "error": error, "tol": case.tol,
                     "passed": bool(error <= case.tol),
                     "seconds": time.perf_counter() - start})
    return rows


def format_table(rows):
    """The rows of ``run`` as a text table."""
    head = (f"{'case':<22} {'quantity':<40} {'reference':>13} {'ours':>13} {'rel.err':>9} "
            f"{'tol':>8} {'result':>6} {'time[s]':>7}")
    lines = [head, "-" * len(head)]
    for r in rows:
        lines.append(f"{r['name']:<22} {r['quantity']:<40} {r['reference']:13.7g} "
                     f"{r['ours']:13.7g} {r['error']:9.2e} {r['tol']:8.0e} "
                     f"{'pass' if r['passed'] else 'FAIL':>6} {r['seconds']:7.2f}")
    passed = sum(r["passed"] for r in rows)
    lines.append(f"{passed} passed, {len(rows) - passed} failed")
    return "\n".join(lines)
