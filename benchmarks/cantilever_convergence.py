"""Elastica cantilever: tip error against the exact solution versus the number of elements.

``EA L^2 / EI = 1e7``; relative error ``max(|u - u_ex|/u_ex, |w - w_ex|/w_ex)`` for the
load parameters ``k = P L^2 / EI`` in {1, 2, 5, 10}, with the observed order per halving.
Run ``python benchmarks/cantilever_convergence.py``.
"""

import time

import numpy as np

import skfem_cable as sc
from skfem_cable.analytic import elastica_tip_load
from skfem_cable.scenes import classics


def tip_error(k, n_elements):
    scene = classics.cantilever(n_elements, k)
    start = time.perf_counter()
    state = sc.solve_static(scene.system, load_steps=20)
    wall = time.perf_counter() - start
    tip = state.position(scene.cable, 1.0)
    u_ex, w_ex = elastica_tip_load(k)
    return max(abs(1 - tip[0] - u_ex) / u_ex, abs(-tip[1] - w_ex) / w_ex), wall


def main(ks=(1, 2, 5, 10), elements=(4, 8, 16, 32, 64)):
    tip_error(1, 2)  # compile
    print("| elements | " + " | ".join(f"k={k}" for k in ks) + " | time k=10 [s] |")
    print("|---" * (len(ks) + 2) + "|")
    errors = {}
    for n in elements:
        row = [tip_error(k, n) for k in ks]
        errors[n] = [e for e, _ in row]
        print(f"| {n} | " + " | ".join(f"{e:.2e}" for e, _ in row) + f" | {row[-1][1]:.3f} |")
    print("\nobserved order per halving (k=5):",
          [round(float(np.log2(errors[a][2] / errors[b][2])), 2)
           for a, b in zip(elements[:-1], elements[1:])])
    return errors


if __name__ == "__main__":
    main()
