"""Reels on a spinning hub pay out two tethers from 10 m to 1 km: the spin rate the
angular momentum predicts.

A hub (a cylinder of 5 m radius spinning at 0.5 rad/s about its axis ``x``, no external
load) carries two reels
(``sc.Reel``) whose tethers leave through exit guides fixed on the hub (clamped radially,
``System.deploy(..., direction=...)``), each with a 0.1 kg end mass.  Centrifugal force
pulls the tethers out; each reel's motor and brake (``sc.Servo``) hold its free length on
a smooth profile from 10 m to 1000 m over ``duration`` seconds, then hold it.  The wound
tether turns with each drum and rides with the hub (``capacity``).  Nothing acts from
outside, so the angular momentum ``H`` is conserved and, once the tethers have settled,
the system turns rigidly at ``H / I``, with ``I`` the moment of inertia of the deployed,
centrifugally stretched configuration.

The reference is independent of the finite elements: the steady radial state of an
extensible string spinning at ``omega`` with its end mass (``analytic.rotating_string``,
the straight radial tether leaving the guide carries no bending), its moment of inertia
``int mu r^2 ds + m r(L)^2`` at the run's final free length, and ``omega`` found such that
``(I_hub + I_reels + 2 I_tether(omega)) omega`` equals the run's initial ``H`` (secant
iterations).  The run's spin rate is the hub's, averaged over the last ``average``
seconds (the residual libration of the tethers is an oscillation about it).

``main`` returns the run's spin rate, the predicted one, their relative difference, the
drift of ``H`` over the run, and the run.
"""

import numpy as np
from scipy.optimize import root_scalar

import skfem_cable as sc
from skfem_cable.analysis.analytic import rotating_string
from skfem_cable.bodies.catenary import green_stretch
from skfem_cable.constraints.deploy import smooth_profile

SECTION = sc.Section.circular(5e-4, 1e11, 1000.0)    # 0.8 g/m, EA = 79 kN
HUB_RADIUS, TIP_MASS, OMEGA0, CAPACITY = 5.0, 0.1, 0.5, 1010.0
DRUM_RADIUS, DRUM_INERTIA = 0.1, 1e-4                # m, kg m^2
STIFFNESS, DAMPING = 40.0, 20.0                      # of the servo: N m / m, N m s / m


def build(length, n_elements, drives):
    """The hub and two tethers of ``length`` (m) along ``+y`` and ``-y`` from its rim,
    leaving through exit guides from reels with the torque ``drives``; returns ``(system,
    hub, tethers, reels)``."""
    hub = sc.RigidBody.cylinder(radius=HUB_RADIUS, height=2.0, density=500.0)
    bodies, tethers, reels = [hub], [], []
    for k, sign in enumerate((1.0, -1.0)):
        e = np.array([0.0, sign, 0.0])
        tethers.append(sc.Cable.straight(HUB_RADIUS * e, (HUB_RADIUS + length) * e,
                                         n_elements, SECTION, name=f"tether{k}"))
        reels.append(sc.Reel(length, DRUM_RADIUS, DRUM_INERTIA, drive=drives[k],
                             name=f"reel{k}"))
        bodies += [tethers[-1], reels[-1]]
    system = sc.System(bodies)
    for tether, reel in zip(tethers, reels):
        system.deploy(tether, hub.point(tether.q0[:3]), reel=reel, capacity=CAPACITY,
                      direction=tether.q0[3:6])
        system.add_point_mass(tether.node(-1), TIP_MASS)
    return system, hub, tethers, reels


def tether_inertia(length, omega, points=64):
    """Moment of inertia (kg m^2) about the axis of one tether of free ``length`` (m) with
    its end mass in the steady radial state at ``omega`` (rad/s), and its root tension
    (N), from ``analytic.rotating_string`` (Gauss-Legendre rule on ``points`` points)."""
    x, w = np.polynomial.legendre.leggauss(points)
    s = np.concatenate([0.5 * length * (x + 1), [0.0, length]])
    r, T = rotating_string(s, length, SECTION.E * SECTION.A, SECTION.mass_per_length,
                           TIP_MASS, omega, HUB_RADIUS)
    mu = SECTION.mass_per_length
    return 0.5 * length * mu * (w @ r[:-2] ** 2) + TIP_MASS * r[-1] ** 2, T[-2]


def steady_start(system, tethers, length):
    """The coordinates of the steady spinning state at ``OMEGA0`` with tethers of free
    ``length`` as built: nodes on the analytic radii and slopes ``1 + e(T)`` along the
    radius (``analytic.rotating_string``), so that the run starts without a transient."""
    q = system.q0.copy()
    for tether in tethers:
        s = tether.mesh.p[0]
        r, T = rotating_string(s, length, SECTION.E * SECTION.A, SECTION.mass_per_length,
                               TIP_MASS, OMEGA0, HUB_RADIUS)
        e = tether.q0[3:6] / np.linalg.norm(tether.q0[3:6])
        stretch = 1 + green_stretch(T, SECTION.E * SECTION.A)
        q[system.dofs(tether)] = np.hstack([r[:, None] * e, stretch[:, None] * e]).ravel()
    return q


def predicted_rate(hub, length, H, guess):
    """The spin rate at which the hub, the reels' content and two tethers of free
    ``length`` in their steady state have the angular momentum ``H`` (secant iterations of
    ``scipy.optimize.root_scalar``, to 1e-14 relative)."""
    fixed = hub.inertia[0, 0] + 2 * SECTION.mass_per_length * (CAPACITY - length) \
        * HUB_RADIUS**2

    def excess(w):
        return (fixed + 2 * tether_inertia(length, w)[0]) * w - H

    return root_scalar(excess, x0=guess, x1=guess * (1 + 1e-4), method="secant", xtol=1e-300,
                       rtol=1e-14).root


def whole_periods(t, rate, start):
    """The saved steps from the first to the last maximum of ``rate`` after ``start``: a
    whole number of periods of the residual libration, over which its oscillation of the
    spin rate averages out (all steps after ``start`` when there are fewer than two)."""
    after = np.flatnonzero(t >= start)
    inner = after[1:-1]
    peaks = inner[(rate[inner] > rate[inner - 1]) & (rate[inner] >= rate[inner + 1])]
    return after if len(peaks) < 2 else np.arange(peaks[0], peaks[-1] + 1)


def _mean(t, x, steps):
    """Time average of ``x`` over the saved steps ``steps`` (trapezoidal rule)."""
    return float(np.trapezoid(x[steps], t[steps]) / (t[steps[-1]] - t[steps[0]]))


def main(duration=1500.0, settle=500.0, average=300.0, dt=0.1, n_elements=6, l1=1000.0,
         rho_inf=0.8):
    """Deploy to ``l1`` in ``duration`` s and settle ``settle`` s, from the steady state
    at 10 m (``steady_start``), with steps ``dt`` and the spectral radius ``rho_inf``
    (with steps of more than a tenth of a radian of spin, ``rho_inf = 0.8`` can let a
    period-two oscillation of the tethers' tension grow; 0.6 damps it, and spins the
    system down faster).

    Returns
    -------
    dict
        ``measured``: the hub's spin rate averaged over whole periods of the residual
        libration in the last ``average`` s (rad/s, ``whole_periods``); ``predicted``: the
        rate of the deployed configuration with the run's angular momentum averaged
        there; ``difference``: their relative difference;
        ``momentum_drift``: the largest relative change of the angular momentum over the
        run (the integrator's, second order in the step); ``from_start``: the rate
        predicted from the initial angular momentum; ``lengths``: the final free lengths;
        ``rate``, ``result``, ``system``, ``tethers``.
    """
    l0 = 10.0
    profile = smooth_profile(l0, l1, duration)
    hold = tether_inertia(l0, OMEGA0)[1] * DRUM_RADIUS / STIFFNESS
    servos = [sc.Servo(lambda t: profile[0](t) - hold, STIFFNESS, DAMPING, rate=profile[1])
              for _ in range(2)]    # in equilibrium with the tension at the start
    system, hub, tethers, reels = build(l0, n_elements, servos)
    q = steady_start(system, tethers, l0)
    v = system.rigid_motion_velocity(q, [OMEGA0, 0.0, 0.0])
    r = sc.simulate(system, t_end=duration + settle, dt=dt, rho_inf=rho_inf, newton="full",
                    initial=sc.State(system, q, v=v), every=5)
    H = np.array([system.angular_momentum(qi, vi, t=ti)[0]
                  for qi, vi, ti in zip(r.q, r.v, r.t)])
    d = system.dofs(hub)
    rate = hub.angular_velocity(r.q[:, d], r.v[:, d])[:, 0]
    window = whole_periods(r.t, rate, r.t[-1] - average)
    lengths = r.q[-1, [system.dofs(reel)[0] for reel in reels]]
    length, measured = float(lengths.mean()), _mean(r.t, rate, window)
    predicted = predicted_rate(hub, length, _mean(r.t, H, window), measured)
    return {"measured": measured, "predicted": predicted,
            "difference": abs(measured / predicted - 1),
            "momentum_drift": float(np.abs(H / H[0] - 1).max()),
            "from_start": predicted_rate(hub, length, float(H[0]), measured),
            "lengths": lengths, "rate": rate, "result": r, "system": system,
            "tethers": tethers}


def gallery_figure(path):
    """The gallery's picture (``scripts/gallery.py``) into ``path``: the hub spin rate and
    the free length while the reels pay out, with the angular-momentum prediction."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out = main()
    r = out["result"]
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(7.5, 3.0), layout="constrained")
    ax.plot(r.t, out["rate"], "C0", label="hub")
    ax.axhline(out["predicted"], color="k", lw=0.8, ls="--", label="H / I, deployed")
    ax.set(xlabel="t [s]", ylabel="spin rate [rad/s]")
    ax.legend(fontsize=8)
    system = out["system"]
    reel = system.bodies[2]
    bx.plot(r.t, r.q[:, system.dofs(reel)[0]], "C1")
    bx.set(xlabel="t [s]", ylabel="free length [m]")
    fig.suptitle(f"Settled spin {out['measured']:.8f} rad/s, predicted "
                 f"{out['predicted']:.8f} ({out['difference']:.1e}); angular momentum drift "
                 f"{out['momentum_drift']:.1e}", fontsize=9)
    fig.savefig(path, dpi=90, bbox_inches="tight", pad_inches=0.05)
    plt.close(fig)


if __name__ == "__main__":
    out = main()
    print(f"settled spin rate {out['measured']:.10f} rad/s, predicted "
          f"{out['predicted']:.10f} rad/s (relative difference {out['difference']:.2e}); "
          f"angular momentum drift {out['momentum_drift']:.2e} (from the initial one: "
          f"{out['from_start']:.10f} rad/s); free lengths {out['lengths']}")
