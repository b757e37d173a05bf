"""Accuracy and cost of the three formulations of the cable (``Cable(...,
formulation=...)``, ``skfem_cable.bodies.formulation``): the paper's (every term on the 5-point
Gauss rule), the Lobatto (the axial part on the 3-point Gauss-Lobatto rule, nodes and
midpoint) and the default, the assumed strain (the axial strain interpolated from its
nodal values and element means, ``kernels.assumed_strain``).  Both locking-free ones put
the bending part on the 3-point Gauss rule; their strain and tension are recovered
(``Cable.tension``).  This script measures, for the three:

1. The elastica: a cantilever (``classics.cantilever``, ``EA L^2/EI = 1e7``) under a
   transverse dead tip load ``P = k EI/L^2``, solved statically with ``max(10, 2k)`` load
   steps as ``tests/test_locking.py`` does.  Tip error ``max(|u_num - u|, |w_num - w|)``
   against the exact inextensible elastica (``analytic.elastica_tip_load``) for
   ``n = 4 .. 32`` elements and ``k = 1 .. 20``, with the observed orders between
   successive meshes.  The model is extensible, so the error against the inextensible
   solution stops at the extensibility of the model (about ``k EI/EA``): that floor is the
   error of the converged model (``REFERENCE_ELEMENTS`` elements of the default
   formulation), and a second table gives the discretisation error, the distance to that
   converged solution.  A third table gives the largest error of the tension ``N(s)`` over
   321 points against the exact axial force ``P sin(theta(s))``
   (``analytic.elastica_tip_load_angle``), relative to ``P``.
2. The hanging wire of the tension issue (steel, 2 mm radius, 12 m between pins 10 m
   apart, built straight): tension (largest error over 321 points relative to the
   largest tension), support tension and positions (relative to the span) against the
   planar elastica-catenary with bending (``analytic.elastica_catenary``).  The elastic
   catenaries of ``tests/test_validation_statics.py`` (``validation.CATENARIES``), "rope"
   (2.7 % strain) and "steel", cable law: support force ``H``, midspan sag, positions and
   tension.  And the steel case with the truss law from its stress-free start: solved or
   not.
3. Frequencies of a rotating tether: one E-sail tether (``esail.spinning_tether``) pinned
   at the hub rim with its remote unit, in the frame spinning at ``4e-3 rad/s``
   (``modes(..., spin=...)``), about the static centrifugal state; the ten frequencies
   above the (near-zero) in-plane lag mode (coning, four bending pairs, first axial mode)
   against the paper's formulation with ``TETHER_REFERENCE`` elements.  The taut string of
   ``tests/test_validation_statics.py`` (``validation.STEEL``, 1 m, Green pre-strain 1e-3,
   pinned-pinned): first three transverse frequencies against the exact string (truss
   law) and tensioned-beam (cable law) formulas.  The first axial frequency of the
   unstressed clamped-free bar.
4. The stiffness spectrum of a free straight cable: the number of zero modes of the three
   formulations and of the 2-point Gauss rule (``intorder=3``).
5. Cost, side by side in one run, each measurement in a fresh Python process with warm
   caches (one untimed call first), alternating the formulations, minimum over
   ``--repeats`` processes: (a) one force and tangent evaluation
   ``system.evaluate(q, v, 0.0, lam, cK=1.0, cC=0.5, data=data)`` of a free damped cable at
   a random perturbation (as ``benchmarks/laws.py``), mean over calls filling
   ``--seconds``; (b) ms per step of the flexible pendulum (``classics.pendulum(16)``,
   ``dt = 1e-3 s``, ``rho_inf = 0.8``, 200 steps) and of the E-sail
   (``esail.BaselineConfig()``, ``alpha = 10 deg``, 5 elements, ``dt = 0.1 s``,
   ``rho_inf = 0.25``, 600 steps), as ``benchmarks/commit_compare.py``, and per Newton
   iteration (the step over its Newton iterations).
6. Whether the results change: the pendulum (1 s) and the E-sail (one spin period,
   1571 s) in each formulation and with twice the elements; the difference from the
   paper's formulation against each formulation's difference between the meshes (its
   discretisation error).

``--plots DIR`` saves ``cantilever_tension.png`` (N(s)/P of the 16-element cantilever at
``k = 5``) and ``locking_convergence.png`` (errors against elements).

Run ``python benchmarks/locking.py [--plots DIR] [--repeats 5] [--no-timing] [--quick]``
(``--quick``: the cost of section 5 with one repeat of 0.1 s unless given).  Machines are
noisy: read the ratios, not the absolute times.
"""

import argparse
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np

import skfem_cable as sc
from skfem_cable.analysis.analytic import (
    elastica_catenary,
    elastica_tip_load,
    elastica_tip_load_angle,
)
from skfem_cable.cli import validation as V  # the cases of tests/test_validation_statics.py
from skfem_cable.scenes import classics, esail
from skfem_cable.scenes.classics import ELASTICA_SECTION

ROOT = Path(__file__).resolve().parents[1]
#: The formulations compared, in the order of the tables (the default last).
OPTIONS = ("paper", "lobatto", "assumed-strain")
DEFAULT = "assumed-strain"
ELEMENTS = (4, 8, 16, 32)
LOADS = (1.0, 2.0, 5.0, 10.0, 20.0)
#: Elements of the converged extensible elastica (default formulation): fourth order, so
#: its discretisation error is below 1e-10.
REFERENCE_ELEMENTS = 512
#: Elements of the reference tether (paper's formulation).
TETHER_REFERENCE = 64
SIZES = (60, 1000, 6000)



# --------------------------------------------------------------------------------------
# 1. the elastica
# --------------------------------------------------------------------------------------
def elastica(n, k, formulation):
    """The tip-loaded cantilever of ``classics.cantilever`` solved statically.

    Parameters
    ----------
    n : int
        Elements.
    k : float
        Load ``P L^2 / EI``.
    formulation : str

    Returns
    -------
    cable : sc.Cable
    q : ndarray
        The cable's coordinates at equilibrium.
    """
    scene = classics.cantilever(n, k, formulation=formulation)
    state = sc.solve_static(scene.system, load_steps=max(10, int(2 * k)))
    return scene.cable, state.q[:scene.cable.n_dofs]


def tip(cable, q):
    """Tip shortening and deflection of the cantilever over its length, ``(u, w)``."""
    r = cable.interpolate(q, cable.length)[0]
    return np.array([1.0 - r[0], -r[1]])


def elastica_errors(ns=ELEMENTS, ks=LOADS, reference=REFERENCE_ELEMENTS):
    """Tip and tension errors of the elastica.

    Returns
    -------
    dict
        ``exact[k, option]`` and ``discretisation[k, option]``: tip errors on each mesh
        against the exact inextensible elastica and against the converged model;
        ``floor[k]``: the converged model against the exact elastica;
        ``tension[k, option]``: ``max |N - P sin(theta)| / P`` over 321 points.
    """
    s = np.linspace(0.0, 1.0, 321)
    out = {"exact": {}, "discretisation": {}, "floor": {}, "tension": {}}
    for k in ks:
        exact = np.array(elastica_tip_load(k))
        converged = tip(*elastica(reference, k, DEFAULT))
        out["floor"][k] = np.abs(converged - exact).max()
        axial = np.sin(elastica_tip_load_angle(k, s))
        for option in OPTIONS:
            rows = {"exact": [], "discretisation": [], "tension": []}
            for n in ns:
                cable, q = elastica(n, k, option)
                uw = tip(cable, q)
                rows["exact"].append(np.abs(uw - exact).max())
                rows["discretisation"].append(np.abs(uw - converged).max())
                P = k * cable.section.EI
                rows["tension"].append(np.abs(cable.tension(q, s) / P - axial).max())
            for key, row in rows.items():
                out[key][k, option] = np.array(row)
    return out


# --------------------------------------------------------------------------------------
# 2. hanging cables
# --------------------------------------------------------------------------------------
#: The hanging wire of the tension issue: steel, radius (m), length (m), span (m).
WIRE = (sc.Section.circular(2e-3, 2.1e11, 7850.0), 12.0, 10.0)


def hanging(n, formulation, samples=321):
    """The hanging wire (``WIRE``) built straight and solved statically (10 load steps),
    against the elastica-catenary with bending.

    Returns
    -------
    dict
        ``tension`` (largest error over ``samples`` points relative to the largest
        tension), ``support`` (relative error of the tension at the first pin),
        ``position`` (largest error relative to the span), ``root`` (the support tension
        reported, N), ``reference`` (the exact one, N).
    """
    sec, length, span = WIRE
    cable = sc.Cable.straight([0, 0, 0], [length, 0, 0], n, sec, formulation=formulation)
    system = sc.System([cable]).pin(cable.node(0)).pin(cable.node(-1), [span, 0, 0])
    state = sc.solve_static(system.add_gravity([0, 0, -V.G]), load_steps=10)
    s = np.linspace(0.0, length, samples)
    xz, N, _, _ = elastica_catenary(s, span, length, sec.mass_per_length * V.G, sec.EA,
                                    sec.EI)
    T = state.tension(cable, s)
    return {"tension": np.abs(T - N).max() / N.max(), "support": abs(T[0] / N[0] - 1),
            "position": np.abs(state.position(cable, s)[:, [0, 2]] - xz).max() / span,
            "root": T[0], "reference": N[0]}


def hanging_table(ns=ELEMENTS + (64,)):
    """``{(quantity, option): errors on the meshes ns}`` of ``hanging`` (and the support
    tension reported with 16 elements under ``("root", option)``)."""
    out = {}
    for option in OPTIONS:
        rows = [hanging(n, option) for n in ns]
        for key in ("tension", "support", "position"):
            out[key, option] = np.array([r[key] for r in rows])
        out["root", option] = rows[ns.index(16)]["root"]
    out["reference"] = rows[0]["reference"]
    return out


def catenary_table(cases=("rope", "steel"), ns=ELEMENTS):
    """Errors of the validation tests' ``validation.catenary_errors`` (cable law) on each
    mesh.

    Returns
    -------
    dict
        ``{(case, quantity, option): ndarray of the errors on the meshes ns}``.
    """
    out = {}
    for case in cases:
        for option in OPTIONS:
            errors = [V.catenary_errors(case, n, "cable", formulation=option) for n in ns]
            for key in ("H", "sag", "position", "tension"):
                out[case, key, option] = np.array([e[key] for e in errors])
    return out


def truss_start_check(ns=ELEMENTS):
    """The steel catenary with the truss law (no bending) from its stress-free start (the
    inextensible catenary): solved or not in each formulation, and the least and largest
    raw Green strain of the start at the element midpoints.

    Returns
    -------
    dict
        ``{n: (outcome per option..., min, max midpoint strain)}``, an outcome being the H
        error or the first words of the solver's message.
    """
    out = {}
    for n in ns:
        cells = []
        for option in OPTIONS:
            try:
                err = V.catenary_errors("steel", n, "truss", formulation=option)
                cells.append(f"H error {err['H']:.1e}")
            except sc.StaticConvergenceError as error:
                message = str(error)  # ... residual history [1.0, 'singular matrix at ...']
                reason = message.split("'")[1] if "'" in message else message
                cells.append(f"fails: {reason}")
        start, _ = V.catenary_system("steel", n, "truss")
        e = np.arange(start.n_elements)
        mid = start.green(start.q0, e, np.full(e.size, 0.5))
        out[n] = (*cells, mid.min(), mid.max())
    return out


# --------------------------------------------------------------------------------------
# 3. frequencies of taut and spinning cables
# --------------------------------------------------------------------------------------
def tether_frequencies(n, formulation, config=None):
    """Frequencies (Hz) of one E-sail tether about its steady spin, in the rotating frame
    (``esail.spinning_tether``, static centrifugal state, ``modes(spin=)``).

    Returns
    -------
    ndarray, shape (11,)
        The lowest eleven: the in-plane lag mode (near zero), the coning mode, four bending
        pairs and the first axial mode.
    """
    cfg = config or esail.BaselineConfig()
    system = esail.spinning_tether(cfg, n, formulation=formulation)
    state = sc.solve_static(system)
    freqs, _ = sc.modes(system, state, k=11, spin=[cfg.spin_rate, 0.0, 0.0])
    return freqs


def tether_table(ns=ELEMENTS, reference=TETHER_REFERENCE):
    """Relative frequency errors of the spinning tether against the paper's formulation
    with ``reference`` elements.

    Returns
    -------
    errors : dict
        ``{option: (len(ns), 10) relative errors of frequencies 1..10}``.
    ref : ndarray
        The reference frequencies 1..10 (Hz).
    checks : dict
        Largest relative difference of frequencies 1..10 of the default formulation on the
        reference mesh and of the paper's formulation with half the elements from ``ref``.
    """
    ref = tether_frequencies(reference, "paper")[1:]
    errors = {option: np.array([np.abs(tether_frequencies(n, option)[1:] / ref - 1)
                                for n in ns]) for option in OPTIONS}
    checks = {
        DEFAULT: np.abs(tether_frequencies(reference, DEFAULT)[1:] / ref - 1).max(),
        "half": np.abs(tether_frequencies(reference // 2, "paper")[1:] / ref - 1).max(),
    }
    return errors, ref, checks


def string_errors(n, kind, formulation):
    """Largest relative error of the first three transverse frequencies of the taut
    string of the validation tests (steel, L0 = 1 m, Green pre-strain ``V.EPS0``, both
    ends pinned) against the string (truss) or tensioned-beam (cable) formula."""
    sec = V.STEEL
    stretch = np.sqrt(1 + 2 * V.EPS0)
    x = np.linspace(0.0, 1.0, n + 1)
    cable = sc.Cable(sc.Cable.straight([0, 0, 0], [1, 0, 0], n, sec).mesh, sec,
                     np.column_stack([stretch * x, 0 * x, 0 * x]),
                     np.tile([stretch, 0.0, 0.0], (n + 1, 1)), law=kind,
                     formulation=formulation)
    system = sc.System([cable]).pin(cable.node(0)).pin(cable.node(-1))
    state = sc.solve_static(system)
    freqs, shapes = sc.modes(system, state, k=12)
    f = V.transverse_pairs(freqs, V.axial_fraction(system, shapes, [1, 0, 0]), 3)
    N = sec.EA * V.EPS0
    beta = np.arange(1, 4) * np.pi
    EI = sec.EI if kind == "cable" else 0.0
    ref = np.sqrt(beta**2 * (N + beta**2 * EI / stretch**4) / sec.mass_per_length) / (2 * np.pi)
    return np.abs(f / ref - 1).max()


def axial_error(n, formulation):
    """Relative error of the first axial frequency of the unstressed clamped-free steel
    bar of the validation tests (``c / 4L``)."""
    freqs, frac = V.beam_modes(n, "clamped-free", formulation=formulation)
    return abs(freqs[frac > 0.999][0] / (np.sqrt(V.STEEL.E / V.STEEL.rho) / 4) - 1)


def string_table(ns=ELEMENTS):
    """``{(case, option): errors on each mesh}``: the taut string of each law
    (``string_errors``) and the bar's axial frequency (``axial_error``, case "bar")."""
    out = {(kind, option): np.array([string_errors(n, kind, option) for n in ns])
           for kind in ("truss", "cable") for option in OPTIONS}
    out.update({("bar", option): np.array([axial_error(n, option) for n in ns])
                for option in OPTIONS})
    return out


# --------------------------------------------------------------------------------------
# 4. zero modes of a free straight cable
# --------------------------------------------------------------------------------------
def zero_modes(ns=(1, 2, 12, 40)):
    """Zero eigenvalues (below 1e-13 of the largest) of the stiffness of a free straight
    cable and truss (E = 1e9, A = 1e-4, I = 1e-10, 1 m) in the three formulations and with
    the 2-point Gauss rule (``intorder=3``, paper's formulation).

    Returns
    -------
    dict
        ``{(law, n): (zero modes of each rule)}``.
    """
    section = sc.Section(E=1e9, A=1e-4, I=1e-10, rho=7850.0)
    rules = [{"formulation": option} for option in OPTIONS]
    rules.append({"formulation": "paper", "intorder": 3})
    out = {}
    for law in ("cable", "truss"):
        for n in ns:
            counts = []
            for rule in rules:
                cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], n, section, law=law, **rule)
                K = sc.System([cable]).assemble(cable.q0)[1]
                eig = np.abs(np.linalg.eigvalsh(K.toarray()))
                counts.append(int(np.sum(eig < 1e-13 * eig.max())))
            out[law, n] = tuple(counts)
    return out


# --------------------------------------------------------------------------------------
# 5. cost
# --------------------------------------------------------------------------------------
#: One force + tangent evaluation of a free damped cable (as ``benchmarks/laws.py``).
EVALUATE = r"""
import json, math, sys, time
import numpy as np
import skfem_cable as sc

formulation, n, seconds = sys.argv[1], int(sys.argv[2]), float(sys.argv[3])
section = sc.Section(E=7e10, A=4.28e-9, I=1.47e-18, rho=7653.0,
                     gamma_axial=0.01, gamma_bending=0.01)
cable = sc.Cable.straight([0, 0, 0], [1000.0, 0, 0], n, section, formulation=formulation)
system = sc.System([cable])
rng = np.random.default_rng(n)
q = system.q0 + 1e-3 * rng.standard_normal(system.n_dofs)
v = 1e-2 * rng.standard_normal(system.n_dofs)
data, lam = np.zeros(system.layout.nnz), np.zeros(0)


def evaluate():
    return system.evaluate(q, v, 0.0, lam, cK=1.0, cC=0.5, data=data, layout=system.layout)


evaluate()  # compile or load the kernels
start = time.perf_counter()
evaluate()
one = time.perf_counter() - start
calls = max(3, math.ceil(seconds / max(one, 1e-9)))
start = time.perf_counter()
for _ in range(calls):
    evaluate()
print(json.dumps({"ms": 1e3 * (time.perf_counter() - start) / calls, "file": sc.__file__}))
"""

#: ms per step of the pendulum or the E-sail (as ``benchmarks/commit_compare.py``).
STEP = r"""
import json, sys, time
import skfem_cable as sc
from skfem_cable.scenes import classics, esail

case, formulation, steps = sys.argv[1], sys.argv[2], int(sys.argv[3])
if case == "esail":
    scene = esail.build(esail.BaselineConfig(), alpha_deg=10.0, n_elements=5, kind="cable",
                        formulation=formulation)
    system, initial, dt, rho = scene.system, scene.initial, 0.1, 0.25
else:
    scene = classics.pendulum(n_elements=16, formulation=formulation)
    system, initial, dt, rho = scene.system, scene.initial, 1e-3, 0.8
sc.simulate(system, t_end=2 * dt, dt=dt, rho_inf=rho, initial=initial)  # compile, layout
start = time.perf_counter()
r = sc.simulate(system, t_end=steps * dt, dt=dt, rho_inf=rho, initial=initial, every=steps)
wall = time.perf_counter() - start
print(json.dumps({"ms": 1e3 * wall / steps, "newton": r.stats["newton"] / r.stats["steps"],
                  "file": sc.__file__}))
"""

STEPS = {"pendulum": 200, "esail": 600}


def run(snippet, args):
    """Run ``snippet`` with ``args`` in a fresh interpreter importing this checkout; its
    last printed line is a JSON object, returned decoded."""
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    proc = subprocess.run([sys.executable, "-c", snippet, *map(str, args)], env=env,
                          cwd=ROOT, capture_output=True, text=True)
    if proc.returncode != 0:
        raise RuntimeError(f"benchmark process failed ({args}):\n{proc.stderr[-3000:]}")
    out = json.loads(proc.stdout.strip().splitlines()[-1])
    if not Path(out["file"]).resolve().is_relative_to(ROOT):
        raise RuntimeError(f"imported {out['file']}, not this checkout")
    return out


def costs(repeats, seconds, sizes=SIZES):
    """Minimum over ``repeats`` fresh processes, alternating the formulations, of the ms
    per evaluation (free cable of each size) and per step (pendulum, E-sail).

    Returns
    -------
    dict
        ``{(case, option): {"ms": ..., "newton": ...}}`` with ``case`` a size or a scene.
    """
    best = {}

    def keep(key, out):
        if key not in best or out["ms"] < best[key]["ms"]:
            best[key] = out

    for _ in range(repeats):
        for n in sizes:
            for option in OPTIONS:
                keep((n, option), run(EVALUATE, (option, n, seconds)))
        for case, steps in STEPS.items():
            for option in OPTIONS:
                keep((case, option), run(STEP, (case, option, steps)))
    return best


# --------------------------------------------------------------------------------------
# 6. do the results change?
# --------------------------------------------------------------------------------------
def pendulum_tips(n, formulation, t_end=1.0):
    """Tip positions (m) of the flexible pendulum (``classics.pendulum`` of ``n``
    elements, ``dt = 1e-3 s``, ``rho_inf = 0.8``) every 10 steps, shape (nt, 3)."""
    scene = classics.pendulum(n_elements=n, formulation=formulation)
    r = sc.simulate(scene.system, t_end=t_end, dt=1e-3, rho_inf=0.8, initial=scene.initial,
                    every=10)
    return r.position(scene.cable, scene.cable.length)


def esail_series(n, formulation, t_end=None):
    """The E-sail (baseline, ``alpha = 10 deg``, ``dt = 0.1 s``, ``rho_inf = 0.25``) up to
    ``t_end`` (default one spin period), saved every 100 steps.

    Returns
    -------
    dict
        ``thrust`` (nt, 3, N), ``thrust_angle`` and ``coning`` of tether 1 (nt, deg),
        ``hub`` and ``hub_velocity`` (hub centre, nt, 3), ``tension`` (root tension of
        tether 1, nt, N).
    """
    cfg = esail.BaselineConfig()
    t_end = cfg.spin_period if t_end is None else t_end
    scene = esail.build(cfg, alpha_deg=10.0, n_elements=n, kind="cable",
                        formulation=formulation)
    r = sc.simulate(scene.system, t_end=t_end, dt=0.1, rho_inf=0.25, initial=scene.initial,
                    every=100)
    out = esail.outputs(scene, r)
    dofs = scene.system.dofs(scene.hub)
    return {"thrust": out["thrust"], "thrust_angle": np.rad2deg(out["thrust_angle"]),
            "coning": np.rad2deg(out["coning"][:, 0]),
            "hub": scene.hub.positions(r.q[:, dofs], np.zeros(3)),
            "hub_velocity": scene.hub.positions(r.v[:, dofs], np.zeros(3)),
            "tension": r.tension(scene.tethers[0], 0.0), "t": r.t}


def _distances(runs, key, n, at_end=False, scale=1.0):
    """``(option - paper at n, then each option's 2n - n)`` of ``runs[(n, option)][key]``
    (largest over the run, or at its end), over ``scale``."""
    def distance(a, b):
        d = runs[a][key] - runs[b][key]
        d = np.abs(d) if d.ndim == 1 else np.linalg.norm(d, axis=1)
        return (d[-1] if at_end else d.max()) / scale

    return (*(distance((n, o), (n, "paper")) for o in OPTIONS if o != "paper"),
            *(distance((2 * n, o), (n, o)) for o in OPTIONS))


def result_changes():
    """Differences between the formulations (``n`` elements) and between meshes (``2n``
    against ``n``, same formulation): pendulum ``n = 16``, E-sail ``n = 5``.

    Returns
    -------
    rows : dict
        ``{(scene, quantity): (lobatto - paper, assumed-strain - paper, then paper,
        lobatto and assumed-strain 2n - n)}``.
    extra : dict
        Sizes of the results, for scale.
    """
    tips = {(n, o): {"tip": pendulum_tips(n, o)} for n in (16, 32) for o in OPTIONS}
    rows = {("pendulum", "tip position at t = 1 s (m)"): _distances(tips, "tip", 16, True),
            ("pendulum", "tip position, max over 0..1 s (m)"): _distances(tips, "tip", 16)}
    sails = {(n, o): esail_series(n, o) for n in (5, 10) for o in OPTIONS}
    paper = sails[5, "paper"]
    scale = np.linalg.norm(paper["thrust"], axis=1).max()
    for label, key, at_end, norm in (
            ("thrust, max over the run (relative to the largest thrust)", "thrust", False, scale),
            ("thrust angle, max over the run (deg)", "thrust_angle", False, 1.0),
            ("coning of tether 1, max over the run (deg)", "coning", False, 1.0),
            ("root tension of tether 1, max over the run (relative)", "tension", False,
             np.abs(paper["tension"]).max()),
            ("hub centre position at the end (m)", "hub", True, 1.0),
            ("hub centre velocity at the end (m/s)", "hub_velocity", True, 1.0)):
        rows["E-sail", label] = _distances(sails, key, 5, at_end, norm)
    extra = {"hub_travel": np.linalg.norm(paper["hub"][-1] - paper["hub"][0]),
             "thrust": scale, "t_end": paper["t"][-1],
             "tip_travel": np.linalg.norm(tips[16, "paper"]["tip"][-1]
                                          - tips[16, "paper"]["tip"][0])}
    return rows, extra


# --------------------------------------------------------------------------------------
# figures
# --------------------------------------------------------------------------------------
STYLES = {"paper": dict(color="C3", marker="s", ms=9, mfc="none", ls="--"),
          "lobatto": dict(color="C2", marker="^"), "assumed-strain": dict(color="C0", marker="o")}


def figures(plots, elastica_rows, hanging_rows, strings, tether, ns=ELEMENTS):
    """Save ``cantilever_tension.png`` and ``locking_convergence.png``.

    Parameters
    ----------
    plots : path-like
        Folder of the figures (created if needed).
    elastica_rows, hanging_rows, strings, tether
        ``elastica_errors()`` (needs ``k = 5`` and ``k = 10``), ``hanging_table()``,
        ``string_table()`` and ``tether_table()``.
    ns : sequence of int
        The meshes of the tables.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    plots = Path(plots)
    plots.mkdir(parents=True, exist_ok=True)
    k, n = 5.0, 16
    s = np.linspace(0.0, 1.0, 100 * n + 1)
    exact = np.sin(elastica_tip_load_angle(k, s))
    P = k * ELASTICA_SECTION.EI
    cables = {option: elastica(n, k, option) for option in OPTIONS}
    fig, axes = plt.subplots(3, 1, figsize=(7.5, 8.5), sharex=True,
                             gridspec_kw={"height_ratios": [1.2, 1, 0.8]})
    ax = axes[0]
    cable, q = cables["paper"]
    ax.plot(s, cable.tension(q, s) / P, color="C3", lw=0.8,
            label="paper's formulation, sampled every L/1600")
    ax.plot(s, exact, "k--", lw=1.2, label=r"exact $P\sin\theta$")
    ax.set_ylabel("N / P")
    ax.set_title(f"(a) paper's formulation: membrane-locking stripes ({n} elements, k = {k:g})")
    ax.legend(loc="upper right", fontsize=8)
    for option in ("assumed-strain", "lobatto"):
        cable, q = cables[option]
        axes[1].plot(s, cable.tension(q, s) / P, color=STYLES[option]["color"],
                     lw=1.5 if option == DEFAULT else 1.0, label=f"{option}, recovered")
        axes[2].plot(s, cable.tension(q, s) / P - exact, color=STYLES[option]["color"],
                     lw=1.0, label=option)
    axes[1].plot(s, exact, "k--", lw=1.0, label=r"exact $P\sin\theta$")
    axes[1].set_ylabel("N / P")
    axes[1].set_title("(b) the locking-free formulations: recovered tension")
    axes[1].legend(loc="lower right", fontsize=8)
    axes[2].axhline(0.0, color="k", lw=0.5)
    axes[2].set_ylabel(r"$(N - P\sin\theta)/P$")
    axes[2].set_xlabel("s / L")
    axes[2].set_title("(c) error of the recovered tension")
    axes[2].legend(loc="upper right", fontsize=8)
    for ax in axes:
        ax.grid(alpha=0.3)
        for x in np.linspace(0, 1, n + 1):
            ax.axvline(x, color="0.85", lw=0.5, zorder=0)
    fig.tight_layout()
    fig.savefig(plots / "cantilever_tension.png", dpi=130)
    plt.close(fig)

    errors, _, _ = tether
    hanging_ns = ns + (64,)
    panels = (
        ("elastica, k = 5: tip error (to the converged model)", ns,
         {o: elastica_rows["discretisation"][5.0, o] for o in OPTIONS}, 4),
        ("elastica, k = 10: tension, max |N - P sin(theta)| / P", ns,
         {o: elastica_rows["tension"][10.0, o] for o in OPTIONS}, 2),
        ("hanging wire: tension, max |N - N_ex| / max N_ex", hanging_ns,
         {o: hanging_rows["tension", o] for o in OPTIONS}, 2),
        ("taut string (truss): frequencies 1-3", ns,
         {o: strings["truss", o] for o in OPTIONS}, 6),
        ("spinning E-sail tether: frequencies 1-10", ns,
         {o: errors[o].max(axis=1) for o in OPTIONS}, 6),
        ("unstressed bar: first axial frequency", ns,
         {o: strings["bar", o] for o in OPTIONS}, 6),
    )
    fig, axes = plt.subplots(2, 3, figsize=(14, 8.5))
    for ax, (title, meshes, rows, order) in zip(axes.ravel(), panels):
        for option in OPTIONS:
            ax.loglog(meshes, np.maximum(rows[option], 1e-16), **STYLES[option],
                      label=option + (" (default)" if option == DEFAULT else ""))
        guide = np.array([meshes[0], meshes[-1]], float)
        e0 = 0.5 * max(rows[DEFAULT][0], 1e-12)
        ax.loglog(guide, e0 * (guide / guide[0]) ** -order, color="0.6", lw=0.8,
                  label=f"slope -{order}")
        ax.set_title(title, fontsize=10)
        ax.set_xlabel("elements")
        ax.set_ylabel("relative error")
        ax.set_xticks(meshes)
        ax.set_xticklabels([str(m) for m in meshes])
        ax.minorticks_off()
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=7, loc="lower left")
    fig.tight_layout()
    fig.savefig(plots / "locking_convergence.png", dpi=130)
    plt.close(fig)


# --------------------------------------------------------------------------------------
# tables
# --------------------------------------------------------------------------------------
def _row(cells):
    return "| " + " | ".join(cells) + " |"


def _error_table(title, first, rows, ns=ELEMENTS):
    """Print a markdown table of errors on each mesh and the orders between them.

    Parameters
    ----------
    title : str
    first : sequence of str
        Headers of the label columns.
    rows : sequence of (labels, errors)
    ns : sequence of int
        The meshes.
    """
    print(f"\n### {title}\n")
    heads = [*first, *(f"n = {n}" for n in ns),
             *(f"order {a}-{b}" for a, b in zip(ns[:-1], ns[1:]))]
    print(_row(heads))
    print("|" + "---|" * len(first) + "---:|" * (len(heads) - len(first)))
    for labels, errors in rows:
        print(_row([*labels, *(f"{e:.2e}" for e in errors),
                    *(f"{o:.2f}" for o in V.observed_rates(ns, errors))]))


def print_accuracy(elastica_rows, hanging_rows, catenary_rows, truss, tether, strings,
                   zeros):
    """Print the accuracy tables (sections 1-4)."""
    rows = [((f"{k:g}", o), elastica_rows["exact"][k, o]) for k in LOADS for o in OPTIONS]
    _error_table("1a. Elastica: tip error against the exact inextensible elastica",
                 ("k", "formulation"), rows)
    print(f"\nExtensibility floor (the converged model, {REFERENCE_ELEMENTS} elements of the "
          "default formulation, against the exact elastica): "
          + ", ".join(f"k = {k:g}: {elastica_rows['floor'][k]:.2e}" for k in LOADS) + ".")
    rows = [((f"{k:g}", o), elastica_rows["discretisation"][k, o])
            for k in LOADS for o in OPTIONS]
    _error_table(f"1b. Elastica: discretisation error (tip against the converged model, "
                 f"{REFERENCE_ELEMENTS} elements)", ("k", "formulation"), rows)
    rows = [((f"{k:g}", o), elastica_rows["tension"][k, o]) for k in LOADS for o in OPTIONS]
    _error_table("1c. Elastica: max |N(s) - P sin(theta(s))| / P over 321 points",
                 ("k", "formulation"), rows)
    ns = ELEMENTS + (64,)
    rows = [((key, o), hanging_rows[key, o]) for key in ("tension", "support", "position")
            for o in OPTIONS]
    _error_table("2a. The hanging wire: relative errors against the elastica-catenary",
                 ("quantity", "formulation"), rows, ns)
    print("\nSupport tension reported with 16 elements: "
          + ", ".join(f"{o} {hanging_rows['root', o]:.4g} N" for o in OPTIONS)
          + f" (exact {hanging_rows['reference']:.4g} N).")
    rows = [((case, key, o), catenary_rows[case, key, o])
            for case in ("rope", "steel") for key in ("H", "sag", "position", "tension")
            for o in OPTIONS]
    _error_table("2b. Elastic catenary (cable law): relative errors against the exact "
                 "Green-law catenary", ("case", "quantity", "formulation"), rows)
    print("\n### 2c. Steel catenary, truss law (no bending), from the stress-free start\n")
    print(_row(["n", *OPTIONS, "Green strain of the start at the midpoints (min / max)"]))
    print("|---:|" + "---|" * (len(OPTIONS) + 1))
    for n, cells in truss.items():
        print(_row([str(n), *cells[:-2], f"{cells[-2]:.1e} / {cells[-1]:.1e}"]))
    errors, ref, checks = tether
    modes = (("coning", 0), ("bending 1 (out of plane)", 1), ("bending 2", 3),
             ("bending 4", 7), ("axial 1", 9))
    rows = []
    for option in OPTIONS:
        for name, i in modes:
            rows.append(((f"{name}, {ref[i]:.5e} Hz", option), errors[option][:, i]))
        rows.append((("max over frequencies 1-10", option), errors[option].max(axis=1)))
    _error_table(f"3a. Spinning E-sail tether (rotating frame): relative frequency error "
                 f"against the paper's formulation with {TETHER_REFERENCE} elements",
                 ("mode", "formulation"), rows)
    print(f"\nReference check: the default formulation with {TETHER_REFERENCE} elements "
          f"differs from the reference by {checks[DEFAULT]:.1e}, the paper's with "
          f"{TETHER_REFERENCE // 2} by {checks['half']:.1e} (largest over frequencies 1-10).")
    rows = [((kind, o), strings[kind, o]) for kind in ("truss", "cable") for o in OPTIONS]
    _error_table("3b. Taut string (steel, pre-strain 1e-3, pinned-pinned): largest relative "
                 "error of the first three transverse frequencies against the exact "
                 "string (truss) / tensioned beam (cable)", ("law", "formulation"), rows)
    rows = [((o,), strings["bar", o]) for o in OPTIONS]
    _error_table("3c. Unstressed clamped-free bar: relative error of the first axial "
                 "frequency", ("formulation",), rows)
    print("\n### 4. Zero modes of the stiffness of a free straight cable\n")
    print(_row(["law", "n", *OPTIONS, "2-point Gauss", "nonzero (each rule)"]))
    print("|---|---:|" + "---:|" * (len(OPTIONS) + 1) + "---|")
    for (law, n), counts in zeros.items():
        dofs = 6 * (n + 1)
        print(_row([law, str(n), *map(str, counts),
                    " / ".join(str(dofs - c) for c in counts)]))


def print_costs(best, repeats):
    """Print the cost table (section 5): ratios to the paper's formulation."""
    print(f"\n### 5. Cost: minimum over {repeats} fresh processes, alternating the "
          f"formulations (CPUs: {os.cpu_count()})\n")
    others = [o for o in OPTIONS if o != "paper"]
    print(_row(["case", *OPTIONS, *(f"{o} / paper" for o in others)]))
    print("|---|" + "---:|" * (len(OPTIONS) + len(others)))
    for n in SIZES:
        ms = {o: best[n, o]["ms"] for o in OPTIONS}
        print(_row([f"free cable, {n} elements: ms per force + tangent evaluation",
                    *(f"{ms[o]:.3f}" for o in OPTIONS),
                    *(f"{ms[o] / ms['paper']:.2f}" for o in others)]))
    for case, steps in STEPS.items():
        b = {o: best[case, o] for o in OPTIONS}
        newton = " / ".join(f"{b[o]['newton']:.2f}" for o in OPTIONS)
        print(_row([f"{case}: ms per step ({steps} steps; Newton iterations per step "
                    f"{newton})", *(f"{b[o]['ms']:.3f}" for o in OPTIONS),
                    *(f"{b[o]['ms'] / b['paper']['ms']:.2f}" for o in others)]))
        per = {o: b[o]["ms"] / b[o]["newton"] for o in OPTIONS}
        print(_row([f"{case}: ms per Newton iteration", *(f"{per[o]:.3f}" for o in OPTIONS),
                    *(f"{per[o] / per['paper']:.2f}" for o in others)]))


def print_changes(rows, extra):
    """Print the result-difference table (section 6)."""
    print("\n### 6. Do the results change? Difference from the paper's formulation and "
          "between meshes\n")
    print(f"Pendulum: 16 / 32 elements, 1 s (the tip travels {extra['tip_travel']:.2f} m); "
          f"E-sail: 5 / 10 elements, {extra['t_end']:.0f} s (one spin period; max |thrust| "
          f"{extra['thrust']:.3f} N, the hub centre travels {extra['hub_travel']:.3f} m).\n")
    others = [o for o in OPTIONS if o != "paper"]
    print(_row(["scene", "quantity", *(f"{o} - paper (n)" for o in others),
                *(f"{o}: 2n - n" for o in OPTIONS)]))
    print("|---|---|" + "---:|" * (len(others) + len(OPTIONS)))
    for (scene, label), values in rows.items():
        print(_row([scene, label, *(f"{v:.2e}" for v in values)]))


def records(accuracy, best, changes):
    """The results as plain rows (per table) for a JSON record.

    Parameters
    ----------
    accuracy : tuple
        The arguments of ``print_accuracy``.
    best : dict or None
        ``costs()`` (``None`` without timing).
    changes : tuple
        ``result_changes()``.

    Returns
    -------
    dict
    """
    (elastica_rows, hanging_rows, catenary_rows, truss, (errors, ref, checks), strings,
     zeros) = accuracy
    rows, extra = changes
    others = [o for o in OPTIONS if o != "paper"]
    return {
        "elements": ELEMENTS,
        "elastica": [{"k": k, "formulation": o, "floor": elastica_rows["floor"][k],
                      **{key: elastica_rows[key][k, o]
                         for key in ("exact", "discretisation", "tension")}}
                     for k in LOADS for o in OPTIONS],
        "hanging": [{"quantity": key, "formulation": o, "errors": hanging_rows[key, o]}
                    for key in ("tension", "support", "position") for o in OPTIONS],
        "catenary": [{"case": case, "quantity": key, "formulation": o, "errors": e}
                     for (case, key, o), e in catenary_rows.items()],
        "truss_start": [{"n": n, **dict(zip(OPTIONS, cells)), "strain_min": cells[-2],
                         "strain_max": cells[-1]} for n, cells in truss.items()],
        "tether": {"reference_hz": ref, "checks": checks, "errors": errors},
        "string": [{"case": kind, "formulation": o, "errors": e}
                   for (kind, o), e in strings.items()],
        "zero_modes": [{"law": law, "n": n, **dict(zip((*OPTIONS, "gauss2"), counts))}
                       for (law, n), counts in zeros.items()],
        "cost": None if best is None else [{"case": case, "formulation": o, **value}
                                           for (case, o), value in best.items()],
        "changes": [{"scene": scene, "quantity": label,
                     **{f"{o}_minus_paper": v for o, v in zip(others, values)},
                     **{f"{o}_2n_n": v for o, v in zip(OPTIONS, values[len(others):])}}
                    for (scene, label), values in rows.items()],
        "changes_scale": extra,
    }


def main(argv=None):
    """Parse the arguments, measure and print the tables, save the figures; returns the
    results (``records``)."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--plots", type=Path, default=None,
                        help="folder for cantilever_tension.png and locking_convergence.png")
    parser.add_argument("--quick", action="store_true",
                        help="defaults --repeats 1 --seconds 0.1")
    parser.add_argument("--repeats", type=int, default=None, help="default 5")
    parser.add_argument("--seconds", type=float, default=None,
                        help="timed duration of each evaluation process (at least 3 calls; "
                        "default 0.5)")
    parser.add_argument("--no-timing", action="store_true",
                        help="skip the cost measurements (section 5)")
    args = parser.parse_args(argv)
    repeats = args.repeats or (1 if args.quick else 5)
    seconds = args.seconds or (0.1 if args.quick else 0.5)
    elastica_rows = elastica_errors()
    hanging_rows = hanging_table()
    strings = string_table()
    tether = tether_table()
    accuracy = (elastica_rows, hanging_rows, catenary_table(), truss_start_check(), tether,
                strings, zero_modes())
    print_accuracy(*accuracy)
    best = None if args.no_timing else costs(repeats, seconds)
    if best is not None:
        print_costs(best, repeats)
    changes = result_changes()
    print_changes(*changes)
    if args.plots is not None:
        figures(args.plots, elastica_rows, hanging_rows, strings, tether)
        print(f"\nfigures saved in {args.plots}")
    return records(accuracy, best, changes)


if __name__ == "__main__":
    main()
