"""What a contact with a surface carried by a rigid body costs against one with a fixed
surface (issue 49; ``docs/contact.md``, Surfaces on a rigid body): the compiled term of a
rope of 32 elements (the capstan's, 16 of them on the drum) on a drum of R = 0.5 m with
``mu = 0.3``, evaluated with its tangent and velocities, side by side:

* ``fixed``: ``sc.Cylinder`` (``loads.contact.LineSurfaceContact``: the line's blocks);
* ``body``: ``drum.cylinder`` on a rigid body (``loads.contact_body.LineBodyContact``:
  each element's block with the body's 12 coordinates).

Every element is evaluated (no broad phase: the term is called outside a run).  CPU time
(``time.process_time``) per evaluation, the minimum over the repeats of 200 calls, after
a call that compiles.

    OPENBLAS_NUM_THREADS=1 .venv/bin/python benchmarks/contact_body_cost.py [--quick]
"""

import time

import numpy as np

import skfem_cable as sc
from skfem_cable.cli.bench import arguments
from skfem_cable.core.contract import Evaluation
from skfem_cable.scenes.capstan import R, wrapped

#: The body's x axis along world z: the drum's axis.
UP = np.array([[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]]).T


def rig(case):
    """``(term, index, packed evaluation)``: the contact term of ``case`` on the rope
    pressed 1 um into the drum, with small velocities, and the tangent wanted."""
    cable = wrapped(R + 5e-3 - 1e-6, 1.0, 16, 8)
    drum = sc.RigidBody.cylinder(R, 0.1, 100.0, rotation=UP, name="drum")
    surface = sc.Cylinder([0, 0, 0], [0, 0, 1], R) if case == "fixed" else \
        drum.cylinder([0, 0, 0], [1, 0, 0], R)
    system = sc.System([cable, drum]).contact(cable, surface, friction=0.3)
    term = system.loads[-1].bind(system)
    rows, _ = np.broadcast_arrays(term.rows, term.cols)
    index = np.arange(rows.size, dtype=np.int64).reshape(rows.shape)
    v = 0.01 * np.random.default_rng(0).standard_normal(system.n_dofs)
    ev = Evaluation(system, 0.0, system.q0, v, np.zeros(system.n_constraints), cK=1.0,
                    cC=1e-3, data=np.zeros(rows.size))
    return term, index, ev.packed()


def cost(case, repeats, calls=200):
    """The least CPU time per evaluation (us) of ``case`` over ``repeats``."""
    term, index, packed = rig(case)
    for function, pack in term.kernels:                       # compiles
        function(pack, index, packed)
    best = float("inf")
    for _ in range(repeats):
        start = time.process_time()
        for _ in range(calls):
            for function, pack in term.kernels:
                function(pack, index, packed)
        best = min(best, (time.process_time() - start) / calls * 1e6)
    return best


def main(argv=None):
    """Parse the arguments (``--quick``: two repeats) and print the cost of each case and
    its ratio to ``fixed``."""
    repeats = 2 if arguments(__doc__, "two repeats", argv).quick else 5
    costs = {case: cost(case, repeats) for case in ("fixed", "body")}
    for case, us in costs.items():
        print(f"{case:>6}: {us:7.1f} us per evaluation ({us / costs['fixed']:.2f}x)")


if __name__ == "__main__":
    main()
