"""Cost of one force + tangent evaluation and one KKT solve versus the number of elements.

Prints a table (median of repeated runs) and the fitted growth exponents, which must be
about 1 (linear cost).  Run ``python benchmarks/kernel_cost.py``.
"""

import time

import numpy as np

import skfem_cable as sc
from skfem_cable.linalg import PatternSolver


def median_time(fn, repeat):
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        fn()
        times.append(time.perf_counter() - start)
    return float(np.median(times))


def measure(n_elements, repeat=7):
    sec = sc.Section(E=7e10, A=4.28e-9, I=1.47e-18, rho=7653.0)
    cable = sc.Cable.straight([0, 0, 0], [1e4, 0, 0], n_elements, sec)
    system = sc.System([cable]).pin(cable.node(0))
    lay = system.layout
    rng = np.random.default_rng(0)
    q = system.q0 + 1e-3 * rng.standard_normal(system.n_dofs)
    lam = np.zeros(lay.n_c)
    data = np.zeros(lay.nnz)

    def assemble():
        data[:] = lay.linear_data  # the constant constraint rows
        system.evaluate(q, None, 0.0, lam, data=data)

    assemble()
    solver = PatternSolver(lay.indptr, lay.indices)
    rhs = rng.standard_normal(lay.N)

    def solve():
        solver.factor(data + lay.mass_data)
        solver.solve(rhs)

    return median_time(assemble, repeat), median_time(solve, repeat), solver.method, solver.band


def main(sizes=(10, 30, 100, 300, 1000, 3000, 10000)):
    rows = [(n, *measure(n)) for n in sizes]
    print(f"{'elements':>9} {'force+tangent [ms]':>19} {'factor+solve [ms]':>18} {'solver':>8} "
          f"{'band':>5}")
    for n, ta, ts, method, band in rows:
        print(f"{n:9d} {1e3 * ta:19.3f} {1e3 * ts:18.3f} {method:>8} {band:5d}")
    n = np.array([r[0] for r in rows], float)
    big = n >= np.sort(n)[len(n) // 2]  # the larger half of the sizes
    for label, col in (("force+tangent", 1), ("factor+solve", 2)):
        t = np.array([r[col] for r in rows])
        slope = np.polyfit(np.log(n[big]), np.log(t[big]), 1)[0]
        print(f"growth exponent of {label} (larger half of the sizes): {slope:.2f}")
    return rows


if __name__ == "__main__":
    main()
