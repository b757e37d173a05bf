"""The floor of the E-sail step on this machine, and where the step stands against it
(issue 47, "close to the limit").

The E-sail rig of ``benchmarks/commit_compare.py`` (``esail.build(BaselineConfig(), 10 deg,
5)``: 12 tethers x 5 cubic elements in the default assumed-strain formulation, damped, with
bending, the solar wind's Coulomb force, a rigid hub with spherical joints; ``dt = 0.1 s``,
``rho_inf = 0.25``).  What the script measures:

- **the machine**, one core: the vector peak (numpy's ``dgemm`` of 1000 x 1000 on one
  OpenBLAS thread), the scalar peak (a numba loop of eight independent multiply-add chains,
  not vectorised) and the bandwidth of a STREAM triad ``a = b + s c`` in numba, on arrays
  that stay in the 2 MB L2 cache (the step's working set, some 0.6 MB, stays there) and on
  arrays of 96 MB (memory); each in a fresh process (``OPENBLAS_NUM_THREADS=1``), the
  least CPU time of repeats;
- **the counts of a step**, from a run of ``steps`` steps: Newton evaluations of the
  residual, corrections (band solves) and factorizations (with a tangent evaluation) per
  step;
- **the work of each part**, counted from the loops of the kernels (``FLOPS``: the
  assumed-strain cable kernel per element and Gauss point, the Coulomb force per element
  and Gauss point, the rigid hub's constraints, the products of the mass matrix and the
  linear constraints, and the bordered band LU from its storage, ``kernels.bordered``) and
  the bytes it must touch at least (its tables, the state, the factor);
- **the time of each part**, alone, in a compiled loop (minimum of repeats, CPU time).

The floor of a part is ``max(flops / peak, bytes / bandwidth)``, at the vector and at the
scalar peak (the kernels' loops over 4 functions and 3 Gauss points are short: the scalar
peak is the one within reach), with the in-cache bandwidth.  The floor of a step adds the
parts' floors times their counts; the Python of a step (books, guard, step control, the
compiled call's unboxing) has a floor of zero.  Run ``python benchmarks/esail_floor.py
[--quick]`` (``--quick``: fewer repeats and steps, indicative only).
"""

import json
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

import skfem_cable as sc
from skfem_cable.cli.bench import arguments
from skfem_cable.kernels import step as step_template
from skfem_cable.scenes import esail
from skfem_cable.solvers import compiled as compiled_step

sys.path.insert(0, str(Path(__file__).resolve().parent / "lib"))
from step_parts import Probe, compiled_parts, cpu_us  # noqa: E402

SETTINGS = {"full": {"steps": 600, "repeats": 7}, "quick": {"steps": 120, "repeats": 2}}

#: The machine's peaks, measured in a fresh process on one thread: prints a JSON dict.
PEAKS = """
import json, sys, time
import numpy as np
from numba import njit

repeats = int(sys.argv[1])


def best(run, *args):
    run(*args)
    times = []
    for _ in range(repeats):
        start = time.process_time()
        run(*args)
        times.append(time.process_time() - start)
    return min(times)


@njit(fastmath={"contract"})
def chains(n, x, y):
    a0, a1, a2, a3, a4, a5, a6, a7 = 1.0, 1.1, 1.2, 1.3, 1.4, 1.5, 1.6, 1.7
    for _ in range(n):
        a0 = a0 * x + y
        a1 = a1 * x + y
        a2 = a2 * x + y
        a3 = a3 * x + y
        a4 = a4 * x + y
        a5 = a5 * x + y
        a6 = a6 * x + y
        a7 = a7 * x + y
    return a0 + a1 + a2 + a3 + a4 + a5 + a6 + a7


@njit
def triad(a, b, c, s, sweeps):
    for _ in range(sweeps):
        for i in range(a.size):
            a[i] = b[i] + s * c[i]


a = np.random.rand(1000, 1000)
gemm = 2e-9 * 1000**3 / best(np.dot, a, a)
n = 10**8
scalar = 16e-9 * n / best(chains, n, 0.999999, 1e-7)
bandwidth = {}
for key, size, sweeps in (("cache", 8192, 4000), ("memory", 4 * 10**6, 5)):
    x, y, z = (np.random.rand(size) for _ in range(3))
    bandwidth[key] = 24e-9 * size * sweeps / best(triad, x, y, z, 1.5, sweeps)
print(json.dumps({"gemm_gflops": gemm, "scalar_gflops": scalar,
                  "cache_gbs": bandwidth["cache"], "memory_gbs": bandwidth["memory"]}))
"""


def machine(repeats):
    """The machine's peaks on one thread (``PEAKS``, in a fresh process): ``gemm_gflops``,
    ``scalar_gflops``, ``cache_gbs``, ``memory_gbs``."""
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1",
               MKL_NUM_THREADS="1", NUMBA_NUM_THREADS="1")
    out = subprocess.run([sys.executable, "-c", PEAKS, str(repeats)], env=env, check=True,
                         capture_output=True, text=True).stdout
    return json.loads(out.strip().splitlines()[-1])


#: Flops of the law's point functions (generated, ``laws.codegen``), estimated from the
#: Green law with linear damping and the bending law: the axial point (energy, stress,
#: stiffness, damping, power) and the bending point's gradient (and Hessian).
LAW_AXIAL, LAW_BENDING, LAW_BENDING_HESSIAN = 20, 60, 200


def cable_flops(nf, ns, ng, tangent):
    """Flops of one element of the assumed-strain kernel (``kernels.assumed_strain.span``,
    damped, with bending), its loops counted one by one (a multiply-add is 2).  A residual
    without tangent sums the axial and damping forces over the samples (``n_j``,
    ``nsd_j``) and makes none of the tangent's products ``beta``, ``gamma``, ``sb`` and
    the damping rows ``Bdj`` (since ``64849ad`` and ``6b5c13e``)."""
    nd = 3 * nf
    raw = ns * (3 * (4 * nf + 4) + 2 + nd)              # slopes, rates, strains, B rows
    axial = ng * (4 * ns + LAW_AXIAL + 6 * ns + 4)      # eps, the point, n_j and nsd_j
    force = 4 * ns * nd                                 # fe and fde from n_j and nsd_j
    bend = ng * (12 * nf + LAW_BENDING + 10 * nd + 2)   # r_xx, the point, fe and fde
    scatter = 2 * nd
    flops = raw + axial + force + bend + scatter
    if tangent:
        flops += ns * nd + ng * (4 * ns * nd + 5 * nd)               # Bdj, beta, gamma, sb
        flops += 2 * ng * nd * nd + nf * nf * (3 * ns + 4)           # axial K, geometric
        flops += ng * (LAW_BENDING_HESSIAN + 6 * nd * 8 + 4 * nd * nd)  # bending B^T H B
        flops += nd * nd                                             # scatter
    return flops


def coulomb_flops(nf, nq, tangent):
    """Flops of one element of the Coulomb force (the point function
    ``kernels.coulomb.point`` in ``kernels.line``'s loop: the interpolation of ``x`` and
    ``a``, the force, its sum into the element's) on ``nq`` Gauss points (a square root
    and a power counted as 20 flops each)."""
    nd = 3 * nf
    point = 12 * nf + 3 + 2 * (20 + 5) + 6 + 5 + 2 + 40 + 3 * (5 + 2 * nd // 3 * 2)
    flops = nq * point + nd
    if tangent:
        flops += nq * (45 + 9 * 30 + nf * nf * 9 * 5) + 2 * nd * nd
    return flops


def band_flops(lu):
    """Flops of the bordered band LU's factorization and of one solve, from its storage
    (``kernels.bordered``): per block of ``n`` band unknowns of half-width ``b``,
    ``dgbtrf`` (``2 n b (2 b)``), a band solve per coupling row, ``W`` and ``F W``; the
    border's dense LU; a solve: a band solve per block (``2 n (3 b)``), the border and
    the correction ``W x_D``."""
    blocks = lu[0][0]
    ab, band, starts, rows, cols = blocks[1], blocks[3], blocks[6], blocks[8], blocks[10]
    nb, k = ab.shape[0], lu[1].shape[0]
    sizes = np.diff(starts)
    substitute = 6 * band * nb
    factor = int(np.sum(4 * band * band * sizes)) + rows.size * 6 * band * sizes.max() \
        + 2 * k * rows.size * sizes.max() + 2 * cols.size * k * k + 2 * k**3 // 3
    solve = substitute + 2 * cols.size * k + 2 * k * k + 2 * k * nb
    return factor, solve


def part_bytes(ne, lu, nnz):
    """Least bytes each part touches (8 per float or index): the element tables, the
    state it reads and the forces it writes, the matrix values and their positions with a
    tangent, the factor."""
    nf = 4
    element = 8 * (3 * nf + 5 * nf + 3 * nf + 3 + 1) + 8 * 3 * 3 * nf   # tables, q v f fd
    coulomb = 8 * (3 * nf + 2 * 5 * nf + 5 + 1) + 8 * 2 * 3 * nf
    matrix = 8 * 3 * ne * (3 * nf) ** 2                                  # index, data RMW
    ab, W = lu[0][0][1], lu[0][0][18]
    factor = 8 * (3 * ab.size + 2 * W.size) + 8 * 2 * nnz
    solve = 8 * (ab.size + W.size + 4 * ab.shape[0])
    return {"cable": ne * element, "coulomb": ne * coulomb, "matrix": matrix,
            "factor": factor, "solve": solve}


def run_counts(scene, steps, repeats):
    """CPU ms per step (difference of runs of ``steps`` and ``steps // 6`` steps, minimum
    of ``repeats``), and per step: evaluations, corrections, factorizations; the
    ``CompiledNewton`` of the run and its integrator (``step_parts.Probe``)."""
    run = {"dt": 0.1, "rho_inf": 0.25, "initial": scene.initial}
    sc.simulate(scene.system, t_end=0.2, **run)  # compile, layout
    best = {}
    for _ in range(repeats):
        for k in (steps // 6, steps):
            start = time.process_time()
            sc.simulate(scene.system, t_end=k * 0.1, every=k, **run)
            best[k] = min(best.get(k, np.inf), time.process_time() - start)
    with Probe() as probe:
        result = sc.simulate(scene.system, t_end=steps * 0.1, every=steps, **run)
    n = result.stats["steps"]
    return {"ms_per_step": 1e3 * (best[steps] - best[steps // 6]) / (steps - steps // 6),
            "evaluations": probe.evaluations / n,
            "corrections": result.stats["newton"] / n,
            "factorizations": result.stats["factorizations"] / n}, probe.newton, \
        probe.integrator


#: The kernels of the rig's step whose work ``counted`` counts, in the step's order.
KERNELS = ("cable", "coulomb")


def elements(integrator):
    """The cable elements of the step: the rows of the index of its first term."""
    return integrator.lay.body_terms[0][1].shape[0]


def part_times(newton, integrator, repeats):
    """CPU us of the parts of a Newton iteration, each alone in a compiled loop: each term
    kernel without and with the tangent, the factorization and a solve
    (``step_parts.compiled_parts``), and the whole residual (``kernels.step._residual``:
    kernels, constraints, products) without and with the tangent."""
    measured = compiled_parts(newton, integrator, repeats)
    terms = [k["term"] for k in measured["kernels"]]
    if len(terms) != len(KERNELS):
        raise ValueError(f"the step has the kernels of {terms}: esail_floor counts the work "
                         f"of {len(KERNELS)}, {KERNELS} (a cable term and the solar wind)")
    times = {"factor": measured["factor_us"], "solve": measured["solve_us"]}
    for name, kernel in zip(KERNELS, measured["kernels"]):
        times[(name, False)], times[(name, True)] = kernel["residual_us"], kernel["tangent_us"]
    a, residual, prm = newton.arrays, compiled_step.module()._residual, newton.prm
    written = step_template.forces_written(prm)
    for tangent, matrix in ((False, a["nodata"]), (True, a["data"])):
        args = (newton.terms, newton.model, a["q1"], a["v1"], a["a1"], a["lam1"], a["r"],
                matrix, newton.out, float(prm[step_template.MBAR]), 1.0, written)
        times[("residual", tangent)] = cpu_us(residual, args, 200 if tangent else 400,
                                              repeats)
    return times


def parts(counts, times, flops, nbytes):
    """The rows ``(part, per step, flops, bytes, measured us)`` of a step: per evaluation
    the cable kernel, the Coulomb force and the rest of the residual (constraints, the
    products of the mass and the linear constraints), per factorization the tangent
    evaluation and the factorization, per correction the solve."""
    ev, fa, co = counts["evaluations"], counts["factorizations"], counts["corrections"]
    rest = times[("residual", False)] - times[("cable", False)] - times[("coulomb", False)]
    tangent = times[("residual", True)]
    return [("cable kernel (assumed strain), residual", ev, flops["cable"], nbytes["cable"],
             times[("cable", False)]),
            ("Coulomb force, residual", ev, flops["coulomb"], nbytes["coulomb"],
             times[("coulomb", False)]),
            ("constraints, M a, residual rows", ev, flops["rest"], nbytes["rest"], rest),
            ("tangent evaluation (all terms)", fa, flops["tangent"], nbytes["matrix"],
             tangent),
            ("bordered band LU factor", fa, flops["factor"], nbytes["factor"],
             times["factor"]),
            ("bordered band solve", co, flops["solve"], nbytes["solve"], times["solve"])]


def counted(newton, integrator):
    """Flops of each part (``cable_flops``, ``coulomb_flops``, ``band_flops``, the rigid
    hub's 6 quadratic constraints on 12 coordinates, the mass and constraint products)
    and its bytes (``part_bytes``)."""
    model, lu, a = newton.model, integrator.solver.lu, newton.arrays
    ne = elements(integrator)
    factor, solve = band_flops(lu)
    mass_nnz = model[0][0][-1] * model[0][3]  # M = M_s ⊗ I_k (linalg.FastCSR.strided)
    rest = 6 * 12 * (2 * 12 + 4) + 2 * mass_nnz + 4 * model[6][-1] + 6 * a["q1"].size
    tangent = ne * (cable_flops(4, 5, 3, True) + coulomb_flops(4, 5, True)) + rest \
        + 6 * 12 * 12 * 3 + a["data"].size
    flops = {"cable": ne * cable_flops(4, 5, 3, False), "coulomb": ne * coulomb_flops(4, 5, False),
             "rest": rest, "tangent": tangent, "factor": factor, "solve": solve}
    nbytes = part_bytes(ne, lu, a["data"].size)
    nbytes["rest"] = 8 * (3 * mass_nnz + 6 * 12 * 12 + 6 * a["q1"].size)
    nbytes["matrix"] += nbytes["cable"] + nbytes["coulomb"] + nbytes["rest"]
    return flops, nbytes


def table(steps=600, repeats=7, quick=False):
    """Measure the machine, the step's counts and its parts; print the floor table.

    Returns
    -------
    dict
        ``machine`` (``machine``), ``counts`` (``run_counts``), ``rows`` (per part:
        ``part``, ``per_step``, ``flops``, ``bytes``, ``measured_us``, ``floor_us`` at the
        vector and ``scalar_floor_us`` at the scalar peak, ``ratio`` measured / scalar
        floor) and ``step`` (measured and floor us per step).
    """
    peak = machine(repeats)
    print(f"one core: dgemm {peak['gemm_gflops']:.1f} GFLOP/s, scalar multiply-add "
          f"{peak['scalar_gflops']:.1f} GFLOP/s, triad {peak['cache_gbs']:.0f} GB/s in L2 "
          f"and {peak['memory_gbs']:.1f} GB/s from memory")
    scene = esail.build(esail.BaselineConfig(), 10.0, 5)
    counts, newton, integrator = run_counts(scene, steps, repeats)
    print(f"per step: {counts['ms_per_step'] * 1e3:.1f} us CPU, {counts['evaluations']:.2f} "
          f"evaluations, {counts['corrections']:.2f} corrections, "
          f"{counts['factorizations']:.4f} factorizations ({steps} steps)")
    times = part_times(newton, integrator, repeats)
    flops, nbytes = counted(newton, integrator)
    rows, floor, scalar_floor, inside = [], 0.0, 0.0, 0.0
    print(f"{'part':<42} {'per step':>8} {'kflop':>7} {'kB':>6} {'floor us':>9} "
          f"{'scalar us':>9} {'measured us':>11} {'/ scalar':>8}")
    for part, per_step, fl, by, us in parts(counts, times, flops, nbytes):
        memory = 1e-3 * by / peak["cache_gbs"]
        low = max(1e-3 * fl / peak["gemm_gflops"], memory)
        scalar = max(1e-3 * fl / peak["scalar_gflops"], memory)
        rows.append({"part": part, "per_step": per_step, "flops": fl, "bytes": by,
                     "measured_us": us, "floor_us": low, "scalar_floor_us": scalar,
                     "ratio": us / scalar})
        floor += per_step * low
        scalar_floor += per_step * scalar
        inside += per_step * us
        print(f"{part:<42} {per_step:8.3f} {fl / 1e3:7.1f} {by / 1e3:6.1f} {low:9.2f} "
              f"{scalar:9.2f} {us:11.2f} {us / scalar:8.1f}")
    step = counts["ms_per_step"] * 1e3
    print(f"{'Python and the call (books, guard, copies)':<42} {1:8.3f} {'':>7} {'':>6} "
          f"{0:9.2f} {0:9.2f} {step - inside:11.2f}")
    print(f"{'step':<42} {'':>8} {'':>7} {'':>6} {floor:9.2f} {scalar_floor:9.2f} "
          f"{step:11.2f} {step / scalar_floor:8.1f}")
    print(f"the step at {step / floor:.0f} times its vector floor, {step / scalar_floor:.1f} "
          f"times its scalar floor; its compiled parts at {inside / scalar_floor:.1f} times"
          + (" (quick: indicative only)" if quick else ""))
    return {"machine": peak, "counts": counts, "rows": rows,
            "step": {"measured_us": step, "floor_us": floor, "scalar_floor_us": scalar_floor,
                     "compiled_parts_us": inside}}


def main(argv=None):
    """Parse the arguments (``--quick``), print the table and return its figures."""
    args = arguments(__doc__, "120 steps, two repeats", argv)
    return table(**SETTINGS["quick" if args.quick else "full"], quick=args.quick)


if __name__ == "__main__":
    main()
