"""What tether-tether contact costs the sail's step where no contact occurs (issue 49,
must-show 6), measured inside the step: the 12-tether sail (``esail.BaselineConfig``) and
the full-size sail (``esail.FULL_SIZE``: 100 tethers of 20 km), 10 elements per tether,
each built twice, without contact and with the contact over all its tethers
(``system.contact(scene.tethers, tangent="own")``: one broad phase, refreshed once per
step, the compiled narrow phase over its pairs at every Newton evaluation, each element's
own tangent so that the bordered band LU still solves the sail), and a third time with
the contact on the corrected own tangent (``tangent="woodbury"``, the default for more
than two lines: the step's Woodbury correction, empty without contact), run side by
side:

* ``without``, ``with``, ``woodbury``: CPU per step (fixed steps of ``DT`` s,
  ``rho_inf = 0.25``, from the windless spin), the minimum over the repeats, the runs
  alternating;
* ``pairs``: the broad phase's candidate pairs at the last step, ``contacts`` the
  contacts there (none: the tethers stay thousands of metres apart);
* ``check us``: the crossing guard's call (the term's ``check``, once per attempted step,
  ``loads.contact_crossing``; inside ``with``) on the last step's states, CPU per call;
* ``ratio`` = with / without, ``w ratio`` = woodbury / without.  Goal: at most 1.2 (12
  tethers) and 1.3 (100 tethers).

CPU time (``time.process_time``), after a run of each that compiles.

    OPENBLAS_NUM_THREADS=1 PYTHONPATH=. .venv/bin/python benchmarks/contact_cost.py [--quick]
"""

import time

import skfem_cable as sc
from skfem_cable.cli.bench import arguments
from skfem_cable.scenes import esail

SETTINGS = {"full": {"steps": 20, "repeats": 3}, "quick": {"steps": 4, "repeats": 1}}

#: The goals of the ratio, by number of tethers.
GOALS = {12: 1.2, 100: 1.3}

N_ELEMENTS, DT = 10, 5.0


def scenes(config):
    """The sail of ``config`` without, with the contact over its tethers on the own
    tangent, and with it on the corrected own tangent."""
    plain, touching, exact = (esail.build(config, 10.0, N_ELEMENTS) for _ in range(3))
    touching.system.contact(touching.tethers, tangent="own")
    exact.system.contact(exact.tethers, tangent="woodbury")
    return plain, touching, exact


def per_step(scene, steps):
    """``(cpu, result)``: the CPU per step (s) of ``steps`` steps of ``scene``."""
    start = time.process_time()
    result = sc.simulate(scene.system, steps * DT, DT, initial=scene.initial, rho_inf=0.25)
    return (time.process_time() - start) / steps, result


def measure(config, steps, repeats):
    """``(without, with, woodbury, pairs, contacts, solver, check)``: the CPU per step
    (s) of the sail of ``config`` without contact, with it and with it on the corrected
    tangent (min of ``repeats``, alternating), the broad phase's candidate pairs and the
    contacts at the last state, the linear solver used and the crossing guard's cost."""
    plain, touching, exact = scenes(config)
    for scene in (plain, touching, exact):
        per_step(scene, 2)                                       # compiles
    best = [float("inf")] * 3
    for _ in range(repeats):
        for k, scene in enumerate((plain, touching, exact)):
            cpu, result = per_step(scene, steps)
            best[k] = min(best[k], cpu)
            if k == 1:
                last = result
    contact = touching.system.loads[-1]
    term = last_term(touching.system, contact)
    state = last.state(-1)
    found = contact.contacts(touching.system, state.q, state.v)
    return (*best, int(term.hooks[0].count[0]), len(found["normal"]),
            last.stats["solver"], check_cost(term, last.state(-2).q, state.q))


def last_term(system, contact):
    """The term of ``contact`` in the system's current layout (its step hook, the broad
    phase, holds the last step's pairs)."""
    return [term for term, _ in system.layout.load_terms if term.name == contact.name][0]


def check_cost(term, q0, q1, calls=10000):
    """CPU per call (s) of the crossing guard of ``term`` on the step from ``q0`` to
    ``q1`` over its broad phase's pairs."""
    start = time.process_time()
    for _ in range(calls):
        term.check(q0, q1)
    return (time.process_time() - start) / calls


def main(argv=None):
    """Parse the arguments (``--quick``: fewer steps and repeats) and print the table."""
    args = SETTINGS["quick" if arguments(__doc__, "fewer steps and repeats", argv).quick
                    else "full"]
    print(f"{'tethers':>8} {'without ms':>11} {'with ms':>9} {'ratio':>6} "
          f"{'woodbury ms':>12} {'w ratio':>8} {'goal':>5} {'pairs':>6} {'contacts':>9} "
          f"{'solver':>7} {'check us':>9}")
    for config in (esail.BaselineConfig(), esail.FULL_SIZE):
        without, with_contact, exact, pairs, contacts, solver, check = measure(
            config, args["steps"], args["repeats"])
        n = config.n_tethers
        print(f"{n:>8} {1e3 * without:11.2f} {1e3 * with_contact:9.2f} "
              f"{with_contact / without:6.3f} {1e3 * exact:12.2f} {exact / without:8.3f} "
              f"{GOALS[n]:5.1f} {pairs:>6} {contacts:>9} {solver:>7} {1e6 * check:9.3f}")


if __name__ == "__main__":
    main()
