"""Elastica cantilever: tip error against the exact solution versus the number of elements.

``EA L^2 / EI = 1e7``; relative error ``max(|u - u_ex|/u_ex, |w - w_ex|/w_ex)`` for the
load parameters ``k = P L^2 / EI`` in {1, 2, 5, 10}, with the observed order per halving.
Run ``python benchmarks/cantilever_convergence.py [--quick]`` (``--quick``: 4 to 16
elements).
"""

import time

import numpy as np

import skfem_cable as sc
from skfem_cable.analysis.analytic import elastica_tip_load
from skfem_cable.cli.bench import arguments
from skfem_cable.scenes import classics

KS = (1, 2, 5, 10)
ELEMENTS = {"full": (4, 8, 16, 32, 64), "quick": (4, 8, 16)}


def tip_error(k, n_elements):
    scene = classics.cantilever(n_elements, k)
    start = time.perf_counter()
    state = sc.solve_static(scene.system, load_steps=20)
    wall = time.perf_counter() - start
    tip = state.position(scene.cable, 1.0)
    u_ex, w_ex = elastica_tip_load(k)
    return max(abs(1 - tip[0] - u_ex) / u_ex, abs(-tip[1] - w_ex) / w_ex), wall


def table(ks=KS, elements=ELEMENTS["full"]):
    """Print the error table and the observed orders (of ``k = 5`` if present, else of the
    last ``k``).

    Returns
    -------
    list of dict
        Per mesh: ``elements``, ``errors`` (``{k: relative tip error}``) and ``wall_s`` (the
        solve of the last ``k``).
    """
    tip_error(1, 2)  # compile
    print("| elements | " + " | ".join(f"k={k}" for k in ks) + f" | time k={ks[-1]} [s] |")
    print("|---" * (len(ks) + 2) + "|")
    rows = []
    for n in elements:
        row = [tip_error(k, n) for k in ks]
        rows.append({"elements": n, "errors": {k: e for k, (e, _) in zip(ks, row)},
                     "wall_s": row[-1][1]})
        print(f"| {n} | " + " | ".join(f"{e:.2e}" for e, _ in row) + f" | {row[-1][1]:.3f} |")
    k = 5 if 5 in ks else ks[-1]
    print(f"\nobserved order per halving (k={k}):",
          [round(float(np.log2(a["errors"][k] / b["errors"][k])), 2)
           for a, b in zip(rows[:-1], rows[1:])])
    return rows


def main(argv=None):
    """Parse the arguments (``--quick``), print the table and return its rows."""
    args = arguments(__doc__, "4 to 16 elements", argv)
    return table(elements=ELEMENTS["quick" if args.quick else "full"])


if __name__ == "__main__":
    main()
