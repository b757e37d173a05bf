"""Checks of a system's constraints: independent equations, the dependent ones named."""

import numpy as np
import scipy.sparse as sp


def check_independent(system, constraint):
    """Refuse a linear ``constraint`` (constant Jacobian) whose equations are dependent,
    or dependent on those of a linear constraint of ``system`` on shared coordinates: a
    node pinned to itself, the same node pinned or clamped twice.  Either makes the
    system's matrix singular at every state (its factorization could only name an
    unknown).  Exact for linear constraints; nonlinear ones are not checked.

    Raises
    ------
    ValueError
        Naming the constraint and the one it repeats.

    Examples
    --------
    >>> import skfem_cable as sc
    >>> cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], 2, sc.Section.circular(1e-3, 2e11, 7850.0))
    >>> sc.System([cable]).pin(cable.node(0)).clamp(cable.node(0))  # doctest: +ELLIPSIS
    Traceback (most recent call last):
        ...
    ValueError: constraint 'clamp Node(cable, 0)' repeats equations of 'pin Node(cable, 0)'...
    """
    if not constraint.linear:
        return
    q0 = system.q0
    dofs, J = _distinct_jacobian(system, constraint, q0)
    rank = np.linalg.matrix_rank(J)
    if rank < constraint.n_eq:
        raise ValueError(f"constraint {constraint.name!r} is degenerate: its {constraint.n_eq} "
                         f"equations have rank {rank} on its coordinates; a constraint's "
                         "equations must be independent")
    full_off = {}  # whether J has its full row rank on the columns of a mask
    theirs = np.zeros(q0.size, dtype=bool)  # the other's coordinates (set, read, cleared)
    for other in system.constraints:
        if not other.linear:
            continue
        other_dofs = other.dofs(system)
        theirs[other_dofs] = True
        off = ~theirs[dofs]
        theirs[other_dofs] = False
        if off.all() or _full_rank_off(J, off, full_off):
            continue
        other_dofs, other_J = _distinct_jacobian(system, other, q0)
        if _dependent(dofs, J, other_dofs, other_J):
            raise ValueError(
                f"constraint {constraint.name!r} repeats equations of {other.name!r}, added "
                "before: the same node pinned or clamped twice makes the system's matrix "
                "singular; constrain each coordinate once (a clamp already pins its node)")


#: Constraint equations beyond which ``dependent_constraints`` does not look (its dense
#: eigendecomposition of ``n_c x n_c`` would take long; it runs after a failure only).
DEPENDENCE_LIMIT = 3000


def dependent_constraints(system, jacobian, tol=1e-10):
    """The constraints whose equations are dependent at a state, named where a matrix
    turns out singular (pins in a closed loop: ``a`` to ``b``, ``b`` to ``c`` and ``c``
    to ``a``, each pair independent, which ``check_independent`` cannot see).

    Parameters
    ----------
    system : System
    jacobian : sparse matrix (n_c, n_dofs)
        The constraint Jacobian ``C_q`` at the state (its rows may be scaled).
    tol : float
        Eigenvalues of the Gram matrix of the normalized rows below ``tol`` count as zero.

    Returns
    -------
    names : list of str
        The constraints with equations in a dependent set (in the system's order), empty
        when the rows are independent or when there are more than ``DEPENDENCE_LIMIT``.
    rank : int
        The rank of the rows of those constraints.
    """
    C = sp.csr_matrix(jacobian)
    if not 0 < C.shape[0] <= DEPENDENCE_LIMIT:
        return [], C.shape[0]
    norms = np.sqrt(np.asarray(C.multiply(C).sum(axis=1)).ravel())
    rows = sp.diags(1.0 / np.where(norms > 0, norms, 1.0)) @ C
    values, vectors = np.linalg.eigh((rows @ rows.T).toarray())
    null = vectors[:, values < tol * max(values.max(), 1.0)]
    involved = np.abs(null).max(axis=1, initial=0.0) > 1e-6
    ends = np.cumsum([c.n_eq for c in system.constraints])
    owners = np.searchsorted(ends, np.flatnonzero(involved), side="right")
    names = [system.constraints[k].name for k in np.unique(owners)]
    rank = int(involved.sum()) - null.shape[1]
    return names, rank


def dependence_message(names, rank, where):
    """What dependent constraints (``dependent_constraints``' ``names`` and ``rank``) at
    ``where`` (a state) make of a system's matrix."""
    return (f"dependent constraints at {where}: {', '.join(map(repr, names))} (their "
            f"equations have rank {rank}): one follows from the others (pins in a closed "
            "loop, or together over-constraining the same coordinates), which makes the "
            "system's matrix singular; remove one of them")


def _distinct_jacobian(system, constraint, q0):
    """The distinct global coordinates of a linear constraint and its Jacobian on them
    (the columns of a repeated coordinate summed)."""
    d = np.asarray(constraint.dofs(system), dtype=np.int64)
    dofs, where = np.unique(d, return_inverse=True)
    J = np.zeros((constraint.n_eq, dofs.size))
    np.add.at(J.T, where, np.asarray(constraint.jacobian(q0[d], 0.0), dtype=float).T)
    return dofs, J


def _full_rank_off(J, off, known):
    """Whether the columns ``off`` of ``J`` (those off another constraint's coordinates)
    alone have its full row rank (memo ``known``, by mask).  Then no combination of the
    rows of both constraints vanishes unless ``J``'s part does: the rank of both is the
    other's plus ``len(J)`` (a tether's node pinned to a hub that other pins share)."""
    key = off.tobytes()
    if key not in known:
        known[key] = np.linalg.matrix_rank(J[:, off]) == len(J) if off.any() else False
    return known[key]


def _dependent(dofs, J, other_dofs, other_J):
    """True if the rows of ``J`` (on ``dofs``) and of ``other_J`` together have a smaller
    rank than ``other_J``'s plus the rows of ``J``."""
    union = np.union1d(dofs, other_dofs)
    stacked = np.zeros((len(J) + len(other_J), union.size))
    stacked[:len(J), np.searchsorted(union, dofs)] = J
    stacked[len(J):, np.searchsorted(union, other_dofs)] = other_J
    rank = np.linalg.matrix_rank
    return rank(stacked) < rank(other_J) + len(J)
