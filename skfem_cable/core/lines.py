"""Line bodies as line loads see them: the hook ``line_points(system)`` and its tables.

A *line body* (``protocols.LineBody``: a cable, a rod, a user's element with fields along an
arc length) declares its quadrature by returning ``LinePoints`` from
``line_points(system)``: where its points are as linear combinations of its 3-vector
coordinates, their slopes, and their weights.
That is all a line load reads of it (``Gravity``'s constant field and the differential
gravity of an orbit read the generic ``Body`` hooks ``mass_matrix`` and ``mass_points``):
the gather, interpolation and scatter are written once, in ``kernels.line``.  A body's
other coordinates (a twist, a rotation, a deployment's length) do not enter: ``edofs``
names only the 3-vectors that the position is interpolated from.

Examples
--------
>>> import numpy as np, skfem_cable as sc
>>> cable = sc.Cable.straight([0, 0, 0], [2, 0, 0], 4, sc.Section.circular(1e-3, 2e11, 7850.0))
>>> points = cable.line_points(sc.System([cable]))
>>> points.edofs.shape, points.S.shape          # 4 elements, 4 cubic functions, 5 points
((4, 12), (4, 5, 4))
>>> round(float(points.w.sum()), 12)                # the weights add up to the length
2.0
>>> x, a, v = points.at(cable.q0)
>>> np.allclose(a, [1, 0, 0])
True
"""

from dataclasses import dataclass

import numpy as np

from ..kernels import line as kernel
from .linalg import thread_count


@dataclass(frozen=True)
class LinePoints:
    """The points of a line body's quadrature, as a line load uses them.

    At point ``g`` of element ``e``, with ``q_A = q[edofs[e, 3 A : 3 A + 3]]`` the element's
    ``nf`` 3-vectors,

    ``x = sum_A S[e, g, A] q_A`` (position),  ``a = sum_A Sx[e, g, A] q_A`` (slope
    ``dx/ds`` along the reference arc length ``s``),  ``xd = sum_A S[e, g, A] v_A``,

    and ``int f ds`` is ``sum w[e, g] f(x, a, xd)``.  The rule must integrate the
    products ``S_A S_B`` of the element's functions exactly (a constant line load and the
    added mass are then consistent).

    Attributes
    ----------
    edofs : int64 ndarray (ne, 3 nf)
        Global coordinates of each element's ``nf`` 3-vectors.
    S, Sx : ndarray (ne, nq, nf)
        The element's functions and their derivatives with respect to ``s`` at its points.
    w : ndarray (ne, nq)
        The weights (m): the rule's weights times the elements' reference lengths.
    """

    edofs: np.ndarray
    S: np.ndarray
    Sx: np.ndarray
    w: np.ndarray

    def __post_init__(self):
        ne, nq, nf = np.shape(self.S)
        shapes = {"edofs": (ne, 3 * nf), "Sx": (ne, nq, nf), "w": (ne, nq)}
        for name, shape in shapes.items():
            if np.shape(getattr(self, name)) != shape:
                raise ValueError(f"LinePoints.{name} must have shape {shape} (S has "
                                 f"{(ne, nq, nf)}), got {np.shape(getattr(self, name))}")
        object.__setattr__(self, "edofs", np.ascontiguousarray(self.edofs, dtype=np.int64))
        for name in ("S", "Sx", "w"):
            object.__setattr__(self, name, np.ascontiguousarray(getattr(self, name), float))

    @property
    def shape(self):
        """``(ne, nq)``: elements and points per element."""
        return self.w.shape

    def hook(self, point, velocity=True, dissipative=False):
        """The compiled hook (``contract.Term.kernels``) of the line load whose point
        function is ``point`` on these points' element (``kernels.line.module``), on
        numba's threads if the run has more than one (``linalg.thread_count``)."""
        module = kernel.module(point, self.S.shape[2], velocity, dissipative)
        return module.kernel_parallel if thread_count() > 1 else module.kernel

    def at(self, q, v=None):
        """Positions, slopes and velocities (ne, nq, 3) of the points for the global
        coordinates ``q`` and velocities ``v`` (default zero), by the compiled gather of
        ``kernels.line``."""
        q = np.ascontiguousarray(q, dtype=float)
        v = np.zeros_like(q) if v is None else np.ascontiguousarray(v, dtype=float)
        X, A, V = (np.empty(self.shape + (3,)) for _ in range(3))
        kernel.points(self.edofs, self.S, self.Sx, q, v, X, A, V)
        return X, A, V

    def force(self, force_per_length):
        """``(dofs, values)``: the generalized force ``sum w S_A f`` of a uniform line load
        ``force_per_length`` (3,) (N/m), on the coordinates ``dofs``."""
        F = np.broadcast_to(np.asarray(force_per_length, float), self.shape + (3,))
        f_ext = np.zeros(int(self.edofs.max()) + 1)
        none = np.zeros(self.shape + (3, 3))
        kernel.assemble(self.edofs, self.S, self.Sx, self.w, np.ascontiguousarray(F), none,
                        none, none, 0.0, 0.0, f_ext, np.zeros(0),
                        np.zeros((0, 0, 0), dtype=np.int64))
        dofs = np.unique(self.edofs)
        return dofs, f_ext[dofs]

    def pack(self, params, scale=None):
        """The ``pack`` of a pointwise load's compiled kernel (``kernels.line.module``):
        these tables, the factor of each element's force ``scale`` (ne,) (default 1), the
        load's ``params`` (a tuple of arrays) and its resultant (3,), which every
        evaluation adds ``sum w scale f`` to."""
        scale = np.ones(self.shape[0]) if scale is None else \
            np.ascontiguousarray(scale, dtype=float)
        return (self.edofs, self.S, self.Sx, self.w, scale, tuple(params), np.zeros(3))

    def tangent_pattern(self):
        """``(rows, cols)`` of the element blocks, broadcastable to (ne, 3 nf, 3 nf): the
        places of a line load's tangent (``contract.Term``)."""
        return self.edofs[:, :, None], self.edofs[:, None, :]

    def mass(self, mass_per_length):
        """``(rows, cols, values)``: the consistent mass ``m sum w S_A S_B`` (on each of
        the three components) of a uniform mass per length ``m`` (kg/m) carried by the
        line, e.g. an added mass (``Term.mass``); exact when the rule integrates the
        products of the functions exactly (class notes)."""
        M = np.einsum("eg,egA,egB->eAB", mass_per_length * self.w, self.S, self.S)
        ne, nf = M.shape[:2]
        vectors = self.edofs.reshape(ne, nf, 3)
        rows = np.broadcast_to(vectors[:, :, None, :], (ne, nf, nf, 3))
        cols = np.broadcast_to(vectors[:, None, :, :], (ne, nf, nf, 3))
        values = np.broadcast_to(M[..., None], (ne, nf, nf, 3))
        return rows.ravel(), cols.ravel(), values.ravel()


def check_line_body(body, name="body"):
    """``body``, or ``TypeError`` naming the parameter ``name`` when it is not a line body
    (it has no hook ``line_points``: no points for a line load)."""
    if not callable(getattr(body, "line_points", None)):
        raise TypeError(f"{name} must be a line body, with the hook line_points(system) -> "
                        f"LinePoints (skfem_cable.core.lines), got {body!r}")
    return body


def line_points(body, system):
    """``body.line_points(system)``, or ``TypeError`` naming the body when it is not a line
    body (``check_line_body``)."""
    return check_line_body(body).line_points(system)


def joined(points):
    """One ``LinePoints`` of the points ``points`` (a sequence of ``LinePoints``) of several
    line bodies, in order: a load on them all runs one loop.  Their elements must have the
    same numbers of points and functions."""
    shapes = sorted({p.S.shape[1:] for p in points})
    if len(shapes) != 1:
        raise ValueError(f"points: the line bodies of one load must have the same points "
                         f"and functions per element, got (nq, nf) = {shapes}")
    return LinePoints(*(np.concatenate([getattr(p, name) for p in points])
                        for name in ("edofs", "S", "Sx", "w")))
