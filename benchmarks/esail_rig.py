"""The full E-sail rig (``esail.FULL_RIG``: 100 tethers of 20 km, a remote unit at each
tip, the ring of auxiliary tethers) against the full-size sail without them (issue 51,
items 2 and 6).

1. The steady spin under the wind (``rig.steady_facing``, at 10 deg): the auxiliary
   tethers' tension against the design's, and the spread of the tethers' coning angles.
2. Cost per step: fixed 5 s steps from the windless spin (``bench``'s full-size case),
   CPU time (``time.process_time``) and wall time, minimum of alternating repeats, rig and
   sail side by side, on one and on two threads (``SKFEM_CABLE_THREADS``, the scenes built
   for each), and the linear solver each gets (method, band half-width, border, levels:
   the ring's tips make the two-level Schur LU of ``kernels.schur``).
3. A day: the cost per step on two threads times the 3284 adaptive steps the full-size
   sail takes for a day at ``esail.MISSION_RTOL`` (``docs/benchmarks.md``), an
   extrapolation that assumes the rig takes as many; and the day run (adaptive steps at
   ``esail.MISSION_RTOL`` from the rig's state under the wind, ``esail.settled``, on two
   threads): its steps, CPU and wall time.  (Parts 3 and 4 run on two threads: the
   results are the same on any number.)
4. Neighbouring remote units under on-off modulation (``esail.modulation``: neighbours
   in antiphase) for one spin period from the state under the wind (``esail.settled``,
   one spin period of relaxation), with and without the ring: the least distance over
   the run over the nominal spacing.

    OPENBLAS_NUM_THREADS=1 .venv/bin/python benchmarks/esail_rig.py [--quick]
"""

import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

import skfem_cable as sc
from skfem_cable.cli.bench import arguments
from skfem_cable.core import linalg
from skfem_cable.core.linalg import PatternSolver
from skfem_cable.scenes import esail
from skfem_cable.scenes.esail.modulation import spacing_under_modulation
from skfem_cable.scenes.esail.rig import steady_facing

sys.path.insert(0, str(Path(__file__).resolve().parent / "lib"))
from threads import thread_count  # noqa: E402

#: Steps of a simulated day of the full-size sail at ``esail.MISSION_RTOL`` from its
#: state under the wind (``docs/benchmarks.md``, "Mission-length runs").
DAY_STEPS = 3284

SETTINGS = {"full": {"elements": 10, "steps": 60, "repeats": 5, "per_spin": 180,
                     "day": 86400.0},
            "quick": {"elements": 3, "steps": 6, "repeats": 2, "per_spin": 30,
                      "tethers": 24, "day": 600.0}}



def solver(scene):
    """The linear solver the system's iteration matrix gets: method, band, border,
    levels."""
    lay = scene.system.current_layout()
    s = PatternSolver(lay.indptr, lay.indices, border=lay.border, junctions=lay.junctions)
    return {"unknowns": lay.N, "method": s.method, "band": s.band, "border": s.border,
            "levels": s.levels}


def per_step(scenes, steps, repeats, dt=5.0):
    """CPU and wall ms per step of ``steps`` fixed steps of ``dt`` for each scene (name
    -> scene), each the minimum over ``repeats`` runs taken alternately."""
    best = {name: np.full(2, np.inf) for name in scenes}
    for _ in range(repeats):
        for name, scene in scenes.items():
            start = np.array([time.process_time(), time.perf_counter()])
            sc.simulate(scene.system, steps * dt, dt, initial=scene.initial, rho_inf=0.25,
                        every=10**9)
            spent = np.array([time.process_time(), time.perf_counter()]) - start
            best[name] = np.minimum(best[name], spent)
    return {name: {"cpu": 1e3 * t[0] / steps, "wall": 1e3 * t[1] / steps}
            for name, t in best.items()}


def costs(scenes, build, s):
    """``per_step`` of the sail and the rig (``scenes``, built on one thread) on one
    thread and, built again by ``build()`` (the element loops take the thread count when
    the layout is built), on two; and the scenes built for two."""
    cost = {}
    for threads in (1, 2):
        with thread_count(threads):
            scenes = scenes if threads == 1 else build()
            per_step(scenes, 2, 1)  # compiles both
            cost[threads] = per_step(scenes, s["steps"], s["repeats"])
        for name, row in cost[threads].items():
            print(f"{threads} thread(s), {name}: CPU {row['cpu']:.2f} ms per 5 s step, wall "
                  f"{row['wall']:.2f} ms (min of {s['repeats']})")
        print(f"{threads} thread(s): rig / sail, CPU "
              f"{cost[threads]['rig']['cpu'] / cost[threads]['sail']['cpu']:.2f}, wall "
              f"{cost[threads]['rig']['wall'] / cost[threads]['sail']['wall']:.2f}")
    return cost, scenes


#: Every how many steps the day run saves the state, for the ring's tension over the day.
DAY_EVERY = 10


def day(scene, t_end):
    """``scene`` (from its state under the wind) for ``t_end`` at ``esail.MISSION_RTOL``:
    steps, CPU and wall seconds, and the auxiliary tethers' tension (N) at every
    ``DAY_EVERY``-th step (least, median, largest, and the share of them slack)."""
    clock = time.process_time(), time.perf_counter()
    result = sc.simulate(scene.system, t_end, 1.0, initial=scene.initial, rho_inf=0.25,
                         rtol=esail.MISSION_RTOL, atol=1e-3, every=DAY_EVERY)
    cpu, wall = time.process_time() - clock[0], time.perf_counter() - clock[1]
    tension = np.array([esail.auxiliary_tension(scene, q) for q in result.q])
    ring = {"least": tension.min(), "median": float(np.median(tension)),
            "largest": tension.max(), "slack": float(np.mean(tension == 0.0))}
    print(f"{t_end:.0f} s of the rig at rtol {esail.MISSION_RTOL:g} on "
          f"{linalg.thread_count()} thread(s): "
          f"{result.stats['steps']} steps, CPU {cpu:.1f} s, wall {wall:.1f} s; the ring's "
          f"tension at every {DAY_EVERY}th step: least {ring['least'] * 1e3:.2f} mN, median "
          f"{ring['median'] * 1e3:.2f}, largest {ring['largest'] * 1e3:.2f}, slack "
          f"{ring['slack']:.1%} of the samples")
    return {"steps": result.stats["steps"], "cpu": cpu, "wall": wall, "ring": ring}


def main(argv=None):
    """Parse the arguments (``--quick``), run and return the figures."""
    quick = arguments(__doc__, "24 tethers of 3 elements, 6 steps, 2 repeats", argv).quick
    s = SETTINGS["quick" if quick else "full"]
    config = replace(esail.FULL_SIZE, n_tethers=s.get("tethers", 100))
    rig = replace(esail.FULL_RIG, config=config)
    start = time.process_time()
    ringed = rig.build(10.0, s["elements"])
    built = time.process_time() - start
    plain = esail.build(config, 10.0, s["elements"], remote_units=rig.remote_units)
    state, R = steady_facing(ringed)
    tension = esail.auxiliary_tension(ringed, state.q)
    axis = R @ ringed.hub.rotation(ringed.initial.q[ringed.system.dofs(ringed.hub)])[:, 0]
    hub = state.q[ringed.system.dofs(ringed.hub)].reshape(4, 3)
    tips = esail.tip_positions(ringed, state.q) - 0.5 * (hub[0] + hub[1])
    coning = np.degrees(np.arcsin(tips @ axis / np.linalg.norm(tips, axis=1)))
    print(f"rig of {config.n_tethers} x {s['elements']} built in {built:.1f} s CPU; steady "
          f"spin under the wind: auxiliary tension {tension.mean() * 1e3:.4f} mN (design "
          f"{rig.auxiliary_tension * 1e3:.4f}, {tension.mean() / rig.auxiliary_tension - 1:+.2e}"
          f"), spread {np.ptp(tension) / tension.mean():.1e}; coning {coning.mean():.4f} deg, "
          f"spread {np.ptp(coning):.1e} deg")
    structure = {"sail": solver(plain), "rig": solver(ringed)}
    for name, row in structure.items():
        print(f"{name}: {row['unknowns']} unknowns, {row['method']}, band {row['band']}, "
              f"border {row['border']}, {row['levels']} level(s)")
    cost, threaded = costs({"sail": plain, "rig": ringed}, lambda: {
        "sail": esail.build(config, 10.0, s["elements"], remote_units=rig.remote_units),
        "rig": rig.build(10.0, s["elements"])}, s)
    ratio = {t: cost[t]["rig"]["cpu"] / cost[t]["sail"]["cpu"] for t in cost}
    print(f"a day of the rig ({DAY_STEPS} steps) extrapolated on two threads: wall "
          f"{DAY_STEPS * cost[2]['rig']['wall'] / 1e3:.0f} s, CPU "
          f"{DAY_STEPS * cost[2]['rig']['cpu'] / 1e3:.0f} s")
    with thread_count(2):  # the same results on any number of threads
        settled = {name: esail.settled(scene, spins=1.0) for name, scene in threaded.items()}
        run = day(settled["rig"], s["day"])
        spacing = {name: float(spacing_under_modulation(
            scene, steps_per_spin=s["per_spin"])[0].min()) for name, scene in settled.items()}
    print(f"one spin period of on-off modulation: least spacing / nominal, with the ring "
          f"{spacing['rig']:.3f}, without {spacing['sail']:.3f}")
    return {"tension": tension, "coning": coning, "structure": structure, "cost": cost,
            "ratio": ratio, "day": run, "spacing": spacing}


if __name__ == "__main__":
    main()
