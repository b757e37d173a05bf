"""A mooring line in a current, skfem_cable beside MoorDyn 2.7 (and an exact reference).

The scene is ``demos/mooring_current.py``: a line of 100 m (diameter 5 cm, 10 kg/m,
``EA = 1e7 N``, no bending stiffness) hanging in water (1025 kg/m^3) between two fixed
points at the same depth 80 m apart, Morison drag ``C_dn = 1.2``, ``C_dt = 0.1`` (on
``pi d``), no added mass, a uniform current of 1 m/s along the span switched on at
``t = 0`` on the line at rest in still water.

* Ours: ``solve_static`` of the settled state; the transient by ``simulate``
  (generalized-alpha, ``rho_inf = 0.8``, ``dt = 0.05 s``) from our still-water
  equilibrium.  Tensions: the magnitudes of the pins' reactions.
* MoorDyn: a line of N lumped-mass segments with the same diameter, mass, EA, EI = 0,
  ``Cd = 1.2``, ``CdAx = 0.1``, ``Ca = CaAx = 0``, axial damping at critical
  (``BA = -1``), the current given as external water kinematics (``WaveKin 1``) after
  its own still-water initial condition, RK4 at CFL 0.1 (at CFL 0.5 it blows up); run
  ``t_settle`` seconds to settle.  Tensions: the magnitudes of the end nodes' net forces
  (the segment tension plus the end node's share of weight and drag: the reaction of the
  support).
* Reference: the equilibrium equations of the extensible cable solved by
  ``scipy.integrate.solve_bvp`` to 1e-10 (``mooring_current.equilibrium``).

The table gives the settled end tensions, the sag and the midpoint of both codes and
their relative differences from the reference; the transient table the largest
difference between the codes over the samples (every 0.5 s) of the midpoint (relative to
its final displacement) and of the end tensions (relative to their final values).
Without ``moordyn`` (``pip install moordyn``) only our rows are printed.

Examples
--------
``python benchmarks/mooring_moordyn.py`` (about a minute),
``python benchmarks/mooring_moordyn.py --quick``,
``python benchmarks/mooring_moordyn.py --figure docs/figures/mooring_moordyn.png``.
"""

import argparse
import importlib.util
import os
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]


def load(path):
    """Import a script by its path (the demo, the peers' helpers)."""
    spec = importlib.util.spec_from_file_location(Path(path).stem, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


demo = load(ROOT / "demos" / "mooring_current.py")
peers = load(ROOT / "benchmarks" / "peers.py")

KEYS = ("tension_a", "tension_b", "sag", "mid_x", "mid_z")
SAMPLE = 0.5  # s between compared samples of the transient
DT = 0.05  # s, our time step
Z0 = -50.0  # depth of the supports in MoorDyn's frame (water surface z = 0)

MOORDYN_INPUT = """MoorDyn input: mooring line in a current (benchmarks/mooring_moordyn.py)
---------------------- LINE TYPES -----------------------------------
TypeName Diam Mass/m EA BA/-zeta EI Cd Ca CdAx CaAx
(name) (m) (kg/m) (N) (N-s/-) (N-m^2) (-) (-) (-) (-)
line {d!r} {mu!r} {EA!r} -1.0 0.0 {cdn!r} 0.0 {cdt!r} 0.0
---------------------- POINTS ---------------------------------------
ID Attachment X Y Z Mass Volume CdA Ca
(#) (word) (m) (m) (m) (kg) (m^3) (m^2) (-)
1 Fixed 0.0 0.0 {z0!r} 0 0 0 0
2 Fixed {span!r} 0.0 {z0!r} 0 0 0 0
---------------------- LINES ----------------------------------------
ID LineType AttachA AttachB UnstrLen NumSegs LineOutputs
(#) (name) (ID) (ID) (m) (-) (-)
1 line 1 2 {L!r} {n} -
---------------------- OPTIONS --------------------------------------
{g!r} g
{rho!r} rho
500.0 WtrDpth
1 WaveKin
0.1 CFL
RK4 tScheme
0 writeLog
1 disableOutput
---------------------- OUTPUTS --------------------------------------
---------------------------------------------------------------------
"""


def moordyn_input(n_segments, p=demo.LINE):
    """The MoorDyn input file of the scene (``x`` along the span, ``z`` up)."""
    return MOORDYN_INPUT.format(d=p["diameter"], mu=p["mass_per_length"], EA=p["EA"],
                                cdn=p["cd_normal"], cdt=p["cd_tangential"], z0=Z0,
                                span=p["span"], L=p["length"], n=n_segments, g=p["g"],
                                rho=p["rho_water"])


def moordyn_numbers(md, line, n):
    """The numbers of ``demo.numbers`` from MoorDyn's nodes (the lowest point from the
    parabola through the lowest node and its neighbours) and the node positions."""
    r = np.array([md.GetLineNodePos(line, i) for i in range(n + 1)]) - [0.0, 0.0, Z0]
    k = int(np.clip(np.argmin(r[:, 2]), 1, n - 1))
    zm, z0, zp = r[k - 1:k + 2, 2]
    low = z0 - (zp - zm) ** 2 / (8 * (zp - 2 * z0 + zm))
    mid = r[n // 2] if n % 2 == 0 else 0.5 * (r[n // 2] + r[n // 2 + 1])
    return {"tension_a": float(np.linalg.norm(md.GetLineNodeForce(line, 0))),
            "tension_b": float(np.linalg.norm(md.GetLineNodeForce(line, n))),
            "sag": float(-low), "mid_x": float(mid[0]), "mid_z": float(mid[2])}, r


def moordyn_run(md, n_segments, t_end):
    """MoorDyn's still-water state, the current switched on, ``t_end`` seconds sampled
    every ``SAMPLE``: ``(wall, history rows, final numbers, still and final nodes, dt)``."""
    with tempfile.TemporaryDirectory() as tmp, peers.quiet():
        path = os.path.join(tmp, "line.txt")
        with open(path, "w") as f:
            f.write(moordyn_input(n_segments))
        system = md.Create(path)
        try:
            md.Init(system, [], [])
            md.ExternalWaveKinInit(system)
            n_points = len(md.ExternalWaveKinGetCoordinates(system))
            current = [[demo.LINE["current"], 0.0, 0.0]] * n_points
            md.ExternalWaveKinSet(system, current, [[0.0, 0.0, 0.0]] * n_points, 0.0)
            line = md.GetLine(system, 1)
            numbers, still = moordyn_numbers(md, line, n_segments)
            history = [{"t": 0.0, **numbers}]
            start = time.perf_counter()
            for k in range(int(round(t_end / SAMPLE))):
                md.Step(system, [], [], k * SAMPLE, SAMPLE)
                history.append({"t": (k + 1) * SAMPLE, **moordyn_numbers(md, line,
                                                                          n_segments)[0]})
            wall = time.perf_counter() - start
            final, nodes = moordyn_numbers(md, line, n_segments)
            dt = peers.moordyn_dt(md, system)
        finally:
            md.Close(system)
    return wall, history, final, (still, nodes), dt


def ours_run(n_elements, t_end):
    """Our settled state and transient: ``(wall, history rows, settled numbers, still
    and settled shapes (x, z), t_settle)``."""
    state, line = demo.settled(n_elements)
    settled = demo.numbers(state, line)
    every = int(round(SAMPLE / DT))
    start = time.perf_counter()
    result, cable = demo.switched_on(n_elements, t_end, DT, every=every)
    wall = time.perf_counter() - start
    history = [{"t": float(t), **demo.numbers(result.state(i), cable)}
               for i, t in enumerate(result.t)]
    s = np.linspace(0.0, cable.length, 401)
    shapes = (result.state(0).position(cable, s), state.position(line, s))
    return wall, history, settled, shapes, result.stats["path"]


def transient_difference(ours, theirs):
    """Largest differences over common samples: midpoint (relative to its final
    displacement from the still-water midpoint) and end tensions (relative to the final
    tensions)."""
    n = min(len(ours), len(theirs))
    a, b = ours[:n], theirs[:n]
    scale = np.hypot(a[-1]["mid_x"] - a[0]["mid_x"], a[-1]["mid_z"] - a[0]["mid_z"])
    mid = max(np.hypot(x["mid_x"] - y["mid_x"], x["mid_z"] - y["mid_z"]) for x, y in zip(a, b))
    ten = max(abs(x[k] - y[k]) / a[-1][k] for x, y in zip(a, b) for k in KEYS[:2])
    return {"midpoint": mid / scale, "tension": ten}


def figure(path, ours, theirs):
    """Shapes (still water and settled), the displacement by the current along the line
    and the midpoint's downstream motion after the switch-on, of both codes."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax, cx, bx) = plt.subplots(1, 3, figsize=(14, 4.2))
    (still, settled), history = ours["shapes"], ours["history"]
    s = np.linspace(0.0, demo.LINE["length"], len(still))
    ax.plot(still[:, 0], still[:, 2], "C7-", label="ours, still water")
    ax.plot(settled[:, 0], settled[:, 2], "C0-", label="ours, settled")
    for k, c in ((0, "C0"), (2, "C2")):
        cx.plot(s, settled[:, k] - still[:, k], f"{c}-", label=f"ours, d{'xyz'[k]}")
    t = [h["t"] for h in history]
    bx.plot(t, [h["mid_x"] - demo.LINE["span"] / 2 for h in history], "C0-",
            label=f"ours ({ours['n']} elements)")
    if theirs is not None:
        md_still, md_settled = theirs["nodes"]
        n = len(md_still) - 1
        ax.plot(md_still[:, 0], md_still[:, 2], "C7o", ms=3, mfc="none",
                label="MoorDyn, still water")
        ax.plot(md_settled[:, 0], md_settled[:, 2], "C3o", ms=3, mfc="none",
                label="MoorDyn, settled")
        sn = np.linspace(0.0, demo.LINE["length"], n + 1)
        for k, c in ((0, "C3"), (2, "C1")):
            cx.plot(sn, md_settled[:, k] - md_still[:, k], f"{c}o", ms=3, mfc="none",
                    label=f"MoorDyn, d{'xyz'[k]}")
        th = theirs["history"]
        bx.plot([h["t"] for h in th], [h["mid_x"] - demo.LINE["span"] / 2 for h in th],
                "C3o", ms=3, mfc="none", label=f"MoorDyn ({theirs['n']} segments)")
    ax.set(xlabel="x (m)", ylabel="z (m)", aspect="equal", ylim=(-52, 5),
           title="shapes (current 1 m/s along +x)")
    cx.set(xlabel="unstretched arc length s (m)", ylabel="displacement (m)",
           title="settled minus still-water shape")
    bx.set(xlabel="t (s)", ylabel="midpoint x - span/2 (m)",
           title="current switched on at t = 0")
    for a in (ax, cx, bx):
        a.grid(alpha=0.3)
        a.legend(fontsize=8, loc="lower right" if a is not ax else "lower center",
                 ncol=1 if a is not ax else 2)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="10 elements, 20 segments, 20 s")
    parser.add_argument("--figure", metavar="PNG", help="write the figure of both codes")
    args = parser.parse_args(argv)
    n_el, segments, t_end = (10, (20,), 20.0) if args.quick else (20, (40, 80), 40.0)
    reference, _ = demo.equilibrium()
    wall, history, settled, shapes, path = ours_run(n_el, t_end)
    ours = {"n": n_el, "history": history, "shapes": shapes}
    rows = [{"code": "reference (solve_bvp)", **reference},
            {"code": f"ours, {n_el} elements", "wall_s": wall, "path": path, **settled}]
    md = peers.import_peer("moordyn")
    transients, theirs = [], None
    for n in segments if md is not None else ():
        md_wall, md_history, final, nodes, dt = moordyn_run(md, n, t_end)
        rows.append({"code": f"MoorDyn, {n} segments", "wall_s": md_wall, "dt": dt, **final})
        transients.append({"segments": n, **transient_difference(history, md_history)})
        theirs = {"n": n, "history": md_history, "nodes": nodes}
    for row in rows:
        row.update({f"err_{k}": row[k] / reference[k] - 1 for k in KEYS})
    print(f"\nsettled line in a 1 m/s current (ours: solve_static; MoorDyn: {t_end:g} s of "
          "dynamics after switch-on)")
    peers.print_table("", [], [("code", "code", "s"), *((k, k, ".5g") for k in KEYS),
                               *((f"err {k}", f"err_{k}", ".1e") for k in KEYS)], rows)
    if transients:
        peers.print_table(f"transient, 0-{t_end:g} s, samples every {SAMPLE} s: largest "
                          f"difference ours ({n_el} elements, dt = {DT} s) - MoorDyn",
                          ["midpoint: relative to its final displacement; tensions: "
                           "relative to their final values"],
                          [("MoorDyn segments", "segments", "d"),
                           ("midpoint", "midpoint", ".2e"), ("tensions", "tension", ".2e")],
                          transients)
    if args.figure:
        figure(args.figure, ours, theirs)
        print(f"\nfigure: {args.figure}")
    return rows + transients


if __name__ == "__main__":
    main()
