"""A bare-tape deorbit from 720 km at 63 deg (issue 50, must-show 4): the decay rate of
the orbit at a ladder of altitudes, integrated in altitude into a deorbit time, against
the published "about 2 weeks" of Sanmartín et al. (2015).

**The publication.** J. R. Sanmartín, A. Sánchez-Torres, S. B. Khan, G. Sánchez-Arriaga
and M. Charro, *Optimum sizing of bare-tape tethers for de-orbiting satellites at end of
mission*, Adv. Space Res. 56(7) (2015) 1485-1492, doi:10.1016/j.asr.2015.06.030: from a
circular 720 km orbit at 63 deg (and 92 deg), satellites of 37.5, 375 and 3750 kg, tapes
of 1-6 cm x 10-54 um x 2.8-8.6 km, "at mid-inclination and a mass ratio of a few percent,
de-orbit time takes about 2 weeks" (the abstract; its per-case table was not found with
the search tool, see ``docs/environment.md``, "A published deorbit").  The case here is
one inside those ranges, stated in full (``CASE``): a 375 kg satellite carrying the
hollow cathode (10 V drop, no load) at the tape's lower end, a 2 cm x 50 um x 4 km
aluminium tape (3.5e7 S/m, 2700 kg/m^3: 10.8 kg, a mass ratio of 2.9 %), a 20 kg tip
mass; IGRF, IRI (F10.7 = 150) and NRLMSIS (F10.7 = F10.7a = 150, Ap = 4; the drag on the
tape only) from 2026-01-01 00:00 UTC; the scene of ``skfem_cable.scenes.ed_deorbit``
(OML current solved along the tape, models at 60 s knots, full Newton).

**Rate-integrated deorbit time.** A whole deorbit (weeks, some 200 orbits at 200 steps
each) is not run: at each altitude ``h_i`` of ``ALTITUDES`` the tape starts in its
gravity-gradient steady state and flies ``ORBITS`` orbits; the decay rate
``r_i = da/dt`` is the drop of the centre of mass's osculating semi-major axis over
those orbits divided by their duration (Lorentz force and drag).  The deorbit time
from ``h_0`` down to ``h_n`` is ``T = int dh / |r(h)|``, with ``log |r|`` linear in ``h``
between the ladder's rungs (``deorbit_time``): the altitude falls slowly compared with an
orbit (a few km per orbit), so the rate at a given altitude is the local one.  What this
leaves out: the libration built up over the deorbit (each rung starts at rest in the
orbiting frame), the epoch and local time moving on with the weeks (every rung starts at
the same epoch), and the eccentricity the force may build.

    OPENBLAS_NUM_THREADS=1 .venv/bin/python benchmarks/bare_tether_deorbit.py [--quick]
"""

import time

import numpy as np

import skfem_cable as sc
from skfem_cable.cli.bench import arguments
from skfem_cable.scenes.ed_deorbit import (
    NEWTON,
    TETHER,
    build,
    centre_of_mass,
    gauss_rate,
    semi_major_axis,
    start,
)

#: The case (SI units; ``scenes.ed_deorbit.TETHER``'s keys): module notes.
CASE = dict(TETHER, length=4e3, width=0.02, thickness=5e-5, end_mass=(375.0, 20.0),
            cathode=10.0, load=0.0, altitude=720e3, inclination=63.0)
#: The altitudes (m) at which the decay rate is measured.
ALTITUDES = np.array([720e3, 650e3, 580e3, 510e3, 440e3, 370e3, 300e3])
#: Orbits flown at each altitude.
ORBITS = 1.0
#: The solar activities run (F10.7, sfu, for IRI and NRLMSIS): moderate and maximum.
ACTIVITIES = (150.0, 250.0)
#: The publication's deorbit time (s): "about 2 weeks".
PUBLISHED = 14 * 86400.0


def tape_mass(p=CASE):
    """The tape's mass (kg)."""
    return p["density"] * p["width"] * p["thickness"] * p["length"]


def decay_rate(altitude, orbits=ORBITS, p=CASE):
    """The decay rate at ``altitude`` (m): ``orbits`` orbits of the case from its
    gravity-gradient steady state; returns ``rate`` (m/s, da/dt of the centre of mass's
    osculating orbit), ``lorentz`` (m/s, the rate Gauss's equation gives with the
    Lorentz force the run recorded at its steps, averaged by the trapezoid rule),
    ``current`` (A, mean ``I(0)`` at the steps), ``steps``, ``rejected`` and ``cpu``
    (s)."""
    clock = time.process_time()
    p = dict(p, altitude=float(altitude))
    orbit, state = start(p)
    system, load = build(orbit, p)
    span = orbits * orbit.period
    result = sc.simulate(system, t_start=0.0, t_end=span,
                         dt=orbit.period / p["steps_per_orbit"], every=1,
                         initial=state, newton=NEWTON)
    name, a, lorentz = load.cable.name, [], []
    for k, (q, v, t) in enumerate(zip(result.q, result.v, result.t)):
        R, V, m = centre_of_mass(system, result.reference, q, v, t)
        a.append(semi_major_axis(R, V))
        force = [result.outputs[f"{name}_force_{c}"][k] for c in "xyz"]
        lorentz.append(gauss_rate(a[-1], V, force, m))
    span = result.t[-1] - result.t[0]
    return {"rate": (a[-1] - a[0]) / span,
            "lorentz": float(np.trapezoid(lorentz, result.t)) / span,
            "current": float(np.mean(result.outputs[f"{name}_current"])),
            "steps": result.stats["steps"], "rejected": result.stats["rejected"],
            "cpu": time.process_time() - clock}


def deorbit_time(altitudes, rates):
    """``int dh / |r(h)|`` (s) from the first altitude to the last, ``log |r|`` linear in
    ``h`` between them (exact for a rate exponential in altitude): each interval
    ``|dh| (1/r_0 - 1/r_1) / ln(r_1/r_0)``, ``|dh| / r_0`` where the rates are equal."""
    h, r = np.asarray(altitudes, dtype=float), np.abs(np.asarray(rates, dtype=float))
    dh, x = np.abs(np.diff(h)), np.log(r[1:] / r[:-1])
    factor = np.where(x == 0.0, 1.0, -np.expm1(-x) / np.where(x == 0.0, 1.0, x))
    return float(np.sum(dh / r[:-1] * factor))


def ladder(altitudes, orbits, p=CASE):
    """The decay rates (m/s) at ``altitudes``, each rung printed with the time to reach
    it from the first (rate-integrated, ``deorbit_time``)."""
    rates = []
    for h in altitudes:
        out = decay_rate(h, orbits, p)
        rates.append(out["rate"])
        reached = deorbit_time(altitudes[:len(rates)], rates) if len(rates) > 1 else 0.0
        print(f"{h / 1e3:6.0f} km: da/dt {out['rate'] * 86400 / 1e3:8.2f} km/day "
              f"(Lorentz {out['lorentz'] / out['rate']:.3f} of it), I(0) "
              f"{out['current']:.3f} A, reached after {reached / 86400:5.1f} days; "
              f"{out['steps']} steps ({out['rejected']} refused), CPU {out['cpu']:.1f} s")
    return rates


def main(argv=None):
    """Measure the rates, integrate them and print the table, at each solar activity of
    ``ACTIVITIES`` (``--quick``: one altitude, a tenth of an orbit, no deorbit time)."""
    args = arguments(__doc__, "one altitude, a tenth of an orbit", argv)
    altitudes, orbits = (ALTITUDES[:1], 0.1) if args.quick else (ALTITUDES, ORBITS)
    print(f"tape {CASE['width'] * 100:g} cm x {CASE['thickness'] * 1e6:g} um x "
          f"{CASE['length'] / 1e3:g} km, {tape_mass():.1f} kg; satellite "
          f"{CASE['end_mass'][0]:g} kg (mass ratio {tape_mass() / CASE['end_mass'][0]:.3f}),"
          f" tip {CASE['end_mass'][1]:g} kg; {CASE['inclination']:g} deg")
    times = {}
    for f107 in ACTIVITIES[:1] if args.quick else ACTIVITIES:
        print(f"F10.7 = F10.7a = {f107:g}, Ap = {CASE['ap']:g}")
        rates = ladder(altitudes, orbits, dict(CASE, f107=f107))
        if len(rates) > 1:
            times[f107] = deorbit_time(altitudes, rates)
            print(f"rate-integrated deorbit time {altitudes[0] / 1e3:g} -> "
                  f"{altitudes[-1] / 1e3:g} km: {times[f107] / 86400:.1f} days (published:"
                  f" about {PUBLISHED / 86400:g} days)")
    return times


if __name__ == "__main__":
    main()
