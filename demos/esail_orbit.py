"""The E-sail around the Sun: a week of the paper's 12-tether sail on a circular orbit of
1 AU.

Physics
-------
The baseline sail of Table 1 (``esail.build_orbit``) sits on the circular heliocentric
orbit of 1 AU (``System.add_orbit``): its coordinates are offsets from the orbit's
reference point, the Sun's differential gravity acts on every mass, and the solar wind is
evaluated at each Gauss point's heliocentric position, scaled by ``(AU / r)^(7/6)``.  The
thrust, about 54 mN on 5576 kg (1e-5 m/s^2), pushes the sail off the Keplerian orbit:
``a t^2 / 2`` outwards at first (1800 km after a week), and the Coriolis effect of the
orbit turns the departure backwards along the track.  The departure is compared with a
point mass propagated by DOP853 (rtol 1e-12) under the run's own recorded thrust.  The
spin axis keeps its inertial direction while the Sun line turns with the orbit by
``n = 0.986 deg/day``, so the sailing angle grows by about that much a day.

Run ``python demos/esail_orbit.py [--days D] [--elements N] [--dt S] [--out DIR]``: writes
``esail_orbit.png`` (departure in the orbit frame, spin rate and sailing angle against
days) and ``esail_orbit.npz`` into ``DIR`` and prints the key numbers.
"""

import argparse
import time
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp
from scipy.interpolate import CubicSpline

import skfem_cable as sc
from skfem_cable.loads.orbit_gravity import system_mass_points
from skfem_cable.scenes import esail
from skfem_cable.space.tidal import differential_gravity

DAY = 86400.0


def centre_of_mass(system, x):
    """Centre of mass (nt, 3) of the states ``x`` (nt, n) (positions or velocities)."""
    return system.centre_of_mass(x)


def point_mass(orbit, t, thrust, mass, x0, v0):
    """Departure (nt, 3) from ``orbit`` of a point mass of ``mass`` under the thrust
    samples ``thrust`` (nt, 3) (cubic spline) and the differential gravity (DOP853,
    rtol 1e-12)."""
    force = CubicSpline(t, thrust)

    def rhs(s, y):
        return np.concatenate([y[3:], differential_gravity(orbit.mu, orbit.position(s), y[:3])
                               + force(s) / mass])

    scale = max(1.0, float(np.abs(thrust).max() / mass * t[-1] ** 2))
    sol = solve_ivp(rhs, (t[0], t[-1]), np.concatenate([x0, v0]), method="DOP853",
                    rtol=1e-12, atol=1e-12 * scale, t_eval=t)
    return sol.y[:3].T


def main(days=7.0, elements=5, dt=1.0, alpha=0.0, out="runs/esail_orbit", every=600,
         figure=True):
    """Run the sail for ``days`` with ``elements`` per tether at step ``dt`` (s), sailing
    angle ``alpha`` (deg) at the start, saving every ``every``-th step; returns the key
    numbers (dict) and writes the figure and the series into ``out``."""
    scene = esail.build_orbit(esail.BaselineConfig(), alpha, elements)
    system, orbit = scene.system, scene.orbit
    start = time.perf_counter()
    result = sc.simulate(system, t_end=days * DAY, dt=dt, initial=scene.initial,
                         rho_inf=0.25, every=every)
    wall = time.perf_counter() - start
    outs = esail.outputs(scene, result)
    # the departure from the Keplerian orbit as given: the reference point (re-based by
    # the rectification when the sail has drifted) plus the centre of mass's offset
    kepler = orbit
    com = (result.reference.position(result.t) - kepler.position(result.t)
           + centre_of_mass(system, result.q))
    mass = system_mass_points(system).mass.sum()
    reference = point_mass(kepler, result.t, outs["thrust"], mass, com[0],
                           centre_of_mass(system, result.v)[0])
    series = {"t": result.t, "departure_lvlh": kepler.to_lvlh(result.t, com),
              "point_mass_lvlh": kepler.to_lvlh(result.t, reference),
              "spin_rate": outs["omega_B"][:, 0], "sailing_angle": outs["sailing_angle"],
              "thrust": np.linalg.norm(outs["thrust"], axis=1)}
    departure = np.linalg.norm(com, axis=1)
    summary = {"days": days, "wall_s": wall, "steps": result.stats["steps"],
               "departure_km": departure[-1] / 1e3,
               "point_mass_error_rel": np.linalg.norm(com - reference, axis=1).max()
               / departure.max(),
               "spin_rate_change_rel": series["spin_rate"][-1] / series["spin_rate"][0] - 1,
               "rectifications": result.stats["rectifications"],
               "sailing_angle_deg": np.rad2deg(series["sailing_angle"][-1]),
               "thrust_mean_N": series["thrust"].mean()}
    Path(out).mkdir(parents=True, exist_ok=True)
    np.savez(Path(out) / "esail_orbit.npz", **series)
    if figure:
        summary["figure"] = plot(series, orbit, Path(out) / "esail_orbit.png")
    return summary


#: Window (s) of the spin rate's mean and range in the figure: the samples, minutes
#: apart, alias the spin's swing of a few per cent at its own period.
WINDOW = 6 * 3600.0


def windows(t, x, width):
    """Centres, means, minima and maxima of ``x(t)`` in consecutive windows of ``width``
    (s); a last window shorter than half the others is left out."""
    k = ((t - t[0]) // width).astype(int)
    edges = np.flatnonzero(np.diff(k)) + 1
    parts = np.split(np.arange(len(t)), edges)
    if len(parts) > 1 and t[parts[-1][-1]] - t[parts[-1][0]] < width / 2:
        parts = parts[:-1]
    return tuple(np.array([f(a[p]) for p in parts]) for f, a in
                 ((np.mean, t), (np.mean, x), (np.min, x), (np.max, x)))


def plot(series, orbit, path):
    """Departure from the Keplerian orbit (radial, along-track; point mass dashed), spin
    rate and sailing angle against days; returns the path."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    days = series["t"] / DAY
    fig, ax = plt.subplots(3, 1, figsize=(7, 8), sharex=True)
    for k, name in ((0, "radial"), (1, "along-track")):
        line, = ax[0].plot(days, series["departure_lvlh"][:, k] / 1e3, label=f"{name}")
        ax[0].plot(days, series["point_mass_lvlh"][:, k] / 1e3, "--", color="k", lw=0.8,
                   label="point mass (DOP853)" if k == 0 else None)
    ax[0].set_ylabel("departure from Kepler [km]")
    ax[0].legend()
    centre, mean, low, high = windows(series["t"], series["spin_rate"] * 1e3, WINDOW)
    ax[1].fill_between(centre / DAY, low, high, alpha=0.3, lw=0,
                       label=f"range of the samples in {WINDOW / 3600:g} h")
    ax[1].plot(centre / DAY, mean, label=f"mean over {WINDOW / 3600:g} h")
    ax[1].set_ylabel("spin rate [mrad/s]")
    ax[1].legend()
    ax[2].plot(days, np.rad2deg(series["sailing_angle"]), label="sailing angle")
    ax[2].plot(days, np.rad2deg(orbit.mean_motion * series["t"]), "--", color="k", lw=0.8,
               label="orbit's turn n t")
    ax[2].set_ylabel("sailing angle [deg]")
    ax[2].set_xlabel("days")
    ax[2].legend()
    fig.suptitle("E-sail around the Sun (12 tethers, 1 AU)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return str(path)


def gallery_figure(path, out=None):
    """The gallery's picture (``scripts/gallery.py``) into ``path``: the figure of a week
    with 2 elements per tether (``main``, about 5 minutes) run into ``out`` (default
    ``runs/esail_orbit`` of the repository)."""
    import shutil

    out = Path(out) if out else Path(__file__).resolve().parents[1] / "runs" / "esail_orbit"
    main(elements=2, out=str(out))
    shutil.copyfile(out / "esail_orbit.png", path)


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--days", type=float, default=7.0, help="days to run")
    parser.add_argument("--elements", type=int, default=5, help="elements per tether")
    parser.add_argument("--dt", type=float, default=1.0, help="time step (s)")
    parser.add_argument("--alpha", type=float, default=0.0, help="sailing angle (deg)")
    parser.add_argument("--out", default="runs/esail_orbit", help="output directory")
    args = parser.parse_args()
    summary = main(args.days, args.elements, args.dt, args.alpha, args.out)
    for key, value in summary.items():
        print(f"{key}: {value}")
