"""Convergence of the three element types side by side (``Cable(..., element=...)``,
``skfem_cable.elements``): ``"linear"`` (two nodes, positions only, the ``"segment"``
formulation), ``"hermite3"`` (the cubic Hermite, its default ``"assumed-strain"``
formulation) and ``"hermite5"`` (the quintic Hermite, its default ``"assumed-strain"``
formulation; its ``"paper"`` formulation, every term on 9 Gauss points, for comparison in
the elastica, membrane locking and the tether).

1. Elastic catenary: a cable of 12 m hanging under gravity between pins at ``(0, 0, 0)``
   and ``(10, 0, 2)`` m (``EA = 1e4 N``, weight 0.98 N/m, strain 7e-4 at the supports),
   the truss law (no bending) on all three elements, against the exact Green-law catenary
   (``analytic.elastic_catenary``).  Each cable starts from the exact nodal values (the
   positions and, on the Hermite elements, the slopes; ``r_xx`` of the quintic from the
   cubic interpolant), so that Newton only removes the discretisation error: the study is
   about the discretisation, not the continuation from a slack start.  Errors: the largest
   position error over the cable (2001 points and 9 points in every element) relative to
   the span; the root tension ``state.tension(cable, 0)`` and the support force (the
   magnitude of the left pin's multiplier), relative to the exact root tension.  For
   context, the cubic element with its ``"lobatto"`` formulation too.
2. Elastica: a cantilever of 1 m clamped at its root with a transverse dead tip load
   ``P = k EI / L^2``, ``k = 5`` (``classics.ELASTICA_SECTION``, ``EA L^2 / EI = 1e7``),
   the cable law, 10 load steps; cubic and quintic Hermite (the linear element has no
   bending).  The model is extensible, so against the exact inextensible elastica
   (``analytic.elastica_tip_load``) the error stops at about ``k EI / EA`` (7.6e-7): the
   tip error is measured against the converged model (``REFERENCE`` quintic elements,
   checked against 512 cubic ones) and printed against the exact elastica too.  Also the
   largest position error over the cable (against the converged model) and the largest
   tension error ``max |N - P sin(theta)| / P`` over 401 points
   (``analytic.elastica_tip_load_angle``).
3. Membrane locking: the elastica's tip error (against ``REFERENCE`` quintic elements)
   and tension error at ``EA L^2 / EI`` = 1e7, 1e9 and 1e11 for the cubic element
   and the quintic one, each in the assumed strain and the paper's formulation
   (``solve_static`` to ``LOCKING_TOL``); the reference is checked against half its
   elements.
4. The catenary from a straight start: built straight along the chord and solved by
   ``solve_static``'s continuation, on 4, 16 and 64 elements: Newton iterations, time and
   the distance from the solution of section 1 (the same equilibrium, or not).
5. Cost at equal DOFs (about 600, 6000 and 60000): one static force and tangent evaluation
   (``System.evaluate``) and the catenary's solve of section 1, per Newton iteration.
6. Spinning tether frequencies: ``classics.spinning_tether`` (10 m aluminium wire of
   0.5 mm radius, pinned on the spin axis ``z``, a 0.5 kg tip mass, 2 rad/s), truss law on
   all three elements (and the cubic's ``"paper"`` and ``"lobatto"`` formulations for
   context): ``solve_steady`` and ``modes(..., spin=)`` in the rotating frame, as
   ``tests/test_orbit_system.py`` does.  The package has no closed form for these
   frequencies, so the out-of-plane ones (along the spin axis) are compared with a
   reference derived here (``tether_reference``): that displacement is decoupled from the
   in-plane motion (no centrifugal force along the axis, no Coriolis force from a velocity
   along it), and satisfies the Sturm-Liouville problem of a string under the centrifugal
   tension of ``analytic.rotating_string``, solved by shooting.  The first out-of-plane
   mode is the spinning state tilted about the pin, at the spin frequency exactly on every
   mesh (a check); the errors are those of the next three (the string modes ``f1 .. f3``).
7. Flexible pendulum: ``classics.pendulum`` (1.2 m, radius 1 cm, ``E = 7e10 Pa``, pinned,
   released horizontal at rest), the cable law, cubic and quintic Hermite; ``simulate``
   with ``dt = PENDULUM_DT``, ``rho_inf = 0.8``, Newton ``tol = PENDULUM_TOL`` to
   ``t = 1 s``.  The tip error (at 1 s and the largest over the run, saved every 5 ms) is
   measured against 64 quintic elements **at the same step**: the time error of any
   affordable step is larger than the quintic's spatial error (a second table measures
   it, 16 quintic elements at ``dt``, ``dt/2``, ``dt/4`` against ``dt/8``), so only a
   reference at the same step isolates the spatial error and its order.

For each case and element: DOFs (``cable.n_dofs``), the errors, the observed orders
(``log2`` of the ratio between successive meshes; not printed where the finer error is
below 1e-12, round-off, or the pendulum's ``PENDULUM_FLOOR``) and the wall time of the work
(``solve_static``; ``solve_steady`` and ``modes``; ``simulate``: the least over
``--repeats`` runs after an untimed one that loads the compiled kernels).  Then the
smallest mesh of each element that reaches a relative error of 1e-4 and 1e-6, its DOFs
and its wall time side by side.

Run ``OPENBLAS_NUM_THREADS=1 python benchmarks/elements.py [--quick] [--figure PATH]
[--dynamics-figure PATH] [--repeats 3] [--cases ...]`` (``--quick``: fewer meshes and
sizes, one repeat, two slendernesses: about 15 s; the full run takes about 90 s).  One
BLAS thread: on a shared machine OpenBLAS's threads can make the dense eigenproblem of
``modes(..., spin=)`` many times slower (a 150 x 150 one took 500 ms instead of 21 ms
under load on 2 CPUs).  Machines are noisy: read the ratios, not the absolute times.
"""

import argparse
import dataclasses
import time
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq
from skfem import MeshLine

import skfem_cable as sc
from skfem_cable.analysis.analytic import (
    elastic_catenary,
    elastica_tip_load,
    elastica_tip_load_angle,
    rotating_string,
    string_frequency,
)
from skfem_cable.bodies.catenary import green_stretch
from skfem_cable.cli.validation import observed_rates
from skfem_cable.scenes import classics
from skfem_cable.scenes.classics import ELASTICA_SECTION

#: Gravity (m/s^2).
G = 9.81
#: The catenary: span, height of the right pin, unstretched length (m), section (truss
#: law: ``I`` is not used).  ``EA = 1e4 N``, ``w = 0.981 N/m``.
SPAN, HEIGHT, LENGTH = 10.0, 2.0, 12.0
CATENARY_SECTION = sc.Section(E=1e8, A=1e-4, I=1e-12, rho=1e3)
#: Load parameter ``k = P L^2 / EI`` of the elastica.
K = 5.0
#: Quintic elements of the converged elastica (its discretisation error is below 1e-14).
REFERENCE = 64
#: Errors below this are round-off: no observed order is printed from them.
ROUNDOFF = 1e-12
#: ``solve_static``'s tolerance in the locking study: with the default 1e-10 the recovered
#: tension of the cubic element at ``EA L^2 / EI = 1e11`` stops at 0.85 P (8 elements),
#: the Newton iteration's, not the discretisation's.
LOCKING_TOL = 1e-12
TARGETS = (1e-4, 1e-6)
#: The spinning tether (``classics.spinning_tether``, its section and length): tip mass
#: (kg) and spin about z (rad/s); string modes compared after the tilt mode.
TETHER_TIP_MASS, TETHER_SPIN, TETHER_MODES = 0.5, 2.0, 3
#: The pendulum (``classics.pendulum``): step (s), end time (s), ``rho_inf``, saving
#: interval (s) and Newton tolerance of ``simulate`` (default 1e-11).  With ``tol = 1e-10``
#: (``benchmarks/pendulum_speed_error.py``) the Newton iterations leave differences of 1 to
#: 2e-8 m at 1 s between 16, 32 and 48 quintic elements, above the quintic's spatial
#: error; with 1e-12, 5 to 7e-11 m (measured separately).
PENDULUM_DT, PENDULUM_T_END, PENDULUM_RHO_INF = 2.5e-4, 1.0, 0.8
PENDULUM_SAVE, PENDULUM_TOL = 5e-3, 1e-13
#: Relative tip errors of the pendulum below this are the floor of the time integration
#: (meshes of 16 to 64 quintic elements differ by about 2e-11 m): no order from them.
PENDULUM_FLOOR = 1e-10

#: The variants compared: label -> (element, formulation); None: the element's default.
VARIANTS = {
    "linear": ("linear", None),
    "hermite3": ("hermite3", None),
    "hermite5": ("hermite5", None),
    "hermite3 (lobatto)": ("hermite3", "lobatto"),
    "hermite3 (paper)": ("hermite3", "paper"),
    "hermite5 (paper)": ("hermite5", "paper"),
}
#: Meshes (elements) of each case and variant, full and ``--quick``.
MESHES = {
    "full": {
        "catenary": {"linear": (2, 4, 8, 16, 32, 64, 128, 256),
                     "hermite3": (2, 4, 8, 16, 32, 64),
                     "hermite5": (2, 4, 8, 16, 32, 64),
                     "hermite3 (lobatto)": (2, 4, 8, 16, 32, 64)},
        "elastica": {"hermite3": (2, 4, 8, 16, 32, 64),
                     "hermite5": (2, 4, 8, 16, 32), "hermite5 (paper)": (2, 4, 8, 16, 32)},
        "locking": ((1e7, 1e9, 1e11), (4, 8, 16)),
        "cost": (600, 6000, 60000),
        "straight": (4, 16, 64),
        "tether": {"linear": (4, 8, 16, 32, 64, 128), "hermite3": (2, 4, 8, 16, 32),
                   "hermite5": (1, 2, 4, 8), "hermite5 (paper)": (1, 2, 4, 8),
                   "hermite3 (paper)": (2, 4, 8, 16, 32),
                   "hermite3 (lobatto)": (2, 4, 8, 16, 32)},
        "pendulum": {"hermite3": (2, 4, 8, 16, 32), "hermite5": (2, 4, 8, 16)},
        # reference (quintic elements) at PENDULUM_DT; time-error mesh and step divisions
        "pendulum_reference": 64,
        "pendulum_time": (16, (1, 2, 4, 8)),
    },
    "quick": {
        "catenary": {"linear": (4, 8, 16, 32), "hermite3": (2, 4, 8),
                     "hermite5": (2, 4, 8), "hermite3 (lobatto)": (2, 4, 8)},
        "elastica": {"hermite3": (2, 4, 8), "hermite5": (2, 4, 8)},
        "locking": ((1e7, 1e9), (4, 8)),
        "cost": (600, 6000),
        "straight": (4, 16),
        "tether": {"linear": (4, 8, 16), "hermite3": (2, 4, 8), "hermite5": (1, 2, 4)},
        "pendulum": {"hermite3": (2, 4, 8), "hermite5": (2, 4)},
        "pendulum_reference": 16,
        "pendulum_time": (8, (1, 2, 4)),
    },
}
#: The cases of ``--cases`` (all by default).
CASES = ("catenary", "elastica", "locking", "straight", "cost", "tether", "pendulum")
#: Variants of the figure and of the target table (the three elements).
ELEMENTS = ("linear", "hermite3", "hermite5")
STYLES = {"linear": {"color": "C2", "marker": "s"}, "hermite3": {"color": "C0", "marker": "o"},
          "hermite5": {"color": "C3", "marker": "^"},
          "hermite3 (paper)": {"color": "C0", "marker": "o", "ls": "--", "mfc": "none"},
          "hermite5 (paper)": {"color": "C3", "marker": "^", "ls": "--", "mfc": "none"}}


def timed_solve(system, repeats, **kwargs):
    """``sc.solve_static(system, **kwargs)`` once untimed (compiled kernels loaded, the
    state returned), then ``repeats`` times timed from the same start.

    Returns
    -------
    state : State
    wall : float
        The least wall time of the timed solves (s); NaN without repeats.
    """
    state = sc.solve_static(system, **kwargs)
    walls = []
    for _ in range(repeats):
        start = time.perf_counter()
        sc.solve_static(system, **kwargs)
        walls.append(time.perf_counter() - start)
    return state, min(walls, default=float("nan"))


def samples(cable, points=2001, per_element=9):
    """Arc lengths where positions are compared: ``points`` over the cable and
    ``per_element`` inside every element (sorted)."""
    x = cable.mesh.p[0]
    inside = (x[:-1, None] + np.outer(np.diff(x), (np.arange(per_element) + 0.5)
                                      / per_element)).ravel()
    return np.unique(np.concatenate([np.linspace(0.0, cable.length, points), inside]))


# --------------------------------------------------------------------------------------
# 1. the elastic catenary
# --------------------------------------------------------------------------------------
def catenary_exact(s):
    """Exact positions ``(len(s), 3)`` (in the x-z plane), tension and slopes ``r_x`` of
    the catenary at the unstretched arc lengths ``s``."""
    sec = CATENARY_SECTION
    w = sec.mass_per_length * G
    xz, T, H, VA = elastic_catenary(s, SPAN, HEIGHT, LENGTH, w, sec.EA)
    stretch = 1.0 + green_stretch(T, sec.EA)
    t = np.column_stack([H + 0 * s, w * s - VA]) * (stretch / T)[:, None]
    zero = np.zeros_like(s)
    return (np.column_stack([xz[:, 0], zero, xz[:, 1]]), T,
            np.column_stack([t[:, 0], zero, t[:, 1]]))


def catenary_system(n, element, formulation=None):
    """The catenary of ``n`` elements started from the exact nodal values; returns the
    cable and the system (pins at both ends, gravity along -z)."""
    s = np.linspace(0.0, LENGTH, n + 1)
    positions, _, slopes = catenary_exact(s)
    cable = sc.Cable(MeshLine(s), CATENARY_SECTION, positions, slopes, law="truss",
                     element=element, formulation=formulation)
    system = sc.System([cable]).pin(cable.node(0))
    system.pin(cable.node(-1), [SPAN, 0.0, HEIGHT]).add_gravity([0.0, 0.0, -G])
    return cable, system


def catenary_row(n, variant, repeats):
    """Errors, DOFs, Newton iterations and solve time of one catenary."""
    cable, system = catenary_system(n, *VARIANTS[variant])
    state, wall = timed_solve(system, repeats)
    s = samples(cable)
    positions, T, _ = catenary_exact(s)
    reaction = np.linalg.norm(state.multipliers[system.constraints[0].name])
    return {"n": n, "dofs": cable.n_dofs,
            "position": np.abs(state.position(cable, s) - positions).max() / SPAN,
            "tension": abs(float(state.tension(cable, 0.0)) / T[0] - 1.0),
            "reaction": abs(reaction / T[0] - 1.0),
            "iterations": int(sum(state.stats["iterations"])), "wall_s": wall}


# --------------------------------------------------------------------------------------
# 2. the elastica
# --------------------------------------------------------------------------------------
def elastica_system(n, element, formulation=None, section=ELASTICA_SECTION, k=K):
    """The cantilever of ``n`` elements with its dead tip load ``k EI / L^2`` along -y."""
    cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], n, section, element=element,
                              formulation=formulation)
    system = sc.System([cable]).clamp(cable.node(0))
    system.add_point_load(cable.node(-1), [0.0, -k * section.EI, 0.0])
    return cable, system


def elastica_solve(n, element, formulation=None, section=ELASTICA_SECTION, k=K, repeats=0,
                   tol=1e-10):
    """Solved cantilever: ``(cable, state, wall)`` (10 load steps, as the validation;
    ``tol`` of ``solve_static``)."""
    cable, system = elastica_system(n, element, formulation, section, k)
    state, wall = timed_solve(system, repeats, load_steps=max(10, int(2 * k)), tol=tol)
    return cable, state, wall


def tip(cable, state):
    """Tip shortening and deflection ``(u, w)`` (the length is 1 m)."""
    r = state.position(cable, cable.length)
    return np.array([1.0 - r[0], -r[1]])


class Converged:
    """The converged extensible elastica at one slenderness: ``REFERENCE`` quintic
    elements; its tip, its positions at ``s`` and the exact axial force ``P sin(theta)``
    (relative to ``P``) at 401 points."""

    def __init__(self, section=ELASTICA_SECTION, k=K, tol=1e-10):
        self.section, self.k = section, k
        self.cable, self.state, _ = elastica_solve(REFERENCE, "hermite5", None, section, k,
                                                   tol=tol)
        self.tip = tip(self.cable, self.state)
        self.s_tension = np.linspace(0.0, 1.0, 401)
        self.axial = np.sin(elastica_tip_load_angle(k, self.s_tension))

    def errors(self, cable, state):
        """Tip error, largest position error over the cable and largest tension error
        ``max |N - P sin(theta)| / P``."""
        s = samples(cable)
        P = self.k * self.section.EI
        return {"tip": np.abs(tip(cable, state) - self.tip).max(),
                "position": np.abs(state.position(cable, s)
                                   - self.state.position(self.cable, s)).max(),
                "tension": np.abs(state.tension(cable, self.s_tension) / P
                                  - self.axial).max()}


def elastica_rows(meshes, repeats):
    """Rows of the elastica (``k = K``) for each variant, and the reference checks."""
    converged = Converged()
    exact = np.array(elastica_tip_load(K))
    rows = {}
    for variant, ns in meshes.items():
        rows[variant] = []
        for n in ns:
            cable, state, wall = elastica_solve(n, VARIANTS[variant][0], VARIANTS[variant][1],
                                                repeats=repeats)
            rows[variant].append({"n": n, "dofs": cable.n_dofs, **converged.errors(cable, state),
                                  "tip_exact": np.abs(tip(cable, state) - exact).max(),
                                  "iterations": int(sum(state.stats["iterations"])),
                                  "wall_s": wall})
    cubic = tip(*elastica_solve(512, "hermite3")[:2])
    checks = {"floor": np.abs(converged.tip - exact).max(),
              "cubic_512": np.abs(cubic - converged.tip).max()}
    return rows, checks


# --------------------------------------------------------------------------------------
# 3. membrane locking
# --------------------------------------------------------------------------------------
def locking_rows(slendernesses, ns, variants=("hermite3", "hermite3 (paper)", "hermite5",
                                              "hermite5 (paper)")):
    """Tip and tension errors of the elastica at ``EA L^2 / EI`` in ``slendernesses`` (the
    area of ``ELASTICA_SECTION`` scaled): ``{(slenderness, variant): [errors per n]}``,
    and ``{slenderness: |tip(REFERENCE) - tip(REFERENCE / 2)|}`` (quintic) under
    ``"reference"``."""
    base = ELASTICA_SECTION
    out = {"reference": {}}
    for ratio in slendernesses:
        section = dataclasses.replace(base, A=base.I * ratio)
        converged = Converged(section, tol=LOCKING_TOL)
        coarser = tip(*elastica_solve(REFERENCE // 2, "hermite5", None, section,
                                      tol=LOCKING_TOL)[:2])
        out["reference"][ratio] = np.abs(coarser - converged.tip).max()
        for variant in variants:
            out[ratio, variant] = [
                converged.errors(*elastica_solve(n, *VARIANTS[variant], section,
                                                 tol=LOCKING_TOL)[:2]) for n in ns]
    return out


def straight_start_rows(ns, repeats):
    """The catenary built straight along the chord (12 m, stress-free) and solved by
    ``solve_static``'s continuation from that state (``initial=``: by default the solver
    starts it hanging, ``hanging_start``; the far pin is closed onto its support): Newton
    iterations, solve time and the largest distance of its positions from the solution
    started from the exact nodal values (``catenary_system``)."""
    out = []
    direction = np.array([SPAN, 0.0, HEIGHT]) / np.hypot(SPAN, HEIGHT)
    for variant in ELEMENTS:
        for n in ns:
            cable = sc.Cable.straight([0, 0, 0], LENGTH * direction, n, CATENARY_SECTION,
                                      law="truss", element=variant)
            system = sc.System([cable]).pin(cable.node(0))
            system.pin(cable.node(-1), [SPAN, 0.0, HEIGHT]).add_gravity([0.0, 0.0, -G])
            try:
                state, wall = timed_solve(system, repeats, initial=sc.State(system, system.q0))
            except sc.StaticConvergenceError as error:
                out.append({"element": variant, "n": n, "failed": str(error)[:80]})
                continue
            exact_cable, exact_system = catenary_system(n, variant)
            s = samples(cable)
            other = sc.solve_static(exact_system).position(exact_cable, s)
            out.append({"element": variant, "n": n, "iterations":
                        int(sum(state.stats["iterations"])), "wall_s": wall,
                        "difference": np.abs(state.position(cable, s) - other).max() / SPAN})
    return out


def print_straight(rows):
    print("\n### The catenary from a straight start\n")
    print("Built straight along the chord, the far pin closed by `solve_static`'s "
          "continuation; 'difference': largest position difference from the solution "
          "started from the exact nodal values, relative to the span.\n")
    print(_row(["element", "n", "Newton its", "solve [ms]", "difference"]))
    print("|---|---:|---:|---:|---:|")
    for r in rows:
        if "failed" in r:
            print(_row([r["element"], str(r["n"]), "fails", r["failed"], ""]))
        else:
            print(_row([r["element"], str(r["n"]), str(r["iterations"]),
                        f"{1e3 * r['wall_s']:.1f}", f"{r['difference']:.1e}"]))


# --------------------------------------------------------------------------------------
# 4. cost at equal DOFs
# --------------------------------------------------------------------------------------
def evaluation_ms(system, q, seconds, repeats):
    """ms per static force + tangent evaluation ``system.evaluate`` at ``q``: one untimed
    call, then the mean over calls filling ``seconds``, the least over ``repeats``."""
    data, lam = np.zeros(system.layout.nnz), np.zeros(system.n_constraints)

    def evaluate():
        data[:] = 0.0
        return system.evaluate(q, None, 0.0, lam, cK=1.0, data=data, layout=system.layout)

    evaluate()
    start = time.perf_counter()
    evaluate()
    calls = max(3, int(seconds / max(time.perf_counter() - start, 1e-9)))
    best = float("inf")
    for _ in range(max(repeats, 1)):
        start = time.perf_counter()
        for _ in range(calls):
            evaluate()
        best = min(best, (time.perf_counter() - start) / calls)
    return 1e3 * best


def cost_rows(sizes, repeats, seconds=0.2):
    """The catenary of each element at about ``sizes`` DOFs: one force + tangent
    evaluation at the start (``evaluation_ms``) and the static solve from the exact nodal
    values (``timed_solve``), per Newton iteration too."""
    out = []
    for dofs in sizes:
        for variant in ELEMENTS:
            per_node = 3 * len(sc.elements.ELEMENTS[variant].orders)
            n = max(1, round(dofs / per_node) - 1)
            cable, system = catenary_system(n, variant)
            state, wall = timed_solve(system, repeats)
            its = int(sum(state.stats["iterations"]))
            out.append({"target_dofs": dofs, "element": variant, "n": n,
                        "dofs": cable.n_dofs,
                        "evaluate_ms": evaluation_ms(system, system.q0, seconds, repeats),
                        "solve_ms": 1e3 * wall, "iterations": its,
                        "ms_per_iteration": 1e3 * wall / max(its, 1)})
    return out


def print_costs(rows):
    print("\n### Cost at equal DOFs: the catenary\n")
    print("One static force + tangent evaluation (`System.evaluate`) at the start, and the "
          "solve from the exact nodal values.\n")
    print(_row(["DOFs", "element", "n", "evaluation [ms]", "solve [ms]", "Newton its",
                "solve per iteration [ms]"]))
    print("|---:|---|---:|---:|---:|---:|---:|")
    for r in rows:
        print(_row([str(r["dofs"]), r["element"], str(r["n"]), f"{r['evaluate_ms']:.3f}",
                    f"{r['solve_ms']:.2f}", str(r["iterations"]),
                    f"{r['ms_per_iteration']:.2f}"]))


# --------------------------------------------------------------------------------------
# 6. frequencies of the spinning tether
# --------------------------------------------------------------------------------------
def least_wall(run, repeats):
    """``run()`` once untimed (compiled kernels loaded), then ``repeats`` times; ``run``
    returns ``(value, wall)``.  Returns the untimed run's value and the least wall time of
    the timed runs (NaN without repeats)."""
    value, _ = run()
    walls = [run()[1] for _ in range(repeats)]
    return value, min(walls, default=float("nan"))


def tether_system(n, element, formulation=None, law="truss"):
    """``classics.spinning_tether`` (its section and length) rebuilt with ``n`` elements of
    ``element`` and ``law`` (the scene has no ``element=``): pinned at the origin on the
    spin axis z, the tip mass ``TETHER_TIP_MASS``; returns the cable and the system."""
    base = classics.spinning_tether(n_elements=1, tip_mass=TETHER_TIP_MASS,
                                    spin=TETHER_SPIN, kind=law).cable
    cable = sc.Cable.straight([0, 0, 0], [base.length, 0, 0], n, base.section, law=law,
                              element=element, formulation=formulation)
    system = sc.System([cable]).pin(cable.node(0))
    return cable, system.add_point_mass(cable.node(-1), TETHER_TIP_MASS)


def tether_reference(count=TETHER_MODES + 1, rtol=1e-13):
    """The lowest ``count`` out-of-plane frequencies (Hz) of the spinning tether, in the
    rotating frame: the extensible string (Green law, no bending) with its tip mass.

    The steady state has the radius ``r(s)`` and the tension ``T(s)`` of
    ``analytic.rotating_string`` (``r' = lambda(T)``, ``T' = -mu Omega^2 r``, ``s`` the
    unstretched arc length, ``mu`` the mass per unstretched length).  A small displacement
    ``w(s)`` along the spin axis turns the tension, ``T t``, by ``w' / lambda``: the force
    across a section gains ``p = T w' / lambda`` along the axis; the centrifugal force has
    no component along the axis and the Coriolis force of a velocity along it vanishes, so
    ``w`` is decoupled from the in-plane motion and, at the frequency ``omega``,

        p' = -mu omega^2 w,   w' = lambda p / T,   w(0) = 0,   p(L) = m omega^2 w(L)

    (the pin at the root, the tip mass ``m``).  The lowest root is ``omega = Omega``
    exactly (``w = r``: the spinning state tilted about the pin).  Solved by shooting from
    ``s = 0`` with ``w = 0, p = 1``: ``(r, T, w, p)`` integrated by ``solve_ivp`` (DOP853,
    relative tolerance ``rtol``; 1e-11 instead moves the roots by 1e-12), the tip mismatch
    ``p(L) - m omega^2 w(L)`` scanned in steps of a quarter of the string's spacing
    ``(pi / L) sqrt(T(L) / mu)`` and its sign changes refined by ``brentq``.
    """
    base = classics.spinning_tether(n_elements=1, kind="truss").cable
    L, EA, mu = base.length, base.section.EA, base.section.mass_per_length
    m, spin = TETHER_TIP_MASS, TETHER_SPIN
    T0 = float(rotating_string([0.0], L, EA, mu, m, spin)[1][0])

    def stretch(T):  # lambda^3 - lambda = 2 T / EA (the Green law), Newton from 1 + T/EA
        lam = 1.0 + T / EA
        for _ in range(3):
            lam -= (lam**3 - lam - 2 * T / EA) / (3 * lam * lam - 1)
        return lam

    def mismatch(omega):
        def rhs(_, y):
            lam = stretch(y[1])
            return [lam, -mu * spin**2 * y[0], lam * y[3] / y[1], -mu * omega**2 * y[2]]

        y = solve_ivp(rhs, (0.0, L), [0.0, T0, 0.0, 1.0], method="DOP853", rtol=rtol,
                      atol=1e-16).y[:, -1]
        return y[3] - m * omega**2 * y[2]

    step = 0.25 * np.pi / L * np.sqrt(m * spin**2 * L / mu)
    roots, a = [], 0.5 * spin
    fa = mismatch(a)
    while len(roots) < count:
        b = a + step
        fb = mismatch(b)
        if fa * fb < 0:
            roots.append(brentq(mismatch, a, b, xtol=1e-14, rtol=1e-15))
        a, fa = b, fb
    return np.array(roots) / (2 * np.pi)


def tether_frequencies(n, element, formulation=None, law="truss"):
    """Steady spin (``solve_steady``) and modes in the rotating frame (``add_centrifugal``,
    ``modes(..., spin=)``) of the tether of ``n`` elements: ``((cable, state, out-of-plane
    frequencies in Hz, all frequencies), wall)``, the wall time of the two calls.  A mode
    is out of plane when most of its shape (squared moduli) lies along the axis."""
    cable, system = tether_system(n, element, formulation, law)
    spin = [0.0, 0.0, TETHER_SPIN]
    start = time.perf_counter()
    state = sc.solve_steady(system, spin)
    system.add_centrifugal(spin)
    freqs, shapes = sc.modes(system, state, k=min(12, system.n_dofs - system.n_constraints),
                             spin=spin)
    wall = time.perf_counter() - start
    along = np.array([np.sum(np.abs(v[2::3]) ** 2) / np.sum(np.abs(v) ** 2) for v in shapes])
    return (cable, state, freqs[along > 0.5], freqs), wall


def tether_rows(meshes, repeats):
    """Rows of the spinning tether for each variant: relative errors of the string modes
    ``f1 .. f3`` (``f1``, ``f2``, ``f3`` and their largest, ``frequency``) and of the tilt
    mode (``tilt``, against the spin frequency); the reference frequencies; and the
    bending check: ``f1`` of 16 cubic elements with the cable law (``EI``) against the
    string reference, and the first-order bending correction of a tensioned string
    ``EI (pi / L)^2 / (2 T)`` (``analytic.string_frequency``) at the mean tension."""
    reference = tether_reference()
    rows = {}
    for variant, ns in meshes.items():
        rows[variant] = []
        for n in ns:
            (cable, state, f, _), wall = least_wall(
                lambda n=n, v=variant: tether_frequencies(n, *VARIANTS[v]), repeats)
            e = np.abs(f[:TETHER_MODES + 1] / reference[:len(f)] - 1.0)
            e = np.concatenate([e, np.full(TETHER_MODES + 1 - len(e), np.nan)])
            rows[variant].append({"n": n, "dofs": cable.n_dofs, "tilt": e[0],
                                  **{f"f{i}": e[i] for i in range(1, TETHER_MODES + 1)},
                                  "frequency": e[1:].max(),
                                  "iterations": int(sum(state.stats["iterations"])),
                                  "wall_s": wall})
    (cable, _, f, _), _ = tether_frequencies(16, "hermite3", law="cable")
    sec = cable.section
    _, T = rotating_string(np.linspace(0.0, cable.length, 1001), cable.length, sec.EA,
                           sec.mass_per_length, TETHER_TIP_MASS, TETHER_SPIN)
    taut = [string_frequency(cable.length, T.mean(), sec.mass_per_length, EI)
            for EI in (0.0, sec.EI)]
    bending = {"EI": sec.EI, "cable_f1": f[1] / reference[1] - 1.0,
               "correction": taut[1] / taut[0] - 1.0}
    return rows, reference, bending


# --------------------------------------------------------------------------------------
# 7. the flexible pendulum
# --------------------------------------------------------------------------------------
def pendulum_system(n, element, formulation=None):
    """``classics.pendulum`` (its section and length, the cable law, pinned at the origin,
    horizontal along +x, gravity along -y) rebuilt with ``n`` elements of ``element`` (the
    scene has no ``element=``); returns the cable and the system."""
    base = classics.pendulum(n_elements=1).cable
    cable = sc.Cable.straight([0, 0, 0], [base.length, 0, 0], n, base.section, law="cable",
                              element=element, formulation=formulation)
    return cable, sc.System([cable]).pin(cable.node(0)).add_gravity([0.0, -G, 0.0])


def pendulum_run(n, element, dt=PENDULUM_DT):
    """The pendulum of ``n`` elements released at rest, ``simulate`` to
    ``PENDULUM_T_END``: ``((times, tip positions (nt, 3), Newton iterations, length),
    wall)``, the wall time of the ``simulate`` call; saved every ``PENDULUM_SAVE``."""
    cable, system = pendulum_system(n, element)
    every = int(round(PENDULUM_SAVE / dt))
    start = time.perf_counter()
    result = sc.simulate(system, t_end=PENDULUM_T_END, dt=dt, rho_inf=PENDULUM_RHO_INF,
                         every=every, tol=PENDULUM_TOL)
    wall = time.perf_counter() - start
    return (result.t, result.position(cable, cable.length), int(result.stats["newton"]),
            cable.length), wall


def _tip_errors(run, reference):
    """Tip errors of ``run`` against ``reference`` (two ``pendulum_run`` values on the
    same saved times), relative to the length: at the end and the largest."""
    t, tips, _, length = run
    if not np.allclose(t, reference[0], rtol=0, atol=1e-9):
        raise RuntimeError("pendulum runs saved at different times")
    e = np.linalg.norm(tips - reference[1], axis=1) / length
    return {"tip_end": float(e[-1]), "tip_max": float(e.max())}


def pendulum_rows(meshes, reference_n, time_check, repeats):
    """Rows of the pendulum for each element at ``PENDULUM_DT`` against ``reference_n``
    quintic elements at the same step; and the time error: ``time_check = (n, divisions)``,
    the quintic of ``n`` elements at ``PENDULUM_DT / d`` for each ``d`` against the last."""
    reference, reference_wall = pendulum_run(reference_n, "hermite5")
    rows = {}
    for variant, ns in meshes.items():
        rows[variant] = []
        for n in ns:
            run, wall = least_wall(lambda n=n, v=variant: pendulum_run(n, v), repeats)
            cable, _ = pendulum_system(n, variant)
            rows[variant].append({"n": n, "dofs": cable.n_dofs,
                                  **_tip_errors(run, reference), "iterations": run[2],
                                  "wall_s": wall})
    n, divisions = time_check
    runs = {d: pendulum_run(n, "hermite5", PENDULUM_DT / d) for d in divisions}
    finest = runs[divisions[-1]][0]
    steps = [{"dt": PENDULUM_DT / d, "n": n, **_tip_errors(runs[d][0], finest),
              "iterations": runs[d][0][2], "wall_s": runs[d][1]} for d in divisions[:-1]]
    return rows, {"reference_wall_s": reference_wall, "reference_tip": reference[1][-1],
                  "steps": steps, "finest_dt": PENDULUM_DT / divisions[-1]}


def print_pendulum_steps(check):
    print(f"\nTime error of the step: {check['steps'][0]['n']} quintic elements against "
          f"dt = {check['finest_dt']:.4g} s (single runs, wall time of simulate).\n")
    print(_row(["dt [s]", "tip at 1 s / L", "largest tip / L", "Newton its",
                "simulate [ms]"]))
    print("|---:|---:|---:|---:|---:|")
    for r in check["steps"]:
        print(_row([f"{r['dt']:.4g}", f"{r['tip_end']:.2e}", f"{r['tip_max']:.2e}",
                    str(r["iterations"]), f"{1e3 * r['wall_s']:.0f}"]))


# --------------------------------------------------------------------------------------
# tables, targets, figure
# --------------------------------------------------------------------------------------
def _row(cells):
    return "| " + " | ".join(cells) + " |"


def orders(rows, key, floor=ROUNDOFF):
    """Observed orders between successive meshes of ``rows`` for ``rows[i][key]`` (NaN
    where the finer error is below ``floor``)."""
    ns = [r["n"] for r in rows]
    e = np.array([r[key] for r in rows], float)
    rates = observed_rates(ns, np.maximum(e, 1e-300)) if len(rows) > 1 else np.zeros(0)
    return [float("nan")] + [o if e[i + 1] > floor else float("nan")
                             for i, o in enumerate(rates)]


def _ms(seconds):
    """Milliseconds to three significant digits (whole ones from 1000 ms)."""
    ms = 1e3 * seconds
    return f"{ms:.0f}" if ms >= 100 else f"{ms:#.3g}"


def _order(value):
    return "—" if not np.isfinite(value) else f"{value:.2f}"


def print_case(title, rows, keys, labels, wall="solve [ms]", floor=ROUNDOFF):
    """One markdown table of a case: a row per variant and mesh, each error with its
    observed order (none below ``floor``), the Newton iterations and the wall time."""
    print(f"\n### {title}\n")
    heads = ["element", "n", "DOFs"]
    for label in labels:
        heads += [label, "order"]
    heads += ["Newton its", wall]
    print(_row(heads))
    print("|---|---:|---:|" + "---:|" * (2 * len(keys) + 2))
    for variant, vrows in rows.items():
        rates = {key: orders(vrows, key, floor) for key in keys}
        for i, r in enumerate(vrows):
            cells = [variant, str(r["n"]), str(r["dofs"])]
            for key in keys:
                cells += [f"{r[key]:.2e}", _order(rates[key][i])]
            cells += [str(r["iterations"]), f"{1e3 * r['wall_s']:.2f}"]
            print(_row(cells))


def first_reaching(rows, key, target):
    """The first row of ``rows`` whose ``key`` error is at most ``target`` (None if
    none), and the DOFs and the wall time interpolated log-log between it and the
    previous row (at the same fraction of the log-error step)."""
    for i, r in enumerate(rows):
        if r[key] <= target:
            if i == 0:
                return r, float(r["dofs"]), float(r["wall_s"])
            a = rows[i - 1]
            t = np.log(a[key] / target) / np.log(a[key] / r[key])
            return r, *(float(np.exp(np.log(a[x]) + t * np.log(r[x] / a[x])))
                        for x in ("dofs", "wall_s"))
    return None, float("nan"), float("nan")


#: Quantities of the target table: label, case (key of ``target_rows``' cases), error.
TARGET_QUANTITIES = (
    ("catenary: positions", "catenary", "position"),
    ("catenary: root tension (Cable.tension)", "catenary", "tension"),
    ("catenary: support force (pin multiplier)", "catenary", "reaction"),
    ("elastica: tip", "elastica", "tip"),
    ("tether: f1 .. f3 (largest)", "tether", "frequency"),
    ("pendulum: tip, spatial (largest over t)", "pendulum", "tip_max"),
)
#: What the wall time of each case measures.
WALLS = {"catenary": "solve_static", "elastica": "solve_static",
         "tether": "solve_steady + modes", "pendulum": "simulate"}


def target_rows(cases):
    """For each quantity, target and element: the smallest mesh of the tables that
    reaches the target (``n``, DOFs, wall time) and the interpolated DOFs and wall time;
    ``cases``: ``{case: rows}`` of the cases run."""
    out = []
    for label, case, key in TARGET_QUANTITIES:
        if case not in cases:
            continue
        rows = cases[case]
        for target in TARGETS:
            for variant in ELEMENTS:
                if variant not in rows:
                    continue
                r, dofs, wall = first_reaching(rows[variant], key, target)
                out.append({"quantity": label, "target": target, "element": variant,
                            "n": None if r is None else r["n"],
                            "dofs": None if r is None else r["dofs"],
                            "wall_s": None if r is None else r["wall_s"],
                            "dofs_interpolated": dofs, "wall_interpolated_s": wall,
                            "work": WALLS[case]})
    return out


def print_targets(rows):
    print("\n### Which element reaches a target error for less work\n")
    print("The first mesh of the tables above that reaches the relative error, its DOFs "
          "and the wall time of its work (solve_static; solve_steady + modes; simulate); "
          "'(interp.)': interpolated log-log between it and the mesh before; "
          "'—': not reached on the meshes of the table.\n")
    print(_row(["quantity", "target", "element", "n", "DOFs", "DOFs (interp.)",
                "wall [ms]", "wall (interp.) [ms]"]))
    print("|---|---:|---|---:|---:|---:|---:|---:|")
    for r in rows:
        if r["n"] is None:
            cells = ["—"] * 5
        else:
            cells = [str(r["n"]), str(r["dofs"]), f"{r['dofs_interpolated']:.0f}",
                     _ms(r["wall_s"]), _ms(r["wall_interpolated_s"])]
        print(_row([r["quantity"], f"{r['target']:.0e}", r["element"], *cells]))


def print_locking(rows, ns):
    print("\n### Membrane locking: the elastica (k = 5) at three slendernesses\n")
    print(f"Tip error (against {REFERENCE} quintic elements) / tension error "
          "max |N - P sin(theta)| / P.\n")
    heads = ["EA L^2/EI", "element", *(f"n = {n}" for n in ns)]
    print(_row(heads))
    print("|---:|---|" + "---:|" * len(ns))
    for key, errors in rows.items():
        if key == "reference":
            continue
        ratio, variant = key
        print(_row([f"{ratio:.0e}", variant,
                    *(f"{e['tip']:.1e} / {e['tension']:.1e}" for e in errors)]))
    print(f"\nReference check, |tip({REFERENCE}) - tip({REFERENCE // 2})| of the quintic "
          "element: "
          + ", ".join(f"{r:.0e}: {v:.1e}" for r, v in rows["reference"].items()) + ".")


def figure(path, catenary, elastica):
    """Errors against DOFs, log-log: (a) the catenary (positions, root tension, support
    force), (b) the elastica (tip, tension)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.ticker import NullFormatter

    fig, axes = plt.subplots(1, 2, figsize=(12, 5))
    panels = ((axes[0], catenary, (("position", "-", "positions"),
                                   ("tension", "--", "root tension"),
                                   ("reaction", ":", "support force"))),
              (axes[1], elastica, (("tip", "-", "tip"), ("tension", "--", "tension"))))
    for ax, rows, keys in panels:
        for variant in ELEMENTS:
            if variant not in rows:
                continue
            dofs = [r["dofs"] for r in rows[variant]]
            for key, line, label in keys:
                e = np.maximum([r[key] for r in rows[variant]], 1e-16)
                ax.loglog(dofs, e, line, **STYLES[variant], mfc=None if line == "-"
                          else "none", ms=4 if line == ":" else 6, label=f"{variant}: {label}")
        ax.set_xlabel("degrees of freedom (cable.n_dofs)")
        ax.set_ylabel("relative error")
        ax.xaxis.set_minor_formatter(NullFormatter())
        ticks = [x for x in (10, 20, 50, 100, 200, 500, 1000)
                 if ax.get_xlim()[0] <= x <= ax.get_xlim()[1]]
        ax.set_xticks(ticks, [str(x) for x in ticks])
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=8, ncol=2 if ax is axes[0] else 1, loc="lower left")
    axes[0].set_title("(a) elastic catenary, truss law: max position error / span;\n"
                      "root tension (Cable.tension) and support force (pin) / exact",
                      fontsize=10)
    axes[1].set_title(f"(b) elastica, $k = {K:g}$, $EA L^2/EI = 10^7$: tip error / $L$ (to "
                      "the\nconverged model); max $|N - P \\sin\\theta| / P$", fontsize=10)
    fig.tight_layout()
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=120)
    plt.close(fig)


def dynamics_figure(path, tether, pendulum, time_error=None):
    """Errors against DOFs (left) and against wall time (right), log-log: (top) the
    spinning tether's string frequencies, (bottom) the pendulum's tip (spatial), with
    the time error of its step (``time_error``, relative) as a horizontal line."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.ticker import FuncFormatter, LogLocator

    plain = FuncFormatter(lambda x, _: f"{x:g}")
    fig, axes = plt.subplots(2, 2, figsize=(12, 9))
    panels = ((axes[0], tether, "frequency", ELEMENTS + ("hermite3 (paper)",),
               "spinning tether, truss law: largest relative error of f1 .. f3"),
              (axes[1], pendulum, "tip_max", ELEMENTS,
               "flexible pendulum, cable law: largest tip error / L over 1 s (same dt)"))
    for row, rows, key, variants, title in panels:
        for variant in variants:
            if variant not in rows:
                continue
            style = {"ls": "-", **STYLES[variant]}
            e = np.maximum([r[key] for r in rows[variant]], 1e-16)
            row[0].loglog([r["dofs"] for r in rows[variant]], e, **style, label=variant)
            row[1].loglog([1e3 * r["wall_s"] for r in rows[variant]], e, **style,
                          label=variant)
        row[0].set_xlabel("degrees of freedom (cable.n_dofs)")
        row[1].set_xlabel("wall time [ms] (" + ("solve_steady + modes" if rows is tether
                                                 else "simulate") + ", least of the runs)")
        for ax, what in zip(row, ("DOFs", "wall time")):
            ax.xaxis.set_major_formatter(plain)
            ax.xaxis.set_minor_locator(LogLocator(subs=(2.0, 5.0)))
            ax.xaxis.set_minor_formatter(plain)
            ax.set_ylabel("relative error")
            ax.set_title(f"{title}\nagainst {what}", fontsize=10)
            if rows is pendulum and time_error is not None:
                ax.axhline(time_error, color="0.4", ls=":",
                           label=f"time error of dt = {PENDULUM_DT:g} s")
            ax.grid(alpha=0.3, which="both")
            ax.legend(fontsize=8, loc="lower left" if ax is not axes[0][1] else "upper right")
    fig.tight_layout()
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(argv=None):
    """Parse the arguments, measure, print the tables and save the figures; returns the
    rows."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true",
                        help="fewer meshes, two slendernesses, --repeats 1 unless given")
    parser.add_argument("--repeats", type=int, default=None,
                        help="timed runs per mesh, the least is kept (default 3)")
    parser.add_argument("--figure", type=Path, default=None, metavar="PNG",
                        help="write the convergence figure (errors against DOFs)")
    parser.add_argument("--dynamics-figure", type=Path, default=None, metavar="PNG",
                        help="write the tether and pendulum figure (errors against DOFs "
                             "and against wall time)")
    parser.add_argument("--cases", nargs="+", choices=CASES, default=list(CASES),
                        metavar="CASE", help=f"cases to run (default all: {' '.join(CASES)})")
    args = parser.parse_args(argv)
    meshes = MESHES["quick" if args.quick else "full"]
    repeats = args.repeats or (1 if args.quick else 3)
    start = time.perf_counter()
    out, cases = {}, {}

    if "catenary" in args.cases:
        cases["catenary"] = {v: [catenary_row(n, v, repeats) for n in ns]
                             for v, ns in meshes["catenary"].items()}
        print_case("1. Elastic catenary (truss law): errors relative to the span "
                   "(positions) and to the exact root tension", cases["catenary"],
                   ("position", "tension", "reaction"),
                   ("position", "root tension", "support force"))
    if "elastica" in args.cases:
        cases["elastica"], checks = elastica_rows(meshes["elastica"], repeats)
        print_case(f"2. Elastica (k = {K:g}, EA L^2/EI = 1e7): errors against the converged "
                   f"model ({REFERENCE} quintic elements), tip also against the exact "
                   "inextensible elastica", cases["elastica"],
                   ("tip", "position", "tension", "tip_exact"),
                   ("tip", "max position", "tension / P", "tip vs exact"))
        print(f"\nThe converged model differs from the exact inextensible elastica by "
              f"{checks['floor']:.2e} (extensibility) and from 512 cubic elements by "
              f"{checks['cubic_512']:.1e}.")
        out["elastica_checks"] = checks
    if "locking" in args.cases:
        slendernesses, ns = meshes["locking"]
        locking = locking_rows(slendernesses, ns)
        print_locking(locking, ns)
        out["locking"] = [{"slenderness": key[0], "element": key[1], "n": n, **e}
                          for key, errors in locking.items() if key != "reference"
                          for n, e in zip(ns, errors)]
        out["locking_reference"] = locking["reference"]
    if "straight" in args.cases:
        out["straight_start"] = straight_start_rows(meshes["straight"], repeats)
        print_straight(out["straight_start"])
    if "cost" in args.cases:
        out["cost"] = cost_rows(meshes["cost"], repeats)
        print_costs(out["cost"])
    if "tether" in args.cases:
        cases["tether"], reference, bending = tether_rows(meshes["tether"], repeats)
        print_case("6. Spinning tether (truss law): relative errors of the out-of-plane "
                   "string frequencies f1 .. f3 against the shooting reference "
                   f"({', '.join(f'{f:.9g}' for f in reference[1:])} Hz)", cases["tether"],
                   tuple(f"f{i}" for i in range(1, TETHER_MODES + 1)),
                   tuple(f"f{i}" for i in range(1, TETHER_MODES + 1)),
                   wall="steady + modes [ms]")
        tilt = max(r["tilt"] for rows in cases["tether"].values() for r in rows)
        print(f"\nThe tilt mode ({reference[0]:.9g} Hz = spin / 2 pi, to "
              f"{abs(2 * np.pi * reference[0] / TETHER_SPIN - 1):.0e} in the reference) on "
              f"every mesh: largest relative error {tilt:.1e}.")
        print(f"With the cable law (bending, EI = {bending['EI']:.3g} N m^2), f1 of 16 cubic "
              f"elements lies {bending['cable_f1']:.2e} above the string reference; the "
              "bending correction of a tensioned string at the mean tension is "
              f"{bending['correction']:.2e}.")
        out["tether_reference_hz"], out["tether_bending"] = reference, bending
    if "pendulum" in args.cases:
        cases["pendulum"], check = pendulum_rows(meshes["pendulum"],
                                                 meshes["pendulum_reference"],
                                                 meshes["pendulum_time"], repeats)
        print_case(f"7. Flexible pendulum (cable law, dt = {PENDULUM_DT:g} s, rho_inf = "
                   f"{PENDULUM_RHO_INF:g}, tol = {PENDULUM_TOL:g}): tip error / L against "
                   f"{meshes['pendulum_reference']} quintic elements at the same step, at "
                   f"t = {PENDULUM_T_END:g} s and the largest over the run",
                   cases["pendulum"], ("tip_end", "tip_max"),
                   ("tip at 1 s", "largest tip"), wall="simulate [ms]",
                   floor=PENDULUM_FLOOR)
        print(f"\nReference tip at t = {PENDULUM_T_END:g} s: {check['reference_tip']} m "
              f"({check['reference_wall_s']:.1f} s).")
        print_pendulum_steps(check)
        out["pendulum_time"] = check
    targets = target_rows(cases)
    if targets:
        print_targets(targets)
    if args.figure is not None and {"catenary", "elastica"} <= set(cases):
        figure(args.figure, cases["catenary"], cases["elastica"])
        print(f"\nfigure saved to {args.figure}")
    if args.dynamics_figure is not None and {"tether", "pendulum"} <= set(cases):
        dynamics_figure(args.dynamics_figure, cases["tether"], cases["pendulum"],
                        out["pendulum_time"]["steps"][0]["tip_max"])
        print(f"\nfigure saved to {args.dynamics_figure}")
    print(f"\ntotal {time.perf_counter() - start:.0f} s (repeats {repeats})")
    return {**cases, **out, "targets": targets}


if __name__ == "__main__":
    main()
