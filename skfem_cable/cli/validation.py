"""Fast validation cases against closed-form references (``skfem-cable validate``).

Each case is a reduced version of a test of the suite (``tests/test_validation_statics.py``,
``tests/test_dynamics*.py``) that runs in about a second and returns the reference value and
ours; the table lists the relative error against the case's tolerance.

Below them, the statics and modal cases that ``tests/test_validation_statics.py`` and
``benchmarks/locking.py`` share: modes of straight beams (``beam_modes``, ``axial_fraction``,
``transverse_pairs``), the taut elastic catenaries ``CATENARIES`` against the exact solution
(``catenary_reference``, ``catenary_system``, ``catenary_errors``; the reference is
``analytic.solve_catenary``) and the observed orders of convergence (``observed_rates``).
"""

import time
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq
from skfem import MeshLine

from ..analysis.analytic import compound_pendulum_period, elastica_tip_load, string_frequency
from ..bodies.cable import Cable
from ..bodies.catenary import catenary_xz, solve_catenary
from ..bodies.section import Section
from ..model.system import System
from ..results.timeseries import decay_rate, period, zero_crossings
from ..scenes import classics
from ..solvers.modal import modes
from ..solvers.simulate import simulate
from ..solvers.static import solve_static

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


# --- statics and modes: the cases of tests/test_validation_statics.py ---------------------
#: Gravity of the catenaries (m/s^2).
G = 9.81
#: Green pre-strain of the taut string (steel, 1 m, both ends pinned).
EPS0 = 1e-3


def axial_fraction(system, shapes, axis):
    """Share of each mode's nodal displacement that lies along ``axis``.

    Parameters
    ----------
    system : System
        A system of one cable (6 coordinates per node).
    shapes : ndarray, shape (k, n_dofs)
        Mode shapes as returned by ``modes``.
    axis : array_like, shape (3,)
        Unit vector of the undeformed cable axis.

    Returns
    -------
    ndarray, shape (k,)
        ``sum |u . axis|^2 / sum |u|^2`` over the nodal positions ``u``: 1 for an axial
        mode, 0 for a transverse one.
    """
    u = shapes.reshape(len(shapes), system.n_dofs // 6, 6)[:, :, :3]
    along = np.einsum("kni,i->kn", u, np.asarray(axis, float))
    return np.sum(along**2, axis=1) / np.sum(u**2, axis=(1, 2))


def transverse_pairs(freqs, fraction, count, pair_rtol=1e-9):
    """Distinct transverse frequencies of a straight 3-D beam (each appears twice).

    Parameters
    ----------
    freqs : ndarray
        Ascending frequencies (Hz).
    fraction : ndarray
        Axial fraction of each mode (``axial_fraction``).
    count : int
        Number of distinct frequencies wanted.
    pair_rtol : float
        The two planes of bending must agree to this relative tolerance.

    Returns
    -------
    ndarray, shape (count,)

    Raises
    ------
    ValueError
        With fewer than ``2 count`` transverse modes, or when the two planes disagree.
    """
    f = freqs[fraction < 1e-6]
    if len(f) < 2 * count:
        raise ValueError(f"only {len(f)} transverse modes in {freqs}")
    first, second = f[0:2 * count:2], f[1:2 * count:2]
    if not np.all(np.abs(second - first) <= pair_rtol * np.abs(first)):
        raise ValueError(f"bending pairs split: {first} and {second}")
    return first


def beam_modes(n_elements, supports, k=None, section=STEEL, length=1.0, formulation=None):
    """Modes of a straight, stress-free beam along x (in ``formulation``, default the
    library's).

    Parameters
    ----------
    n_elements : int
    supports : {"clamped-free", "pinned-pinned"}
    k : int, optional
        Number of modes; default all of them (dense eigensolver).
    section : Section
    length : float

    Returns
    -------
    freqs : ndarray
        Ascending frequencies (Hz).
    fraction : ndarray
        Axial fraction of each mode.
    """
    cable = Cable.straight([0, 0, 0], [length, 0, 0], n_elements, section,
                           formulation=formulation)
    system = System([cable])
    if supports == "clamped-free":
        system.clamp(cable.node(0))
    elif supports == "pinned-pinned":
        system.pin(cable.node(0)).pin(cable.node(-1))
    else:
        raise ValueError(supports)
    k = system.n_dofs - system.n_constraints if k is None else k
    freqs, shapes = modes(system, k=k)
    return freqs, axial_fraction(system, shapes, [1, 0, 0])


def observed_rates(n_elements, errors):
    """Observed convergence orders of successive meshes.

    Parameters
    ----------
    n_elements : sequence of int
    errors : sequence of float
        Error on each mesh.

    Returns
    -------
    ndarray
        ``log(e_i / e_{i+1}) / log(n_{i+1} / n_i)``.
    """
    n, e = np.asarray(n_elements, float), np.asarray(errors, float)
    return np.log(e[:-1] / e[1:]) / np.log(n[1:] / n[:-1])


def midspan_sag(position_x, position_z, span, height, L0):
    """Vertical distance of the cable below the chord at ``x = span/2``.

    Parameters
    ----------
    position_x, position_z : callable
        ``x`` and ``z`` of the cable at unstretched arc length ``s`` (scalar).
    span, height, L0 : float
        Horizontal span, height of the right support, unstretched length.

    Returns
    -------
    float
    """
    s_mid = brentq(lambda s: position_x(s) - span / 2, 0.0, L0, xtol=1e-13)
    return height / 2 - position_z(s_mid)


#: Catenary cases: span (m), height difference (m), unstretched length (m), section.
#: "steel": 20 mm solid steel rod (strain 5e-5); "rope": a soft rope, 2.7 % strain,
#: shorter than the chord so that it hangs only by stretching (its support forces differ
#: by 1.5 % from the Hooke-law catenary: the test sees the constitutive law).  I is tiny
#: (EI / (H span^2) < 1e-10) so that the "cable" kind is a flexible catenary too.
CATENARIES = {
    "steel": (100.0, 10.0, 103.0, Section(E=2.1e11, A=np.pi * 1e-4, I=1e-14, rho=7850.0)),
    "rope": (100.0, 10.0, 100.0, Section(E=5e8, A=1e-4, I=1e-14, rho=1e4)),
}


def catenary_reference(case, law="green"):
    """Exact support forces and midspan sag of a case of ``CATENARIES``
    (``analytic.solve_catenary``).

    Parameters
    ----------
    case : str
        Key of ``CATENARIES``.
    law : {"green", "hooke"}
        Material law (``analytic.stretch_minus_one``); ``"hooke"`` only for comparison.

    Returns
    -------
    H, VA, VB, sag : float
        Horizontal force, upward support forces (N) and midspan sag (m).
    """
    span, height, L0, sec = CATENARIES[case]
    w = sec.mass_per_length * G
    EA = sec.EA
    H, VA, VB = solve_catenary(span, height, L0, w, EA, law)
    sag = midspan_sag(lambda s: catenary_xz(s, H, VA, w, EA, law)[0, 0],
                      lambda s: catenary_xz(s, H, VA, w, EA, law)[0, 1], span, height, L0)
    return H, VA, VB, sag


def catenary_system(case, n_elements, kind="truss", R=None, formulation=None):
    """FE model of a catenary case in the frame rotated by ``R`` (default: identity).

    The start is stress-free and independent of the answer: the inextensible catenary of
    length ``L0`` (``EA = None``) when ``L0`` exceeds the chord, else the straight chord
    (uniformly stretched, in tension).  Gravity is ``-g`` along the (rotated) z axis.

    Parameters
    ----------
    case : str
        Key of ``CATENARIES``.
    n_elements : int
    kind : {"truss", "cable"}
    R : ndarray (3, 3), optional
        Rotation of the frame.
    formulation : str, optional
        The cable's formulation (default: the library's).

    Returns
    -------
    cable : Cable
    system : System
        Pins at ``R (0, 0, 0)`` and ``R (span, 0, height)``; the pin at the left support is
        ``system.constraints[0]``.
    """
    R = np.eye(3) if R is None else np.asarray(R, dtype=float)
    span, height, L0, sec = CATENARIES[case]
    w = sec.mass_per_length * G
    s = np.linspace(0.0, L0, n_elements + 1)
    chord = np.array([span, height])
    if L0 > np.linalg.norm(chord):
        H, VA, _ = solve_catenary(span, height, L0, w, None)
        xz = catenary_xz(s, H, VA, w, None)
        txz = np.column_stack([H + 0 * s, w * s - VA]) / np.hypot(H, w * s - VA)[:, None]
    else:
        xz = s[:, None] * chord / L0
        txz = np.tile(chord / L0, (len(s), 1))
    zero = np.zeros_like(s)
    positions = np.column_stack([xz[:, 0], zero, xz[:, 1]]) @ R.T
    slopes = np.column_stack([txz[:, 0], zero, txz[:, 1]]) @ R.T
    cable = Cable(MeshLine(s), sec, positions, slopes, law=kind, formulation=formulation)
    system = System([cable])
    system.pin(cable.node(0), R @ [0.0, 0.0, 0.0])
    system.pin(cable.node(-1), R @ [span, 0.0, height])
    system.add_gravity(R @ [0.0, 0.0, -G])
    return cable, system


def catenary_errors(case, n_elements, kind="truss", formulation=None):
    """Relative errors of the FE catenary against ``catenary_reference``.

    Parameters
    ----------
    case : str
        Key of ``CATENARIES``.
    n_elements : int
    kind : {"truss", "cable"}

    Returns
    -------
    dict
        ``H``, ``V`` (both supports; the support force on the cable is ``-lambda``),
        ``out_of_plane`` (the support forces across the plane, relative to ``H``),
        ``sag`` (relative to the sag), ``position`` (max over 201 points, relative to the
        span), ``tension`` (max over 201 points, relative), ``state``, ``system``.
    """
    span, height, L0, sec = CATENARIES[case]
    w = sec.mass_per_length * G
    H, VA, VB, sag = catenary_reference(case)
    cable, system = catenary_system(case, n_elements, kind, formulation=formulation)
    state = solve_static(system, load_steps=2)
    lam_a, lam_b = (state.multipliers[c.name] for c in system.constraints)
    support_a, support_b = -lam_a, -lam_b
    s = np.linspace(0.0, L0, 201)
    exact = catenary_xz(s, H, VA, w, sec.EA)
    got = state.position(cable, s)[:, [0, 2]]
    fe_sag = midspan_sag(lambda t: state.position(cable, t)[0],
                         lambda t: state.position(cable, t)[2], span, height, L0)
    tension = np.hypot(H, w * s - VA)
    return {
        "H": max(abs(support_a[0] + H), abs(support_b[0] - H)) / H,
        "V": max(abs(support_a[2] - VA) / VA, abs(support_b[2] - VB) / VB),
        "out_of_plane": max(abs(support_a[1]), abs(support_b[1])) / H,
        "sag": abs(fe_sag - sag) / sag,
        "position": np.max(np.abs(got - exact)) / span,
        "tension": np.max(np.abs(state.tension(cable, s) / tension - 1.0)),
        "state": state,
        "system": system,
    }
