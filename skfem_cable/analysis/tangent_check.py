"""Central-difference check of a system's tangents (``sc.check_tangent``).

Every contributor that declares tangent entries (a body's internal forces, a load) is
evaluated alone, and its tangent ``d(f - f_ext)/dq`` (and ``d/dv`` in dynamics) is compared
with central differences of its own forces; the constraints' Jacobian ``C_q`` and the
Hessian term ``d(C_q^T lambda)/dq`` (at random multipliers) are compared with differences
of ``C`` and ``C_q^T lambda``.  Each part's error is the largest difference relative to the
largest entry of its differences, so that a wrong entry is named with its term, row and
column.  Run it on a small system whenever a law, a load or a constraint is written
(``docs/extending.md``).
"""

from dataclasses import dataclass

import numpy as np

from ..core.contract import Evaluation


@dataclass(frozen=True)
class PartCheck:
    """The check of one part: ``name`` (the term, or ``constraints``), ``wrt`` (``q``,
    ``v`` or ``a``), ``error`` (largest difference relative to ``scale``, the largest entry of the
    differences), and where it is (``row``, ``col``: described coordinates)."""

    name: str
    wrt: str
    error: float
    scale: float
    row: str
    col: str


@dataclass(frozen=True)
class TangentCheck:
    """The checks of every part (``parts``); ``worst`` is the one with the largest error,
    ``error`` its error."""

    parts: tuple

    @property
    def worst(self):
        return max(self.parts, key=lambda p: p.error)

    @property
    def error(self):
        return self.worst.error if self.parts else 0.0

    def __str__(self):
        lines = [f"{'part':<32} {'wrt':<3} {'error':>9}  worst entry"]
        for p in self.parts:
            lines.append(f"{p.name[:32]:<32} {p.wrt:<3} {p.error:9.2e}  d[{p.row}] / "
                         f"d[{p.col}] (differences up to {p.scale:.3g})")
        return "\n".join(lines)


def check_tangent(system, q=None, v=None, t=0.0, a=None, step=1e-6, seed=0):
    """Compare every tangent of ``system`` at ``(q, v, t)`` with central differences.

    Parameters
    ----------
    system : System
    q : array_like (n_dofs,), optional
        Coordinates (default: the bodies' initial ones; perturb them for a general check).
    v : array_like (n_dofs,), optional
        Velocities: the check is then dynamic (damping and velocity-dependent loads on)
        and includes the tangents in ``v``.
    t : float
    a : array_like (n_dofs,), optional
        Accelerations, for terms with inertia beyond the constant mass (a deploying
        cable): the check then includes their tangents in ``a`` (``contract``).
    step : float
        Difference step relative to each coordinate's scale (the system's size for
        positions, 1 for slopes).
    seed : int
        Seed of the random multipliers of the constraints' Hessian term.

    Returns
    -------
    TangentCheck
        ``error`` (the worst relative difference), ``worst`` (its part, row and column),
        ``parts``; ``print`` it for the table.  Exact tangents give about ``step^2`` and
        round-off: 1e-7 or less.

    Examples
    --------
    >>> import numpy as np, skfem_cable as sc
    >>> cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], 3, sc.Section.circular(1e-3, 2e11, 7850))
    >>> system = sc.System([cable]).pin(cable.node(0)).add_gravity([0, -9.81, 0])
    >>> q = system.q0 + 1e-3 * np.random.default_rng(1).standard_normal(system.n_dofs)
    >>> bool(sc.check_tangent(system, q).error < 1e-6)
    True
    """
    lay = system.current_layout()
    q = np.array(system.q0 if q is None else q, dtype=float)
    v = None if v is None else np.array(v, dtype=float)
    a = None if a is None else np.array(a, dtype=float)
    h = step * lay.coordinate_scale
    parts = []
    for term, index in lay.body_terms + lay.load_terms:
        if term.has_tangent:
            parts += _term_parts(system, term, index, (q, v, a), t, h)
    if lay.n_c:
        lam = np.random.default_rng(seed).standard_normal(lay.n_c)
        parts += _constraint_parts(system, q, t, lam, h)
    return TangentCheck(tuple(parts))


def _forces(system, term, index, state, t, coefficients=(1.0, 0.0, 0.0), data=None):
    """``f - f_ext`` of ``term`` alone at ``state = (q, v, a)`` (and its tangent with
    ``coefficients = (cK, cC, cM)`` into ``data``)."""
    q, v, a = state
    cK, cC, cM = coefficients
    ev = Evaluation(system, t, q, v, np.zeros(system.layout.n_c), cK, cC, data, a, cM)
    term.evaluate(ev, index)
    return ev.f - ev.f_ext


def _term_parts(system, term, index, state, t, h):
    lay, n = system.layout, system.n_dofs
    cols = np.unique(np.broadcast_to(term.cols, np.broadcast_shapes(
        np.shape(term.rows), np.shape(term.cols))))
    parts = []
    for k, wrt in enumerate("qva"):
        if state[k] is None:
            continue
        data = np.zeros(lay.nnz)
        _forces(system, term, index, state, t, tuple(np.eye(3)[k]), data)
        tangent = lay.matrix(data)[:n][:, cols].toarray()
        differences = np.column_stack([_difference(system, term, index, state, t, h[j], j,
                                                   k) for j in cols])
        parts.append(_compare(system, term.name or "term", wrt, tangent, differences,
                              np.arange(n), cols))
    return parts


def _difference(system, term, index, state, t, step, j, k):
    """Central difference of the term's ``f - f_ext`` in entry ``j`` of ``state[k]``
    (coordinates, velocities or accelerations)."""
    forces = []
    for sign in (1.0, -1.0):
        shifted = [None if x is None else x.copy() for x in state]
        shifted[k][j] += sign * step
        forces.append(_forces(system, term, index, shifted, t))
    return (forces[0] - forces[1]) / (2 * step)


def _constraint_parts(system, q, t, lam, h):
    """``C_q`` against differences of ``C``, and ``d(C_q^T lambda)/dq`` against differences
    of ``C_q^T lambda``."""
    lay, n = system.layout, system.n_dofs

    def values(x, data=None):
        f_con, r_c = np.zeros(n), np.zeros(lay.n_c)
        lay.constraints(x, t, lam, f_con, r_c, 1.0, data, 1.0)
        return r_c, f_con

    data = np.zeros(lay.nnz)
    values(q, data)
    matrix = lay.matrix(data + lay.linear_data)
    cols = np.arange(n)
    dC, dF = [], []
    for j in cols:
        e = np.zeros(n)
        e[j] = h[j]
        (c_up, f_up), (c_down, f_down) = values(q + e), values(q - e)
        dC.append((c_up - c_down) / (2 * h[j]))
        dF.append((f_up - f_down) / (2 * h[j]))
    dC, dF = np.column_stack(dC), np.column_stack(dF)
    return [_compare(system, "constraints C_q", "q", matrix[n:, :n].toarray(), dC,
                     n + np.arange(lay.n_c), cols),
            _compare(system, "constraints d(C_q^T lam)/dq", "q", matrix[:n, :n].toarray(),
                     dF, np.arange(n), cols)]


def _compare(system, name, wrt, tangent, differences, rows, cols):
    scale = float(np.abs(differences).max())
    gap = np.abs(tangent - differences)
    i, j = np.unravel_index(int(np.argmax(gap)), gap.shape)
    error = float(gap[i, j] / scale) if scale > 0 else float(gap[i, j])
    return PartCheck(name, wrt, error, scale, system.describe_dof(int(rows[i])),
                     system.describe_dof(int(cols[j])))
