"""One compiled Newton step for every linear solver (issue 47, must-show 5): the step
calls its solver's ``factor`` and ``solve`` at their machine addresses, on the solver's
storage held at an address (``solvers.step_lu``), so that the bordered, two-level, sparse
and corrected LUs share one step module and one signature (before: a step module of 8 to
13 s of compilation each), and the LU's code is not linked into the step.  No timing is
asserted: these check what the step holds and that it computes the same."""


import numba
import numpy as np
import pytest

import skfem_cable as sc
from skfem_cable.solvers import step_lu
from skfem_cable.solvers.galpha import GeneralizedAlpha


def _pendulum():
    cable = sc.Cable.straight([0, 0, 0], [1.0, 0, 0], n_elements=2,
                              section=sc.Section.circular(radius=0.01, E=7e10, rho=7800.0))
    return sc.System([cable]).pin(cable.node(0)).add_gravity([0, -9.81, 0])


@pytest.fixture(scope="module")
def steps():
    """The pendulum's compiled steps on the banded and on the sparse LU."""
    system = _pendulum()
    return {method: GeneralizedAlpha(system, method=method).compiled
            for method in ("auto", "sparse")}


def test_the_banded_and_the_sparse_lu_share_one_step(steps):
    """Before: a step module per kind of solver (its storage's type in the step's
    arguments).  Now one module and one type of arguments: the solver is three integers,
    the addresses of its two functions and of its storage; each solver has a small module
    of its own."""
    banded, sparse = steps["auto"], steps["sparse"]
    assert banded.newton is sparse.newton and banded.kind == sparse.kind
    assert numba.typeof(banded.lu) == numba.types.UniTuple(numba.types.int64, 3)
    assert banded.lu[:2] != sparse.lu[:2]


#: The modules of the linear solvers' compiled functions.
SOLVERS = {"skfem_cable.kernels.bordered", "skfem_cable.kernels.schur",
           "skfem_cable.kernels.woodbury", "skfem_cable.kernels.lapack"}


def test_the_step_names_no_function_of_the_solvers(steps):
    """The step module names no compiled function of the solvers (numba links the code of
    what a module calls into it, and LLVM optimised the LU again in every step module):
    it reaches them at their addresses.  The solver's module names none either (it calls
    the banded LU at its addresses too); the corrected one links the Woodbury
    correction."""
    step = steps["auto"].step
    callees = {value.py_func.__module__ for value in vars(step).values()
               if hasattr(value, "py_func")}
    assert "skfem_cable.kernels.books" in callees and not callees & SOLVERS
    storage = steps["auto"].lu_storage
    solver = step_lu.module("bordered", False, numba.typeof(storage[1]),
                             numba.typeof(storage))
    assert not {value.py_func.__module__ for value in vars(solver).values()
                if hasattr(value, "py_func")} & SOLVERS


def test_the_step_s_lu_computes_what_the_solver_does(steps):
    """The step module's ``lu_factor`` and ``lu_solve`` reach the bordered LU through
    the held storage: the same bits as the solver's own ``factor`` and ``solve``."""
    step = steps["auto"]
    solver = step_lu.BANDED["bordered"]
    data = step.arrays["data"]
    data[:] = np.random.default_rng(0).standard_normal(data.size)
    for i in step.model[3]:  # a dominant diagonal
        data[i] += 1e3
    rhs = np.random.default_rng(1).standard_normal(step.arrays["rhs"].size)
    assert step.step.lu_factor(step.lu, data) == -1
    out = np.zeros_like(rhs)
    step.step.lu_solve(step.lu, rhs, out)
    storage = step.lu_storage[1]
    assert solver.factor(storage, data) == -1
    expected = np.zeros_like(rhs)
    solver.solve(storage, rhs, expected)
    assert np.array_equal(out, expected)
