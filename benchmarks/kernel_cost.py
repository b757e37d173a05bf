"""Cost of one force + tangent evaluation and one KKT solve versus the number of elements.

Prints a table (median of repeated runs) and the fitted growth exponents, which must be
about 1 (linear cost).  Run ``python benchmarks/kernel_cost.py [--quick]`` (``--quick``:
100 to 10,000 elements).
"""


import numpy as np

import skfem_cable as sc
from skfem_cable.cli.bench import arguments, timings
from skfem_cable.core.linalg import PatternSolver

SIZES = {"full": (10, 30, 100, 300, 1000, 3000, 10000), "quick": (100, 300, 1000, 3000, 10000)}


def median_time(fn, repeat):
    return float(np.median(timings(fn, repeat)))


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
        system.evaluate(q, None, 0.0, lam, data=data, layout=lay)

    assemble()
    solver = PatternSolver(lay.indptr, lay.indices)
    rhs = rng.standard_normal(lay.N)

    def solve():
        solver.factor(data + lay.mass_data)
        solver.solve(rhs)

    return median_time(assemble, repeat), median_time(solve, repeat), solver.method, solver.band


def exponents(rows):
    """Growth exponents (log-log slopes over the larger half of the sizes) of
    ``force_tangent_ms`` and ``factor_solve_ms`` of ``rows``."""
    n = np.array([r["elements"] for r in rows], float)
    big = n >= np.sort(n)[len(n) // 2]
    return {key: float(np.polyfit(np.log(n[big]),
                                  np.log([r[key] for r, b in zip(rows, big) if b]), 1)[0])
            for key in ("force_tangent_ms", "factor_solve_ms")}


def table(sizes=SIZES["full"]):
    """Print the cost table and the growth exponents.

    Returns
    -------
    dict
        ``rows`` (per size: ``elements``, ``force_tangent_ms``, ``factor_solve_ms``,
        ``solver``, ``band``) and ``growth_exponents`` (of both costs).
    """
    print(f"{'elements':>9} {'force+tangent [ms]':>19} {'factor+solve [ms]':>18} {'solver':>8} "
          f"{'band':>5}")
    rows = []
    for n in sizes:
        ta, ts, method, band = measure(n)
        rows.append({"elements": n, "force_tangent_ms": 1e3 * ta, "factor_solve_ms": 1e3 * ts,
                     "solver": method, "band": band})
        print(f"{n:9d} {1e3 * ta:19.3f} {1e3 * ts:18.3f} {method:>8} {band:5d}")
    slopes = exponents(rows)
    for label, key in (("force+tangent", "force_tangent_ms"), ("factor+solve", "factor_solve_ms")):
        print(f"growth exponent of {label} (larger half of the sizes): {slopes[key]:.2f}")
    return {"rows": rows, "growth_exponents": slopes}


def main(argv=None):
    """Parse the arguments (``--quick``), print the table and return its figures."""
    args = arguments(__doc__, "100 to 10,000 elements", argv)
    return table(SIZES["quick" if args.quick else "full"])


if __name__ == "__main__":
    main()
