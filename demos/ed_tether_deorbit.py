"""An electrodynamic tether lowers its orbit: altitude against days.

A 5 km aluminium tether (radius 1 mm) hangs along the local vertical between two 500 kg
end masses in a 400 km circular equatorial orbit, gravity-gradient stabilised.  It
crosses the Earth's dipole field (``MagneticDipole``: 8.0e22 A m^2, not tilted, so
``B = mu_0 M / (4 pi a^3)`` points north on the equator) at the speed ``v - Omega_E a``
relative to the co-rotating ionosphere.  The motional EMF ``E = (v - Omega_E a) B L``
(about 920 V) drives the short-circuit current ``I = E / R_c`` through the circuit's
resistance ``R_c = 1000 ohm`` (tether, contactors and load: about 0.9 A), and the Lorentz
force ``I L x B`` points against the motion: a drag of about 0.12 N.

Gauss's equation for a tangential force ``F_t`` on a near-circular orbit (the specific
energy ``-mu / (2 a)`` changes at ``v F_t / m``, with ``v = n a``) gives the averaged decay

    da/dt = 2 F_t / (m n) = -2 (n - Omega_E) a B(a)^2 L^2 / (R_c m n),
    B(a) = mu_0 M / (4 pi a^3),

integrated here by ``scipy.integrate.solve_ivp`` as the reference: about 18 km a day,
faster as the orbit sinks (``da/dt`` grows as ``a^-5``).

The simulation follows the tether itself (``ElectrodynamicForce`` with
``current="short-circuit"``, on the compiled step, 200 steps per orbit).  The system's
coordinates are offsets from a Keplerian reference point; as the tether sinks it drifts
away from it, so after every orbit the reference is moved onto the centre of mass's
osculating orbit (``Orbit.from_state``) and the offsets shifted accordingly: the offsets
stay small, which keeps the integrator's error on the relative orbit small.  The altitude
is that of the osculating semi-major axis of the centre of mass, ``a - R_E``.

The test (``tests/test_electrodynamic.py``) checks the drop over a quarter of a day
against the reference within 2 %.  Run ``python demos/ed_tether_deorbit.py`` (two days).
"""

import numpy as np
from scipy.integrate import solve_ivp

import skfem_cable as sc
from skfem_cable.loads.electrodynamic import MU0_OVER_4PI, OMEGA_EARTH
from skfem_cable.loads.orbit_gravity import system_mass_points

#: The tether and its circuit (SI units).
TETHER = {"length": 5e3, "radius": 1e-3, "E": 7e10, "density": 2700.0, "end_mass": 500.0,
          "resistance": 1000.0, "altitude": 400e3, "moment": 8.0e22, "n_elements": 4,
          "steps_per_orbit": 200}


def build(orbit, p=TETHER, lorentz=True):
    """The tether between its end masses, in orbit on ``orbit``, short-circuited through
    the co-rotating ionosphere (without the Lorentz force if not ``lorentz``):
    ``(system, load)``."""
    half = p["length"] / 2
    cable = sc.Cable.straight([-half, 0, 0], [half, 0, 0], p["n_elements"],
                              sc.Section.circular(p["radius"], p["E"], p["density"]))
    load = sc.ElectrodynamicForce(cable, "short-circuit", sc.MagneticDipole(p["moment"]),
                                  resistance=p["resistance"],
                                  plasma_rotation=[0, 0, OMEGA_EARTH])
    system = (sc.System([cable]).add_point_mass(cable.node(0), p["end_mass"])
              .add_point_mass(cable.node(-1), p["end_mass"]).add_orbit(orbit))
    return (system.add_load(load) if lorentz else system), load


def start(p=TETHER):
    """The circular orbit and the gravity-gradient steady state (found without the
    Lorentz force), at rest in the orbiting frame: ``(orbit, State)``."""
    orbit = sc.Orbit(sc.MU_EARTH, sc.R_EARTH + p["altitude"])
    n = orbit.mean_motion
    free = build(orbit, p, lorentz=False)[0]   # no steady state with the drag
    steady = sc.solve_steady(free, omega=[0, 0, n])
    system = build(orbit, p)[0]
    v = system.rotation_operator(np.cross([0, 0, n], np.eye(3)).T) @ steady.q
    return orbit, sc.State(system, steady.q, steady.lam, v=v)


def centre_of_mass(system, q, v):
    """Offset and velocity of the centre of mass and the total mass."""
    return system.centre_of_mass(q), system.centre_of_mass(v), \
        system_mass_points(system).mass.sum()


def recentred(system, orbit, q, v, t):
    """The osculating orbit of the centre of mass at ``t`` and the offsets ``(q, v)``
    measured from its reference point (the same absolute state)."""
    x, u, _ = centre_of_mass(system, q, v)
    new = sc.Orbit.from_state(sc.MU_EARTH, orbit.position(t) + x, orbit.velocity(t) + u,
                              t0=t)
    zero = np.zeros(3)
    return (new, q - system.rigid_motion_velocity(q, zero, velocity=x),
            v - system.rigid_motion_velocity(q, zero, velocity=u))


def reference(t, a0, p=TETHER):
    """Gauss's averaged decay: the semi-major axis (m) at the times ``t`` (s)."""
    L = p["length"]
    m = 2 * p["end_mass"] + p["density"] * np.pi * p["radius"] ** 2 * L

    def rate(_, a):
        n = np.sqrt(sc.MU_EARTH / a**3)
        B = MU0_OVER_4PI * p["moment"] / a**3
        return -2 * (n - OMEGA_EARTH) * a * B**2 * L**2 / (p["resistance"] * m * n)

    return solve_ivp(rate, (0.0, t[-1]), [a0], rtol=1e-10, atol=1e-6, t_eval=t).y[0]


def main(days=2.0, p=TETHER):
    """Simulate ``days`` days, one orbit at a time: times (days), altitudes (km) of the
    simulation and of the reference, the current (A), the drop and the reference's drop
    (m)."""
    orbit, state = start(p)
    q, v, t = state.q, state.v, 0.0
    t_end = days * 86400.0
    times, a, currents = [], [], []
    while t < t_end - 1e-6:
        system, load = build(orbit, p)
        span = min(orbit.period, t_end - t)
        result = sc.simulate(system, t_start=t, t_end=t + span,
                             dt=orbit.period / p["steps_per_orbit"], every=20,
                             initial=sc.State(system, q, v=v))
        arcs = result.reference  # the run's reference: the orbit and its rebases
        for qk, vk, tk in zip(result.q[:-1], result.v[:-1], result.t[:-1]):
            x, u, _ = centre_of_mass(system, qk, vk)
            a.append(sc.Orbit.from_state(sc.MU_EARTH, arcs.position(tk) + x,
                                         arcs.velocity(tk) + u).a)
            times.append(tk)
            currents.append(load.evaluate(system, qk, vk, tk, arcs)["current"])
        q, v, t = result.q[-1], result.v[-1], result.t[-1]
        orbit, q, v = recentred(system, arcs, q, v, t)
    times.append(t)
    a.append(orbit.a)
    times, a = np.array(times), np.array(a)
    exact = reference(times, a[0], p)
    out = {"days": times / 86400.0, "altitude": (a - sc.R_EARTH) / 1e3,
           "reference_altitude": (exact - sc.R_EARTH) / 1e3, "current": np.array(currents),
           "drop": a[0] - a[-1], "reference_drop": exact[0] - exact[-1]}
    print(f"{days:g} days: altitude {out['altitude'][0]:.2f} -> {out['altitude'][-1]:.2f} km, "
          f"drop {out['drop'] / 1e3:.3f} km (Gauss's equation {out['reference_drop'] / 1e3:.3f} "
          f"km), current {np.mean(currents):.3f} A")
    return out


def gallery_figure(path):
    """The gallery's picture (``scripts/gallery.py``) into ``path``: the altitude of the
    centre of mass's osculating orbit over two days, and the short-circuit current,
    against Gauss's averaged equation."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out = main()
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(7.5, 3.0), layout="constrained")
    ax.plot(out["days"], out["reference_altitude"], color="0.6", lw=3,
            label="Gauss's equation")
    ax.plot(out["days"], out["altitude"], "C0", lw=1, label="tether model")
    ax.set(xlabel="t [days]", ylabel="altitude a - R_E [km]")
    ax.legend(fontsize=8)
    bx.plot(out["days"][:-1], out["current"], "C1")
    bx.set(xlabel="t [days]", ylabel="short-circuit current [A]")
    fig.suptitle(f"Drop {out['drop'] / 1e3:.3f} km, Gauss's equation "
                 f"{out['reference_drop'] / 1e3:.3f} km", fontsize=10)
    fig.savefig(path, dpi=90, bbox_inches="tight", pad_inches=0.05)
    plt.close(fig)


if __name__ == "__main__":
    main()
