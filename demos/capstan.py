"""The capstan: a rope over a fixed drum, held at T1 = 100 N on one side and pulled on
the other until it slides (wrap angle pi, mu = 0.3): T2 / T1 = exp(mu pi)
(Euler-Eytelwein), ``docs/contact.md``.

The rig is the ``capstan`` scene's (``skfem_cable.scenes.capstan``: why the rope is made
to slide, and how the tensions are read; ``skfem-cable run capstan`` writes its run
store).  Run ``python demos/capstan.py``; ``tests/test_contact.py`` checks it.
"""

import numpy as np

import skfem_cable as sc
from skfem_cable.scenes.capstan import LEG, R, capstan, leg_tensions


def main(mu=0.3, t_end=0.35):
    """``(T1, T2, exp(mu pi))`` of the rope sliding over the drum with friction ``mu``:
    the legs' tensions averaged over the last 0.1 s of a run of ``t_end``."""
    system, cable, _ = capstan(mu)
    result = sc.simulate(system, t_end=t_end, dt=1e-3, every=2)
    left, right = leg_tensions(result, cable, since=t_end - 0.1)
    return left, right, np.exp(mu * np.pi)


def gallery_figure(path, mu=0.3):
    """The gallery's picture (``scripts/gallery.py``) into ``path``: the rope on the drum
    with the drum's force on each element drawn as an arrow, and the tension along the
    arc against ``T1 exp(mu phi)``."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    system, cable, contact = capstan(mu)
    result = sc.simulate(system, t_end=0.35, dt=1e-3, every=10)
    state = result.state(-1)
    q = state.q[system.dofs(cable)]
    forces = contact.forces(state)
    s = np.linspace(0, cable.length, 400)
    x = cable.interpolate(q, s)[0]
    mid = cable.interpolate(q, 0.5 * (cable.mesh.p[0, 1:] + cable.mesh.p[0, :-1]))[0]
    normal = mid[:, :2] / np.linalg.norm(mid[:, :2], axis=1, keepdims=True)
    push = forces["normal"][:, None] * normal + forces["tangential"][:, :2]
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(8.0, 3.4), layout="constrained")
    ax.add_patch(plt.Circle((0, 0), R, color="0.85"))
    ax.plot(x[:, 0], x[:, 1], "k-", lw=1.2)
    scale = 0.15 / np.abs(push).max()
    ax.quiver(mid[:, 0], mid[:, 1], push[:, 0], push[:, 1], angles="xy", scale_units="xy",
              scale=1 / scale, color="tab:red", width=0.006)
    ax.set_aspect("equal")
    ax.set_title("drum's force on each element", fontsize=10)
    arc = s[(s > LEG + 0.05) & (s < cable.length - LEG - 0.05)]
    xa = cable.interpolate(q, arc)[0]
    phi = np.arctan2(xa[:, 1], -xa[:, 0])
    left, right = leg_tensions(result, cable, since=0.25)
    bx.plot(phi, left * np.exp(mu * phi), "k-", lw=0.8, label="T1 exp(mu phi)")
    bx.plot(phi[::8], state.tension(cable, arc[::8]), ".", ms=5, label="rope")
    bx.set_xlabel("phi [rad]")
    bx.set_ylabel("tension [N]")
    bx.legend(fontsize=8)
    bx.set_title(f"mu = {mu}: T2 / T1 / exp(mu pi) - 1 = "
                 f"{right / left / np.exp(mu * np.pi) - 1:.1e}", fontsize=10)
    fig.savefig(path, dpi=90, bbox_inches="tight", pad_inches=0.05)
    plt.close(fig)


if __name__ == "__main__":
    for mu in (0.0, 0.3):
        t1, t2, ratio = main(mu)
        print(f"mu = {mu}: T1 = {t1:.3f} N, T2 = {t2:.3f} N, T2 / T1 = {t2 / t1:.5f}, "
              f"exp(mu pi) = {ratio:.5f}")
