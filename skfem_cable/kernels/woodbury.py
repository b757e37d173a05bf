"""An exact Newton step on a fixed sparsity pattern: the entries of a term's tangent that
its pattern leaves out, added back to the factored iteration matrix as a low-rank
correction by the Sherman-Morrison-Woodbury identity.

A term whose exact tangent couples coordinates its declared pattern does not hold (the
contact of two tethers that the E-sail's band blocks keep apart, ``loads.contact_lines``
with ``tangent="woodbury"``) writes, at every evaluation with the tangent, the coupling
left out as *records*: each the four points ``P_j = sum_A S[e_j, g_j, A] x_(e_j, A)`` of
one pair of segments (``(e_j, g_j)``: element and quadrature point, ``S`` and ``edofs``
those of ``core.lines.LinePoints``) and the 12 x 12 block ``G`` over their coordinates.
With ``U`` the ``N x 12 r`` matrix of the points' maps (``U^T x`` stacks the points of
every record) and ``C`` the block diagonal of the ``G``, the iteration matrix is
``A = K0 + U C U^T``, ``K0`` the matrix on the pattern, and, by the Sherman-Morrison-
Woodbury formula ``(A + U V^T)^-1 = A^-1 - A^-1 U (I + V^T A^-1 U)^-1 V^T A^-1`` (Golub &
Van Loan, *Matrix Computations*, 3rd ed., 1996, Sect. 2.1.3, p. 51) with ``V^T = C U^T``
(``C`` need not be invertible),

    A^-1 r = y - Z (I + C U^T Z)^-1 C U^T y,    y = K0^-1 r,    Z = K0^-1 U.

At a factorization (``lu_factor``) the records are copied (the factored ones: an
evaluation with the tangent that no factorization follows leaves them alone), ``Z`` is
``12 r`` solves with the factor of ``K0`` and the capacitance ``I + C U^T Z``
(``12 r x 12 r``) is factored by LAPACK's dense LU (``kernels.lapack``).  A solve
(``lu_solve``) is one solve with ``K0``, ``12 r`` gathers, a small dense solve and
``12 r`` updates of length ``N``.  Without records both are the factor's own, and a
vector's length.

``refresh``, ``lu_factor`` and ``lu_solve`` are templates: ``solvers.step_lu`` copies
their source into the generated module of the Newton step's solver, after naming the
factor and solve of ``K0`` (the bordered, two-level or sparse LU) ``inner_factor`` and
``inner_solve``.  ``storage`` makes the arrays they work in, ``lu = (inner, (record,
factored))``.
"""

import inspect

import numpy as np
from numba import njit

from .lapack import ADDRESSES, dense_factor, dense_solve

#: Columns of ``U`` per record: the three coordinates of its four points.
RANK = 12


def source():
    """Text for the generated module of the Newton step's solver, after its ``lu_factor`` and
    ``lu_solve`` (those of ``K0``): renamed ``inner_factor`` and ``inner_solve``, and
    replaced by the corrected ``lu_factor`` and ``lu_solve``, with ``refresh`` (module
    notes)."""
    return "\n\n\n".join(
        ["from skfem_cable.kernels.woodbury import capacitance, correct, place, take\n"
         "inner_factor, inner_solve = lu_factor, lu_solve  # noqa: F821"]
        + ["@njit(cache=True)\n" + inspect.getsource(f) for f in (refresh, lu_factor, lu_solve)])


def new_record(capacity):
    """The arrays a term writes its left-out coupling into (module notes): ``count``
    (2,) the records of the last evaluation with the tangent (those beyond ``capacity``
    counted, not written: their coupling is left out) and the most of one evaluation
    since ``count[1]`` was last cleared, ``points``
    (capacity, 4, 2) each record's points ``(element, point)``, ``values`` (capacity, 12,
    12) its block ``G``; capacity 0 for a term without correction."""
    return (np.zeros(2, dtype=np.int64), np.zeros((capacity, 4, 2), dtype=np.int64),
            np.zeros((capacity, RANK, RANK)))


def storage(correction, size):
    """``(record, factored)`` of ``lu_factor``/``lu_solve`` for a term's ``correction =
    (edofs, S, count, points, values)`` (``contract.Term.correction``) and ``size``
    unknowns: ``factored = (count, points, values, Z, W, capacitance, pivots, ints,
    addresses, column, gathered, z)``."""
    edofs, S, count, points, values = correction
    m = RANK * points.shape[0]
    factored = (np.zeros(1, dtype=np.int64), np.zeros_like(points), np.zeros_like(values),
                np.zeros((m, size)), np.zeros(m * m), np.zeros(m * m),
                np.zeros(max(m, 1), dtype=np.int32), np.zeros(8, dtype=np.int32), ADDRESSES,
                np.zeros(size), np.zeros(m), np.zeros(m))
    return (np.ascontiguousarray(edofs, dtype=np.int64), np.ascontiguousarray(S, float),
            count, points, values), factored


@njit(cache=True)
def take(record, factored):
    """Copy the records of the last evaluation into ``factored``; returns the columns of
    ``U`` (``RANK`` per record)."""
    count, points, values = record[2], record[3], record[4]
    fcount, fpoints, fvalues = factored[0], factored[1], factored[2]
    r = min(count[0], points.shape[0])
    fcount[0] = r
    for k in range(r):
        for j in range(4):
            fpoints[k, j, 0], fpoints[k, j, 1] = points[k, j, 0], points[k, j, 1]
        for a in range(RANK):
            for b in range(RANK):
                fvalues[k, a, b] = values[k, a, b]
    return RANK * r


@njit(cache=True)
def place(record, factored, c, value):
    """Column ``c`` of ``U`` times ``value`` into ``factored``'s ``column`` (0 clears
    it): the map of coordinate ``c % 3`` of point ``c // 3 % 4`` of record ``c // 12``."""
    edofs, S = record[0], record[1]
    column = factored[9]
    k, j = c // RANK, (c % RANK) // 3
    e, g = factored[1][k, j, 0], factored[1][k, j, 1]
    i = c % 3
    for A in range(S.shape[2]):
        column[edofs[e, 3 * A + i]] = value * S[e, g, A]


@njit(cache=True)
def _gather(record, factored, x, r):
    """``U^T x`` over the first ``r`` records into ``factored``'s ``gathered``."""
    edofs, S = record[0], record[1]
    fpoints, gathered = factored[1], factored[10]
    nf = S.shape[2]
    for k in range(r):
        for j in range(4):
            e, g = fpoints[k, j, 0], fpoints[k, j, 1]
            for i in range(3):
                acc = 0.0
                for A in range(nf):
                    acc += S[e, g, A] * x[edofs[e, 3 * A + i]]
                gathered[RANK * k + 3 * j + i] = acc


@njit(cache=True)
def capacitance(record, factored, m):
    """Factor the capacitance ``I + C U^T Z`` (held transposed, LAPACK's column-major
    order) of the ``m`` columns of ``Z``; returns -1, or -2 where it is singular (the
    step's code of a zero pivot it does not locate)."""
    if m == 0:
        return -1
    fvalues, Z, W, cap, pivots, ints, addresses, gathered = (
        factored[2], factored[3], factored[4], factored[5], factored[6], factored[7],
        factored[8], factored[10])
    r = m // RANK
    for c in range(m):               # W[:, c] = U^T Z[c]
        _gather(record, factored, Z[c], r)
        for row in range(m):
            W[row * m + c] = gathered[row]
    A = cap[:m * m].reshape((m, m))  # A[c, row] = (I + C W)[row, c]
    for k in range(r):
        for a in range(RANK):
            row = RANK * k + a
            for c in range(m):
                acc = 1.0 if row == c else 0.0
                for b in range(RANK):
                    acc += fvalues[k, a, b] * W[(RANK * k + b) * m + c]
                A[c, row] = acc
    return -1 if dense_factor(addresses, A, pivots[:m], ints) == 0 else -2


@njit(cache=True)
def correct(record, factored, out):
    """``out = y - Z (I + C U^T Z)^-1 C U^T y`` in place, ``y = out = K0^-1 r`` (module
    notes); nothing without records."""
    r = factored[0][0]
    if r == 0:
        return
    m = RANK * r
    fvalues, Z, cap, pivots, ints, addresses, gathered, z = (
        factored[2], factored[3], factored[5], factored[6], factored[7], factored[8],
        factored[10], factored[11])
    _gather(record, factored, out, r)
    for k in range(r):
        for a in range(RANK):
            acc = 0.0
            for b in range(RANK):
                acc += fvalues[k, a, b] * gathered[RANK * k + b]
            z[RANK * k + a] = acc
    dense_solve(addresses, cap[:m * m].reshape((m, m)), pivots[:m], z[:m], ints)
    for c in range(m):
        zc = z[c]
        if zc != 0.0:
            Zc = Z[c]
            for i in range(out.size):
                out[i] -= zc * Zc[i]


def refresh(lu):
    """The correction of the records of the last evaluation with the tangent, for ``K0``
    just factored (module notes): ``Z`` and the capacitance's factor; returns -2 for a
    singular capacitance, or -1.  Called by ``lu_factor``, and from Python after a
    factorization the step did not make (``CompiledNewton.refresh``: a resumed run's
    first factor)."""
    inner, (record, factored) = lu
    m = take(record, factored)
    Z = factored[3]
    for c in range(m):
        place(record, factored, c, 1.0)
        inner_solve(inner, factored[9], Z[c])  # noqa: F821 (names of the generated module)
        place(record, factored, c, 0.0)
    return capacitance(record, factored, m)


def lu_factor(lu, data):
    """Factor ``K0`` (``inner_factor``, the pattern's values ``data``) and the correction
    of the records of the last evaluation (``refresh``); returns the unknown of a zero
    pivot of ``K0``, -2 for a singular capacitance, or -1."""
    singular = inner_factor(lu[0], data)  # noqa: F821
    return singular if singular != -1 else refresh(lu)


def lu_solve(lu, rhs, out):
    """``out = (K0 + U C U^T)^-1 rhs`` with the last factorization (module notes)."""
    inner, (record, factored) = lu
    inner_solve(inner, rhs, out)  # noqa: F821
    correct(record, factored, out)
