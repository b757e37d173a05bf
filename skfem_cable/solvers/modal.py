"""Natural frequencies and mode shapes of the system linearised about a state."""

import numpy as np
from scipy.sparse.linalg import LinearOperator, eigs

from ..core.linalg import PatternSolver
from ..core.protocols import IntegrableSystem
from ..loads.point import vector3
from ..solvers.static import constraint_scale
from .steady import frame_rates, rotating_frame

#: Below this many unknowns the eigenproblem is solved densely.
DENSE_LIMIT = 600


def modes(system: IntegrableSystem, state=None, k=6, sigma=None, spin=None, shapes=True):
    """Lowest ``k`` natural frequencies (Hz) and mode shapes about ``state``.

    With ``spin`` (rad/s, a 3-vector) the system is taken in a frame rotating at that rate
    (``state`` a steady spinning state, e.g. from ``solve_steady(system, spin)``): the
    tangent holds the centrifugal softening ``-M (I (x) [spin]_x^2)`` (added here, as
    ``solve_steady`` adds it, unless the system has ``add_centrifugal(spin)`` already),
    the Coriolis (gyroscopic) matrix ``2 M (I (x) [spin]_x)`` enters and the quadratic
    eigenproblem is solved densely in first-order form; shapes are then complex.  A system
    in orbit spinning at the mean motion ``n`` about the orbit normal is in the orbiting
    (LVLH) frame: the differential gravity and the centrifugal term together give the
    librations at ``sqrt(3) n`` in the plane and ``2 n`` out of it.  A system with
    ``add_centrifugal`` at a rate other than ``spin`` (``spin`` omitted included) is
    refused: its frame rotates at that rate.

    Solves ``(K_t + H(lambda)) phi = omega^2 M phi`` subject to ``C_q phi = 0`` through the
    KKT pencil, by shift-invert about ``sigma`` (rad^2/s^2; default a small negative shift
    so that rigid-body modes of a free system are found as zero frequencies).  ``K_t``
    includes the geometric stiffness of the pre-stress in ``state``, and the constraint
    Hessian term uses the state's multipliers.  ``shapes=False`` leaves the shapes out
    (``None``): with ``spin`` the dense eigenproblem's eigenvectors then go uncomputed
    (a third of the work of the 12 x 5 E-sail's 804 eigenvalues).

    Returns
    -------
    freqs : ndarray (k,)
        Frequencies in Hz, ascending (``sqrt`` of negative ``omega^2``, from an unstable
        state, is returned as a negative number).
    shapes : ndarray (k, n_dofs) or None
        Mass-normalised mode shapes (None with ``shapes=False``).
    """
    if system.deployments:
        raise ValueError("modes: the system has deploying cables, whose mass and stiffness "
                         "depend on the free length (and a reel's length has inertia the "
                         "constant mass matrix does not hold); build the cables at their "
                         "free length, without deploy, for their modes")
    system = _in_frame(system, spin)
    lay = system.current_layout()
    n = system.n_dofs
    if int(k) != k or not 1 <= k <= n - system.n_constraints:
        raise ValueError(f"k must be an integer in [1, {n - system.n_constraints}], got {k!r}")
    q = system.q0 if state is None else state.q
    lam = np.zeros(lay.n_c) if state is None else state.lam
    scale = constraint_scale(system, q, lam, lay)
    data = scale * lay.linear_data
    system.evaluate(q, None, 0.0, lam, scale=scale, data=data, layout=lay)
    if spin is not None:
        return _gyroscopic_modes(system, lay.matrix(data), k, spin, shapes)
    mass = lay.mass_data
    if sigma is None:
        diag = lay.matrix(data).diagonal()[:n]
        mdiag = lay.matrix(mass).diagonal()[:n]
        sigma = -1e-8 * float(np.mean(np.abs(diag)) / np.mean(mdiag))
    solver = PatternSolver(lay.indptr, lay.indices, border=lay.border, junctions=lay.junctions)
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
    freqs = np.sign(omega2) * np.sqrt(np.abs(omega2)) / (2 * np.pi)
    if not shapes:
        return freqs, None
    phi = vec[:n, order].real.T
    Mq = B[:n, :n]
    for i in range(len(phi)):
        phi[i] /= np.sqrt(abs(phi[i] @ (Mq @ phi[i])))
    return freqs, phi


def _in_frame(system, spin):
    """``system`` in the frame rotating at ``spin`` (None: at rest): itself when its
    centrifugal loads (``add_centrifugal``) are of that frame, a copy with the centrifugal
    load added when it has none (``steady.rotating_frame``); ``ValueError`` when they
    are of another rate."""
    rates = frame_rates(system)
    if spin is not None:
        spin = vector3(spin, "spin")
    if spin is not None and not rates:
        return rotating_frame(system, spin)
    if all(spin is not None and np.allclose(rate, spin, rtol=1e-12, atol=0.0)
           for rate in rates):
        return system
    raise ValueError(
        f"modes: spin={None if spin is None else spin.tolist()} rad/s, but the system has "
        f"add_centrifugal at {[rate.tolist() for rate in rates]} rad/s: the modes of a "
        "system in a rotating frame need that frame's rate as spin (its Coriolis and "
        "centrifugal terms together); pass spin equal to the add_centrifugal rate, or "
        "leave add_centrifugal out (spin= adds the centrifugal term itself)")


def _gyroscopic_modes(system, kkt, k, spin, shapes):
    """``(lambda^2 M + lambda G + K) x + C^T mu = 0``, ``C x = 0``: frequencies
    ``|Im lambda| / 2 pi`` of the ``k`` eigenvalues of least modulus with ``Im lambda >=
    0``, and their complex shapes (None unless ``shapes``: no eigenvectors computed).

    The constraints are eliminated (``x = Z y``, ``Z`` an orthonormal basis of the null
    space of ``C``) and the reduced mass factored (``Z^T M Z = L L^T``, ``y = L^-T w``):
    ``lambda^2 w + lambda G~ w + K~ w = 0`` with ``G~ = L^-1 Z^T G Z L^-T`` and ``K~``
    alike, in first-order form ``[[0, I], [-K~, -G~]] (w, lambda w) = lambda (w, lambda
    w)``, a standard eigenproblem.  The 12 x 5 E-sail's (444 coordinates, 42 constraints):
    0.3 s of CPU against 3.1 s for the QZ algorithm on the first-order KKT pencil (930
    unknowns), which also scattered the sail's double root at the spin frequency by
    ``1e-4`` relative where this keeps it to ``1e-10``."""
    from scipy.linalg import cholesky, eig, null_space, solve_triangular

    from ..loads.gravity import spin_matrix

    n = system.n_dofs
    if n > 2000:
        raise ValueError("modes with spin are solved densely: the system is too large "
                         f"({n} coordinates; at most 2000)")
    K = kkt.toarray()
    Z = null_space(K[n:, :n]) if K.shape[0] > n else np.eye(n)
    mass = system.layout.mass.scipy
    G = 2.0 * spin_matrix(system, mass, np.asarray(spin, dtype=float), 1)
    try:
        L = cholesky(Z.T @ (mass @ Z), lower=True)
    except np.linalg.LinAlgError:
        raise ValueError("modes with spin: the mass matrix is singular on the motions the "
                         "constraints allow (a coordinate without inertia)") from None
    ZL = solve_triangular(L, Z.T, lower=True).T  # Z L^-T
    r = ZL.shape[1]
    A = np.block([[np.zeros((r, r)), np.eye(r)],
                  [-ZL.T @ K[:n, :n] @ ZL, -ZL.T @ (G @ ZL)]])
    lam, vec = eig(A) if shapes else (eig(A, right=False), None)
    upper = lam.imag >= 0
    order = np.argsort(np.abs(lam[upper]))[:k]
    freqs = np.abs(lam[upper][order]) / (2 * np.pi)
    if vec is None:
        return freqs, None
    phi = (ZL @ vec[:r, upper][:, order]).T
    for i in range(len(phi)):
        phi[i] /= np.sqrt(abs(np.conj(phi[i]) @ (mass @ phi[i])))
    return freqs, phi
