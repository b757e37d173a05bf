"""Where a full-size E-sail's step goes (``esail.FULL_SIZE``: 100 tethers of 20 km, 10
elements each, 6612 coordinates), and what adaptive steps buy over an hour.

1. The parts of one Newton iteration at the start: the factorization of the iteration
   matrix (the bordered band LU, ``linalg``), a solve, and an evaluation of the forces
   and the tangent (Python path; the compiled step's is cheaper).
2. Threads: the factorization, the solve and a run of fixed 5 s steps on one thread
   and on all of numba's (``SKFEM_CABLE_THREADS``: the blocks of the bordered LU,
   ``kernels.bordered``, the tethers, run in parallel), side by side.
3. Fixed steps of 0.5, 5 and 20 s, and adaptive steps at ``rtol`` 3e-4 and
   ``esail.MISSION_RTOL`` (``atol`` 1e-3 m), on all of numba's threads: steps, Newton
   iterations and factorizations per step, ms per step, the projected wall time of a
   day, and the largest differences over the run from the fixed 0.5 s run
   (``bench.largest_differences``) of the sail's spin rate, the hub's rate, the mean
   coning and the thrust.  Then the same from the sail's state under the wind
   (``esail.settled``), with fixed 40 s steps and adaptive steps at 1e-4 beside.
4. ``day()``: a simulated day at ``esail.MISSION_RTOL`` on all threads from the sail's
   state under the wind (``settled=False``: from the windless spin), and the largest
   differences of its outputs over the day from a fixed 0.5 s run (about 6 minutes on
   two threads).
5. ``month()``: 30 days on the circular orbit of 1 AU from the sail's state under the
   wind, its first day against fixed 0.5 s steps (about 15 minutes on two threads).

    OPENBLAS_NUM_THREADS=1 .venv/bin/python benchmarks/esail_full.py [--quick]
    cd benchmarks && OPENBLAS_NUM_THREADS=1 python -c "import esail_full as b; b.day()"
    cd benchmarks && OPENBLAS_NUM_THREADS=1 python -c "import esail_full as b; b.month()"
"""

import sys
import time
from pathlib import Path

import numba
import numpy as np

import skfem_cable as sc
from skfem_cable.cli.bench import RESULTS, arguments, largest_differences, timings
from skfem_cable.core.linalg import PatternSolver
from skfem_cable.scenes import esail

sys.path.insert(0, str(Path(__file__).resolve().parent / "lib"))
from threads import thread_count  # noqa: E402

SETTINGS = {"full": {"t_end": 3600.0, "repeats": 10}, "quick": {"t_end": 300.0, "repeats": 5}}

CASES = {"fixed 0.5 s": {"dt": 0.5}, "fixed 5 s": {"dt": 5.0}, "fixed 20 s": {"dt": 20.0},
         "adaptive, rtol 3e-4": {"dt": 1.0, "rtol": 3e-4, "atol": 1e-3},
         f"adaptive, rtol {esail.MISSION_RTOL:g}": {"dt": 1.0, "rtol": esail.MISSION_RTOL,
                                                    "atol": 1e-3}}

#: From the sail's state under the wind: longer fixed steps, and adaptive steps at three
#: tolerances.
SETTLED_CASES = {**{name: CASES[name] for name in ("fixed 0.5 s", "fixed 5 s", "fixed 20 s")},
                 "fixed 40 s": {"dt": 40.0},
                 **{f"adaptive, rtol {rtol:g}": {"dt": 1.0, "rtol": rtol, "atol": 1e-3}
                    for rtol in (3e-4, 1e-4, esail.MISSION_RTOL)}}


def fastest(function, repeats):
    """The least wall time (s) of ``repeats`` calls."""
    return min(timings(function, repeats))


def parts(scene, repeats, threads=1):
    """Milliseconds of a factorization (on ``threads``), a solve and an evaluation at the
    initial state."""
    system, initial = scene.system, scene.initial
    lay = system.current_layout()
    solver = PatternSolver(lay.indptr, lay.indices, border=lay.border, threads=threads)
    data = lay.mass_data + lay.linear_data
    lam = np.zeros(lay.n_c)
    system.evaluate(initial.q, initial.v, 0.0, lam, cK=1e-3, data=data)
    rhs = np.random.default_rng(0).standard_normal(lay.N)
    solver.factor(data)

    def evaluate():
        system.evaluate(initial.q, initial.v, 0.0, lam, cK=1e-3, data=data.copy(), layout=lay)

    return {"factor": 1e3 * fastest(lambda: solver.factor(data), repeats),
            "solve": 1e3 * fastest(lambda: solver.solve(rhs), repeats),
            "evaluate": 1e3 * fastest(evaluate, repeats),
            "unknowns": lay.N, "band": solver.band, "border": solver.border}



def threads(t_end, repeats):
    """Milliseconds of a factorization, a solve and a step of fixed 5 s steps over
    ``t_end`` (and of 0.5 s steps over a tenth of it) on one thread and on all of
    numba's (``SKFEM_CABLE_THREADS``), the sail built for each (its element loops take
    the thread count when its layout is built).  A step's cost is that of the run less
    that of a run of a sixth of the steps, over the steps between: the setup of a run
    (its layout checks, its consistent initial state: 0.1 s, serial) is not in it."""
    rows = {}
    for count in sorted({1, numba.config.NUMBA_NUM_THREADS}):
        with thread_count(count):
            scene = esail.build(esail.FULL_SIZE, 10.0, 10)
            p = parts(scene, repeats, count)

            def step(dt, span, scene=scene):
                """ms per step of ``dt`` over ``span``, the setup taken out."""
                def run(length):
                    sc.simulate(scene.system, length, dt, initial=scene.initial,
                                rho_inf=0.25, every=10**9)
                tries = max(1, repeats // 5)
                return 1e3 * (fastest(lambda: run(span), tries)
                              - fastest(lambda: run(span / 6), tries)) / (5 * span / 6 / dt)

            step(5.0, 10.0)  # compiles the Newton step of this thread count
            rows[count] = {"factor": p["factor"], "solve": p["solve"],
                           "step": step(5.0, t_end), "short": step(0.5, t_end / 10)}
    return rows


#: The outputs compared, in the order of ``outputs``.
OUTPUTS = ("spin rate", "hub's rate", "coning", "thrust")


def outputs(scene, result):
    """The times and the sail's spin rate, the hub's rate (rad/s), the mean coning (deg)
    and the thrust (N) at the saved steps, (nt, 4)."""
    out = esail.outputs(scene, result)
    return result.t, np.stack([out["spin_rate"], out["omega_B"][:, 0],
                               np.degrees(out["coning"]).mean(axis=1),
                               np.linalg.norm(out["thrust"], axis=1)], axis=1)


def main(argv=None):
    """Parse the arguments (``--quick``), run and return the figures."""
    quick = arguments(__doc__, "300 s instead of an hour, 5 repeats", argv).quick
    s = SETTINGS["quick" if quick else "full"]
    scene = esail.build(esail.FULL_SIZE, 10.0, 10)
    p = parts(scene, s["repeats"])
    print(f"full-size sail: {p['unknowns']} unknowns, band {p['band']}, border "
          f"{p['border']}; one factorization {p['factor']:.2f} ms, solve "
          f"{p['solve']:.2f} ms, evaluation (Python path) {p['evaluate']:.2f} ms")
    sc.simulate(scene.system, 2.0, 1.0, initial=scene.initial, rho_inf=0.25)  # compiles
    rows = threads(min(s["t_end"], 600.0), s["repeats"])
    print("\n| threads | factorization [ms] | solve [ms] | step of 5 s [ms] | step of 0.5 s "
          "[ms] |\n|---|---|---|---|---|")
    for count, row in rows.items():
        print(f"| {count} | {row['factor']:.2f} | {row['solve']:.3f} | {row['step']:.2f} | "
              f"{row['short']:.2f} |")
    if len(rows) > 1:
        one, many = rows[1], rows[max(rows)]
        print(f"{max(rows)} threads / 1: factorization {many['factor'] / one['factor']:.2f}, "
              f"solve {many['solve'] / one['solve']:.2f}, step of 5 s "
              f"{many['step'] / one['step']:.2f}, of 0.5 s {many['short'] / one['short']:.2f}")
    print(f"\n{s['t_end']:g} s of the sail from its steady spin (rho_inf = 0.25), on "
          f"{numba.config.NUMBA_NUM_THREADS} threads; largest differences over the run from "
          "fixed 0.5 s\n")
    cases = compare(CASES, s["t_end"])
    print("\nThe same from the sail's state under the wind (esail.settled)\n")
    settled = compare(SETTLED_CASES, s["t_end"], settled=True)
    return {"parts": p, "threads": rows, "cases": cases, "settled": settled}


def compare(cases, t_end, settled=False, orbit=False):
    """Run the sail for ``t_end`` with each of ``cases`` (name: ``simulate`` settings; the
    first is the reference) on all of numba's threads, from the windless spin of
    ``esail.build`` (``esail.build_orbit`` if ``orbit``: the circular orbit of 1 AU) or,
    if ``settled``, from its state under the wind (``esail.settled``); print a row per
    case and return steps, wall time, Newton iterations per step, the largest
    differences, the saved outputs and the last state per case, and the scene.  A case
    saves every step if adaptive, every 2 s if fixed, unless it sets ``every``."""
    rows, reference = {}, None
    with thread_count(numba.config.NUMBA_NUM_THREADS):
        scene = (esail.build_orbit if orbit else esail.build)(esail.FULL_SIZE, 10.0, 10)
        if settled:
            start = time.perf_counter()
            scene = esail.settled(scene)
            rows["settle"] = {"wall": time.perf_counter() - start}
            print(f"settled under the wind in {rows['settle']['wall']:.1f} s\n")
        print("| case | steps | Newton/step | factorizations/step | ms/step | wall [s] | a day "
              "[s] | " + " | ".join(OUTPUTS) + " |\n|---|---|---|---|---|---|---|---|---|---|---|")
        for name, settings in cases.items():
            start = time.perf_counter()
            every = 1 if "rtol" in settings else max(1, round(2.0 / settings["dt"]))
            result = sc.simulate(scene.system, t_end, initial=scene.initial, rho_inf=0.25,
                                 **{"every": every, **settings})
            wall = time.perf_counter() - start
            values = outputs(scene, result)
            reference = values if reference is None else reference
            error = largest_differences(values, reference)
            st = result.stats
            rows[name] = {"steps": st["steps"], "wall": wall, "error": error.tolist(),
                          "newton": st["newton"] / st["steps"], "t": values[0],
                          "outputs": values[1], "last": result.state(-1)}
            print(f"| {name} | {st['steps']} | {st['newton'] / st['steps']:.2f} | "
                  f"{st['factorizations'] / st['steps']:.2f} | {1e3 * wall / st['steps']:.2f} | "
                  f"{wall:.1f} | {wall * 86400.0 / t_end:.0f} | "
                  + " | ".join(f"{e:.1e}" for e in error) + " |", flush=True)
    rows["scene"] = scene
    return rows


def day(settled=True):
    """A day of the sail at ``esail.MISSION_RTOL`` against fixed 0.5 s steps, from its
    state under the wind (``esail.settled``) or, with ``settled=False``, from the
    windless spin."""
    names = ("fixed 0.5 s", f"adaptive, rtol {esail.MISSION_RTOL:g}")
    # saved about every 30 s: a day of every step would not fit in memory
    every = (60, 2 if settled else 10)
    rows = compare({name: {**CASES[name], "every": k} for name, k in zip(names, every)},
                   86400.0, settled)
    adaptive = rows[names[1]]
    draw_day(adaptive["t"], adaptive["outputs"], every[1], RESULTS / "esail_full_day.png")
    return rows


def month(days=30):
    """A month of the sail on the circular orbit of 1 AU at ``esail.MISSION_RTOL`` from its
    state under the wind, on all threads: the first day against fixed 0.5 s steps
    (``compare``), then the other ``days - 1`` continued from the first day's end, saved
    every 100 steps; prints the wall times and draws the month (about 15 minutes on two
    threads, the reference day included)."""
    names = ("fixed 0.5 s", f"adaptive, rtol {esail.MISSION_RTOL:g}")
    rows = compare({name: {**CASES[name], "every": k} for name, k in zip(names, (60, 2))},
                   86400.0, settled=True, orbit=True)
    first, scene = rows[names[1]], rows["scene"]
    with thread_count(numba.config.NUMBA_NUM_THREADS):
        start = time.perf_counter()
        rest = sc.simulate(scene.system, days * 86400.0, 1.0, initial=first["last"],
                           t_start=86400.0, rho_inf=0.25, rtol=esail.MISSION_RTOL,
                           atol=1e-3, every=100)
        wall = time.perf_counter() - start
    t, values = outputs(scene, rest)
    steps = first["steps"] + rest.stats["steps"]
    total = rows["settle"]["wall"] + first["wall"] + wall
    print(f"\n{days} days: {steps} steps, {first['wall'] + wall:.0f} s of steps and "
          f"{rows['settle']['wall']:.1f} s of settling, {total / 60:.1f} minutes in all; "
          f"thrust {values[:, 3].min():.4f} to {values[:, 3].max():.4f} N, mean coning "
          f"{values[:, 2].min():.2f} to {values[:, 2].max():.2f} deg")
    draw_month(np.concatenate([first["t"], t]), np.concatenate([first["outputs"], values]),
               RESULTS / "esail_full_month.png")
    return {"steps": steps, "wall": total, "first_day": first["error"]}


def draw_month(t, outputs, path):
    """The spin rate, the mean coning and the thrust (``outputs``' columns) over the
    month."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    path.parent.mkdir(parents=True, exist_ok=True)
    fig, axes = plt.subplots(3, 1, figsize=(8, 6), sharex=True, layout="constrained")
    days = np.asarray(t) / 86400.0
    for ax, k, scale, label in zip(axes, (0, 2, 3), (1e3, 1.0, 1.0),
                                   ("spin rate [mrad/s]", "mean coning [deg]",
                                    "thrust [N]")):
        ax.plot(days, scale * outputs[:, k], lw=0.6)
        ax.set(ylabel=label)
    axes[-1].set(xlabel="t [days]")
    fig.suptitle(f"full-size E-sail on the orbit of 1 AU, rtol = {esail.MISSION_RTOL:g}",
                 fontsize=10)
    fig.savefig(path, dpi=80)
    plt.close(fig)


def draw_day(t, outputs, every, path):
    """The mean step over each ``every`` steps between the saved times ``t``, the mean
    coning and the hub's rate (``outputs``' columns) over the day."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    path.parent.mkdir(parents=True, exist_ok=True)
    fig, axes = plt.subplots(3, 1, figsize=(8, 6), sharex=True, layout="constrained")
    hours = np.asarray(t) / 3600.0
    axes[0].plot(hours[1:], np.diff(t) / every, lw=0.8)
    axes[0].set(ylabel="step [s]", ylim=(0, None))
    axes[1].plot(hours, outputs[:, 2], lw=0.8)
    axes[1].set(ylabel="mean coning [deg]")
    axes[2].plot(hours, 1e3 * outputs[:, 1], lw=0.6)
    axes[2].set(ylabel="hub's rate [mrad/s]", xlabel="t [h]")
    fig.suptitle(f"full-size E-sail, a day at rtol = {esail.MISSION_RTOL:g} from its state "
                 "under the wind", fontsize=10)
    fig.savefig(path, dpi=80)
    plt.close(fig)


if __name__ == "__main__":
    main()
