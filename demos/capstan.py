"""The capstan: a rope over a fixed drum, held at T1 on one side and pulled on the other
until it slides: T2 / T1 = exp(mu theta) (Euler-Eytelwein), ``docs/contact.md``.

The rope (axial law only, EA = 1e5 N, 0.1 kg/m, d = 1 cm) goes over the top of a fixed
cylinder (R = 0.5 m, wrap angle pi).  Its left end is pulled down by T1 = 100 N (ramped
in over 0.05 s); a pin holds its right end, then pulls it down at V = 0.1 m/s (ramped
in over 0.05 s).  Friction regularised in the slip velocity (``eps`` = 1 mm/s) carries
nothing at rest, so the rope is made to slide (``V / eps = 100``: the friction is
``1 - 5e-5`` of Coulomb's), and the tensions are read in steady sliding, averaged over
the last 0.1 s (the elements passing over the drum ripple them by about 1 %).

Run ``python demos/capstan.py``; ``tests/test_contact.py`` checks it.
"""

import numpy as np
from skfem import MeshLine

import skfem_cable as sc

R, LEG, T1, V, RAMP = 0.5, 0.3, 100.0, 0.1, 0.05
ROPE = sc.Section.circular(5e-3, 1.27e9, 1273.0, gamma_axial=1e-4)  # EA 1e5 N, 0.1 kg/m
DRUM = sc.Cylinder([0, 0, 0], [0, 0, 1], R)


def smooth(t):
    """0 before 0, 1 after 1, ``3 t^2 - 2 t^3`` between."""
    t = min(max(t, 0.0), 1.0)
    return t * t * (3.0 - 2.0 * t)


def wrapped(radius, leg, n_arc, n_leg, section=ROPE, law="truss"):
    """A cable over the top of a cylinder of axis z (through the origin): left leg up,
    a half circle of ``radius``, right leg down; nodes at the tangent points."""
    arc = np.pi * radius
    s = np.concatenate([np.linspace(0, leg, n_leg + 1)[:-1],
                        leg + np.linspace(0, arc, n_arc + 1)[:-1],
                        leg + arc + np.linspace(0, leg, n_leg + 1)])
    phi = np.clip((s - leg) / radius, 0, np.pi)
    left, right = s < leg, s > leg + arc
    x = np.where(left, -radius, np.where(right, radius, -radius * np.cos(phi)))
    y = np.where(left, s - leg, np.where(right, leg + arc - s, radius * np.sin(phi)))
    tx = np.where(left | right, 0.0, np.sin(phi))
    ty = np.where(left, 1.0, np.where(right, -1.0, np.cos(phi)))
    return sc.Cable(MeshLine(s), section, np.stack([x, y, 0 * x], 1),
                    np.stack([tx, ty, 0 * x], 1), law=law)


def capstan(mu, speed=V, cable=None):
    """The capstan rig (module notes) on ``cable`` (default a new one): ``(system,
    cable, contact)``; ``speed = 0``: the pin holds, and T1 is constant."""
    radius = R + 5e-3 + 1e-5          # the rope's axis, 10 um off the drum at the start
    cable = wrapped(radius, LEG, 24, 4) if cable is None else cable

    def pull(t):
        u = t - RAMP                  # the pull starts when T1 is in
        d = 0.0 if u <= 0 else speed * (u - RAMP / 2) if u > RAMP else \
            speed * u**3 / RAMP**2 * (1 - u / (2 * RAMP))
        return np.array([radius, -LEG - d, 0.0])

    system = (sc.System([cable]).pin(cable.node(-1), pull)
              .add_point_load(cable.node(0), lambda t: [0.0, -T1 * smooth(t / RAMP), 0.0]
                              if speed else [0.0, -T1, 0.0])
              .contact(cable, DRUM, friction=mu, slip_velocity=1e-3))
    return system, cable, system.loads[-1]


def leg_tensions(result, cable, since):
    """The tensions (N) in the middle of the left and right legs, averaged over the saved
    steps from ``since``."""
    states = [result.state(i) for i in range(len(result)) if result.t[i] >= since - 1e-12]
    left = np.mean([s.tension(cable, LEG / 2) for s in states])
    right = np.mean([s.tension(cable, cable.length - LEG / 2) for s in states])
    return left, right


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
