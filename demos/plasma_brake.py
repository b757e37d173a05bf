"""A plasma brake lowers a 260 kg object from 800 km: altitude against days, in the IRI
ionosphere (Janhunen, Ann. Geophys. 32, 1207, 2014: a 5 km, 0.055 kg tether at -1 kV,
0.43 mN, about 100 km of altitude a year).

The scene is ``skfem_cable.scenes.plasma_brake`` (``skfem-cable run plasma-brake``): the
object at the lower end of a 5 km tether with a 0.5 kg tip mass, gravity-gradient
stabilised along the local vertical, in a sun-synchronous circular 800 km orbit from
2026-01-01 00:00 UTC; the tether at -1 kV meets the ram flow of the co-rotating
ionosphere, whose density is IRI's (F10.7 = 150, O+), sampled at knots every 60 s along
the orbit (``PlasmaBrake(sample_every=60)``).  The run's Encke rectification keeps the
reference point on the centre of mass's orbit; the altitude is that of the osculating
semi-major axis of the centre of mass, ``a - R_E``, and Gauss's equation
``da/dt = 2 a^2 (V . F) / (mu m)`` integrated with the brake's force at the saved steps
(evaluated with IRI at the tether's points) gives the drop it should have
(``reference_drop``).

Run ``python demos/plasma_brake.py [days]`` (default 2 days, 68.9 s CPU: a drop of
394.7 m against Gauss's 400.3 m, the braking force 0.31 mN on average, between 0.12 and
0.64 mN around each orbit with IRI's day and night; its CPU time is printed) and
``--figure PATH`` for the picture.
"""

import argparse
import time

import numpy as np

import skfem_cable as sc
from skfem_cable.loads.orbit_gravity import system_mass_points
from skfem_cable.runner.summary import centre_of_mass_orbit
from skfem_cable.scenes.plasma_brake import BRAKE, start


def main(days=2.0, p=BRAKE, plasma=None, every=20):
    """Simulate ``days`` days: times (days), altitudes (km) and the along-track force
    (mN) at every ``every``-th step, the drop (m) and Gauss's equation's drop with the
    force the run reports (m), the yearly rate of the mean force (km/year), the run's CPU
    time (s)."""
    clock = time.process_time()
    orbit, state = start(p, plasma=plasma)
    system, load = state.system, state.system.loads[-1]
    period = orbit.period
    result = sc.simulate(system, t_end=days * 86400.0, dt=period / p["steps_per_orbit"],
                         every=every, initial=state)
    mass = system_mass_points(system).mass.sum()
    a, rate, along = [], [], []
    for q, v, t in zip(result.q, result.v, result.t):
        osculating = centre_of_mass_orbit(system, sc.State(system, q, v=v, t=t),
                                          result.reference)
        V = result.reference.velocity(t) + system.centre_of_mass(v)
        force = load.evaluate(system, q, v, t, result.reference)["force"]
        a.append(osculating.a)
        rate.append(2 * osculating.a**2 * (V @ force) / (sc.MU_EARTH * mass))
        along.append(V @ force / np.linalg.norm(V))
    a, rate, along = np.array(a), np.array(rate), np.array(along)
    out = {"days": result.t / 86400.0, "altitude": (a - sc.R_EARTH) / 1e3,
           "force": along * 1e3, "drop": a[0] - a[-1],
           "reference_drop": -np.trapezoid(rate, result.t),
           "km_per_year": -rate.mean() * 3.15576e7 / 1e3,
           "cpu": time.process_time() - clock}
    print(f"{days:g} days: altitude {out['altitude'][0]:.3f} -> {out['altitude'][-1]:.3f} "
          f"km, drop {out['drop']:.1f} m (Gauss's equation with the brake's force "
          f"{out['reference_drop']:.1f} m), mean along-track force "
          f"{out['force'].mean():.3f} mN ({out['km_per_year']:.0f} km/year), CPU "
          f"{out['cpu']:.1f} s")
    return out


def figure(out, path):
    """Altitude and along-track force against days into ``path``."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, 1, figsize=(6.5, 4.5), layout="constrained", sharex=True)
    axes[0].plot(out["days"], out["altitude"], lw=0.8)
    axes[0].set(ylabel="altitude a - R_E [km]")
    axes[1].plot(out["days"], -out["force"], lw=0.8)
    axes[1].axhline(0.43, color="k", ls="--", lw=0.8, label="Janhunen (2014): 0.43 mN")
    axes[1].set(xlabel="t [days]", ylabel="braking force [mN]")
    axes[1].legend(fontsize=8)
    fig.suptitle(f"5 km plasma brake at -1 kV in IRI, 260 kg from 800 km: drop "
                 f"{out['drop']:.0f} m in {out['days'][-1]:.2f} days "
                 f"({out['km_per_year']:.0f} km/year)", fontsize=10)
    fig.savefig(path, dpi=90, bbox_inches="tight", pad_inches=0.05)
    plt.close(fig)


def gallery_figure(path):
    """The gallery's picture (``scripts/gallery.py``) into ``path``: two days."""
    figure(main(), path)


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("days", nargs="?", type=float, default=2.0)
    parser.add_argument("--figure", help="save the figure to this PNG")
    args = parser.parse_args()
    result = main(args.days)
    if args.figure:
        figure(result, args.figure)
