"""A slack cable found by statics from a straight start: the elastic catenary.

Physics
-------
A 12 m cable (``EA = 1 kN``, 0.1 kg/m, no bending stiffness: the truss law) is built
straight along ``x`` and pinned at its start and, with its far end, at a point 10 m from
the first: the initial state violates that pin by 2 m.  Under gravity it hangs as the
elastic catenary (Irvine, *Cable Structures*, 1981), here with the stretch of the
element's Green-strain law, ``T = EA lambda (lambda^2 - 1) / 2``
(``skfem_cable.analysis.analytic.elastic_catenary``): horizontal force 4.51 N, sag 3.0 m, strain
up to 7e-3.

``sc.solve_static`` gets there by one continuation in two stages: the loads are applied
to the system as built (the violated pin held where the cable ends), then the violation
of the pin is closed.  A straight cable without tension has no stiffness across itself
(the truss tangent is singular), so where Newton's method fails the step is taken by
pseudo-transient continuation (a damped implicit pseudo-dynamics whose mass shift falls
with the residual, ending in Newton steps).  With the default (assumed-strain) formulation
the positions converge at third order, 64 elements within 2.2e-7 of the span, and the
tension within 4.6e-7; in the paper's formulation (``--formulation paper``) the positions
converge at fourth order (8.0e-9) but the tension, read from the raw strain of the cubic
field, only to 1.6e-4 (``docs/locking.md``).

Run ``python demos/slack_catenary.py [--figure PNG] [--formulation NAME]``.
"""

import argparse

import numpy as np

import skfem_cable as sc
from skfem_cable.analysis.analytic import elastic_catenary

LENGTH, SPAN, G = 12.0, 10.0, 9.81
SECTION = sc.Section(E=1e7, A=1e-4, I=1e-20, rho=1e3)


def hang(n_elements, law="truss", formulation=None):
    """The cable built straight, pinned at the origin and at ``(SPAN, 0, 0)``, solved by
    ``solve_static`` from that state; returns ``(cable, state)``."""
    cable = sc.Cable.straight([0, 0, 0], [LENGTH, 0, 0], n_elements, SECTION, law=law,
                              formulation=formulation)
    system = sc.System([cable]).pin(cable.node(0)).pin(cable.node(-1), [SPAN, 0.0, 0.0])
    system.add_gravity([0.0, 0.0, -G])
    return cable, sc.solve_static(system)


def errors(cable, state, samples=401):
    """Largest position error (relative to the span), tension error (relative) and error
    of the horizontal support force (relative) against the exact elastic catenary."""
    s = np.linspace(0.0, LENGTH, samples)
    xz, T, H, _ = elastic_catenary(s, SPAN, 0.0, LENGTH, SECTION.mass_per_length * G,
                                   SECTION.EA)
    position = np.abs(state.position(cable, s)[:, [0, 2]] - xz).max() / SPAN
    tension = np.abs(state.tension(cable, s) / T - 1).max()
    pin = state.multipliers[state.system.constraints[-1].name]
    return position, tension, abs(-pin[0] - H) / H          # support force: -lambda


def main(elements=(8, 16, 32, 64), law="truss", figure=None, formulation=None):
    """Solve the catenary with each element count; returns the errors, the convergence
    rates of the position error and the statistics of the finest solve."""
    rows = []
    for n in elements:
        cable, state = hang(n, law, formulation)  # the finest is plotted and reported
        rows.append((n, *errors(cable, state)))
    rows = np.array(rows)
    out = {"elements": rows[:, 0].astype(int).tolist(), "position_error": rows[:, 1].tolist(),
           "tension_error": rows[:, 2].tolist(), "H_error": rows[:, 3].tolist(),
           "rates": (-np.diff(np.log(rows[:, 1])) / np.diff(np.log(rows[:, 0]))).tolist(),
           "relaxed": state.stats["relaxed"], "iterations": state.stats["iterations"]}
    if figure:
        plot(cable, state, rows, figure)
    return out


def plot(cable, state, rows, path):
    """The hanging cable with the exact catenary, and the convergence of the errors."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    s = np.linspace(0.0, LENGTH, 201)
    xz = elastic_catenary(s, SPAN, 0.0, LENGTH, SECTION.mass_per_length * G, SECTION.EA)[0]
    fig, (a, b) = plt.subplots(1, 2, figsize=(8.5, 3.2), constrained_layout=True)
    a.plot([0, LENGTH], [0, 0], color="0.7", ls="--", label="start (straight, 12 m)")
    a.plot(xz[:, 0], xz[:, 1], "k", lw=3, alpha=0.3, label="elastic catenary (exact)")
    p = state.position(cable, s)
    a.plot(p[:, 0], p[:, 2], "C0", label=f"solve_static, {cable.n_elements} elements")
    a.plot([0, SPAN], [0, 0], "ko", ms=4)
    a.set_aspect("equal")
    a.set_ylim(-3.6, 3.2)
    a.set_xlabel("x (m)")
    a.set_ylabel("z (m)")
    a.legend(fontsize=7, loc="upper center", ncol=1, frameon=False)
    b.loglog(rows[:, 0], rows[:, 1], "o-", label="position / span")
    b.loglog(rows[:, 0], rows[:, 2], "s-", label="tension")
    b.loglog(rows[:, 0], rows[:, 1][0] * (rows[:, 0] / rows[0, 0]) ** -3, "k:",
             label="slope -3")
    b.set_xticks(rows[:, 0], [str(int(n)) for n in rows[:, 0]])
    b.minorticks_off()
    b.set_xlabel("elements")
    b.set_ylabel("largest relative error")
    b.legend(fontsize=7)
    fig.savefig(path, dpi=120)
    plt.close(fig)


def gallery_figure(path):
    """The gallery's picture (``scripts/gallery.py``) into ``path``: the hanging cable and
    the convergence of its errors (``main``'s figure)."""
    main(figure=path)


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--figure", default=None, help="PNG of the catenary")
    parser.add_argument("--formulation", default=None, choices=tuple(sc.FORMULATIONS),
                        help="the cable's formulation (default: the library's)")
    args = parser.parse_args()
    out = main(figure=args.figure, formulation=args.formulation)
    for n, e, t, h in zip(out["elements"], out["position_error"], out["tension_error"],
                          out["H_error"]):
        print(f"{n:4d} elements: position {e:.2e}, tension {t:.2e}, H {h:.2e}")
    print("rates", np.round(out["rates"], 2), "relaxed at", out["relaxed"])
