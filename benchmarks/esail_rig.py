"""The full E-sail rig (``esail.FULL_RIG``: 100 tethers of 20 km, a remote unit at each
tip, the ring of auxiliary tethers) against the full-size sail without them (issue 51,
items 2 and 6).

1. The steady spin under the wind (``rig.steady_facing``, at 10 deg): the auxiliary
   tethers' tension against the design's, and the spread of the tethers' coning angles.
2. Cost per step: fixed 5 s steps from the windless spin (``bench``'s full-size case),
   CPU time (``time.process_time``), minimum of alternating repeats, rig and sail side by
   side, and the linear solver each gets (method, band half-width, border).
3. A day: the cost per step times the 3284 adaptive steps the full-size sail takes for a
   day at ``esail.MISSION_RTOL`` (``docs/benchmarks.md``), an extrapolation that assumes
   the rig takes as many.
4. Neighbouring remote units under on-off modulation (``esail.modulation``: neighbours
   in antiphase) for one spin period from the state under the wind (``esail.settled``,
   one spin period of relaxation), with and without the ring: the least distance over
   the run over the nominal spacing.

    OPENBLAS_NUM_THREADS=1 .venv/bin/python benchmarks/esail_rig.py [--quick]
"""

import time
from dataclasses import replace

import numpy as np

import skfem_cable as sc
from skfem_cable.cli.bench import arguments
from skfem_cable.core.linalg import PatternSolver
from skfem_cable.scenes import esail
from skfem_cable.scenes.esail.modulation import spacing_under_modulation
from skfem_cable.scenes.esail.rig import steady_facing

#: Steps of a simulated day of the full-size sail at ``esail.MISSION_RTOL`` from its
#: state under the wind (``docs/benchmarks.md``, "Mission-length runs").
DAY_STEPS = 3284

SETTINGS = {"full": {"elements": 10, "steps": 60, "repeats": 5, "per_spin": 180},
            "quick": {"elements": 3, "steps": 6, "repeats": 2, "per_spin": 30,
                      "tethers": 24}}


def solver(scene):
    """The linear solver the system's iteration matrix gets: method, band, border."""
    lay = scene.system.current_layout()
    s = PatternSolver(lay.indptr, lay.indices, border=lay.border)
    return {"unknowns": lay.N, "method": s.method, "band": s.band, "border": s.border}


def cpu_per_step(scenes, steps, repeats, dt=5.0):
    """CPU ms per step of ``steps`` fixed steps of ``dt`` for each scene (name -> scene),
    the minimum over ``repeats`` runs taken alternately."""
    best = {name: np.inf for name in scenes}
    for _ in range(repeats):
        for name, scene in scenes.items():
            start = time.process_time()
            sc.simulate(scene.system, steps * dt, dt, initial=scene.initial, rho_inf=0.25,
                        every=10**9)
            best[name] = min(best[name], time.process_time() - start)
    return {name: 1e3 * t / steps for name, t in best.items()}


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
              f"border {row['border']}")
    scenes = {"sail": plain, "rig": ringed}
    cpu_per_step(scenes, 2, 1)  # compiles both
    cost = cpu_per_step(scenes, s["steps"], s["repeats"])
    ratio = cost["rig"] / cost["sail"]
    print(f"CPU ms per 5 s step, min of {s['repeats']}: sail {cost['sail']:.2f}, rig "
          f"{cost['rig']:.2f}, ratio {ratio:.2f}; a day of the rig ({DAY_STEPS} steps): "
          f"{DAY_STEPS * cost['rig'] / 1e3:.0f} s")
    spacing = {}
    for name, scene in scenes.items():
        ratios, _ = spacing_under_modulation(esail.settled(scene, spins=1.0),
                                             steps_per_spin=s["per_spin"])
        spacing[name] = float(ratios.min())
    print(f"one spin period of on-off modulation: least spacing / nominal, with the ring "
          f"{spacing['rig']:.3f}, without {spacing['sail']:.3f}")
    return {"tension": tension, "coning": coning, "structure": structure, "cost": cost,
            "ratio": ratio, "spacing": spacing}


if __name__ == "__main__":
    main()
