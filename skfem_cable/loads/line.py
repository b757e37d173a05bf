"""Line loads along a line body: uniform and ``f(x, v, t)``."""

import numpy as np

from ..core.contract import Term
from ..core.lines import check_line_body, line_points
from ..kernels import line as kernel
from .point import vector3


class AlongCable:
    """Base of the loads that act along one line body (a cable), ``self.cable``: it names
    it in ``cables`` (the contract of loads along lines, ``System.layout`` refuses a
    deploying one unless the load ``stretches``).  The load reads the body through its
    line-body hook only (``lines.line_points``)."""

    @property
    def cables(self):
        return [self.cable]


class UniformLineLoad(AlongCable):
    """Uniform distributed load (N per metre of reference length, fixed in space) along a
    cable or any line body: the consistent generalized force ``int S^T f dx`` over the
    body's points (``lines.LinePoints.force``).

    Parameters
    ----------
    cable : Cable or line body
        The line (any body with the hook ``line_points``, ``lines``).
    force_per_length : array_like (3,)
        The load (N/m).
    """

    label = "line load"

    def __init__(self, cable, force_per_length):
        self.cable = check_line_body(cable, "cable")
        self.value = vector3(force_per_length, "force_per_length")

    def space_fixed_force(self, t):
        """The load (N/m), fixed in space (``solvers.steady.check_space_fixed``)."""
        return self.value

    def __repr__(self):
        return f"{type(self).__name__}({self.cable.name!r}, {self.value.tolist()})"

    def bind(self, system):
        return Term(force=line_points(self.cable, system).force(self.value),
                    name=f"{self.label} {self.cable.name}")


class LineLoad(AlongCable):
    """Distributed force ``force(x, v, t)`` (N per metre of reference length) along a cable
    or any line body, depending on the position ``x``, the velocity ``v`` and the time
    ``t``.

    Parameters
    ----------
    cable : Cable or line body
        The line (any body with the hook ``line_points``, ``lines``).
    force : callable
        ``force(x, v, t) -> (n, 3)`` with ``x`` and ``v`` the positions and velocities at
        the line's ``n`` points (``lines.LinePoints``), ``(n, 3)`` each (vectorised: one call per
        evaluation).
    dq, dv : callable, optional
        Exact Jacobians ``dq(x, v, t)``, ``dv(x, v, t) -> (n, 3, 3)`` with
        ``dq[k, i, j] = d force_i / d x_j`` at point ``k``.  Without them, forward
        differences with the step ``fd_step * (1 + |x_j|)`` (resp. ``|v_j|``) are used;
        the Newton iteration then converges linearly instead of quadratically near the
        solution, but to the same answer.
    fd_step : float
        Relative step of the finite-difference Jacobians (default ``sqrt(eps)``).

    Notes
    -----
    The generalized force is ``int S^T f dx`` and its tangent blocks ``int S^T (df/dx) S dx``
    and ``int S^T (df/dv) S dx`` (``S`` the line's functions), gathered and scattered by
    the compiled passes of ``kernels.line`` (``points``, ``assemble``) around the Python
    ``force``: the term's ``add`` is the only Python of the step.  Its work is booked as
    external work (drag: negative).  ``demos/drag_terminal_speed.py`` is a complete example.

    Examples
    --------
    Linear viscous drag ``f = -c v`` with its exact velocity Jacobian:

    >>> import numpy as np, skfem_cable as sc
    >>> cable = sc.Cable.straight([0, 0, 0], [2, 0, 0], 4, sc.Section.circular(1e-3, 2e11, 7850.0))
    >>> c = 0.5                                          # N s/m^2
    >>> drag = sc.LineLoad(cable, lambda x, v, t: -c * v,
    ...                    dv=lambda x, v, t: np.broadcast_to(-c * np.eye(3), v.shape + (3,)))
    >>> drag.evaluate(np.zeros((2, 3)), np.array([[0.0, -2.0, 0.0]] * 2), 0.0)
    array([[-0.,  1., -0.],
           [-0.,  1., -0.]])
    """

    def __init__(self, cable, force, dq=None, dv=None, fd_step=1.49e-8):
        for name, fn in (("force", force), ("dq", dq), ("dv", dv)):
            if fn is not None and not callable(fn):
                raise TypeError(f"{name} must be a callable (x, v, t) -> array, got {fn!r}")
        if force is None:
            raise TypeError("force must be a callable (x, v, t) -> (n, 3) array")
        if not 0 < fd_step < 1:
            raise ValueError(f"fd_step must lie in (0, 1), got {fd_step!r}")
        self.cable = check_line_body(cable, "cable")
        self.fn, self.dq, self.dv, self.fd_step = force, dq, dv, fd_step

    def evaluate(self, x, v, t):
        """``force(x, v, t)`` with its shape checked."""
        f = np.asarray(self.fn(x, v, t), dtype=float)
        if f.shape != x.shape:
            raise ValueError(f"LineLoad force(x, v, t) must return shape {x.shape} (one "
                             f"3-vector per point of the line), got {f.shape}")
        return f

    def jacobians(self, x, v, t, f, want_dv):
        """``(df/dx, df/dv)`` (n, 3, 3) each: exact when given, else differences."""
        dq = self._jacobian(self.dq, x, v, t, f, 0)
        dv = self._jacobian(self.dv, x, v, t, f, 1) if want_dv else None
        return dq, dv

    def _jacobian(self, exact, x, v, t, f, which):
        if exact is not None:
            J = np.asarray(exact(x, v, t), dtype=float)
            if J.shape != x.shape + (3,):
                raise ValueError(f"LineLoad Jacobian must return shape {x.shape + (3,)}, "
                                 f"got {J.shape}")
            return J
        J = np.empty(x.shape + (3,))
        args = [x, v]
        for j in range(3):
            step = self.fd_step * (1.0 + np.abs(args[which][:, j]))
            moved = args[which].copy()
            moved[:, j] += step
            pair = (moved, v) if which == 0 else (x, moved)
            J[:, :, j] = (self.evaluate(*pair, t) - f) / step[:, None]
        return J

    def bind(self, system):
        """The term: its ``add`` gathers the points' positions and velocities
        (``kernels.line.points``), calls ``force`` (and the Jacobians for a tangent) and
        scatters them (``kernels.line.assemble``), into arrays made once here."""
        points = line_points(self.cable, system)
        rows, cols = points.tangent_pattern()
        ne, nq = points.shape
        X, A, V = (np.empty((ne, nq, 3)) for _ in range(3))
        zero = np.zeros((ne, nq, 3, 3))
        no_tangent = (np.zeros(0), np.zeros((0, 0, 0), dtype=np.int64))

        def add(ev, index):
            kernel.points(points.edofs, points.S, points.Sx, ev.q, ev.v, X, A, V)
            x, v = X.reshape(-1, 3), V.reshape(-1, 3)
            f = self.evaluate(x, v, ev.t)
            Fx = Fv = zero
            data, index = (ev.data, index) if ev.want_tangent else no_tangent
            if ev.want_tangent:
                dq, dv = self.jacobians(x, v, ev.t, f, ev.dynamic)
                Fx = dq.reshape(zero.shape)
                Fv = zero if dv is None else dv.reshape(zero.shape)
            kernel.assemble(points.edofs, points.S, points.Sx, points.w,
                            f.reshape(X.shape), Fx, zero, Fv, ev.cK,
                            ev.cC if ev.dynamic else 0.0, ev.f_ext, data, index)

        return Term(add=add, rows=rows, cols=cols, name=f"line load {self.cable.name}")
