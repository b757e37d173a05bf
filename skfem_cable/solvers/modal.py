"""Natural frequencies and mode shapes of the system linearised about a state."""

import numpy as np
from scipy.sparse.linalg import LinearOperator, eigs

from ..linalg import PatternSolver
from ..solvers.static import constraint_scale

#: Below this many unknowns the eigenproblem is solved densely.
DENSE_LIMIT = 600


def modes(system, state=None, k=6, sigma=None):
    """Lowest ``k`` natural frequencies (Hz) and mode shapes about ``state``.

    Solves ``(K_t + H(lambda)) phi = omega^2 M phi`` subject to ``C_q phi = 0`` through the
    KKT pencil, by shift-invert about ``sigma`` (rad^2/s^2; default a small negative shift
    so that rigid-body modes of a free system are found as zero frequencies).  ``K_t``
    includes the geometric stiffness of the pre-stress in ``state``, and the constraint
    Hessian term uses the state's multipliers.

    Returns
    -------
    freqs : ndarray (k,)
        Frequencies in Hz, ascending (``sqrt`` of negative ``omega^2``, from an unstable
        state, is returned as a negative number).
    shapes : ndarray (k, n_dofs)
        Mass-normalised mode shapes.
    """
    lay = system.layout
    n = system.n_dofs
    if int(k) != k or not 1 <= k <= n - system.n_constraints:
        raise ValueError(f"k must be an integer in [1, {n - system.n_constraints}], got {k!r}")
    q = system.q0 if state is None else state.q
    lam = np.zeros(lay.n_c) if state is None else state.lam
    scale = constraint_scale(system, q, lam)
    data = scale * lay.linear_data
    system.evaluate(q, None, 0.0, lam, scale=scale, data=data)
    mass = lay.mass_data
    if sigma is None:
        diag = lay.matrix(data).diagonal()[:n]
        mdiag = lay.matrix(mass).diagonal()[:n]
        sigma = -1e-8 * float(np.mean(np.abs(diag)) / np.mean(mdiag))
    solver = PatternSolver(lay.indptr, lay.indices)
    solver.factor(data - sigma * mass)
    B = lay.matrix(mass)
    N = lay.N
    if N <= DENSE_LIMIT:
        T = solver.solve(B.toarray())
        mu, vec = np.linalg.eig(T)
        order = np.argsort(-np.abs(mu))[:k]
        mu, vec = mu[order], vec[:, order]
    else:
        op = LinearOperator((N, N), matvec=lambda x: solver.solve(B @ x), dtype=float)
        mu, vec = eigs(op, k=k, which="LM")
    omega2 = sigma + 1.0 / mu.real
    order = np.argsort(omega2)
    omega2 = omega2[order]
    shapes = vec[:n, order].real.T
    Mq = B[:n, :n]
    for i in range(len(shapes)):
        shapes[i] /= np.sqrt(abs(shapes[i] @ (Mq @ shapes[i])))
    freqs = np.sign(omega2) * np.sqrt(np.abs(omega2)) / (2 * np.pi)
    return freqs, shapes
