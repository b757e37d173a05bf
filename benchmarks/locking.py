"""Accuracy and cost of the locking-free cable (``Cable(..., locking_free=True)``) against the
paper's formulation (``locking_free=False``, every term on the 5-point Gauss rule).

A locking-free cable integrates the axial part of its law (the terms without ``r_xx``) with
the 3-point Gauss-Lobatto rule (nodes and midpoint, ``cable.LOBATTO``) and the bending part
with the 3-point Gauss rule; its strain and tension are recovered from the Lobatto points
(``Cable.tension``).  This script measures, for both options:

1. The elastica: a cantilever (``classics.cantilever``, ``EA L^2/EI = 1e7``) under a
   transverse dead tip load ``P = k EI/L^2``, solved statically with
   ``max(10, 2k)`` load steps as ``tests/test_locking.py`` does.  Tip error
   ``max(|u_num - u|, |w_num - w|)`` against the exact inextensible elastica
   (``analytic.elastica_tip_load``) for ``n = 4 .. 32`` elements and ``k = 1 .. 20``, with
   the observed orders between successive meshes.  The model is extensible, so the error
   against the inextensible solution stops at the extensibility of the model (about
   ``k EI/EA``): that floor is the error of the converged model (``REFERENCE_ELEMENTS``
   locking-free elements), and a second table gives the discretisation error, the
   distance to that converged solution.  A third table gives the largest error of the
   tension ``N(s)`` over 321 points against the exact axial force ``P sin(theta(s))``
   (``analytic.elastica_tip_load_angle``), relative to ``P``.
2. The elastic catenary: the "rope" (2.7 % strain) and "steel" cases of
   ``tests/test_validation_statics.py`` (its exact Green-law catenary, same start and
   supports; cable law), errors of the support force ``H``, the midspan sag, the positions
   and the tension against the exact solution, as ``catenary_errors`` there.  And the
   steel case with the truss law from its stress-free start: solved or not with each
   option (``truss_start_check``).
3. Frequencies of a rotating tether: one E-sail tether (``esail.spinning_tether``, rebuilt
   here with the option) pinned at the hub rim with its remote unit, in the frame spinning
   at ``4e-3 rad/s`` (``modes(..., spin=...)``), about the static centrifugal state.  The
   ten frequencies above the (near-zero) in-plane lag mode (coning, four bending pairs,
   first axial mode) against the paper's formulation with ``TETHER_REFERENCE`` elements.
   And the taut string of ``tests/test_validation_statics.py`` (steel, 1 m, Green
   pre-strain 1e-3, pinned-pinned), first three transverse frequencies against the exact
   string (truss law) and tensioned-beam (cable law) formulas.
4. The stiffness spectrum of a free straight cable: the number of zero modes with the
   paper's rule, the locking-free rule and the 2-point Gauss rule (``intorder=3``).
5. Cost, side by side in one run, each measurement in a fresh Python process with warm
   caches (one untimed call first), alternating the two options, minimum over
   ``--repeats`` processes: (a) one force and tangent evaluation
   ``system.evaluate(q, v, 0.0, lam, cK=1.0, cC=0.5, data=data)`` of a free damped cable at
   a random perturbation (as ``benchmarks/laws.py``), mean over calls filling
   ``--seconds``; (b) ms per step of the flexible pendulum (``classics.pendulum(16)``,
   ``dt = 1e-3 s``, ``rho_inf = 0.8``, 200 steps) and of the E-sail
   (``esail.BaselineConfig()``, ``alpha = 10 deg``, 5 elements, ``dt = 0.1 s``,
   ``rho_inf = 0.25``, 600 steps), as ``benchmarks/commit_compare.py``.
6. Whether the results change: the pendulum (1 s) and the E-sail (one spin period,
   1571 s) with both options and with twice the elements; the difference between the
   options against the difference between the meshes (the discretisation error).

``--plots DIR`` saves ``cantilever_tension.png`` (N(s)/P of the 16-element cantilever at
``k = 5``) and ``locking_convergence.png`` (errors against elements).

Run ``python benchmarks/locking.py [--plots DIR] [--repeats 5] [--no-timing] [--quick]``
(``--quick``: the cost of section 5 with one repeat of 0.1 s unless given).  Machines are
noisy: read the ratios, not the absolute times.
"""

import argparse
import importlib.util
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
from skfem import MeshLine

import skfem_cable as sc
from skfem_cable.analytic import elastica_tip_load, elastica_tip_load_angle
from skfem_cable.scenes import classics, esail
from skfem_cable.scenes.classics import ELASTICA_SECTION

ROOT = Path(__file__).resolve().parents[1]
OPTIONS = ((False, "paper"), (True, "locking-free"))
ELEMENTS = (4, 8, 16, 32)
LOADS = (1.0, 2.0, 5.0, 10.0, 20.0)
#: Elements of the converged extensible elastica (locking-free): fourth order, so its
#: discretisation error is below 1e-10.
REFERENCE_ELEMENTS = 512
#: Elements of the reference tether (paper's formulation).
TETHER_REFERENCE = 64
SIZES = (60, 1000, 6000)


def _validation_helpers():
    """The catenary and taut-string helpers of ``tests/test_validation_statics.py``,
    imported by path."""
    path = ROOT / "tests" / "test_validation_statics.py"
    spec = importlib.util.spec_from_file_location("_validation_statics", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


V = _validation_helpers()


# --------------------------------------------------------------------------------------
# 1. the elastica
# --------------------------------------------------------------------------------------
def elastica(n, k, locking_free):
    """The tip-loaded cantilever of ``classics.cantilever`` solved statically.

    Parameters
    ----------
    n : int
        Elements.
    k : float
        Load ``P L^2 / EI``.
    locking_free : bool

    Returns
    -------
    cable : sc.Cable
    q : ndarray
        The cable's coordinates at equilibrium.
    """
    scene = classics.cantilever(n, k, locking_free=locking_free)
    state = sc.solve_static(scene.system, load_steps=max(10, int(2 * k)))
    return scene.cable, state.q[:scene.cable.n_dofs]


def tip(cable, q):
    """Tip shortening and deflection of the cantilever over its length.

    Parameters
    ----------
    cable : sc.Cable
    q : ndarray
        The cable's coordinates.

    Returns
    -------
    ndarray, shape (2,)
        ``(u, w)``: ``1 - x_tip / L`` and ``-y_tip / L``.
    """
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
        converged = tip(*elastica(reference, k, True))
        out["floor"][k] = np.abs(converged - exact).max()
        axial = np.sin(elastica_tip_load_angle(k, s))
        for lf, _ in OPTIONS:
            rows = {"exact": [], "discretisation": [], "tension": []}
            for n in ns:
                cable, q = elastica(n, k, lf)
                uw = tip(cable, q)
                rows["exact"].append(np.abs(uw - exact).max())
                rows["discretisation"].append(np.abs(uw - converged).max())
                P = k * cable.section.EI
                rows["tension"].append(np.abs(cable.tension(q, s) / P - axial).max())
            for key, row in rows.items():
                out[key][k, lf] = np.array(row)
    return out


# --------------------------------------------------------------------------------------
# 2. the elastic catenary
# --------------------------------------------------------------------------------------
def catenary_errors(case, n, locking_free, kind="cable"):
    """Relative errors of the FE catenary ``case`` (``V.CATENARIES``) against the exact
    Green-law catenary, as ``catenary_errors`` of the validation tests.

    Returns
    -------
    dict
        ``H`` (both supports), ``sag``, ``position`` (max over 201 points over the span)
        and ``tension`` (max relative error over 201 points).
    """
    span, height, L0, sec = V.CATENARIES[case]
    w = sec.mass_per_length * V.G
    H, VA, _, sag = V.catenary_reference(case)
    start, _ = V.catenary_system(case, n, kind)
    nodes = start.q0.reshape(-1, 2, 3)
    cable = sc.Cable(start.mesh, sec, nodes[:, 0], nodes[:, 1], law=kind,
                     locking_free=locking_free)
    system = sc.System([cable])
    system.pin(cable.node(0), [0.0, 0.0, 0.0])
    system.pin(cable.node(-1), [span, 0.0, height])
    system.add_gravity([0.0, 0.0, -V.G])
    state = sc.solve_static(system, load_steps=2)
    lam_a, lam_b = (state.multipliers[c.name] for c in system.constraints)
    s = np.linspace(0.0, L0, 201)
    exact = V.catenary_xz(s, H, VA, w, sec.EA)
    fe_sag = V.midspan_sag(lambda t: state.position(cable, t)[0],
                           lambda t: state.position(cable, t)[2], span, height, L0)
    return {
        "H": max(abs(-lam_a[0] + H), abs(-lam_b[0] - H)) / H,
        "sag": abs(fe_sag - sag) / sag,
        "position": np.max(np.abs(state.position(cable, s)[:, [0, 2]] - exact)) / span,
        "tension": np.max(np.abs(state.tension(cable, s) / np.hypot(H, w * s - VA) - 1)),
    }


def catenary_table(cases=("rope", "steel"), ns=ELEMENTS):
    """Errors of ``catenary_errors`` for both options on each mesh.

    Returns
    -------
    dict
        ``{(case, quantity, locking_free): ndarray of the errors on the meshes ns}``.
    """
    out = {}
    for case in cases:
        for lf, _ in OPTIONS:
            errors = [catenary_errors(case, n, lf) for n in ns]
            for key in errors[0]:
                out[case, key, lf] = np.array([e[key] for e in errors])
    return out


def truss_start_check(ns=ELEMENTS):
    """The steel catenary with the truss law (no bending) from its stress-free start (the
    inextensible catenary): solved or not with each option, and the largest and smallest
    Green strain of the start at the element midpoints.

    Returns
    -------
    dict
        ``{n: (outcome paper, outcome locking-free, min, max midpoint strain)}``, an
        outcome being the H error or the first words of the solver's message.
    """
    out = {}
    for n in ns:
        cells = []
        for lf, _ in OPTIONS:
            try:
                cells.append(f"H error {catenary_errors('steel', n, lf, kind='truss')['H']:.1e}")
            except sc.StaticConvergenceError as err:
                message = str(err)  # ... residual history [1.0, 'singular matrix at ...']
                reason = message.split("'")[1] if "'" in message else message
                cells.append(f"fails in the first load increment: {reason}"
                             if "load step 1," in message else f"fails: {reason}")
        start, _ = V.catenary_system("steel", n, "truss")
        mid = start.strain(start.q0, start.mesh.p[0][:-1] + start.h / 2)
        out[n] = (*cells, mid.min(), mid.max())
    return out


# --------------------------------------------------------------------------------------
# 3. frequencies of a rotating tether and of a taut string
# --------------------------------------------------------------------------------------
def tether_frequencies(n, locking_free, config=None):
    """Frequencies (Hz) of one E-sail tether about its steady spin, in the rotating frame:
    ``esail.spinning_tether`` with the option, static centrifugal state, ``modes(spin=)``.

    Returns
    -------
    ndarray, shape (11,)
        The lowest eleven: the in-plane lag mode (near zero), the coning mode, four bending
        pairs and the first axial mode.
    """
    cfg = config or esail.BaselineConfig()
    sec, L = cfg.section, cfg.tether_length
    s = np.linspace(0.0, L, int(n) + 1)
    r, lam = esail.rotating_cable_stretch(s, cfg.hub_radius, L, sec.EA, sec.mass_per_length,
                                          cfg.remote_mass, cfg.spin_rate)
    e = np.array([0.0, 1.0, 0.0])
    cable = sc.Cable(MeshLine(s), sec, r[:, None] * e, lam[:, None] * e, name="tether1",
                     locking_free=locking_free)
    system = sc.System([cable]).pin(cable.node(0))
    system.add_point_mass(cable.node(-1), cfg.remote_mass)
    system.add_centrifugal([cfg.spin_rate, 0.0, 0.0])
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
        Largest relative difference of frequencies 1..10 of the locking-free reference
        mesh and of the paper's formulation with half the elements from ``ref``.
    """
    ref = tether_frequencies(reference, False)[1:]
    errors = {lf: np.array([np.abs(tether_frequencies(n, lf)[1:] / ref - 1) for n in ns])
              for lf, _ in OPTIONS}
    checks = {
        "locking-free": np.abs(tether_frequencies(reference, True)[1:] / ref - 1).max(),
        "half": np.abs(tether_frequencies(reference // 2, False)[1:] / ref - 1).max(),
    }
    return errors, ref, checks


def string_errors(n, kind, locking_free):
    """Largest relative error of the first three transverse frequencies of the taut
    string of the validation tests (steel, L0 = 1 m, Green pre-strain ``V.EPS0``, both
    ends pinned) against the string (truss) or tensioned-beam (cable) formula.

    Parameters
    ----------
    n : int
        Elements.
    kind : {"truss", "cable"}
        The law.
    locking_free : bool

    Returns
    -------
    float
    """
    sec = V.STEEL
    stretch = np.sqrt(1 + 2 * V.EPS0)
    x = np.linspace(0.0, 1.0, n + 1)
    cable = sc.Cable(MeshLine(x), sec, np.column_stack([stretch * x, 0 * x, 0 * x]),
                     np.tile([stretch, 0.0, 0.0], (n + 1, 1)), law=kind,
                     locking_free=locking_free)
    system = sc.System([cable]).pin(cable.node(0)).pin(cable.node(-1))
    state = sc.solve_static(system)
    freqs, shapes = sc.modes(system, state, k=12)
    f = V.transverse_pairs(freqs, V.axial_fraction(system, shapes, [1, 0, 0]), 3)
    N = sec.EA * V.EPS0
    beta = np.arange(1, 4) * np.pi
    EI = sec.EI if kind == "cable" else 0.0
    ref = np.sqrt(beta**2 * (N + beta**2 * EI / stretch**4) / sec.mass_per_length) / (2 * np.pi)
    return np.abs(f / ref - 1).max()


def string_table(ns=ELEMENTS):
    """``{(kind, option): errors on each mesh}`` of ``string_errors``."""
    return {(kind, lf): np.array([string_errors(n, kind, lf) for n in ns])
            for kind in ("truss", "cable") for lf, _ in OPTIONS}


# --------------------------------------------------------------------------------------
# 4. zero modes of a free straight cable
# --------------------------------------------------------------------------------------
def zero_modes(ns=(1, 2, 12)):
    """Zero eigenvalues (below 1e-9 of the largest) of the stiffness of a free straight
    cable and truss (E = 1e9, A = 1e-4, I = 1e-10, 1 m) for three rules of the axial part:
    the paper's (5-point Gauss), the locking-free (3-point Lobatto) and 2-point Gauss
    (``intorder=3``, which also integrates the bending of a straight cable exactly).

    Returns
    -------
    dict
        ``{(law, n): (zero modes with each rule)}``.
    """
    section = sc.Section(E=1e9, A=1e-4, I=1e-10, rho=7850.0)
    rules = ({}, {"locking_free": True}, {"intorder": 3})
    out = {}
    for law in ("cable", "truss"):
        for n in ns:
            counts = []
            for rule in rules:
                cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], n, section, law=law, **rule)
                eig = np.abs(np.linalg.eigvalsh(cable.assemble(cable.q0)[1].toarray()))
                counts.append(int(np.sum(eig < 1e-9 * eig.max())))
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

lf, n, seconds = sys.argv[1] == "1", int(sys.argv[2]), float(sys.argv[3])
section = sc.Section(E=7e10, A=4.28e-9, I=1.47e-18, rho=7653.0,
                     gamma_axial=0.01, gamma_bending=0.01)
cable = sc.Cable.straight([0, 0, 0], [1000.0, 0, 0], n, section, locking_free=lf)
system = sc.System([cable])
rng = np.random.default_rng(n)
q = system.q0 + 1e-3 * rng.standard_normal(system.n_dofs)
v = 1e-2 * rng.standard_normal(system.n_dofs)
data, lam = np.zeros(system.layout.nnz), np.zeros(0)


def evaluate():
    return system.evaluate(q, v, 0.0, lam, cK=1.0, cC=0.5, data=data)


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

case, lf, steps = sys.argv[1], sys.argv[2] == "1", int(sys.argv[3])
if case == "esail":
    scene = esail.build(esail.BaselineConfig(), alpha_deg=10.0, n_elements=5, kind="cable",
                        locking_free=lf)
    system, initial, dt, rho = scene.system, scene.initial, 0.1, 0.25
else:
    scene = classics.pendulum(n_elements=16, locking_free=lf)
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
    """Run ``snippet`` with ``args`` in a fresh interpreter importing this checkout.

    Parameters
    ----------
    snippet : str
        Python source; its last printed line is a JSON object.
    args : sequence
        Its command-line arguments.

    Returns
    -------
    dict
        The decoded JSON line.
    """
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
    """Minimum over ``repeats`` fresh processes, alternating the options, of the ms per
    evaluation (free cable of each size) and per step (pendulum, E-sail).

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
            for lf, _ in OPTIONS:
                keep((n, lf), run(EVALUATE, ("1" if lf else "0", n, seconds)))
        for case, steps in STEPS.items():
            for lf, _ in OPTIONS:
                keep((case, lf), run(STEP, (case, "1" if lf else "0", steps)))
    return best


# --------------------------------------------------------------------------------------
# 6. do the results change?
# --------------------------------------------------------------------------------------
def pendulum_tips(n, locking_free, t_end=1.0):
    """Tip positions of the flexible pendulum.

    Parameters
    ----------
    n : int
        Elements of ``classics.pendulum``.
    locking_free : bool
    t_end : float
        Duration (s); ``dt = 1e-3 s``, ``rho_inf = 0.8``.

    Returns
    -------
    ndarray, shape (nt, 3)
        The tip position (m) every 10 steps.
    """
    scene = classics.pendulum(n_elements=n, locking_free=locking_free)
    r = sc.simulate(scene.system, t_end=t_end, dt=1e-3, rho_inf=0.8, initial=scene.initial,
                    every=10)
    return r.position(scene.cable, scene.cable.length)


def esail_series(n, locking_free, t_end=None):
    """The E-sail (baseline, ``alpha = 10 deg``, ``dt = 0.1 s``, ``rho_inf = 0.25``) up to
    ``t_end`` (default one spin period), saved every 100 steps.

    Returns
    -------
    dict
        ``thrust`` (nt, 3, N), ``thrust_angle`` and ``coning`` of tether 1 (nt, deg),
        ``hub`` and ``hub_velocity`` (hub centre, nt, 3).
    """
    cfg = esail.BaselineConfig()
    t_end = cfg.spin_period if t_end is None else t_end
    scene = esail.build(cfg, alpha_deg=10.0, n_elements=n, kind="cable",
                        locking_free=locking_free)
    r = sc.simulate(scene.system, t_end=t_end, dt=0.1, rho_inf=0.25, initial=scene.initial,
                    every=100)
    out = esail.outputs(scene, r)
    dofs = scene.system.dofs(scene.hub)
    return {"thrust": out["thrust"], "thrust_angle": np.rad2deg(out["thrust_angle"]),
            "coning": np.rad2deg(out["coning"][:, 0]),
            "hub": scene.hub.positions(r.q[:, dofs], np.zeros(3)),
            "hub_velocity": scene.hub.positions(r.v[:, dofs], np.zeros(3)),
            "t": r.t}


def result_changes():
    """Differences between the options (``n`` elements) and between meshes (``2n`` against
    ``n``, same option): pendulum ``n = 16``, E-sail ``n = 5``.

    Returns
    -------
    rows : dict
        ``{(scene, quantity): (locking-free - paper, paper 2n - n, locking-free 2n - n)}``.
    extra : dict
        Sizes of the results, for scale.
    """
    rows = {}
    tips = {(n, lf): pendulum_tips(n, lf) for n in (16, 32) for lf, _ in OPTIONS}
    pairs = (((16, True), (16, False)), ((32, False), (16, False)), ((32, True), (16, True)))

    def distance(a, b):
        return np.linalg.norm(tips[a] - tips[b], axis=-1)

    rows["pendulum", "tip position at t = 1 s (m)"] = tuple(
        distance(a, b)[-1] for a, b in pairs)
    rows["pendulum", "tip position, max over 0..1 s (m)"] = tuple(
        distance(a, b).max() for a, b in pairs)
    sails = {(n, lf): esail_series(n, lf) for n in (5, 10) for lf, _ in OPTIONS}
    pairs = (((5, True), (5, False)), ((10, False), (5, False)), ((10, True), (5, True)))
    paper = sails[5, False]
    scale = np.linalg.norm(paper["thrust"], axis=1).max()
    for label, key, at_end, norm in (
            ("thrust, max over the run (relative to the largest thrust)", "thrust", False, scale),
            ("thrust angle, max over the run (deg)", "thrust_angle", False, 1.0),
            ("coning of tether 1, max over the run (deg)", "coning", False, 1.0),
            ("hub centre position at the end (m)", "hub", True, 1.0),
            ("hub centre velocity at the end (m/s)", "hub_velocity", True, 1.0)):
        values = []
        for a, b in pairs:
            d = sails[a][key] - sails[b][key]
            d = np.abs(d) if d.ndim == 1 else np.linalg.norm(d, axis=1)
            values.append((d[-1] if at_end else d.max()) / norm)
        rows["E-sail", label] = tuple(values)
    extra = {"hub_travel": np.linalg.norm(paper["hub"][-1] - paper["hub"][0]),
             "thrust": scale, "t_end": paper["t"][-1],
             "tip_travel": np.linalg.norm(tips[16, False][-1] - tips[16, False][0])}
    return rows, extra


# --------------------------------------------------------------------------------------
# figures
# --------------------------------------------------------------------------------------
def figures(plots, elastica_rows, catenary_rows, ns=ELEMENTS):
    """Save ``cantilever_tension.png`` and ``locking_convergence.png``.

    Parameters
    ----------
    plots : path-like
        Folder of the figures (created if needed).
    elastica_rows : dict
        ``elastica_errors()`` (needs ``k = 5`` and ``k = 10``).
    catenary_rows : dict
        ``catenary_table()`` (needs the "rope" case).
    ns : sequence of int
        The meshes of both.
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
    paper, qp = elastica(n, k, False)
    free, qf = elastica(n, k, True)
    points = np.linspace(0.0, 1.0, 2 * n + 1)
    fig, axes = plt.subplots(3, 1, figsize=(7.5, 8.5), sharex=True,
                             gridspec_kw={"height_ratios": [1.2, 1, 0.8]})
    ax = axes[0]
    ax.plot(s, paper.tension(qp, s) / P, color="C3", lw=0.8,
            label="paper's formulation, sampled every L/1600")
    ax.plot(s, exact, "k--", lw=1.2, label=r"exact $P\sin\theta$")
    ax.set_ylabel("N / P")
    ax.set_title(f"(a) paper's formulation: membrane-locking stripes ({n} elements, k = {k:g})")
    ax.legend(loc="upper right", fontsize=8)
    ax = axes[1]
    ax.plot(s, free.tension(qf, s) / P, color="C0", lw=1.5, label="locking-free, recovered")
    ax.plot(points, free.tension(qf, points) / P, "o", color="C0", ms=3.5,
            label="Lobatto points (nodes, midpoints)")
    ax.plot(s, exact, "k--", lw=1.0, label=r"exact $P\sin\theta$")
    ax.set_ylabel("N / P")
    ax.set_title("(b) locking-free cable: tension recovered from the Lobatto points")
    ax.legend(loc="lower right", fontsize=8)
    ax = axes[2]
    ax.plot(s, free.tension(qf, s) / P - exact, color="C0", lw=1.0)
    ax.axhline(0.0, color="k", lw=0.5)
    ax.set_ylabel(r"$(N - P\sin\theta)/P$")
    ax.set_xlabel("s / L")
    ax.set_title("(c) error of the recovered tension")
    for ax in axes:
        ax.grid(alpha=0.3)
        for x in np.linspace(0, 1, n + 1):
            ax.axvline(x, color="0.85", lw=0.5, zorder=0)
    fig.tight_layout()
    fig.savefig(plots / "cantilever_tension.png", dpi=130)
    plt.close(fig)

    fig, axes = plt.subplots(1, 3, figsize=(14, 5))
    guide = np.array([ns[0], ns[-1]], float)
    styles = {False: dict(color="C3", marker="s"), True: dict(color="C0", marker="o")}
    for ax, k in zip(axes[:2], (5.0, 10.0)):
        for lf, label in OPTIONS:
            ax.loglog(ns, elastica_rows["exact"][k, lf], **styles[lf],
                      label=f"{label}: to the exact elastica")
        ax.loglog(ns, elastica_rows["discretisation"][k, True], ls=":", lw=1.2,
                  **{**styles[True], "marker": "."},
                  label="locking-free: to the converged model")
        ax.axhline(elastica_rows["floor"][k], color="0.5", ls="--", lw=1,
                   label="converged model to exact (extensibility)")
        e0 = 0.3 * elastica_rows["exact"][k, True][0]
        ax.loglog(guide, e0 * (guide / guide[0]) ** -4, color="0.6", lw=0.8, label="slope -4")
        ax.set_title(f"elastica, k = {k:g}: tip error")
        ax.set_xlabel("elements")
        ax.set_ylabel(r"max(|u - u$_{ex}$|, |w - w$_{ex}$|) / L")
        ax.legend(fontsize=7, loc="lower left")
    ax = axes[2]
    for lf, label in OPTIONS:
        ax.loglog(ns, catenary_rows["rope", "H", lf], **styles[lf], label=f"{label}: H")
        ax.loglog(ns, catenary_rows["rope", "tension", lf], ls="--", **styles[lf],
                  mfc="none", label=f"{label}: tension N(s)")
    e0 = 0.3 * catenary_rows["rope", "H", True][0]
    ax.loglog(guide, e0 * (guide / guide[0]) ** -4, color="0.6", lw=0.8, label="slope -4")
    ax.set_title("elastic catenary ('rope'): relative error")
    ax.set_xlabel("elements")
    ax.set_ylabel("relative error")
    ax.legend(fontsize=7, loc="lower left")
    for ax in axes:
        ax.set_xticks(ns)
        ax.set_xticklabels([str(n) for n in ns])
        ax.minorticks_off()
        ax.grid(alpha=0.3, which="both")
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
    """
    print(f"\n### {title}\n")
    heads = [*first, *(f"n = {n}" for n in ns),
             *(f"order {a}-{b}" for a, b in zip(ns[:-1], ns[1:]))]
    print(_row(heads))
    print("|" + "---|" * len(first) + "---:|" * (len(heads) - len(first)))
    for labels, errors in rows:
        print(_row([*labels, *(f"{e:.2e}" for e in errors),
                    *(f"{o:.2f}" for o in V.observed_rates(ns, errors))]))


def print_accuracy(elastica_rows, catenary_rows, truss, tether, strings, zeros):
    """Print the accuracy tables (sections 1-4)."""
    names = dict(OPTIONS)
    rows = [((f"{k:g}", names[lf]), elastica_rows["exact"][k, lf])
            for k in LOADS for lf, _ in OPTIONS]
    _error_table("1a. Elastica: tip error against the exact inextensible elastica",
                 ("k", "option"), rows)
    print(f"\nExtensibility floor (the converged model, {REFERENCE_ELEMENTS} locking-free "
          "elements, against the exact elastica): "
          + ", ".join(f"k = {k:g}: {elastica_rows['floor'][k]:.2e}" for k in LOADS) + ".")
    rows = [((f"{k:g}", names[lf]), elastica_rows["discretisation"][k, lf])
            for k in LOADS for lf, _ in OPTIONS]
    _error_table(f"1b. Elastica: discretisation error (tip against the converged model, "
                 f"{REFERENCE_ELEMENTS} locking-free elements)", ("k", "option"), rows)
    rows = [((f"{k:g}", names[lf]), elastica_rows["tension"][k, lf])
            for k in LOADS for lf, _ in OPTIONS]
    _error_table("1c. Elastica: max |N(s) - P sin(theta(s))| / P over 321 points",
                 ("k", "option"), rows)
    rows = [((case, key, names[lf]), catenary_rows[case, key, lf])
            for case in ("rope", "steel") for key in ("H", "sag", "position", "tension")
            for lf, _ in OPTIONS]
    _error_table("2. Elastic catenary (cable law): relative errors against the exact "
                 "Green-law catenary", ("case", "quantity", "option"), rows)
    print("\n### 2b. Steel catenary, truss law (no bending), from the stress-free start\n")
    print(_row(["n", "paper", "locking-free", "Green strain of the start at the midpoints "
                "(min / max)"]))
    print("|---:|---|---|---|")
    for n, (paper, free, low, high) in truss.items():
        print(_row([str(n), paper, free, f"{low:.1e} / {high:.1e}"]))
    errors, ref, checks = tether
    modes = (("coning", 0), ("bending 1 (out of plane)", 1), ("bending 2", 3),
             ("bending 4", 7), ("axial 1", 9))
    rows = []
    for lf, label in OPTIONS:
        for name, i in modes:
            rows.append(((f"{name}, {ref[i]:.5e} Hz", label), errors[lf][:, i]))
        rows.append((("max over frequencies 1-10", label), errors[lf].max(axis=1)))
    _error_table(f"3a. Spinning E-sail tether (rotating frame): relative frequency error "
                 f"against the paper's formulation with {TETHER_REFERENCE} elements",
                 ("mode", "option"), rows)
    print(f"\nReference check: the locking-free tether with {TETHER_REFERENCE} elements "
          f"differs from the reference by {checks['locking-free']:.1e}, the paper's with "
          f"{TETHER_REFERENCE // 2} by {checks['half']:.1e} (largest over frequencies 1-10).")
    rows = [((kind, names[lf]), strings[kind, lf]) for kind in ("truss", "cable")
            for lf, _ in OPTIONS]
    _error_table("3b. Taut string (steel, pre-strain 1e-3, pinned-pinned): largest relative "
                 "error of the first three transverse frequencies against the exact "
                 "string (truss) / tensioned beam (cable)", ("law", "option"), rows)
    print("\n### 4. Zero modes of the stiffness of a free straight cable\n")
    print(_row(["law", "n", "paper (5-point Gauss)", "locking-free (3-point Lobatto)",
                "2-point Gauss", "nonzero: paper / Lobatto / 2-point"]))
    print("|---|---:|---:|---:|---:|---|")
    for (law, n), counts in zeros.items():
        dofs = 6 * (n + 1)
        print(_row([law, str(n), *map(str, counts),
                    " / ".join(str(dofs - c) for c in counts)]))


def print_costs(best, repeats):
    """Print the cost table (section 5)."""
    print(f"\n### 5. Cost: minimum over {repeats} fresh processes, alternating the options "
          f"(CPUs: {os.cpu_count()})\n")
    print(_row(["case", "paper", "locking-free", "ratio locking-free / paper"]))
    print("|---|---:|---:|---:|")
    for n in SIZES:
        a, b = best[n, False]["ms"], best[n, True]["ms"]
        print(_row([f"free cable, {n} elements: ms per force + tangent evaluation",
                    f"{a:.3f}", f"{b:.3f}", f"{b / a:.2f}"]))
    for case, steps in STEPS.items():
        a, b = best[case, False], best[case, True]
        print(_row([f"{case}: ms per step ({steps} steps; Newton iterations per step "
                    f"{a['newton']:.2f} / {b['newton']:.2f})",
                    f"{a['ms']:.3f}", f"{b['ms']:.3f}", f"{b['ms'] / a['ms']:.2f}"]))


def print_changes(rows, extra):
    """Print the result-difference table (section 6)."""
    print("\n### 6. Do the results change? Difference between the options and between "
          "meshes\n")
    print(f"Pendulum: 16 / 32 elements, 1 s (the tip travels {extra['tip_travel']:.2f} m); "
          f"E-sail: 5 / 10 elements, {extra['t_end']:.0f} s (one spin period; max |thrust| "
          f"{extra['thrust']:.3f} N, the hub centre travels {extra['hub_travel']:.3f} m).\n")
    print(_row(["scene", "quantity", "locking-free - paper (n)", "paper: 2n - n",
                "locking-free: 2n - n"]))
    print("|---|---|---:|---:|---:|")
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
    elastica_rows, catenary_rows, truss, (errors, ref, checks), strings, zeros = accuracy
    names = dict(OPTIONS)
    rows, extra = changes
    return {
        "elements": ELEMENTS,
        "elastica": [{"k": k, "option": names[lf], "floor": elastica_rows["floor"][k],
                      **{key: elastica_rows[key][k, lf]
                         for key in ("exact", "discretisation", "tension")}}
                     for k in LOADS for lf, _ in OPTIONS],
        "catenary": [{"case": case, "quantity": key, "option": names[lf], "errors": e}
                     for (case, key, lf), e in catenary_rows.items()],
        "truss_start": [{"n": n, "paper": a, "locking_free": b, "strain_min": low,
                         "strain_max": high} for n, (a, b, low, high) in truss.items()],
        "tether": {"reference_hz": ref, "checks": checks,
                   "errors": {names[lf]: e for lf, e in errors.items()}},
        "string": [{"law": kind, "option": names[lf], "errors": e}
                   for (kind, lf), e in strings.items()],
        "zero_modes": [{"law": law, "n": n, "paper": a, "lobatto": b, "gauss2": c}
                       for (law, n), (a, b, c) in zeros.items()],
        "cost": None if best is None else [{"case": case, "option": names[lf], **value}
                                           for (case, lf), value in best.items()],
        "changes": [{"scene": scene, "quantity": label, "options": a, "paper_2n_n": b,
                     "locking_free_2n_n": c} for (scene, label), (a, b, c) in rows.items()],
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
    catenary_rows = catenary_table()
    accuracy = (elastica_rows, catenary_rows, truss_start_check(), tether_table(),
                string_table(), zero_modes())
    print_accuracy(*accuracy)
    best = None if args.no_timing else costs(repeats, seconds)
    if best is not None:
        print_costs(best, repeats)
    changes = result_changes()
    print_changes(*changes)
    if args.plots is not None:
        figures(args.plots, elastica_rows, catenary_rows)
        print(f"\nfigures saved in {args.plots}")
    return records(accuracy, best, changes)


if __name__ == "__main__":
    main()
