"""What Encke's rectification keeps (``solvers.rectify``): a 1 km tether along-track
on a circular orbit at 1 AU, its leading 10 kg end mass pushed forward with 0.02 N, so
that it tows the trailing 10 kg mass at 1 mm/s^2 (an E-sail's characteristic
acceleration) for ``--days`` days, with and without rectification.

The towed mass keeps the tether at a tension of ``m a = 0.01 N`` (strain 3.2e-8).
Without rectification the offsets from the Keplerian reference grow as ``a t^2 / 2``
(3.7e8 m in ten days) and the tether's coordinates lose their last digits to them.
Reported: the largest offset of the centre of mass, the largest jump of the strain
between neighbouring samples along the tether over the last day, relative to its mean
(physical: 1e-5, the tether's own 3 g hanging on the towed 10 kg; more is rounding
noise), the distance of the absolute centre of mass to a
point mass propagated independently (DOP853, rtol 1e-13), the number of rebases and the
integration time (without numba's compiling).

    OPENBLAS_NUM_THREADS=1 .venv/bin/python benchmarks/rectification.py [--days 10]
"""

import argparse

import numpy as np
from scipy.integrate import solve_ivp

import skfem_cable as sc

L, M, ACCEL = 1e3, 10.0, 1e-3


def build():
    orbit = sc.Orbit(sc.MU_SUN, sc.AU)
    cable = sc.Cable.straight([0, -L / 2, 0], [0, L / 2, 0], 8,
                              sc.Section.circular(1e-3, 1e11, 1.0))
    system = sc.System([cable]).add_point_mass(cable.node(0), M)
    system.add_point_mass(cable.node(-1), M)
    system.add_load(sc.PointLoad(cable.node(-1), [0.0, 2 * M * ACCEL, 0.0]))
    return system.add_orbit(orbit), orbit, cable


def point_mass(t, mass, force):
    orbit = sc.Orbit(sc.MU_SUN, sc.AU)

    def rhs(_, y):
        r = y[:3]
        return np.concatenate([y[3:], -sc.MU_SUN * r / np.linalg.norm(r) ** 3 + force / mass])

    y0 = np.concatenate([orbit.position(0.0), orbit.velocity(0.0)])
    return solve_ivp(rhs, (0.0, t[-1]), y0, method="DOP853", rtol=1e-13, atol=1e-3,
                     dense_output=True).sol(t)[:3].T


def main(argv=None):
    """Parse the arguments (``--days``, ``--dt``, ``--quick``: one day), print the table
    and return its rows."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--days", type=float, default=10.0)
    parser.add_argument("--dt", type=float, default=60.0)
    parser.add_argument("--quick", action="store_true", help="one day instead of ten")
    args = parser.parse_args(argv)
    return table(1.0 if args.quick else args.days, args.dt)


def table(days, dt):
    """The runs with and without rectification over ``days`` days at steps ``dt`` (s):
    the printed table's rows."""
    t_end = days * 86400.0
    print(f"{days:g} days, dt = {dt:g} s, thrust {ACCEL:g} m/s^2 along-track at 1 AU")
    print(f"{'rectify':>8} {'rebases':>8} {'max offset (m)':>15} {'strain noise':>13} "
          f"{'CoM vs point mass (m)':>22} {'wall (s)':>9}")
    rows = []
    for rectify in (1e-4, None):
        system, orbit, cable = build()
        result = sc.simulate(system, t_end, dt, every=60, rectify=rectify)
        wall = result.stats["integration_time"]
        com = system.centre_of_mass(result.q)
        mass = 2 * M + cable.section.mass_per_length * L
        reference = point_mass(result.t, mass, np.array([0.0, 2 * M * ACCEL, 0.0]))
        error = np.linalg.norm(result.reference.position(result.t) + com - reference,
                               axis=1).max()
        last = result.t >= result.t[-1] - 86400.0
        s = np.linspace(0.0, L, 33)
        strain = np.array([cable.strain(q[system.dofs(cable)], s) for q in result.q[last]])
        noise = np.abs(np.diff(strain, axis=1)).max() / np.abs(strain).mean()
        row = {"rectify": rectify, "rebases": result.stats["rectifications"],
               "max_offset": float(np.linalg.norm(com, axis=1).max()),
               "strain_noise": float(noise), "com_error": float(error), "wall_s": wall}
        rows.append(row)
        print(f"{rectify!s:>8} {row['rebases']:>8d} {row['max_offset']:>15.4g} "
              f"{noise:>13.3g} {error:>22.4g} {wall:>9.2f}")
    return rows


if __name__ == "__main__":
    main()
