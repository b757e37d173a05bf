"""Speed and accuracy of skfem_cable side by side with its peers Exudyn and MoorDyn.

Each case builds one scene in our code and in a peer, runs both in the same process and
prints a table with the minimum wall time over ``--repeats`` runs, the accuracy and the
ratio ours/peer.  Machines are noisy: read the ratios, not the absolute times.  Nothing is
installed: a case whose peer does not import prints ``<peer> not importable: skipped``
(our rows of ``pendulum`` and ``esail_rig`` are still printed).  Our code is timed through
the public ``sc.simulate`` only (one untimed warm-up per system: kernels compiled, layout
built); the peers' model building and initialisation are not timed either.

Scenes
------
pendulum
    ``classics.pendulum(n_elements=16)``: a cable of length 1.2 m, radius 1 cm,
    E = 7e10 Pa, rho = 7800 kg/m^3, pinned (spherical joint) at one end and released at
    rest from horizontal under gravity 9.81 m/s^2; generalized-alpha, rho_inf = 0.8,
    h = 1e-3 s, 1000 steps.  Exudyn: 16 ``ObjectANCFCable`` elements (same EA, EI, rho A),
    mass-proportional gravity, a spherical joint to ground, generalized-alpha
    (spectralRadius 0.8), EigenSparse.  Accuracy: the tip at t = 1 s against our 32
    elements at dt = 2.5e-5 s (1e-4 s with ``--quick``).
esail_rig
    The E-sail of ``esail.build(BaselineConfig(), alpha_deg=10, n_elements=5)`` without
    the solar wind: a rigid cylindrical hub (5554 kg), 12 tethers of 10 km x 5 elements
    pinned to its rim, 1.5 kg remote units at their tips, Kelvin-Voigt damping 1 s, all in
    rigid spin 4e-3 rad/s about the hub axis from the steady stretched state; no external
    load; h = 0.1 s, rho_inf = 0.25, 400 steps (100 with ``--quick``).  Exudyn: an
    ``ObjectRigidBody`` hub (Euler parameters, same mass and inertia), ``ObjectANCFCable``
    tethers (axialDamping = gamma EA, bendingDamping = gamma EI), spherical joints at the
    rim, tip masses as ``ObjectGenericODE2`` mass matrices on the tip nodes, the same
    initial positions and rigid-rotation velocities.  Accuracy: mean tip radius at the end.
catenary
    A steel wire, 10 m long, radius 1 mm, E = 2e11 Pa (and E/100), rho = 7850 kg/m^3,
    g = 9.81 m/s^2, in vacuum, hangs in static equilibrium between two pins 8 m apart at
    the same height; the right end is released and swings for 2 s.  Ours: ``solve_static``
    of the cable pinned at both ends (started from the inextensible catenary), then
    ``simulate`` with only the left pin, rho_inf = 0.8, elements 4..64, dt 1e-2..5e-4 s;
    the same with the linear element (``element="linear"``, the truss law: the segment
    model of MoorDyn in our implicit integrator), 10..160 elements, dt 4e-3..1e-3 s.
    MoorDyn: one line of n = 10..160 lumped-mass segments with the same EA and EI, no
    fluid (water density 0, all drag and added-mass coefficients 0), a fixed anchor and a
    massless ``Free`` end point, RK4 at CFL 0.2 (its stable step).  Error: the largest tip
    distance from the reference (ours, 96 elements, dt = 5e-5 s; 48 elements, 2.5e-4 s
    with ``--quick``) over samples every 0.02 s; then, for each error level, the cheapest
    setting of each code that reaches it.  A third variant drops the bending (EI = 0 in
    MoorDyn, the truss law in ours) and adds our linear element, MoorDyn's segment model.
falling_wire
    The same wire without bending, pinned at one end and released straight and horizontal
    at rest: it falls and whips.  Ours: the linear element (10..160 elements) and the cubic
    one (4..64) with the truss law; MoorDyn: 10..160 segments, EI = 0, RK4 at CFL 0.2,
    started straight.  Error and fronts as for the catenary; reference: our linear element,
    640 elements, dt = 2.5e-4 s.

Notes
-----
* Newton tolerances.  Ours stops when the error left after a correction (estimated from
  the measured contraction, ``kernels.step``), or the scaled residual and the last
  correction, are below ``tol`` times the coordinate scale (the system size for
  positions).  Exudyn's
  default measures the L2 norm of the force residual (relative 1e-8 to the step's first
  residual, absolute 1e-10); the "matched" rows use its ``residualMode = 1`` (the L2 norm
  of the Newton increment, in metres) with both tolerances at our ``tol`` times the system
  size.  With its defaults Exudyn cannot converge the stiff pendulum (EA = 2.2e7 N): the
  force residual stalls at its round-off floor above 1e-8 of the first residual, Exudyn
  halves the step (adaptiveStep) down to about 2e-6 s, takes ~2e4 steps per 0.05 s and
  ends about 1 mm off the reference (generalized-alpha loses its order with varying
  steps).  That row is run once (about a minute; 0.01 s of it with ``--quick``).
* Exudyn's cable uses the engineering strain ``|r'| - 1`` and ``kappa = |r' x r''| /
  |r'|^2``, ours the Green strain ``(|r'|^2 - 1)/2`` and ``|r' x r''| / |r'|^3``: the
  difference is of the order of the strain.  In the pendulum (strain 1e-5) the tips agree
  to 3e-9 m.  In the E-sail (strain 9e-4) Exudyn's steady stretch is ``1.5 eps`` (1.2 cm)
  longer than ours: started from ours, its tethers ring axially about it and the mean tip
  radii differ by millimetres.
* MoorDyn in vacuum: its initial-condition solver relaxes with fluid drag and does not
  converge without it (a 20-segment line ends 0.4 m off the catenary), and its analytic
  catenary start ignores bending, which moves this wire's equilibrium by 4 mm near the
  pins.  Each MoorDyn run therefore starts from our reference static state sampled at its
  nodes (written into a state file saved by MoorDyn itself, then ``LoadState``); its own
  lumped-mass static error is part of its error.  Without any damping MoorDyn's default
  RK2 (even at CFL 0.05) and RK4 at CFL >= 0.25 blow up or drift for some n; RK4 at
  CFL 0.2 is stable for all n.  At the time steps tried our error is spatial: dt = 4e-3 s
  is as accurate as 2.5e-4 s, so our cheapest settings sit at the coarsest dt.
* Without bending (``E, no bending``: MoorDyn's EI = 0, our truss law; the reference our
  linear element, 640 elements, dt = 2.5e-4 s) the released end whips: the string's
  problem is not smooth there, and every code converges at first order in the element
  size.  Our linear element is the segment model of MoorDyn, integrated implicitly: at
  equal segments its error is about half MoorDyn's and, at MoorDyn's stable step, its
  cost a small fraction (``docs/elements.md``).
* MoorDyn with E/100 stalls at an error of about 6e-3 m for every n: at the release its
  lumped end node overshoots the continuum recoil speed ``eps c`` by about 45 % (a Gibbs
  effect of the lumped masses), the last segment goes slack, and its tension-only segments
  exert no compressive force, so the tip drifts inward (a straight released bar: tip speed
  0.173 m/s against eps c = 0.119 m/s, ours follows eps c).  At full E the recoil, and
  the stall, are 100 times smaller.

Examples
--------
``python benchmarks/peers.py`` (all cases, about 5 minutes),
``python benchmarks/peers.py --quick`` (under a minute),
``python benchmarks/peers.py catenary --repeats 5 --json runs/peers.json``.
"""

import argparse
import contextlib
import io
import json
import os
import struct
import sys
import tempfile
import time

import numpy as np
from scipy.optimize import brentq
from skfem import MeshLine

import skfem_cable as sc
from skfem_cable.scenes import classics, esail

CASES = ("pendulum", "esail_rig", "catenary", "falling_wire")
_CACHE = {}  # references computed once per run


# --- helpers --------------------------------------------------------------------------------
def import_peer(name):
    """The peer module ``name``, or None (with the skip message) if it does not import."""
    try:
        return __import__(name)
    except ImportError:
        print(f"{name} not importable: skipped")
        return None


@contextlib.contextmanager
def quiet():
    """Silence stdout, also of C/C++ code writing to file descriptor 1."""
    sys.stdout.flush()
    saved = os.dup(1)
    with open(os.devnull, "w") as null:
        os.dup2(null.fileno(), 1)
        try:
            with contextlib.redirect_stdout(io.StringIO()):
                yield
        finally:
            sys.stdout.flush()
            os.dup2(saved, 1)
            os.close(saved)


def best_of(repeats, run):
    """Call ``run() -> (wall, output)`` ``repeats`` times; the fastest ``(wall, output)``."""
    return min((run() for _ in range(max(1, repeats))), key=lambda r: r[0])


def timed(fn, *args, **kwargs):
    """``(wall time, fn(*args, **kwargs))``."""
    start = time.perf_counter()
    out = fn(*args, **kwargs)
    return time.perf_counter() - start, out


def record(case, code, setting, wall_s, error, **extra):
    """A result record (the JSON rows)."""
    return {"case": case, "code": code, "setting": setting, "wall_s": wall_s,
            "error": error, **extra}


def fmt(value, spec):
    """``value`` formatted, or a dash for None/NaN."""
    if value is None or (isinstance(value, float) and not np.isfinite(value)):
        return "—"
    return format(value, spec)


def print_table(title, notes, columns, rows):
    """Print ``rows`` (dicts) under ``title``; ``columns``: (header, key, format spec)."""
    print(f"\n{title}")
    for line in notes:
        print(f"  {line}")
    cells = [[fmt(row.get(key), spec) for _, key, spec in columns] for row in rows]
    widths = [max(len(h), *(len(c[i]) for c in cells)) for i, (h, _, _) in enumerate(columns)]
    print("  " + "  ".join(h.rjust(w) for (h, _, _), w in zip(columns, widths)))
    for c in cells:
        print("  " + "  ".join(v.rjust(w) for v, w in zip(c, widths)))


def jsonable(value):
    """``value`` with numpy scalars and arrays turned into Python numbers and lists."""
    if isinstance(value, dict):
        return {k: jsonable(v) for k, v in value.items()}
    if isinstance(value, list | tuple | np.ndarray):
        return [jsonable(v) for v in value]
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, float) and not np.isfinite(value):
        return None
    return value


# --- ours ------------------------------------------------------------------------------------
def run_ours(system, initial, t_end, dt, rho_inf, repeats, **options):
    """Warm up once (2 steps), then the fastest of ``repeats`` runs of ``sc.simulate``:
    ``(wall, Result)``."""
    sc.simulate(system, t_end=2 * dt, dt=dt, rho_inf=rho_inf, initial=initial,
                **{k: v for k, v in options.items() if k != "every"})
    return best_of(repeats, lambda: timed(sc.simulate, system, t_end=t_end, dt=dt,
                                          rho_inf=rho_inf, initial=initial, **options))


# --- Exudyn -----------------------------------------------------------------------------------
def exudyn_cable(exu, mbs, positions, slopes, section, element_length, velocities=None,
                 gravity=None):
    """ANCF cable elements through nodes at ``positions`` with ``slopes`` (n, 3); Kelvin-
    Voigt damping from ``section``; optional nodal velocities (n, 6) and gravity.
    Returns the node indices."""
    from exudyn import itemInterface as ii

    if velocities is None:
        velocities = np.zeros((len(positions), 6))
    nodes = [mbs.AddNode(ii.NodePointSlope1(referenceCoordinates=[*p, *s],
                                            initialVelocities=list(v)))
             for p, s, v in zip(positions, slopes, velocities)]
    for a, b in zip(nodes[:-1], nodes[1:]):
        element = mbs.AddObject(ii.ObjectANCFCable(
            length=element_length, massPerLength=section.mass_per_length,
            bendingStiffness=section.EI, axialStiffness=section.EA,
            bendingDamping=section.gamma_bending * section.EI,
            axialDamping=section.gamma_axial * section.EA, nodeNumbers=[a, b],
            visualization={"show": False, "radius": 0.0, "color": [-1.0] * 4}))
        if gravity is not None:
            marker = mbs.AddMarker(ii.MarkerBodyMass(bodyNumber=element))
            mbs.AddLoad(ii.LoadMassProportional(markerNumber=marker, loadVector=list(gravity)))
    return nodes


def exudyn_settings(exu, dt, steps, rho_inf, tol=None):
    """Generalized-alpha, EigenSparse, no files; ``tol`` None: Exudyn's default Newton,
    else the increment criterion (``residualMode = 1``) with both tolerances ``tol``."""
    s = exu.SimulationSettings()
    ti = s.timeIntegration
    ti.numberOfSteps = steps
    ti.endTime = dt * steps
    ti.generalizedAlpha.spectralRadius = rho_inf
    ti.verboseMode = 0
    s.linearSolver.solverType = exu.LinearSolverType.EigenSparse
    s.solution.file.write = False
    s.solution.sensors.active = False
    if tol is not None:
        ti.newton.residualMode = 1
        ti.newton.relativeTolerance = tol
        ti.newton.absoluteTolerance = tol
    return s


def exudyn_solve(exu, mbs, settings):
    """Integrate (silenced): ``(wall, {"steps", "newton", "jacobians", "ok"})``."""
    solver = exu.MainSolverImplicitSecondOrder()
    with quiet():
        wall, ok = timed(solver.SolveSystem, mbs, settings)
    it = solver.it
    return wall, {"steps": it.currentStepIndex - 1, "newton": it.newtonStepsCount,
                  "jacobians": it.newtonJacobiCount, "ok": bool(ok)}


def exudyn_position(exu, mbs, node):
    """Current global position of an Exudyn node."""
    return np.array(mbs.GetNodeOutput(node, exu.OutputVariableType.Position))


# --- case 1: pendulum ----------------------------------------------------------------------------
PENDULUM = {"n_elements": 16, "length": 1.2, "radius": 0.01, "E": 7e10, "rho": 7800.0,
            "g": 9.81}
PENDULUM_RUN = {"t_end": 1.0, "dt": 1e-3, "rho_inf": 0.8, "tol": 1e-10}


def pendulum_reference(quick):
    """Our tip at t = 1 s with 32 elements and dt = 2.5e-5 s (1e-4 s if ``quick``)."""
    dt = 1e-4 if quick else 2.5e-5
    key = ("pendulum", dt)
    if key not in _CACHE:
        scene = classics.pendulum(**{**PENDULUM, "n_elements": 32})
        wall, r = timed(sc.simulate, scene.system, t_end=1.0, dt=dt, rho_inf=0.8, tol=1e-10,
                        every=10**9, initial=scene.initial)
        _CACHE[key] = (r.position(scene.cable, scene.cable.length)[-1], dt, wall)
    return _CACHE[key]


def exudyn_pendulum(exu, scene, t_end, tol, repeats):
    """The pendulum in Exudyn: fastest ``(wall, stats)`` and the tip at ``t_end``."""
    cable, p = scene.cable, PENDULUM_RUN
    steps = int(round(t_end / p["dt"]))

    def once():
        from exudyn import itemInterface as ii

        mbs = exu.SystemContainer().AddSystem()
        nodes_q = cable.q0.reshape(-1, 2, 3)
        nodes = exudyn_cable(exu, mbs, nodes_q[:, 0], nodes_q[:, 1], cable.section,
                             cable.length / cable.n_elements, gravity=[0, -PENDULUM["g"], 0])
        ground = mbs.AddObject(ii.ObjectGround())
        m_ground = mbs.AddMarker(ii.MarkerBodyPosition(bodyNumber=ground, localPosition=[0] * 3))
        m_node = mbs.AddMarker(ii.MarkerNodePosition(nodeNumber=nodes[0]))
        mbs.AddObject(ii.ObjectJointSpherical(markerNumbers=[m_ground, m_node]))
        mbs.Assemble()
        wall, stats = exudyn_solve(exu, mbs, exudyn_settings(exu, p["dt"], steps,
                                                             p["rho_inf"], tol))
        return wall, (stats, exudyn_position(exu, mbs, nodes[-1]))

    return best_of(repeats, once)


def pendulum(quick=False, repeats=3):
    """Flexible pendulum, ours against Exudyn; prints the table, returns its rows."""
    p = PENDULUM_RUN
    ref, ref_dt, ref_wall = pendulum_reference(quick)
    scene = classics.pendulum(**PENDULUM)
    rows = []
    for setting, options in ((f"tol={p['tol']:g}", {}),
                             (f"tol={p['tol']:g}, tol_local=1e-2", {"tol_local": 1e-2})):
        wall, r = run_ours(scene.system, scene.initial, p["t_end"], p["dt"], p["rho_inf"],
                           repeats, tol=p["tol"], every=10**9, **options)
        tip = r.position(scene.cable, scene.cable.length)[-1]
        rows.append(record("pendulum", "ours", setting, wall,
                           float(np.linalg.norm(tip - ref)), steps=r.stats.get("steps"),
                           newton=r.stats.get("newton"), tip=tip[:2].tolist(),
                           t_end=p["t_end"]))
    exu = import_peer("exudyn")
    if exu is not None:
        tol = p["tol"] * PENDULUM["length"]
        default_t = 0.01 if quick else p["t_end"]
        for setting, tol_e, t_end, n in ((f"matched: increment <= {tol:.2g} m", tol,
                                          p["t_end"], repeats),
                                         ("default Newton (1 run)", None, default_t, 1)):
            w, (stats, tip_e) = exudyn_pendulum(exu, scene, t_end, tol_e, n)
            done = abs(t_end - p["t_end"]) < 1e-12
            rows.append(record("pendulum", "exudyn", setting, w,
                               float(np.linalg.norm(tip_e - ref)) if done else None,
                               steps=stats["steps"], newton=stats["newton"], t_end=t_end,
                               tip=tip_e[:2].tolist() if done else None))
    for row in rows:
        row["ms_per_step"] = 1e3 * row["wall_s"] / round(row["t_end"] / p["dt"])
        row["ratio"] = rows[0]["ms_per_step"] / row["ms_per_step"]
        row["tip_x"], row["tip_y"] = row["tip"] or (None, None)
    notes = [f"16 elements, h = {p['dt']:g} s, rho_inf = {p['rho_inf']}, t = 0..1 s; "
             f"reference: ours, 32 elements, dt = {ref_dt:g} s ({ref_wall:.0f} s), tip "
             f"({ref[0]:.8f}, {ref[1]:.8f})",
             f"Newton: ours stops at estimated error left < tol x 1.2 m; Exudyn "
             f"matched: L2 norm of the increment < {p['tol'] * 1.2:.2g} m (residualMode 1); "
             "Exudyn default: force residual < 1e-8 of the first (abs 1e-10), adaptive step",
             "ms/step: per nominal step of 1e-3 s; ratio = ours/peer ms per step"]
    if exu is not None and quick:
        notes.append("--quick: Exudyn default run for 0.01 s only")
    print_table("pendulum: flexible pendulum, ours vs Exudyn (ObjectANCFCable)", notes,
                [("code", "code", "s"), ("setting", "setting", "s"), ("steps", "steps", "d"),
                 ("wall [s]", "wall_s", ".3f"), ("ms/step", "ms_per_step", ".3f"),
                 ("Newton", "newton", "d"), ("tip x [m]", "tip_x", ".8f"),
                 ("tip y [m]", "tip_y", ".8f"), ("tip err [m]", "error", ".2e"),
                 ("ours/peer", "ratio", ".3g")], rows)
    if exu is not None and rows[2]["tip"] is not None:
        print(f"  Exudyn (matched) - ours, tip at t = 1 s: "
              f"{np.linalg.norm(np.subtract(rows[2]['tip'], rows[0]['tip'])):.2e} m; "
              f"ours with tol_local / Exudyn matched: "
              f"{rows[1]['ms_per_step'] / rows[2]['ms_per_step']:.3g}")
    return rows


# --- case 2: E-sail rig -----------------------------------------------------------------------
ESAIL_RUN = {"dt": 0.1, "rho_inf": 0.25, "steps": 400, "quick_steps": 100, "tol": 1e-11}


def esail_state(cfg, n_elements):
    """Hub data and, per tether, the radial direction and the steady stretched nodal
    positions, slopes (``esail.rotating_cable_stretch``) with the hub axis along x."""
    sec = cfg.section
    zeta = 2 * np.pi * np.arange(cfg.n_tethers) / cfg.n_tethers
    radial = np.column_stack([np.zeros_like(zeta), np.cos(zeta), np.sin(zeta)])
    s = np.linspace(0.0, cfg.tether_length, n_elements + 1)
    r, lam = esail.rotating_cable_stretch(s, cfg.hub_radius, cfg.tether_length, sec.EA,
                                          sec.mass_per_length, cfg.remote_mass, cfg.spin_rate)
    return s, radial, [(r[:, None] * e, lam[:, None] * e) for e in radial]


def esail_ours(cfg, n_elements):
    """The rig of ``esail.build`` without the ``SolarWindForce`` (the public API, hub axis
    along x: without loads the orientation does not matter): system, hub, tethers,
    initial state."""
    s, radial, nodes = esail_state(cfg, n_elements)
    hub = sc.RigidBody.cylinder(cfg.hub_radius, cfg.hub_height, cfg.hub_density, name="hub")
    tethers = [sc.Cable(MeshLine(s), cfg.section, pos, slope, name=f"tether{i + 1}")
               for i, (pos, slope) in enumerate(nodes)]
    system = sc.System([hub, *tethers])
    for cable, e in zip(tethers, radial):
        system.pin(cable.node(0), hub.point(cfg.hub_radius * e))
        system.add_point_mass(cable.node(-1), cfg.remote_mass)
    v0 = system.rigid_motion_velocity(system.q0, [cfg.spin_rate, 0.0, 0.0])
    return system, hub, tethers, sc.State(system, system.q0, v=v0)


def mean_tip_radius(centre, tips):
    """Mean distance of the tip positions from the hub centre."""
    return float(np.mean(np.linalg.norm(np.asarray(tips) - centre, axis=1)))


def exudyn_esail(exu, cfg, n_elements, steps, tol, repeats):
    """The rig in Exudyn: fastest ``(wall, (stats, mean tip radius))``."""
    from exudyn import itemInterface as ii
    from exudyn.rigidBodyUtilities import RigidBodyInertia

    hub_model = sc.RigidBody.cylinder(cfg.hub_radius, cfg.hub_height, cfg.hub_density)
    omega = np.array([cfg.spin_rate, 0.0, 0.0])

    def once():
        mbs = exu.SystemContainer().AddSystem()
        hub = mbs.CreateRigidBody(
            inertia=RigidBodyInertia(mass=hub_model.mass, inertiaTensor=hub_model.inertia),
            referencePosition=[0.0] * 3, initialAngularVelocity=list(omega),
            nodeType=exu.NodeType.RotationEulerParameters, returnDict=True, show=False)
        _, radial, nodes = esail_state(cfg, n_elements)
        tips = []
        for e, (pos, slope) in zip(radial, nodes):
            vel = np.hstack([np.cross(omega, pos), np.cross(omega, slope)])
            ids = exudyn_cable(exu, mbs, pos, slope, cfg.section,
                               cfg.tether_length / n_elements, velocities=vel)
            rim = mbs.AddMarker(ii.MarkerBodyPosition(bodyNumber=hub["bodyNumber"],
                                                      localPosition=list(cfg.hub_radius * e)))
            root = mbs.AddMarker(ii.MarkerNodePosition(nodeNumber=ids[0]))
            mbs.AddObject(ii.ObjectJointSpherical(markerNumbers=[rim, root]))
            m = cfg.remote_mass
            mbs.AddObject(ii.ObjectGenericODE2(nodeNumbers=[ids[-1]],
                                               massMatrix=np.diag([m, m, m, 0.0, 0.0, 0.0])))
            tips.append(ids[-1])
        mbs.Assemble()
        wall, stats = exudyn_solve(exu, mbs, exudyn_settings(
            exu, ESAIL_RUN["dt"], steps, ESAIL_RUN["rho_inf"], tol))
        centre = exudyn_position(exu, mbs, hub["nodeNumber"])
        return wall, (stats, mean_tip_radius(centre, [exudyn_position(exu, mbs, t)
                                                      for t in tips]))

    return best_of(repeats, once)


def esail_rig(quick=False, repeats=3, n_elements=5):
    """E-sail rig without solar wind, ours against Exudyn; prints the table, returns its
    rows."""
    p, cfg = ESAIL_RUN, esail.BaselineConfig()
    steps = p["quick_steps"] if quick else p["steps"]
    system, hub, tethers, initial = esail_ours(cfg, n_elements)
    wall, r = run_ours(system, initial, steps * p["dt"], p["dt"], p["rho_inf"], repeats,
                       tol=p["tol"], every=steps)
    q = r.q[-1]
    centre = hub.positions(q[system.dofs(hub)], np.zeros(3))
    radius = mean_tip_radius(centre, [r.position(c, c.length)[-1] for c in tethers])
    rows = [record("esail_rig", "ours", f"tol={p['tol']:g}", wall, 0.0, steps=steps,
                   newton=r.stats.get("newton"), tip_radius=radius)]
    exu = import_peer("exudyn")
    if exu is not None:
        size = 2 * (cfg.tether_length + cfg.hub_radius)
        tol = p["tol"] * size
        for setting, tol_e in ((f"matched: increment <= {tol:.2g} m", tol),
                               ("default Newton", None)):
            w, (stats, rad) = exudyn_esail(exu, cfg, n_elements, steps, tol_e, repeats)
            rows.append(record("esail_rig", "exudyn", setting, w, abs(rad - radius),
                               steps=stats["steps"], newton=stats["newton"], tip_radius=rad))
    for row in rows:
        row["ms_per_step"] = 1e3 * row["wall_s"] / steps
        row["ratio"] = rows[0]["ms_per_step"] / row["ms_per_step"]
        row["diff_mm"] = 1e3 * (row["tip_radius"] - radius)
    notes = [f"12 tethers x {n_elements} elements, rigid hub, tip masses, no solar wind; "
             f"h = {p['dt']} s, rho_inf = {p['rho_inf']}, {steps} steps",
             f"Newton: ours tol = {p['tol']:g} x system size; Exudyn matched: L2 norm of "
             "the increment (residualMode 1); default: force residual 1e-8 relative",
             "tip radius: mean distance of the 12 tips from the hub centre at the end; "
             "ratio = ours/peer ms per step"]
    print_table("esail_rig: E-sail rig without solar wind, ours vs Exudyn", notes,
                [("code", "code", "s"), ("setting", "setting", "s"), ("steps", "steps", "d"),
                 ("wall [s]", "wall_s", ".3f"), ("ms/step", "ms_per_step", ".3f"),
                 ("Newton", "newton", "d"), ("tip radius [m]", "tip_radius", ".6f"),
                 ("- ours [mm]", "diff_mm", "+.2f"), ("ours/peer", "ratio", ".3g")], rows)
    return rows


# --- case 3: released catenary ------------------------------------------------------------------
WIRE = {"length": 10.0, "span": 8.0, "radius": 1e-3, "E": 2e11, "rho": 7850.0, "g": 9.81}
CATENARY_RUN = {"t_end": 2.0, "sample": 0.02, "rho_inf": 0.8}
CATENARY_GRID = {
    "full": {"elements": (4, 8, 16, 32, 48, 64), "dts": (1e-2, 5e-3, 4e-3, 2e-3, 1e-3, 5e-4),
             "linear": (10, 20, 40, 80, 160), "linear_dts": (4e-3, 2e-3, 1e-3),
             "segments": (10, 20, 40, 80, 160), "reference": (96, 5e-5)},
    "quick": {"elements": (4, 8, 16), "dts": (2e-3, 1e-3, 5e-4),
              "linear": (10, 20, 40), "linear_dts": (2e-3, 1e-3),
              "segments": (10, 20, 40), "reference": (48, 2.5e-4)},
}
#: Our codes in the catenary case: the cubic ANCF cable and the linear element (the
#: segment model of lumped-mass codes, ``element="linear"``, no bending: run in the
#: variant without bending only), and their grids' keys.
OUR_ELEMENTS = {"ours": ("hermite3", "elements", "dts"),
                "ours-linear": ("linear", "linear", "linear_dts")}
#: The catenary's variants: (stiffness factor, bending); without bending the wire is a
#: string (EI = 0 in MoorDyn, the truss law in ours) and the reference is the linear
#: element, fine (``LINEAR_REFERENCE``).
CATENARY_VARIANTS = ((1.0, True), (0.01, True), (1.0, False))
LINEAR_REFERENCE = {"full": (640, 2.5e-4), "quick": (160, 5e-4)}
LEVELS = (3e-2, 1e-2, 3e-3, 1e-3)
#: Error levels (m) of the falling wire, whose whipping end no code resolves as finely.
FALLING_LEVELS = (3e-1, 1e-1, 3e-2, 1e-2)
MOORDYN_CFL, MOORDYN_SCHEME = 0.2, "RK4"


def catenary_guess(s):
    """Inextensible catenary through (0, 0) and (span, 0) of the wire's length at arc
    lengths ``s``: positions and unit tangents (n, 3) in the x-y plane (gravity -y)."""
    L, span = WIRE["length"], WIRE["span"]
    x = brentq(lambda x: np.sinh(x) / x - L / span, 1e-9, 20.0)
    a = span / (2 * x)
    u = np.arcsinh((s - L / 2) / a)  # (X - span/2) / a
    X, Y = span / 2 + a * u, a * (np.cosh(u) - np.cosh(x))
    t = np.column_stack([1 / np.cosh(u), np.tanh(u), 0 * u])
    return np.column_stack([X, Y, 0 * u]), t


def catenary_ours(n_elements, stiffness, element="hermite3", bending=True):
    """Static equilibrium pinned at both ends, then the released system: ``(system,
    cable, static State)``; ``element``: the cable's element type; without ``bending``
    the truss law (the linear element's only one)."""
    w = WIRE
    sec = sc.Section.circular(radius=w["radius"], E=w["E"] * stiffness, rho=w["rho"])
    s = np.linspace(0.0, w["length"], n_elements + 1)
    cable = sc.Cable(MeshLine(s), sec, *catenary_guess(s), element=element,
                     law=None if bending else "truss")
    hanging = sc.System([cable]).pin(cable.node(0)).pin(cable.node(-1))
    static = sc.solve_static(hanging.add_gravity([0, -w["g"], 0]))
    released = sc.System([cable]).pin(cable.node(0)).add_gravity([0, -w["g"], 0])
    return released, cable, static


def catenary_run_ours(n_elements, dt, stiffness, repeats, element="hermite3", bending=True):
    """Fastest ``(wall, tip positions (x, y) at the samples)`` of the released swing."""
    p = CATENARY_RUN
    system, cable, static = catenary_ours(n_elements, stiffness, element, bending)
    initial = (static.q, np.zeros_like(static.q))
    wall, r = run_ours(system, initial, p["t_end"], dt, p["rho_inf"], repeats,
                       every=int(round(p["sample"] / dt)))
    return wall, r.position(cable, cable.length)[:, :2]


def catenary_reference(quick, stiffness, bending=True):
    """Reference tips and static shape ``s -> (x, y)`` (ours, fine: the cubic element,
    or without bending the linear one), cached."""
    grade = "quick" if quick else "full"
    n, dt = CATENARY_GRID[grade]["reference"] if bending else LINEAR_REFERENCE[grade]
    element = "hermite3" if bending else "linear"
    key = ("catenary", n, dt, stiffness, bending)
    if key not in _CACHE:
        wall, tips = catenary_run_ours(n, dt, stiffness, 1, element, bending)
        _, cable, static = catenary_ours(n, stiffness, element, bending)
        _CACHE[key] = (tips, lambda s: static.position(cable, s)[:, :2], (n, dt, wall))
    return _CACHE[key]


MOORDYN_INPUT = """MoorDyn input: released catenary in vacuum (written by benchmarks/peers.py)
---------------------- LINE TYPES -----------------------------------
TypeName Diam Mass/m EA BA/-zeta EI Cd Ca CdAx CaAx
(name) (m) (kg/m) (N) (N-s/-) (N-m^2) (-) (-) (-) (-)
wire {d!r} {mu!r} {EA!r} 0.0 {EI!r} 0.0 0.0 0.0 0.0
---------------------- POINTS ---------------------------------------
ID Attachment X Y Z Mass Volume CdA Ca
(#) (word) (m) (m) (m) (kg) (m^3) (m^2) (-)
1 Fixed 0.0 0.0 {z0!r} 0 0 0 0
2 Free {span!r} 0.0 {z0!r} 0 0 0 0
---------------------- LINES ----------------------------------------
ID LineType AttachA AttachB UnstrLen NumSegs LineOutputs
(#) (name) (ID) (ID) (m) (-) (-)
1 wire 1 2 {L!r} {n} -
---------------------- OPTIONS --------------------------------------
{g!r} g
0.0 rho
100.0 WtrDpth
{cfl!r} CFL
{scheme} tScheme
0 writeLog
1 disableOutput
---------------------- OUTPUTS --------------------------------------
---------------------------------------------------------------------
"""
MOORDYN_Z0 = -10.0  # the scene hangs below MoorDyn's water surface z = 0 (no water: rho = 0)


def moordyn_input(n_segments, stiffness, bending=True, span=None):
    """The MoorDyn input file of the wire (x-z plane, z up), its free end ``span`` (default
    the catenary's) from the anchor."""
    w = WIRE
    area, E = np.pi * w["radius"] ** 2, w["E"] * stiffness
    return MOORDYN_INPUT.format(d=2 * w["radius"], mu=w["rho"] * area, EA=E * area,
                                EI=E * np.pi * w["radius"] ** 4 / 4 if bending else 0.0,
                                z0=MOORDYN_Z0,
                                span=w["span"] if span is None else span, L=w["length"],
                                n=n_segments, g=w["g"],
                                cfl=MOORDYN_CFL, scheme=MOORDYN_SCHEME)


def moordyn_load_positions(md, system, path, positions):
    """Set the inner line nodes of ``system`` to ``positions`` (n - 1, 3) at rest: save
    its state, replace the line block (the last one, rows: nodes, columns: position and
    velocity) and load it back."""
    md.SaveState(system, path)
    with open(path, "rb") as f:
        data = f.read()
    head, (size, count), offset, blocks = data[:9], struct.unpack("<QQ", data[9:25]), 25, []
    for _ in range(count):
        rows, cols = struct.unpack("<QQ", data[offset:offset + 16])
        offset += 16
        blocks.append(np.frombuffer(data[offset:offset + 8 * rows * cols]).reshape(rows, cols))
        offset += 8 * rows * cols
    if blocks[-1].shape != (len(positions), 6):
        raise RuntimeError(f"unexpected MoorDyn state layout {[b.shape for b in blocks]}")
    blocks[-1] = np.hstack([positions, np.zeros_like(positions)])
    with open(path, "wb") as f:
        f.write(head + struct.pack("<QQ", size, count))
        for block in blocks:
            f.write(struct.pack("<QQ", *block.shape) + np.ascontiguousarray(block).tobytes())
    md.LoadState(system, path)


def moordyn_dt(md, system):
    """MoorDyn's time step (``moordyn.GetDt`` 2.7 drops the value: ask its C module)."""
    dt = md.GetDt(system)
    if dt is None:
        import cmoordyn

        dt = cmoordyn.get_dt(system)
    return dt


def moordyn_swing(md, n_segments, stiffness, shape, bending=True, span=None):
    """One released swing in MoorDyn from the ``shape`` at rest (``s -> (x, y)``, its end
    at ``span``, default the catenary's): ``(wall, tips (x, y), dt)``; raises
    RuntimeError if it blows up."""
    p, w = CATENARY_RUN, WIRE
    with tempfile.TemporaryDirectory() as tmp, quiet():
        path = os.path.join(tmp, "wire.txt")
        with open(path, "w") as f:
            f.write(moordyn_input(n_segments, stiffness, bending, span))
        system = md.Create(path)
        try:
            md.Init_NoIC(system, [], [])
            xy = shape(np.arange(1, n_segments) * w["length"] / n_segments)
            nodes = np.column_stack([xy[:, 0], 0 * xy[:, 0], xy[:, 1] + MOORDYN_Z0])
            moordyn_load_positions(md, system, os.path.join(tmp, "state.bin"), nodes)
            dt, point = moordyn_dt(md, system), md.GetPoint(system, 2)
            tips = [md.GetPointPos(point)]
            start = time.perf_counter()
            for k in range(int(round(p["t_end"] / p["sample"]))):
                md.Step(system, [], [], k * p["sample"], p["sample"])
                tips.append(md.GetPointPos(point))
            wall = time.perf_counter() - start
        finally:
            md.Close(system)
    tips = np.asarray(tips) - [0.0, 0.0, MOORDYN_Z0]
    return wall, (tips[:, [0, 2]], dt)


def catenary_label(stiffness, bending):
    """``E``, ``E/100``, ``E, no bending``."""
    return ("E" if stiffness == 1 else f"E/{1 / stiffness:g}") + ("" if bending
                                                                   else ", no bending")


def catenary_sweep(md, quick, stiffness, repeats, bending=True):
    """Every setting of every code for one variant: rows with wall time and error."""
    grid = CATENARY_GRID["quick" if quick else "full"]
    ref, shape, _ = catenary_reference(quick, stiffness, bending)
    label = catenary_label(stiffness, bending)
    rows = []
    for code, (element, counts, dts) in OUR_ELEMENTS.items():
        if bending and element == "linear":
            continue
        for n in grid[counts]:
            for dt in grid[dts]:
                wall, tips = catenary_run_ours(n, dt, stiffness, repeats, element, bending)
                rows.append(record("catenary", code, f"{n} el, dt={dt:g}", wall,
                                   float(np.linalg.norm(tips - ref, axis=1).max()),
                                   stiffness=label, elements=n, dt=dt))
    for n in grid["segments"] if md is not None else ():
        try:
            wall, (tips, dt) = best_of(repeats, lambda n=n: moordyn_swing(
                md, n, stiffness, shape, bending))
            err = float(np.linalg.norm(tips - ref, axis=1).max())
        except RuntimeError:
            wall, dt, err = float("nan"), float("nan"), float("inf")
        rows.append(record("catenary", "moordyn",
                           f"{n} seg, {MOORDYN_SCHEME} dt={dt:.2g}", wall, err,
                           stiffness=label, segments=n, dt=dt))
    return rows


def cheapest(rows, code, level):
    """The fastest row of ``code`` with error <= ``level``, or None."""
    fits = [r for r in rows if r["code"] == code and r["error"] <= level]
    return min(fits, key=lambda r: r["wall_s"]) if fits else None


def catenary_front(rows, label, with_peer, case="catenary", levels=LEVELS):
    """For each error level the cheapest setting of each code and the ratio."""
    front = []
    for level in levels:
        ours, peer = cheapest(rows, "ours", level), cheapest(rows, "moordyn", level)
        linear = cheapest(rows, "ours-linear", level)
        front.append(record(
            case, "front", f"{label}, error <= {level:g} m", None, level,
            stiffness=label, ours=ours and ours["setting"], ours_wall=ours and ours["wall_s"],
            linear=linear["setting"] if linear else "—",
            linear_wall=linear and linear["wall_s"],
            moordyn=peer["setting"] if peer else ("—" if with_peer else "skipped"),
            moordyn_wall=peer and peer["wall_s"],
            ratio=ours["wall_s"] / peer["wall_s"] if ours and peer else None,
            linear_ratio=linear["wall_s"] / peer["wall_s"] if linear and peer else None))
    return front


def catenary(quick=False, repeats=3):
    """Released catenary, ours against MoorDyn, at E and E/100 (with bending: our cubic
    element) and at E without bending (a string: our cubic and linear elements, MoorDyn
    with EI = 0); prints the tables, returns the rows (every setting and the fronts)."""
    md = import_peer("moordyn")
    rows = []
    for stiffness, bending in CATENARY_VARIANTS:
        label = catenary_label(stiffness, bending)
        sweep = catenary_sweep(md, quick, stiffness, repeats, bending)
        _, _, (n, dt, wall) = catenary_reference(quick, stiffness, bending)
        notes = [f"wire 10 m, r = 1 mm, {label}: E = {WIRE['E'] * stiffness:.3g} Pa, span 8 m, "
                 "released right end, 2 s in vacuum; wall: the 2 s of dynamics only",
                 f"error: max over 0.02 s samples of |tip - reference|; reference: ours, "
                 f"{n} {'cubic' if bending else 'linear'} elements, dt = {dt:g} s "
                 f"({wall:.0f} s)",
                 f"ours: rho_inf = {CATENARY_RUN['rho_inf']}, default tol; MoorDyn: "
                 f"{MOORDYN_SCHEME}, CFL {MOORDYN_CFL}, started from the reference static state"]
        print_table(f"catenary ({label}): every setting", notes,
                    [("code", "code", "s"), ("setting", "setting", "s"),
                     ("wall [s]", "wall_s", ".3f"), ("max tip err [m]", "error", ".2e")],
                    sweep)
        front = catenary_front(sweep, label, md is not None)
        print_table(f"catenary ({label}): cheapest setting per error level", [],
                    [("error <=", "error", "g"), ("ours (cubic)", "ours", "s"),
                     ("wall [s]", "ours_wall", ".3f"), ("ours (linear)", "linear", "s"),
                     ("wall [s]", "linear_wall", ".3f"), ("MoorDyn", "moordyn", "s"),
                     ("wall [s]", "moordyn_wall", ".3f"), ("cubic/MoorDyn", "ratio", ".3f"),
                     ("linear/MoorDyn", "linear_ratio", ".3f")],
                    front)
        rows += sweep + front
    return rows


# --- case 4: falling wire ---------------------------------------------------------------------
def falling_run_ours(n_elements, dt, element, repeats):
    """The wire pinned at one end, released straight and horizontal at rest, in ours (the
    truss law): fastest ``(wall, tip positions (x, y) at the samples)``."""
    w, p = WIRE, CATENARY_RUN
    section = sc.Section.circular(radius=w["radius"], E=w["E"], rho=w["rho"])
    cable = sc.Cable.straight([0, 0, 0], [w["length"], 0, 0], n_elements, section,
                              element=element, law="truss")
    system = sc.System([cable]).pin(cable.node(0)).add_gravity([0, -w["g"], 0])
    wall, r = run_ours(system, None, p["t_end"], dt, p["rho_inf"], repeats,
                       every=int(round(p["sample"] / dt)))
    return wall, r.position(cable, cable.length)[:, :2]


def falling_wire(quick=False, repeats=3, ours=tuple(OUR_ELEMENTS)):
    """The catenary's wire without bending, pinned at one end and released straight and
    horizontal at rest (a falling wire, the whip at its end): our linear and cubic
    elements (the codes ``ours`` of ``OUR_ELEMENTS``, default both) against MoorDyn (EI =
    0), the reference our linear element, fine (``LINEAR_REFERENCE``); prints the tables,
    returns the rows."""
    md = import_peer("moordyn")
    grade = "quick" if quick else "full"
    grid = CATENARY_GRID[grade]
    n_ref, dt_ref = LINEAR_REFERENCE[grade]
    ref_wall, ref = falling_run_ours(n_ref, dt_ref, "linear", 1)
    rows = []
    for code in ours:
        element, counts, dts = OUR_ELEMENTS[code]
        for n in grid[counts]:
            for dt in grid[dts]:
                wall, tips = falling_run_ours(n, dt, element, repeats)
                rows.append(record("falling_wire", code, f"{n} el, dt={dt:g}", wall,
                                   float(np.linalg.norm(tips - ref, axis=1).max()),
                                   elements=n, dt=dt))
    length = WIRE["length"]
    for n in grid["segments"] if md is not None else ():
        try:
            wall, (tips, dt) = best_of(repeats, lambda n=n: moordyn_swing(
                md, n, 1.0, lambda s: np.column_stack([s, 0 * s]), False, length))
            err = float(np.linalg.norm(tips - ref, axis=1).max())
        except RuntimeError:
            wall, dt, err = float("nan"), float("nan"), float("inf")
        rows.append(record("falling_wire", "moordyn", f"{n} seg, {MOORDYN_SCHEME} dt={dt:.2g}",
                           wall, err, segments=n, dt=dt))
    notes = ["wire 10 m, r = 1 mm, E = 2e11 Pa, no bending, pinned at one end, released "
             "straight and horizontal at rest, 2 s in vacuum; wall: the 2 s of dynamics",
             f"error: max over 0.02 s samples of |tip - reference|; reference: ours, {n_ref} "
             f"linear elements, dt = {dt_ref:g} s ({ref_wall:.0f} s)",
             f"ours: the truss law, rho_inf = {CATENARY_RUN['rho_inf']}; MoorDyn: "
             f"{MOORDYN_SCHEME}, CFL {MOORDYN_CFL}, EI = 0"]
    print_table("falling wire: every setting", notes,
                [("code", "code", "s"), ("setting", "setting", "s"),
                 ("wall [s]", "wall_s", ".3f"), ("max tip err [m]", "error", ".2e")], rows)
    front = catenary_front(rows, "falling wire", md is not None, case="falling_wire",
                           levels=FALLING_LEVELS)
    print_table("falling wire: cheapest setting per error level", [],
                [("error <=", "error", "g"), ("ours (cubic)", "ours", "s"),
                 ("wall [s]", "ours_wall", ".3f"), ("ours (linear)", "linear", "s"),
                 ("wall [s]", "linear_wall", ".3f"), ("MoorDyn", "moordyn", "s"),
                 ("wall [s]", "moordyn_wall", ".3f"), ("cubic/MoorDyn", "ratio", ".3f"),
                 ("linear/MoorDyn", "linear_ratio", ".3f")], front)
    return rows + front


# --- driver ---------------------------------------------------------------------------------------
def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("cases", nargs="*", metavar="case",
                        help=f"any of {', '.join(CASES)} (default: all)")
    parser.add_argument("--quick", action="store_true", help="small settings, < 1 minute")
    parser.add_argument("--repeats", type=int, default=None,
                        help="timed runs per setting, minimum reported (default 3; 1 with "
                             "--quick)")
    parser.add_argument("--json", metavar="PATH", help="write the records as a JSON list")
    args = parser.parse_args(argv)
    unknown = sorted(set(args.cases) - set(CASES))
    if unknown:
        parser.error(f"unknown case(s) {', '.join(unknown)}: choose from {', '.join(CASES)}")
    repeats = args.repeats if args.repeats is not None else (1 if args.quick else 3)
    print(f"peers benchmark ({'quick' if args.quick else 'full'}, {repeats} repeats, "
          f"{os.cpu_count()} CPUs)")
    start, rows = time.perf_counter(), []
    for case in args.cases or CASES:
        rows += globals()[case](quick=args.quick, repeats=repeats)
    print(f"\ntotal {time.perf_counter() - start:.0f} s")
    if args.json:
        with open(args.json, "w") as f:
            json.dump(jsonable(rows), f, indent=1)
    return rows


if __name__ == "__main__":
    main()
