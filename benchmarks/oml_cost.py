"""What the OML current costs per step (issue 50, must-show 6): the 5 km electrodynamic
tether of ``demos/ed_tether_deorbit.py`` (aluminium wire of radius 1 mm between two 500
kg end masses, 400 km circular equatorial orbit, the Earth's dipole, 200 steps per
orbit, ``N_ELEMENTS`` elements) over one orbit, side by side:

* ``prescribed``: a prescribed current of 1 A (``ElectrodynamicForce(cable, 1.0, ...)``);
* ``oml``: ``current="oml"`` in a uniform plasma (1e11 m^-3), a 10 V hollow cathode and
  a 100 ohm load: the current and bias solved at every evaluation on the 5 Gauss points
  of every element (``kernels.oml``), the plasma evaluated once per step
  (``Term.prepare``).

CPU time (``time.process_time``), the minimum over the repeats after a short run that
compiles.  Goal: the OML run costs at most ``GOAL`` times the prescribed one.

    OPENBLAS_NUM_THREADS=1 .venv/bin/python benchmarks/oml_cost.py [--quick]
"""

import time

import numpy as np

import skfem_cable as sc
from skfem_cable.cli.bench import arguments
from skfem_cable.environment import UniformPlasma

SETTINGS = {"full": {"orbits": 1.0, "repeats": 3}, "quick": {"orbits": 0.1, "repeats": 2}}

#: Goal of the ratio of the OML run's CPU time to the prescribed current's.
GOAL = 2.0

N_ELEMENTS, LENGTH, RADIUS, END_MASS, ALTITUDE = 10, 5e3, 1e-3, 500.0, 400e3
ALUMINIUM = 3.5e7  # S/m


def force(kind, cable):
    """The Lorentz force of the case ``kind`` on ``cable``."""
    if kind == "prescribed":
        return sc.ElectrodynamicForce(cable, 1.0, sc.MagneticDipole())
    return sc.ElectrodynamicForce(cable, "oml", sc.MagneticDipole(),
                                  plasma=UniformPlasma(1e11), cathode=sc.Cathode(10.0),
                                  load=100.0, conductivity=ALUMINIUM)


def build(kind=None):
    """``(system, initial state, dt)`` of the case ``kind`` (None: no Lorentz force): the
    gravity-gradient steady state along the local vertical (found without the force), at
    rest in the orbiting frame (``demos/ed_tether_deorbit.py``'s start)."""
    orbit = sc.Orbit(sc.MU_EARTH, sc.R_EARTH + ALTITUDE)
    cable = sc.Cable.straight([-LENGTH / 2, 0, 0], [LENGTH / 2, 0, 0], N_ELEMENTS,
                              sc.Section.circular(RADIUS, 7e10, 2700.0))
    system = (sc.System([cable]).add_point_mass(cable.node(0), END_MASS)
              .add_point_mass(cable.node(-1), END_MASS).add_orbit(orbit))
    if kind is None:
        return system
    n = orbit.mean_motion
    steady = sc.solve_steady(build(), omega=[0, 0, n])
    v = system.rotation_operator(np.cross([0, 0, n], np.eye(3)).T) @ steady.q
    system.add_load(force(kind, cable))
    return system, sc.State(system, steady.q, steady.lam, v=v), orbit.period / 200


def best(kind, t_end, repeats):
    """The minimum CPU time (s) over ``repeats`` runs to ``t_end`` and the last run."""
    system, initial, dt = build(kind)
    sc.simulate(system, t_end=5 * dt, dt=dt, initial=initial)
    times = []
    for _ in range(repeats):
        start = time.process_time()
        result = sc.simulate(system, t_end=t_end, dt=dt, initial=initial)
        times.append(time.process_time() - start)
    return min(times), result


def main(argv=None):
    """Parse the arguments (``--quick``), run and return the figures."""
    quick = arguments(__doc__, "a tenth of an orbit", argv).quick
    s = SETTINGS["quick" if quick else "full"]
    t_end = s["orbits"] * sc.Orbit(sc.MU_EARTH, sc.R_EARTH + ALTITUDE).period
    print(f"5 km tether, {N_ELEMENTS} elements, {t_end:.0f} s at 200 steps per orbit, "
          f"minimum of {s['repeats']}")
    print("| case | CPU [s] | ms/step | Newton/step | rejected | path |\n"
          "|---|---|---|---|---|---|")
    cpu = {}
    for kind in ("prescribed", "oml"):
        cpu[kind], result = best(kind, t_end, s["repeats"])
        steps = result.stats["steps"]
        print(f"| {kind} | {cpu[kind]:.3f} | {1e3 * cpu[kind] / steps:.3f} | "
              f"{result.stats['newton'] / steps:.2f} | {result.stats['rejected']} | "
              f"{result.stats['path']} |")
    ratio = cpu["oml"] / cpu["prescribed"]
    print(f"ratio oml / prescribed: {ratio:.2f} (goal <= {GOAL})")
    return {"ratio": ratio, **cpu}


if __name__ == "__main__":
    main()
