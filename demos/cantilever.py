"""Large-deflection cantilever under a transverse tip load (the elastica).

A straight cable of length ``L = 1 m``, clamped at ``x = 0`` (position and slope
direction), carries a dead load ``P`` at its tip.  For an inextensible Euler-Bernoulli
beam the tip position is known in closed form through elliptic integrals (Bisshopp &
Drucker 1945) as a function of ``k = P L^2 / EI`` only.  The ANCF cable with
``EA L^2 / EI = 1e7`` is solved by Newton's method with 20 load steps and its tip
shortening ``u/L`` and deflection ``w/L`` are compared with the exact values.

Run ``python demos/cantilever.py``.
"""

import time

import numpy as np

import skfem_cable as sc
from skfem_cable.analysis.analytic import elastica_tip_load
from skfem_cable.scenes import classics


def main(n_elements=16, ks=(1.0, 2.0, 5.0, 10.0)):
    """Solve the cantilever for each load parameter; returns one row per ``k``."""
    rows = []
    for k in ks:
        scene = classics.cantilever(n_elements, k)
        start = time.perf_counter()
        state = sc.solve_static(scene.system, load_steps=20)
        wall = time.perf_counter() - start
        tip = state.position(scene.cable, 1.0)
        u, w = 1.0 - tip[0], -tip[1]
        u_ref, w_ref = elastica_tip_load(k)
        rows.append({"k": k, "u": u, "u_exact": u_ref, "w": w, "w_exact": w_ref,
                     "rel_error": max(abs(u - u_ref) / u_ref, abs(w - w_ref) / w_ref),
                     "newton": int(np.sum(state.stats["iterations"])), "seconds": wall})
    return rows


def gallery_figure(path):
    """The gallery's picture (``scripts/gallery.py``) into ``path``: the deformed
    cantilevers for k = 1, 2, 5 and 10 (16 elements) with the exact tips."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(1, 1, figsize=(6.5, 3.6), layout="constrained")
    s = np.linspace(0, 1, 101)
    for k in (1.0, 2.0, 5.0, 10.0):
        scene = classics.cantilever(16, k)
        state = sc.solve_static(scene.system, load_steps=20)
        r = state.position(scene.cable, s)
        u, w = elastica_tip_load(k)
        tip = r[-1]
        err = max(abs(1 - tip[0] - u) / u, abs(-tip[1] - w) / w)
        ax.plot(r[:, 0], r[:, 1], label=f"k = {k:g} (error {err:.1e})")
        ax.plot(1 - u, -w, "kx")
    ax.set_aspect("equal")
    ax.set_xlabel("x / L")
    ax.set_ylabel("y / L")
    ax.legend(fontsize=8, loc="center left", bbox_to_anchor=(1.02, 0.5))
    ax.set_title("Elastica: ANCF cable against the elliptic integrals", fontsize=10)
    fig.savefig(path, dpi=90, bbox_inches="tight", pad_inches=0.05)
    plt.close(fig)


if __name__ == "__main__":
    print("Cantilever elastica, 16 ANCF cable elements, EA L^2/EI = 1e7")
    print(f"{'k':>5} {'u/L':>10} {'exact':>10} {'w/L':>10} {'exact':>10} {'rel.err':>9}"
          f" {'Newton':>7} {'time[s]':>8}")
    for r in main():
        print(f"{r['k']:5.1f} {r['u']:10.6f} {r['u_exact']:10.6f} {r['w']:10.6f} "
              f"{r['w_exact']:10.6f} {r['rel_error']:9.2e} {r['newton']:7d} {r['seconds']:8.3f}")
