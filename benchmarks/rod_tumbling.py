"""A free tape tumbling at 10 rad/s about an oblique axis for 100 turns (issue 48, item 4):
the largest bending and twist energy it stores, relative to its kinetic energy, over the
run (``docs/rods.md``).  A rigid motion must store none: the reference frames are
transported with the rod (``bodies.rod_frames``) and its energy is objective.

The tape (2 cm x 50 um aluminium, 1 m, 8 elements, its normal along ``y``) turns about
``omega = 10 (0.6, 0, 0.8)`` rad/s through its centre: the part along the tape spins its
section (6 rad/s), the rest tumbles it (8 rad/s; a line body has no rotary inertia of
bending, so the centreline turns about ``z`` and the section spins about the tangent at a
constant rate).  A turn is one of the tumble, ``2 pi / 8`` s.  ``tests/test_rods_coupling.py`` runs
a few turns of it.

Usage: ``python benchmarks/rod_tumbling.py [--turns N] [--steps-per-turn M] [--quick]``
(default 100, 400; ``--quick``: 3 turns).
"""

import argparse
import time

import numpy as np

import skfem_cable as sc

TAPE = sc.Section.tape(0.02, 50e-6, E=7e10, rho=2700.0)
OMEGA = 10 * np.array([0.6, 0.0, 0.8])


def run(turns, steps_per_turn=400, n_elements=8, checks_per_turn=4):
    """Simulate ``turns`` turns of the tumble; returns the largest ratio of the bending
    and twist energy to the kinetic energy at ``checks_per_turn`` states per turn, the
    largest spin error ``|phi_dot / (omega . t) - 1|`` over them and the result."""
    rod = sc.Rod.straight([-0.5, 0, 0], [0.5, 0, 0], n_elements, TAPE, normal=[0, 1, 0])
    system = sc.System([rod])
    v = rod.rigid_velocity(OMEGA, [0.0, 0.0, 0.0])
    period = 2 * np.pi / OMEGA[2]
    dt = period / steps_per_turn
    result = sc.simulate(system, t_end=turns * period, dt=dt, initial=(rod.q0, v),
                         every=steps_per_turn // checks_per_turn)
    # the run's books: the rod's bending and twist energy with the run's own frames
    ratios = result.energy["bending"][1:] / result.energy["kinetic"][1:]
    error = np.abs(result.v[:, rod.n_centreline::2] / OMEGA[0] - 1).max()
    return float(ratios.max()), error, result


def main(argv=None):
    """Parse the arguments (``--turns``, ``--steps-per-turn``, ``--quick``: 3 turns) and
    print the figures."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--turns", type=int, default=100)
    parser.add_argument("--steps-per-turn", type=int, default=400)
    parser.add_argument("--quick", action="store_true", help="3 turns instead of 100")
    args = parser.parse_args(argv)
    turns, steps_per_turn = (3 if args.quick else args.turns), args.steps_per_turn
    start = time.process_time()
    ratio, error, result = run(turns, steps_per_turn)
    print(f"{turns} turns, {steps_per_turn} steps per turn: bending and twist energy / "
          f"kinetic energy at most {ratio:.2e} (asked < 1e-10); spin error {error:.1e}; "
          f"CPU {time.process_time() - start:.1f} s")


if __name__ == "__main__":
    main()
