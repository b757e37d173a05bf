"""The states of statics: where a solve starts (a cable held closer than its length starts
from its hanging shape, ``hanging_start``) and which converged states it refuses (a cable
crumpled, folded back in an element or through itself: ``admissible``, ``unfolded``,
``folds``, ``crossings``), with the reasons it gives."""

import numpy as np
from scipy.sparse.linalg import lsqr

from ..kernels.assumed_strain import GAUSS_W, GAUSS_XI


def constraint_jacobian(system, q):
    """``C_q`` of every constraint at ``q`` (sparse, n_constraints x n_dofs), from the
    KKT matrix the solvers assemble."""
    lay, n = system.current_layout(), system.n_dofs
    data = lay.linear_data.copy()
    system.evaluate(q, None, 0.0, np.zeros(lay.n_c), data=data, layout=lay)
    return lay.matrix(data)[n:, :n].tocsr()


def hanging_start(system, q, tol):
    """The coordinates ``q`` with every cable whose ends the constraints hold closer than
    its length, where ``q`` does not satisfy them, hanging instead (``_hanging``): the
    start of ``solve_static`` by default; ``q`` itself when the constraints hold to
    ``tol`` (m).  The points the constraints hold the ends at are the least-norm
    correction of ``q`` onto the linearised constraints."""
    violation = system.constraint_values(q)
    if not np.max(np.abs(violation), initial=0.0) > tol:
        return q
    J = constraint_jacobian(system, q).tocsc()
    held = q + lsqr(J, -violation, atol=1e-15, btol=1e-15)[0]
    lam = np.zeros(system.layout.n_c)
    force = system.evaluate(q, None, 0.0, lam, 0.0)[0] - system.evaluate(q, None, 0.0, lam)[0]
    out = q.copy()
    for cable in system.cables():
        dofs = system.dofs(cable)
        if getattr(cable, "hanging", None) is None or system.deployment(cable) is not None \
                or np.array_equal(held[dofs], q[dofs]):
            continue
        sagged = _hanging(system, cable, held[dofs], J[:, dofs], force)
        out[dofs] = out[dofs] if sagged is None else sagged
    return out


def _hanging(system, cable, held, J, force):
    """The coordinates of ``cable`` hanging (``Cable.hanging``: the inextensible catenary
    of its length) between its end points in ``held`` (its coordinates moved onto the
    constraints), sagging along the net external force on it (its weight; ``force`` the
    system's generalized external force); None unless the constraints (``J``, their
    Jacobian on its coordinates) involve both of its end positions and the force has a
    direction across the line between them."""
    first, last = cable.node_dofs(0)[:3], cable.node_dofs(cable.n_nodes - 1)[:3]
    if min(J[:, first].nnz, J[:, last].nnz) == 0:
        return None
    positions = system.vectors[system.vector_is_position]
    sag = force[positions[np.isin(positions[:, 0], system.dofs(cable))]].sum(axis=0)
    chord = held[last] - held[first]
    across = sag - (sag @ chord) * chord / max(chord @ chord, 1e-300)
    if not np.linalg.norm(across) > 1e-6 * np.linalg.norm(sag):
        return None
    return cable.hanging(held[first], held[last], sag)


def _least_strain(cable, q, samples=8):
    """``(s, strain)`` at the least strain of ``cable`` at its coordinates ``q``, sampled
    ``samples`` times per element."""
    s = np.linspace(0.0, cable.length, samples * cable.n_elements + 1)
    strain = cable.strain(q, s)
    k = int(np.argmin(strain))
    return s[k], strain[k]


def _least_element_strain(cable, q):
    """``(s, strain)``: the least element mean of the Green strain of the cubic field of
    ``cable`` at its coordinates ``q`` (3-point Gauss, exact), at the element's middle:
    independent of the formulation, and of membrane locking, which stripes the strain
    within the elements."""
    a = cable.slopes_at(q, GAUSS_XI)
    means = 0.5 * (np.einsum("eXi,eXi->eX", a, a) - 1.0) @ GAUSS_W
    k = int(np.argmin(means))
    return float(cable.mesh.p[0, k] + cable.h[k] / 2), float(means[k])


#: Compression of an element (strain) that a cable never carries without buckling: the
#: elastic limit of structural metals, far beyond the discretisation error of the strain
#: of a coarse element.
CRUMPLED = 1e-3


def crumpling_strain(cable):
    """The compression (a negative strain) of an element of ``cable`` beyond which an
    equilibrium on a path that started slack is spurious: ``CRUMPLED``, or the Euler
    strain ``pi^2 I / (A h^2)`` of a pinned strut as long as the longest element if that
    is larger.  Beyond both the element would buckle, which the discrete cable cannot: it
    stands compressed and straight, or folds over at a node."""
    section = cable.section
    return -max(CRUMPLED, np.pi**2 * section.I / (section.A * float(cable.h.max()) ** 2))


def admissible(system, q, tol, history):
    """False (noted in ``history``) when a cable is compressed in the state ``q``: a cable
    without bending stiffness anywhere (strain below ``-sqrt(tol)``: it stands as an arch
    or crumples between the quadrature points), a cable with bending stiffness in the
    mean over an element beyond its ``crumpling_strain`` (less ``sqrt(tol)``).  Checked on
    the equilibria reached by relaxation or while a constraint violation is closed, paths
    that start slack: there such an equilibrium is spurious and the step is refused, to be
    bisected.  (A cable built compressed and solved by Newton's method keeps its unstable
    straight equilibrium, which ``modes`` reports.)"""
    for cable in system.cables():
        qc = q[system.dofs(cable)]
        if cable.bending:
            s, strain = _least_element_strain(cable, qc)
            limit = crumpling_strain(cable) - np.sqrt(tol)
        else:
            s, strain = _least_strain(cable, qc)
            limit = -np.sqrt(tol)
        if strain < limit:
            history.append(f"cable {cable.name!r} compressed on a path that started slack "
                           f"(strain {strain:.3g} at s = {s:.4g} m, below {limit:.3g}): "
                           "refused")
            return False
    return True


#: Points per element at which ``folds`` samples the tangent (and the elements' ends).
FOLD_SAMPLES = 9


def folds(system, q):
    """One sentence per cable (with ``slopes_at``) of ``system`` that folds back within
    an element in the state ``q``: its tangent ``r_x`` points against the element's
    chord, or turns by more than 90 degrees between two of ``FOLD_SAMPLES`` points of
    the element.  A smooth cable turns its tangent by far less within one element; a
    fold is a loop through which the cable passes itself (a spurious equilibrium of the
    discrete equations, reached from a straight start, issue 45)."""
    xi = np.linspace(0.0, 1.0, FOLD_SAMPLES)
    reasons = []
    for cable in system.cables():
        slopes_at = getattr(cable, "slopes_at", None)
        if slopes_at is None:
            continue
        qc = q[system.dofs(cable)]
        a = slopes_at(qc, xi)
        a = a / np.maximum(np.linalg.norm(a, axis=-1, keepdims=True), 1e-300)
        x = cable.mesh.p[0]
        chord = np.diff(cable.interpolate(qc, x)[0], axis=0)
        chord /= np.maximum(np.linalg.norm(chord, axis=-1, keepdims=True), 1e-300)
        along = np.einsum("eXi,ei->eX", a, chord)
        turn = np.einsum("eXi,eXi->eX", a[:, 1:], a[:, :-1])
        worst = np.minimum(along.min(axis=1), turn.min(axis=1))
        folded = np.flatnonzero(worst < 0.0)
        if folded.size:
            e = folded[0]
            k = int(np.argmin(along[e]))
            reasons.append(
                f"cable {cable.name!r} folds back in {folded.size} element(s), first in "
                f"element {e} (s = {x[e]:.4g} to {x[e + 1]:.4g} m): its tangent points "
                f"against the element's chord (cosine {along[e, k]:.3g} at s = "
                f"{x[e] + xi[k] * (x[e + 1] - x[e]):.4g} m) or turns by more than 90 "
                "degrees within it, so the cable passes through itself there: a spurious "
                "equilibrium, refused; start from the hanging shape (the default start, "
                "Cable.between or initial=) or refine the mesh")
    return reasons


def crossings(system, q):
    """One sentence per cable (with ``slopes_at`` and a ``section``) of ``system`` whose
    centre line passes within its diameter (that of the circle of its section's area) of
    itself in the state ``q``, between points further apart along it than ``pi`` times
    the diameter and two sampling steps: it passes through itself (or bends more tightly
    than its own thickness).  The centre line is the polygon through ``FOLD_SAMPLES``
    points per element; a cable whose ends meet is taken as a ring."""
    from scipy.spatial import cKDTree

    xi = np.linspace(0.0, 1.0, FOLD_SAMPLES)[:-1]
    reasons = []
    for cable in system.cables():
        if getattr(cable, "slopes_at", None) is None or getattr(cable, "section", None) is None:
            continue
        x = cable.mesh.p[0]
        s = np.append((x[:-1, None] + xi * cable.h[:, None]).ravel(), x[-1])
        r = cable.interpolate(q[system.dofs(cable)], s)[0]
        diameter = 2.0 * np.sqrt(cable.section.A / np.pi)
        step = float(np.linalg.norm(np.diff(r, axis=0), axis=1).max())
        i, j = cKDTree(0.5 * (r[:-1] + r[1:])).query_pairs(step + diameter,
                                                           output_type="ndarray").T
        apart = np.abs(s[i] - s[j])
        if np.linalg.norm(r[-1] - r[0]) <= diameter:
            apart = np.minimum(apart, cable.length - apart)
        far = apart > np.pi * diameter + 2.0 * step
        i, j = i[far], j[far]
        gap = _segment_distance(r[i], r[i + 1], r[j], r[j + 1])
        close = np.flatnonzero(gap < diameter)
        if close.size:
            k = close[np.argmin(gap[close])]
            reasons.append(
                f"cable {cable.name!r} passes through itself: its centre line at s = "
                f"{s[i[k]]:.4g} m and at s = {s[j[k]]:.4g} m is {gap[k]:.3g} m from itself, "
                f"within its diameter {diameter:.3g} m: a spurious equilibrium, refused; "
                "start from the hanging shape (the default start, Cable.between or "
                "initial=) or refine the mesh")
    return reasons


def _segment_distance(a0, a1, b0, b1):
    """Distances between the segments ``a0 a1`` and ``b0 b1`` (rows of (m, 3) arrays):
    the closest points' parameters clamped to [0, 1] (Ericson, Real-Time Collision
    Detection, 2005, Sect. 5.1.9)."""
    d1, d2, w = a1 - a0, b1 - b0, a0 - b0
    a = np.maximum(np.einsum("ij,ij->i", d1, d1), 1e-300)
    e = np.maximum(np.einsum("ij,ij->i", d2, d2), 1e-300)
    b, c, f = (np.einsum("ij,ij->i", u, v) for u, v in ((d1, d2), (d1, w), (d2, w)))
    denom = a * e - b * b
    with np.errstate(divide="ignore", invalid="ignore"):
        sa = np.where(denom > 1e-12 * a * e, np.clip((b * f - c * e) / denom, 0, 1), 0.0)
    t = (b * sa + f) / e
    sa = np.where(t < 0, np.clip(-c / a, 0, 1), np.where(t > 1, np.clip((b - c) / a, 0, 1), sa))
    t = np.clip(t, 0, 1)
    return np.linalg.norm(a0 + sa[:, None] * d1 - b0 - t[:, None] * d2, axis=1)


def unfolded(system, q, history):
    """False (with the reasons noted in ``history``) when a cable folds back within an
    element (``folds``) or passes through itself (``crossings``) in the state ``q``."""
    reasons = folds(system, q) + crossings(system, q)
    history.extend(reasons)
    return not reasons


def without_bending(system, q):
    """Why cables without bending stiffness (the truss law) may defeat a static solve:
    one sentence per such cable that is compressed or slack somewhere in the state
    ``q`` (its tangent then has no stiffness across the cable), with what to do."""
    reasons = []
    for cable in system.cables():
        if cable.bending:
            continue
        s, strain = _least_strain(cable, q[system.dofs(cable)])
        if strain <= 0.0:
            reasons.append(
                f"cable {cable.name!r} has no bending stiffness (law {cable.law.name!r}) and "
                f"is compressed or slack (strain {strain:.3g} at s = {s:.4g} m): "
                "without tension its stiffness across the cable vanishes and the tangent is "
                "singular; start from a stretched state (initial=) or tension it first "
                "(more load_steps, the tensioning loads applied first), give it bending "
                "(law 'cable'), or find the hanging state with simulate and damping")
    return reasons
