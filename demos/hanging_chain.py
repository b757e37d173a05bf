"""Swinging steel chain: a rod-chain tether released from horizontal under gravity.

Physics
-------
Eleven steel rods (density 7801 kg/m^3, radius 1 mm, rest length 0.1 m, E = 207 GPa: the
paper's second experiment) joined by frictionless spherical hinges hang from a fixed point
``O_0``.  At ``t = 0`` the chain lies straight and horizontal along ``+x``, at rest, and falls
under gravity ``g = 9.81 m/s^2`` along ``-y``.  (The paper's initial state, straight along
``-y`` and at rest with gravity along ``-y``, is an equilibrium and does not move; the
horizontal release is that geometry with gravity turned by 90 degrees.)  The chain swings
down like a pendulum whose lower links lag behind, then whips past the vertical: the free
end reaches about 12 m/s.  The rods are so stiff (``EA = 6.5e5 N``) that their strain stays
below 1e-5, and the chain moves like a chain of rigid links.

The rod chain (equations of motion 18-21 of the paper, O(n) mass solve) is integrated with
classical RK4.  Its step must stay below ``2 sqrt(2) / omega_max`` with ``omega_max =
sqrt(12 EA / (l0 m))`` the highest axial frequency: 1.6e-5 s here, not the paper's 1e-4 s.
The result is checked against an independent model, the planar pendulum of n rigid uniform
rods in joint angles with a dense mass matrix, integrated by DOP853 at tight tolerance, and
against RK4 with half the step.

The scene lives in the package (``skfem_cable.scenes.hanging_chain``; the studies in
``skfem_cable.scenes.rodchain_studies``): ``skfem-cable run hanging-chain --out DIR`` writes
the same run into a run directory (VTU series, summary, plots).

Run ``python demos/hanging_chain.py``; the flags ``--energy`` (the paper's first experiment:
20 soft rods falling while turning at 1 rad/s, a check of energy conservation),
``--oscillations`` (small oscillations against rigid links and the Bessel frequencies of the
continuous chain), ``--convergence`` (number of rods at fixed total length and mass) and
``--ancf`` (the same tether as ANCF truss and cable elements) print those studies.
"""

import sys

from skfem_cable.scenes.hanging_chain import main
from skfem_cable.scenes.rodchain_studies import (
    ancf_comparison,
    energy_error,
    n_convergence,
    oscillation_table,
)

__all__ = ["main"]


def gallery_figure(path):
    """The gallery's picture (``scripts/gallery.py``) into ``path``: the eleven rods every
    0.05 s of the first second, released from horizontal."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from skfem_cable.scenes.hanging_chain import simulate_release

    res = simulate_release(11, t_end=1.0, output_dt=1e-3)
    fig, ax = plt.subplots(1, 1, figsize=(5.0, 4.0), layout="constrained")
    n = len(res.t)
    for k in range(0, n, 50):
        joints = res.joints[k]
        ax.plot(joints[:, 0], joints[:, 1], ".-", color="C0", ms=3, lw=1,
                alpha=0.25 + 0.75 * k / (n - 1))
    ax.plot(0, 0, "ko")
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title("steel rod chain released from horizontal, 0 to 1 s", fontsize=10)
    fig.savefig(path, dpi=90, bbox_inches="tight", pad_inches=0.05)
    plt.close(fig)


if __name__ == "__main__":
    for key, value in main().items():
        print(f"{key:>24s}: {value}")
    flags = sys.argv[1:]
    if "--energy" in flags:
        print("paper's energy experiment, max relative energy error (Eq. 31):")
        for dt in (8e-4, 4e-4, 2e-4, 1e-4, 5e-5):
            print(f"  rk4 dt = {dt:.0e}: {energy_error(dt, output_every=1):.3e}")
        for method, rtol in (("RK45", 1e-3), ("RK45", 1e-6), ("RK45", 1e-8), ("DOP853", 1e-8)):
            err = energy_error(1e-3, method=method, rtol=rtol, atol=1e-2 * rtol)
            print(f"  {method} rtol = {rtol:.0e}: {err:.3e}")
        print(f"  slack rods (compression=False), rk4 dt = 1e-4: "
              f"{energy_error(1e-4, compression=False):.3e}")
    if "--oscillations" in flags:
        print("hanging-chain frequencies: rod chain / rigid links - 1 | / continuous - 1:")
        for n, (rigid, cont) in oscillation_table().items():
            print(f"  n = {n:3d}: " + " ".join(f"{x:9.2e}" for x in rigid) + " | "
                  + " ".join(f"{x:9.2e}" for x in cont))
    if "--ancf" in flags:
        print("free end, ANCF vs rod chain, max distance / length (t <= 0.4 s, 1 s):")
        for (kind, n_el, n_rods), d in ancf_comparison().items():
            print(f"  {kind:5s} {n_el:3d} elements vs {n_rods:3d} rods: "
                  + "  ".join(f"{x:.3e}" for x in d))
    if "--convergence" in flags:
        print("free-end distance to the finest chain / length (t <= 0.25 s, 0.4 s, 1 s):")
        for n, d in n_convergence().items():
            print(f"  n = {n:3d}: " + "  ".join(f"{x:.3e}" for x in d))
