"""The E-sail's full rig: a remote unit at each tether tip and the ring of auxiliary
tethers that keeps neighbouring units apart.

Physics
-------
``esail.FULL_RIG`` is the baseline design of Janhunen et al. (Rev. Sci. Instrum. 81,
111301, 2010): 100 tethers of 20 km spinning at 1.2e-3 rad/s, a 1.5 kg remote unit at
each tip, and auxiliary tethers (tension-only, 1.26 km each) joining neighbouring units
into a ring, designed to carry 2.16 mN in the sail's steady spin under the wind.  Facing
the wind, the sail cones; the ring keeps every tether at the same angle and the units
evenly spaced.  Switching the tethers' voltage on and off with neighbours in antiphase
(the hardest modulation on the spacing: one tether pushed while its neighbour is not)
for one spin period, the units keep their spacing with the ring; without it,
neighbouring units swing towards each other.

Run ``python demos/esail_rig.py [--tethers P] [--elements N] [--figure PNG]``: prints
the ring's tension in the steady spin and the least spacing of neighbouring units over
the modulated spin period, with and without the ring, and draws the rig.
"""

import argparse
from dataclasses import replace

import numpy as np

from skfem_cable.scenes import esail
from skfem_cable.scenes.esail.modulation import spacing_under_modulation
from skfem_cable.scenes.esail.rig import steady_facing


def main(tethers=100, elements=4, alpha=30.0, per_spin=90, relax=1.0):
    """The rig of ``tethers`` x ``elements`` at sailing angle ``alpha`` (deg): its steady
    spin facing the wind (the ring's tension, N), and the least distance between
    neighbouring units over one spin period of on-off modulation (steps of a
    ``per_spin``-th of a period, from ``esail.settled`` with ``relax`` periods of
    relaxation) over the nominal spacing, with and without the ring; and the scenes."""
    config = replace(esail.FULL_SIZE, n_tethers=tethers)
    rig = replace(esail.FULL_RIG, config=config)
    ringed = rig.build(alpha, elements)
    free = esail.build(config, alpha, elements, remote_units=rig.remote_units)
    state, R = steady_facing(ringed)
    out = {"tension": esail.auxiliary_tension(ringed, state.q), "design": rig.auxiliary_tension,
           "steady": state.q, "R": R, "ringed": ringed}
    for name, scene in (("with_ring", ringed), ("without_ring", free)):
        ratios, result = spacing_under_modulation(esail.settled(scene, spins=relax),
                                                  steps_per_spin=per_spin)
        out[name] = ratios.min(axis=1)
        out["t"] = result.t - result.t[0]
    return out


def draw(out, path):
    """The rig in its steady spin facing the wind (3-D view, the ring drawn), and the
    least spacing of neighbouring units over the modulated spin period."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    scene, q = out["ringed"], out["steady"]
    fig = plt.figure(figsize=(10.0, 4.0), layout="constrained")
    ax = fig.add_subplot(1, 2, 1, projection="3d")
    system = scene.system
    hub = q[system.dofs(scene.hub)]
    frame = scene.hub.rotation(hub)[:, [1, 2, 0]]  # spin axis last: drawn upwards
    centre = 0.5 * (hub[:3] + hub[3:6])

    def local(x):
        return (x - centre) @ frame / 1e3

    for cable in scene.tethers:
        s = np.linspace(0.0, cable.length, 4 * cable.n_elements + 1)
        ax.plot(*local(cable.interpolate(q[system.dofs(cable)], s)[0]).T, color="tab:blue",
                lw=0.6)
    tips = local(esail.tip_positions(scene, q))
    ax.plot(*np.vstack([tips, tips[:1]]).T, color="tab:orange", lw=1.0,
            label="auxiliary tethers")
    ax.scatter(*tips.T, s=4, color="k", label="remote units")
    ax.set_box_aspect((1.0, 1.0, 0.5))
    ax.view_init(elev=20, azim=-60)
    ax.set_xlabel("x (km)")
    ax.set_ylabel("y (km)")
    ax.set_zlabel("axial (km, stretched)", labelpad=2)
    ax.set_title(f"{len(scene.tethers)} tethers facing the wind (ring at "
                 f"{1e3 * out['tension'].mean():.2f} mN)", fontsize=9)
    ax.legend(fontsize=7, loc="upper left")
    ax2 = fig.add_subplot(1, 2, 2)
    period = scene.config.spin_period
    ax2.plot(out["t"] / period, out["with_ring"], label="with the ring")
    ax2.plot(out["t"] / period, out["without_ring"], label="without")
    ax2.axhline(0.5, color="gray", ls=":", lw=0.8)
    ax2.set_xlabel("time (spin periods)")
    ax2.set_ylabel("least spacing / nominal")
    ax2.set_title("on-off modulation, neighbours in antiphase", fontsize=9)
    ax2.legend(fontsize=8)
    fig.savefig(path, dpi=90, bbox_inches="tight", pad_inches=0.05)
    plt.close(fig)


def gallery_figure(path):
    """The gallery's picture (``scripts/gallery.py``) into ``path``: ``main`` with 24
    tethers of 3 elements (the 100-tether rig is ``benchmarks/esail_rig.py``)."""
    draw(main(tethers=24, elements=3), path)


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--tethers", type=int, default=100)
    parser.add_argument("--elements", type=int, default=4)
    parser.add_argument("--figure", default="esail_rig.png")
    args = parser.parse_args()
    result = main(args.tethers, args.elements)
    print(f"ring tension in the steady spin: {1e3 * result['tension'].mean():.4f} mN "
          f"(design {1e3 * result['design']:.4f} mN)")
    print(f"least spacing over the modulated spin period: with the ring "
          f"{result['with_ring'].min():.3f}, without {result['without_ring'].min():.3f}")
    draw(result, args.figure)
