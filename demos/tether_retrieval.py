"""Retrieving a swinging tether: the swing grows as the tether shortens.

A light tether with a 1 kg end mass hangs from a reel fixed in space and swings with a
small amplitude while the reel pulls it in at a constant rate, from 10 m to 2.5 m.  The
reference is the pendulum of variable length ``l(t)`` (a point mass on an inextensible
massless string reeled in at the pivot), ``l theta'' + 2 l' theta' + g sin(theta) = 0``,
integrated to 1e-10.  Reeling in pumps energy into the swing: for slow retrieval the
adiabatic invariant (energy over frequency) makes the amplitude grow as ``l^(-3/4)``, the
known instability of tether retrieval (for a spinning tether, the in-plane libration);
deployment does the opposite and damps it.

``main`` returns the growth of the swing amplitude (last swing over first) of the cable
model and of the reference.
"""

import numpy as np
from scipy.integrate import solve_ivp

import skfem_cable as sc

SECTION = sc.Section.circular(2e-4, 1e11, 1000.0)   # 0.13 g/m, stretch 8e-4 under 1 kg
G = 9.81


def pendulum(l0, rate, omega0, t):
    """Swing angle of the variable-length pendulum ``l = l0 + rate t`` pushed at rest with
    the angular velocity ``omega0``, at the times ``t``."""
    def rhs(s, y):
        ell = l0 + rate * s
        return [y[1], -(2 * rate * y[1] + G * np.sin(y[0])) / ell]

    return solve_ivp(rhs, (0, t[-1]), [0.0, omega0], t_eval=t, rtol=1e-11,
                     atol=1e-13).y[0]


def amplitudes(t, angle, first_period, last_period):
    """Largest swing angle over the first and the last period."""
    return (np.abs(angle[t <= first_period]).max(),
            np.abs(angle[t >= t[-1] - last_period]).max())


def main(n_elements=8, l0=10.0, l1=2.5, duration=60.0, dt=0.05, swing_deg=2.0, tip_mass=1.0):
    """Retrieve from ``l0`` to ``l1`` (m) in ``duration`` (s); returns the growth of the
    swing amplitude, of the model (``growth``) and of the pendulum (``reference``), the
    adiabatic estimate ``(l0 / l1)^(3/4)``, the angles and the run."""
    tether = sc.Cable.straight([0, 0, 0], [0, -l0, 0], n_elements, SECTION)
    rate = (l1 - l0) / duration
    system = sc.System([tether]).deploy(tether, length=lambda t: l0 + rate * t,
                                        rate=lambda t: rate, acceleration=lambda t: 0.0)
    system.add_point_mass(tether.node(-1), tip_mass).add_gravity([0, -G, 0])
    hanging = sc.solve_static(system)
    omega0 = np.radians(swing_deg) * np.sqrt(G / l0)      # a push: amplitude ~ swing_deg
    v = system.rigid_motion_velocity(hanging.q, [0, 0, omega0]).reshape(-1, 6)
    v += rate * hanging.q.reshape(-1, 6) / l0              # the mesh follows the reel
    r = sc.simulate(system, t_end=duration, dt=dt, rho_inf=0.9,
                    initial=sc.State(system, hanging.q, hanging.lam, v=v.ravel()))
    tip = r.position(tether, tether.length)
    angle = np.arctan2(tip[:, 0], -tip[:, 1])
    reference = pendulum(l0, rate, omega0, r.t)
    periods = (2 * np.pi * np.sqrt(l0 / G), 2 * np.pi * np.sqrt(l1 / G))
    model, exact = amplitudes(r.t, angle, *periods), amplitudes(r.t, reference, *periods)
    return {"growth": model[1] / model[0], "reference": exact[1] / exact[0],
            "adiabatic": (l0 / l1) ** 0.75, "t": r.t, "angle": angle,
            "reference_angle": reference, "result": r}


def gallery_figure(path):
    """The gallery's picture (``scripts/gallery.py``) into ``path``: the swing angle while
    retrieving from 10 m to 2.5 m, the cable model on the pendulum's curve."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out = main()
    fig, ax = plt.subplots(1, 1, figsize=(7.5, 3.0), layout="constrained")
    ax.plot(out["t"], np.degrees(out["reference_angle"]), color="0.6", lw=3,
            label="variable-length pendulum")
    ax.plot(out["t"], np.degrees(out["angle"]), color="C0", lw=1, label="cable model")
    ax.set(xlabel="t [s]", ylabel="swing angle [deg]")
    ax.set_title(f"Retrieval 10 m -> 2.5 m: the swing grows {out['growth']:.4f}x "
                 f"(pendulum {out['reference']:.4f}x)", fontsize=10)
    ax.legend(fontsize=8, loc="upper left")
    fig.savefig(path, dpi=90, bbox_inches="tight", pad_inches=0.05)
    plt.close(fig)


if __name__ == "__main__":
    out = main()
    print(f"swing amplitude growth: model {out['growth']:.4f}, variable-length pendulum "
          f"{out['reference']:.4f}, adiabatic (l0/l1)^(3/4) {out['adiabatic']:.4f}")
