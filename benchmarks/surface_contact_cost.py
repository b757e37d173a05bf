"""What line-to-surface contact costs per Newton iteration, and what its broad phase saves
(issue 49, must-show 6; ``docs/contact.md``): the capstan rig (``scenes.capstan``: a rope
of 32 elements, T1 = 100 N on its left end, its right end pulled down at 0.1 m/s), 0.35 s
at dt = 1e-3, side by side:

* ``rope``: no contact (the rope is pulled through where the drum would be);
* ``far``, ``far+bp``: a contact with a drum 100 m away (no point touches), without and
  with the broad phase (``LineSurfaceContact(broad_phase=...)``);
* ``capstan``, ``capstan+bp``: the rope sliding over the drum (mu = 0.3), without and with.

CPU time (``time.process_time``) per Newton iteration, the minimum over the repeats after
a short run that compiles.

    OPENBLAS_NUM_THREADS=1 .venv/bin/python benchmarks/surface_contact_cost.py [--quick]
"""

import time

import skfem_cable as sc
from skfem_cable.cli.bench import arguments
from skfem_cable.scenes.capstan import DRUM, LEG, RAMP, T1, R, V, smooth, wrapped

FAR = sc.Cylinder([0, 100, 0], [0, 0, 1], R)


def rig(surface=None, broad_phase=True, mu=0.3):
    """The capstan rig with a contact on ``surface`` (None: without contact)."""
    radius = R + 5e-3 + 1e-5
    cable = wrapped(radius, LEG, 24, 4)

    def pull(t):
        u = t - RAMP
        d = 0.0 if u <= 0 else V * (u - RAMP / 2) if u > RAMP else \
            V * u**3 / RAMP**2 * (1 - u / (2 * RAMP))
        return [radius, -LEG - d, 0.0]

    system = (sc.System([cable]).pin(cable.node(-1), pull)
              .add_point_load(cable.node(0), lambda t: [0.0, -T1 * smooth(t / RAMP), 0.0]))
    if surface is not None:
        system.contact(cable, surface, friction=mu, broad_phase=broad_phase)
    return system


CASES = {"rope": (None, True), "far": (FAR, False), "far+bp": (FAR, True),
         "capstan": (DRUM, False), "capstan+bp": (DRUM, True)}


def cost(case, t_end, repeats):
    """The least CPU time per Newton iteration (us) of ``case`` over ``repeats`` runs."""
    best = float("inf")
    sc.simulate(rig(*CASES[case]), t_end=0.01, dt=1e-3)          # compiles
    for _ in range(repeats):
        system = rig(*CASES[case])
        start = time.process_time()
        result = sc.simulate(system, t_end=t_end, dt=1e-3, every=50)
        best = min(best, (time.process_time() - start) / result.stats["newton"] * 1e6)
    return best


def main(argv=None):
    """Parse the arguments (``--quick``: 0.1 s, two repeats) and print the cost of each
    case and its ratio to ``rope``."""
    quick = arguments(__doc__, "0.1 s of the rig and two repeats", argv).quick
    t_end, repeats = (0.1, 2) if quick else (0.35, 3)
    costs = {case: cost(case, t_end, repeats) for case in CASES}
    for case, us in costs.items():
        print(f"{case:>11}: {us:7.1f} us per Newton iteration ({us / costs['rope']:.2f}x)")


if __name__ == "__main__":
    main()
