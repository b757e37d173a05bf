"""What tether-tether contact's broad phase costs per step where no contact occurs (issue
49, must-show 6): the 12-tether sail (``esail.BaselineConfig``) and the full-size sail
(``esail.FULL_SIZE``: 100 tethers of 20 km), 10 elements per tether, side by side:

* ``step``: CPU per step of the sail without contact (fixed steps of ``DT`` s,
  ``rho_inf = 0.25``, from its windless spin);
* ``broad``: CPU of one refresh of the broad phase of ``loads.contact_lines`` on all the
  sail's tethers (``BroadPhase.prepare``: the segments of the sampled centrelines, a
  compiled pass on a grid of their inflated boxes, the pairs of different tethers
  within the margin and their reach) at
  the sail's initial state, which the contact runs once per step;
* ``narrow``: CPU of the compiled narrow phase (``kernels.contact_lines.kernel``,
  without tangent) over those pairs (none touches), times the evaluations of a step
  (Newton iterations and one more, from the run's counters);
* the ratio ``(step + broad + narrow) / step``: the projected cost of the step with the
  contact on and no contact occurring.

The contact term itself is not in the sail's step: its tangent couples the tethers,
which the sail's solver factors apart (``docs/contact.md``, What remains).  CPU time
(``time.process_time``), the minimum over the repeats after a run that compiles.  Goal:
the ratio at most 1.2 (12 tethers) and 1.3 (100 tethers).

    OPENBLAS_NUM_THREADS=1 PYTHONPATH=. .venv/bin/python benchmarks/contact_cost.py [--quick]
"""

import time

import numpy as np

import skfem_cable as sc
from skfem_cable.cli.bench import arguments
from skfem_cable.core.contract import NO_INDEX, Evaluation
from skfem_cable.core.lines import joined
from skfem_cable.kernels import contact_lines as kernel
from skfem_cable.loads.contact_lines import (
    PAIRS_PER_SEGMENT,
    REFERENCE_FORCE,
    BroadPhase,
    segments,
)
from skfem_cable.scenes import esail

SETTINGS = {"full": {"steps": 20, "repeats": 3}, "quick": {"steps": 5, "repeats": 2}}

#: The goals of the ratio, by number of tethers.
GOALS = {12: 1.2, 100: 1.3}

N_ELEMENTS, DT = 10, 5.0


def broad_phase(scene):
    """The ``BroadPhase`` over all the sail's tethers (pairs of different tethers only),
    at the initial state, and the segments' rows."""
    system = scene.system
    points = [tether.line_points(system) for tether in scene.tethers]
    offsets = np.cumsum([0] + [p.shape[0] for p in points])
    parts = [segments(p, o) for p, o in zip(points, offsets)]
    rows = np.vstack([r for r, _ in parts])
    line = np.concatenate([np.full(len(r), k) for k, (r, _) in enumerate(parts)])
    radius = np.sqrt(scene.tethers[0].section.A / np.pi)
    broad = BroadPhase(joined(points), rows, np.vstack([a for _, a in parts]), line, None,
                       2.02 * radius, np.zeros((PAIRS_PER_SEGMENT * len(rows), 2), int),
                       np.zeros(1, int), scene.initial.q)
    broad.accept(scene.initial.q, scene.initial.v, 0.0)
    return broad, rows


def narrow_phase(scene, broad, rows, repeats, calls=50):
    """CPU (s) of one evaluation of the compiled narrow phase
    (``kernels.contact_lines.kernel``, no tangent) over the broad phase's pairs at the
    initial state (none touches), min of ``repeats`` of ``calls``."""
    system, q, v = scene.system, scene.initial.q, scene.initial.v
    section = scene.tethers[0].section
    d = 2 * np.sqrt(section.A / np.pi)
    coef = np.array([REFERENCE_FORCE * section.EA / (1e-2 * d), 0.0, 1e-3, d, 1e-3 * d])
    pack = (broad.points.edofs, broad.points.S, rows, broad.pairs, broad.count, coef,
            np.zeros(system.n_dofs, dtype=np.int64))
    ev = Evaluation(system, 0.0, q, v, np.zeros(0)).packed()
    kernel.kernel(pack, NO_INDEX, ev)
    best = np.inf
    for _ in range(repeats):
        start = time.process_time()
        for _ in range(calls):
            kernel.kernel(pack, NO_INDEX, ev)
        best = min(best, (time.process_time() - start) / calls)
    return best


def measure(config, steps, repeats):
    """``(step, broad, narrow, pairs)``: the CPU per step (s), per broad-phase refresh
    (s), of the narrow phase per step (s: per evaluation times the evaluations per step)
    and the candidate pairs found."""
    scene = esail.build(config, 10.0, N_ELEMENTS)
    run = {"initial": scene.initial, "rho_inf": 0.25}
    sc.simulate(scene.system, 2 * DT, DT, **run)                  # compiles
    step = []
    for _ in range(repeats):
        start = time.process_time()
        result = sc.simulate(scene.system, steps * DT, DT, **run)
        step.append((time.process_time() - start) / steps)
    evaluations = (result.stats["newton"] + result.stats["steps"]) / result.stats["steps"]
    broad, rows = broad_phase(scene)
    cost = []
    for _ in range(repeats):
        start = time.process_time()
        for _ in range(steps):
            broad.done = None
            broad.prepare(DT)
        cost.append((time.process_time() - start) / steps)
    narrow = evaluations * narrow_phase(scene, broad, rows, repeats)
    return min(step), min(cost), narrow, int(broad.count[0])


def main(argv=None):
    """Parse the arguments (``--quick``: fewer steps and repeats) and print the table."""
    args = SETTINGS["quick" if arguments(__doc__, "fewer steps and repeats", argv).quick
                    else "full"]
    print(f"{'tethers':>8} {'step ms':>9} {'broad ms':>9} {'narrow ms':>10} {'pairs':>6} "
          f"{'ratio':>6} {'goal':>5}")
    for config in (esail.BaselineConfig(), esail.FULL_SIZE):
        step, broad, narrow, pairs = measure(config, args["steps"], args["repeats"])
        n = config.n_tethers
        print(f"{n:>8} {1e3 * step:9.2f} {1e3 * broad:9.3f} {1e3 * narrow:10.3f} "
              f"{pairs:>6} {(step + broad + narrow) / step:6.3f} {GOALS[n]:5.1f}")


if __name__ == "__main__":
    main()
