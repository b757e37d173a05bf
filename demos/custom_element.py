"""A new cable element in a few lines: the ANCF cable with the engineering (Biot) strain.

The library's cable uses the Green strain ``eps = (|r_x|^2 - 1) / 2``, whose axial force
``N = EA eps |r_x|`` is not linear in the stretch.  With the engineering strain
``e = |r_x| - 1`` and the energy density

    W = EA e^2 / 2 + EI kappa^2 / 2

the axial force is ``N = EA e``: a bar pulled by a tip force ``P`` stretches by exactly
``P L / EA``, however large.  The law is all there is to write: the framework derives its
gradient and Hessian with respect to ``(a, b) = (r_x, r_xx)``, generates and compiles the
kernel (cached on disk), and gives the same law as scikit-fem forms (``sc.forms``).

Run ``python demos/custom_element.py``: it pulls a bar with ``P = 0.1 EA`` and bends the
elastica with both strain measures.
"""

import skfem_cable as sc
from skfem_cable import laws
from skfem_cable.analysis.analytic import elastica_tip_load


# --8<-- [start:biot]
@sc.cable_law
def biot(a, b, EA, EI):
    """Engineering strain ``e = |r_x| - 1`` and squared curvature."""
    e = laws.norm(a) - 1
    return EA * e**2 / 2 + EI * laws.kappa2(a, b) / 2
# --8<-- [end:biot]


def pulled_bar(law, load=0.1, n_elements=4):
    """Tip stretch ``u / L`` of a bar clamped at one end, pulled by ``P = load EA``."""
    section = sc.Section(E=1e9, A=1e-4, I=1e-10, rho=7850.0)
    bar = sc.Cable.straight([0, 0, 0], [1, 0, 0], n_elements, section, law=law)
    system = sc.System([bar]).clamp(bar.node(0))
    system.add_point_load(bar.node(-1), [load * section.EA, 0, 0])
    return sc.solve_static(system, load_steps=5).position(bar, 1.0)[0] - 1.0


def elastica(law, k=5.0, n_elements=16):
    """Tip deflection ``w / L`` of the cantilever of ``demos/cantilever.py``."""
    section = sc.Section(E=1e9, A=1e-4, I=1e-11, rho=7850.0)
    cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], n_elements, section, law=law)
    system = sc.System([cable]).clamp(cable.node(0))
    system.add_point_load(cable.node(-1), [0, -k * section.EI, 0])
    return -sc.solve_static(system, load_steps=20).position(cable, 1.0)[1]


def main(n_elements=16):
    """Tip stretch of the bar and elastica deflection for both strain measures."""
    return {"stretch_biot": pulled_bar(biot), "stretch_green": pulled_bar("cable"),
            "stretch_exact_biot": 0.1,
            "elastica_biot": elastica(biot, n_elements=n_elements),
            "elastica_green": elastica("cable", n_elements=n_elements),
            "elastica_exact": elastica_tip_load(5.0)[1]}


def gallery_figure(path):
    """The gallery's picture (``scripts/gallery.py``) into ``path``: tip stretch against
    the pull for the Biot law and the built-in Green law, with ``P L / EA``."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    loads = np.linspace(0.02, 0.2, 6)
    biot_stretch = [pulled_bar(biot, p) for p in loads]
    green = [pulled_bar("cable", p) for p in loads]
    fig, ax = plt.subplots(1, 1, figsize=(5.5, 3.4), layout="constrained")
    ax.plot(loads, loads, "k-", lw=0.8, label="P L / EA")
    ax.plot(loads, biot_stretch, "o", label="Biot law (four lines)")
    ax.plot(loads, green, "s", label="Green law (built-in)")
    ax.set_xlabel("P / EA")
    ax.set_ylabel("tip stretch u / L")
    ax.legend(fontsize=8)
    ax.set_title(f"pulled bar: Biot stretch at P = 0.1 EA: {pulled_bar(biot):.10f}",
                 fontsize=10)
    fig.savefig(path, dpi=90, bbox_inches="tight", pad_inches=0.05)
    plt.close(fig)


if __name__ == "__main__":
    for key, value in main().items():
        print(f"{key:>20s}: {value:.10g}")
