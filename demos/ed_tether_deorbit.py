"""A bare electrodynamic tape lowers its orbit: altitude, current, power and EMF against
days, in the IGRF field, the IRI ionosphere and the NRLMSIS atmosphere.

A 5 km aluminium tape (2 cm x 50 um, conductivity 3.5e7 S/m) hangs along the local
vertical between two 500 kg end masses in a 400 km circular orbit inclined 51.6 deg,
from 2026-01-01 00:00 UTC (``EPOCH``), gravity-gradient stabilised.  It is bare: it
collects electrons from the ionosphere along its upper, positively biased part (the
orbital-motion-limited current, ``ElectrodynamicForce(current="oml")``, solved at every
evaluation), and a hollow cathode (10 V drop) with a 100 ohm load at its lower end closes
the circuit.  The field is IGRF and the plasma IRI (F10.7 = 150), both sampled at knots
every 60 s along the orbit and interpolated (``sample_every``: within 3e-5 of the field
and 1e-2 of the density, ``docs/environment.md``); the tape also feels the co-rotating
atmosphere's drag with NRLMSIS's density (``AtmosphericDrag``, at the same 60 s knots).

The Lorentz force ``I r_x x B`` points against the motion where the tether is roughly
perpendicular to the field; the orbit decays at the rate Gauss's equation gives for the
along-track force, ``da/dt = 2 a^2 (V . F) / (mu m)``, which ``main`` integrates along the
run with the force the run reports (``reference_drop``; without drag, ``drag=False``,
it is the Lorentz force alone and ``tests/test_ed_deorbit.py`` checks it within 2 %).

The system's coordinates are offsets from a Keplerian reference point; after every orbit
the reference is moved onto the centre of mass's osculating orbit (``Orbit.from_state``)
and the offsets shifted accordingly.  The altitude is that of the osculating semi-major
axis of the centre of mass, ``a - R_E``.  The current, power, EMF and force reported are
those the run recorded at its saved steps (``Result.outputs``, the load's
``step_outputs``).  The integrator refactors its iteration matrix at every Newton
iteration (``newton="full"``): the stale matrix of modified Newton diverged on a step in
five at the dayside density (976 of 5071 attempted steps refused over a day, against 28
of 3175; with the current's coupling in the tangent, the default on these 4 elements,
43 of 3162).  Run ``python demos/ed_tether_deorbit.py`` (a day, 15.5 s CPU; its CPU
time is printed).
"""

import numpy as np

import skfem_cable as sc
from skfem_cable.scenes.ed_deorbit import (
    NEWTON,
    TETHER,
    build,
    centre_of_mass,
    gauss_rate,
    semi_major_axis,
    start,
)


def recentred(system, orbit, q, v, t):
    """The osculating orbit of the centre of mass at ``t`` and the offsets ``(q, v)``
    measured from its reference point (the same absolute state)."""
    R, V, _ = centre_of_mass(system, orbit, q, v, t)
    new = sc.Orbit.from_state(sc.MU_EARTH, R, V, t0=t)
    zero = np.zeros(3)
    return (new, q - system.rigid_motion_velocity(q, zero, velocity=R - orbit.position(t)),
            v - system.rigid_motion_velocity(q, zero, velocity=V - orbit.velocity(t)))


def main(days=1.0, p=TETHER, drag=True):
    """Simulate ``days`` days, one orbit at a time: times (days), altitudes (km), the
    cathode's current ``I(0)`` (A), the motional power (W) and EMF (V) at every 20th
    step (the numbers the run recorded there, ``Result.outputs``: the models at knots),
    the drop (m) and Gauss's equation's drop with the Lorentz force the run recorded
    (m), and the run's CPU time (s)."""
    import time

    clock = time.process_time()
    orbit, state = start(p)
    q, v, t = state.q, state.v, 0.0
    t_end = days * 86400.0
    rows, rate = [], []
    while t < t_end - 1e-6:
        system, load = build(orbit, p, drag=drag)
        span = min(orbit.period, t_end - t)
        result = sc.simulate(system, t_start=t, t_end=t + span,
                             dt=orbit.period / p["steps_per_orbit"], every=20,
                             initial=sc.State(system, q, v=v), newton=NEWTON)
        arcs = result.reference  # the run's reference: the orbit and its rebases
        out = {key: result.outputs[f"{load.cable.name}_{key}"] for key in
               ("current", "power", "emf", "force_x", "force_y", "force_z")}
        for k, (qk, vk, tk) in enumerate(zip(result.q[:-1], result.v[:-1], result.t[:-1])):
            R, V, m = centre_of_mass(system, arcs, qk, vk, tk)
            force = [out[f"force_{c}"][k] for c in "xyz"]
            a = semi_major_axis(R, V)
            rows.append((tk, a, out["current"][k], out["power"][k], out["emf"][k]))
            rate.append(gauss_rate(a, V, force, m))
        q, v, t = result.q[-1], result.v[-1], result.t[-1]
        orbit, q, v = recentred(system, arcs, q, v, t)
    times, a, current, power, emf = np.array(rows).T
    drop = a[0] - orbit.a
    reference = -np.trapezoid(rate, times) - rate[-1] * (t - times[-1])
    out = {"days": times / 86400.0, "altitude": (a - sc.R_EARTH) / 1e3,
           "current": current, "power": power, "emf": emf, "drop": drop,
           "reference_drop": reference, "cpu": time.process_time() - clock}
    print(f"{days:g} days: altitude {out['altitude'][0]:.2f} -> "
          f"{(orbit.a - sc.R_EARTH) / 1e3:.2f} km, drop {drop / 1e3:.3f} km (Gauss's "
          f"equation with the Lorentz force {reference / 1e3:.3f} km), current "
          f"{current.mean():.3f} A, power {power.mean():.0f} W, EMF {emf.mean():.0f} V, "
          f"CPU {out['cpu']:.1f} s")
    return out


def gallery_figure(path):
    """The gallery's picture (``scripts/gallery.py``) into ``path``: over a day, the
    altitude of the centre of mass's osculating orbit, the cathode's current, the
    motional power and the open-circuit EMF."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out = main()
    fig, axes = plt.subplots(2, 2, figsize=(7.5, 4.5), layout="constrained", sharex=True)
    for ax, key, label in zip(axes.ravel(), ["altitude", "current", "power", "emf"],
                              ["altitude a - R_E [km]", "current I(0) [A]",
                               "motional power [W]", "EMF [V]"]):
        ax.plot(out["days"], out[key], lw=0.8)
        ax.set(ylabel=label)
    for ax in axes[1]:
        ax.set(xlabel="t [days]")
    fig.suptitle(f"5 km bare tape, OML in IGRF/IRI, MSIS drag: drop "
                 f"{out['drop'] / 1e3:.2f} km in {out['days'][-1]:.2f} days", fontsize=10)
    fig.savefig(path, dpi=90, bbox_inches="tight", pad_inches=0.05)
    plt.close(fig)


if __name__ == "__main__":
    main()
