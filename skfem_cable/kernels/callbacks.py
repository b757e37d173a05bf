"""Template of the calls from the compiled Newton step back into Python.

``solvers.compiled`` copies these functions (``source``) into a system's generated terms
module (and the sparse LU's into the module of the step's solver, ``solvers.step_lu``)
where the system has Python parts (``solvers.compiled.PythonParts``, found by its ``key``
with ``python_part``): a term with a Python ``add`` hook, a nonlinear constraint without
kernel, the sparse LU. Each is a
``numba.objmode`` block (not inlined: numba does not inline a function that holds one); a
module without Python parts has none of them.
"""

import inspect

from numba import objmode


def python_term(key, slot, tangent):
    """Evaluate the Python term of ``slot`` (with its tangent if ``tangent``)."""
    with objmode():
        python_part(key).term(slot, tangent)  # noqa: F821 (placed by the generator)


def python_constraint(key, slot, r_c, tangent):
    """Evaluate the Python constraint of ``slot`` into the constraint rows ``r_c``."""
    with objmode():
        python_part(key).constraint(slot, r_c, tangent)  # noqa: F821


def lu_factor(lu, data):
    """Sparse LU of the matrix values ``data``: the unknown of a zero pivot (-2: not
    located), or -1."""
    with objmode(singular="int64"):
        singular = python_part(lu[0]).factor(data)  # noqa: F821
    return singular


def lu_solve(lu, rhs, dx):
    """``dx`` solving the last sparse LU with ``rhs``."""
    with objmode():
        python_part(lu[0]).solve(rhs, dx)  # noqa: F821


def source(names):
    """Text of the callbacks ``names`` for a generated module, each compiled apart
    (``numba.njit(cache=True)``)."""
    return ["@njit(cache=True)\n" + inspect.getsource(globals()[name])
            for name in names]
