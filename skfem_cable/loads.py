"""External loads, point masses and gravity, each a contributor of the evaluation contract
(``contract``): ``bind(system)`` returns a ``Term`` and leaves the load unchanged.

Constant loads (fixed point and line loads, gravity) become constant generalized forces
(``Term.force``) whose potential is booked as potential energy; loads that depend on time,
position or velocity add to ``Evaluation.f_ext`` at every evaluation, with the tangent
blocks ``dF/dq`` and ``dF/dv``, and their work is booked as external work.

Examples
--------
``System.add_gravity``, ``add_point_load``, ``add_point_moment``, ``add_line_load``,
``add_centrifugal`` and ``add_point_mass`` build them; ``System.add_load`` takes any of
them (or a user's contributor):

>>> import numpy as np, skfem_cable as sc
>>> cable = sc.Cable.straight([0, 0, 0], [2, 0, 0], 4, sc.Section.circular(1e-3, 2e11, 7850.0))
>>> drag = sc.LineLoad(cable, lambda x, v, t: -0.5 * v)           # N/m, velocity-dependent
>>> system = sc.System([cable]).pin(cable.node(0)).add_load(drag).add_gravity([0, -9.81, 0])
>>> [type(load).__name__ for load in system.loads]
['LineLoad', 'Gravity']
"""

from dataclasses import replace

import numpy as np

from .contract import Term, combined
from .inputs import declared, reader
from .kernels import drives
from .kernels import line as kernel
from .lines import check_line_body, line_points


def vector3(v, name):
    """``v`` as a finite 3-vector, or ``ValueError`` naming ``name``."""
    v = np.asarray(v, dtype=float)
    if v.shape != (3,) or not np.all(np.isfinite(v)):
        raise ValueError(f"{name} must be a finite 3-vector, got {v!r}")
    return v


class PointLoad:
    """Force (N, fixed in space) at a cable node or a rigid-body point: a 3-vector, or a
    callable ``force(t)`` returning one (a time-dependent load).

    Parameters
    ----------
    point : Node or body point
        ``cable.node(i)`` or ``RigidBody.point(x)``.
    force : array_like (3,) or callable
        The force (N), or ``force(t)``: a constant force is a generalized force with a
        potential (booked as potential energy), a time-dependent one does external work.

    Examples
    --------
    >>> import numpy as np, skfem_cable as sc
    >>> cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], 2, sc.Section.circular(1e-3, 2e11, 7850.0))
    >>> pulse = sc.PointLoad(cable.node(-1), lambda t: [0.0, -np.sin(t), 0.0])
    >>> pulse.force(np.pi / 2)
    array([ 0., -1.,  0.])
    """

    def __init__(self, point, force):
        self.point = point
        self.fn = force if callable(force) else None
        self.value = None if callable(force) else vector3(force, "force")
        if self.fn is not None:
            self.force(0.0)  # fail now, not in the middle of a run

    def force(self, t):
        """The force (N) at time ``t`` (an ``Input`` at its initial value: a run reads
        its own, ``bind``)."""
        if self.fn is None:
            return self.value
        return vector3(self.fn(t), f"force({t!r})")

    def inputs(self):
        """The inputs the force reads (``inputs.declared``): an ``Input`` given as the
        force."""
        return declared(self.fn)

    #: The load's declared force fixed in space (``solvers.steady.check_space_fixed``).
    space_fixed_force = force

    def __repr__(self):
        force = "force(t)" if self.fn is not None else self.value.tolist()
        return f"PointLoad({self.point!r}, {force})"

    def bind(self, system, inputs=None):
        """The load's term: a constant force, or a function of time refreshed once per
        step (compiled, ``kernels.drives.point_force``) reading the run's values of its
        inputs (``inputs``: the run's ``InputTable``; None: their initial values)."""
        dofs, G = system.position_map(self.point)
        if self.fn is None:
            return Term(force=(dofs, G.T @ self.value), name=f"point load {self.point!r}")
        force = self.force(0.0)
        source = reader(self.fn, inputs)

        def prepare(t):
            force[:] = vector3(source(t), f"force({t!r})")

        pack = (np.ascontiguousarray(dofs, dtype=np.int64), np.ascontiguousarray(G), force)
        return Term(kernels=((drives.point_force, pack),), prepare=prepare,
                    name=f"point load {self.point!r}")


class PointMoment:
    """Moment ``M`` (N m, fixed in space) at a cable node.

    From the virtual work ``dW = M . (t x dt)`` with ``t = r_x / |r_x|``, the generalized
    force on the node's slope is ``f = M x r_x / |r_x|^2`` and its derivative is
    ``df/dr_x = ([M]_x |r_x|^2 - 2 (M x r_x) r_x^T) / |r_x|^4``.

    Parameters
    ----------
    node : Node
        ``cable.node(i)``.
    moment : array_like (3,)
        The moment (N m).

    Examples
    --------
    A moment about ``z`` turns a slope along ``x`` towards ``y``:

    >>> import numpy as np, skfem_cable as sc
    >>> cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], 2, sc.Section.circular(1e-3, 2e11, 7850.0))
    >>> sc.PointMoment(cable.node(-1), [0, 0, 1.0]).force(np.array([1.0, 0.0, 0.0]))
    array([0., 1., 0.])
    """

    def __init__(self, node, moment):
        self.node = node
        self.moment = vector3(moment, "moment")

    def force(self, a):
        """Generalized force ``M x a / |a|^2`` on the slope ``a = r_x``."""
        return np.cross(self.moment, a) / (a @ a)

    def stiffness(self, a):
        """``df/da`` (3 x 3)."""
        p = a @ a
        Mx = np.cross(self.moment, np.eye(3)).T  # Mx @ v = M x v
        return Mx / p - 2.0 * np.outer(np.cross(self.moment, a), a) / p**2

    def bind(self, system):
        dofs = system.dofs(self.node)[3:]

        def add(ev, index):
            a = ev.q[dofs]
            ev.f_ext[dofs] += self.force(a)
            ev.add_tangent(index, self.stiffness(a), sign=-1.0)

        return Term(add=add, rows=dofs[:, None], cols=dofs[None, :],
                    name=f"moment {self.node!r}")


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


class Gravity:
    """Uniform gravity ``g`` (m/s^2) on every body and point mass.

    The generalized force is ``M u_g`` with ``u_g`` the coordinates of the uniform field
    ``r(x) = g`` (positions ``g``, slopes 0): ANCF shape functions, natural coordinates and
    point masses all reproduce a constant field exactly, so ``M u_g = int rho S^T g dV`` is
    the consistent gravity load of every body.  The mass a deploying cable gains or loses
    (``System.deploy``) adds a time-dependent weight (``Deployment.weight``), booked as
    external work.

    Parameters
    ----------
    g : array_like (3,)
        Gravitational acceleration (m/s^2).

    Examples
    --------
    The forces on the position coordinates add up to the weight (0.2 kg here):

    >>> import skfem_cable as sc
    >>> sec = sc.Section(E=1e9, A=1e-4, I=1e-10, rho=1000.0)
    >>> cable = sc.Cable.straight([0, 0, 0], [2, 0, 0], 4, sec)
    >>> dofs, f = sc.Gravity([0, -9.81, 0]).bind(sc.System([cable])).force
    >>> f[cable.position_mask].reshape(-1, 3).sum(axis=0)
    array([ 0.   , -1.962,  0.   ])
    """

    def __init__(self, g):
        self.g = vector3(g, "g")

    def space_fixed_force(self, t):
        """The acceleration ``g``, fixed in space (``solvers.steady.check_space_fixed``)."""
        return self.g

    def __repr__(self):
        return f"Gravity({self.g.tolist()})"

    def bind(self, system):
        u = system.rigid_motion_velocity(system.q0, (0, 0, 0), velocity=self.g)
        force = (np.arange(system.n_dofs), system.mass_matrix() @ u)
        weights = [d.bind_weight(system, self.g) for d in system.deployments.values()]
        if not weights:
            return Term(force=force, name="gravity")
        return replace(combined(weights, "gravity"), force=force)


class PointMass:
    """Point mass (kg) at a cable node's position or at a body point (anything
    ``System.position_map`` accepts): a constant mass ``m G^T G``.

    Parameters
    ----------
    point : Node or body point
    mass : float
        Mass (kg), > 0.

    Examples
    --------
    >>> import skfem_cable as sc
    >>> cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], 2, sc.Section.circular(1e-3, 2e11, 7850.0))
    >>> system = sc.System([cable]).add_point_mass(cable.node(-1), 0.5)   # a tip mass
    >>> round(float(system.mass_matrix()[-6, -6] - cable.mass_matrix()[-6, -6]), 12)
    0.5
    """

    def __init__(self, point, mass):
        self.point = point
        if not (np.isfinite(mass) and mass > 0):
            raise ValueError(f"mass must be a finite number > 0, got {mass!r}")
        self.mass = float(mass)

    def bind(self, system):
        dofs, G = system.position_map(self.point)
        rows, cols = np.meshgrid(dofs, dofs, indexing="ij")
        return Term(mass=(rows.ravel(), cols.ravel(), self.mass * (G.T @ G).ravel()),
                    name=f"point mass {self.point!r}")


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


class Centrifugal:
    """Centrifugal force ``-M (Omega x (Omega x (q - u_c)))`` on every 3-vector of
    coordinates in a frame rotating at the constant rate ``omega`` (rad/s) about the axis
    through ``center``.

    All coordinates (ANCF positions and slopes, natural coordinates of rigid bodies) are
    vectors that rotate with the frame, so the kinetic energy in the rotating frame gives
    this force exactly; ``u_c`` holds the coordinates of the uniform field ``r(x) = center``
    (positions ``center``, slopes and unit vectors 0, as in ``Gravity``), so that only
    positions are measured from the axis.  The force is affine in ``q`` with the constant
    tangent ``-M (I (x) [Omega]_x^2)``.  With it ``solve_static`` finds steady spinning
    states of supported systems (``solve_steady`` adds it itself and handles free ones),
    and ``modes(..., spin=omega)`` their vibrations.

    Parameters
    ----------
    omega : array_like (3,)
        Angular velocity of the frame (rad/s).
    center : array_like (3,)
        A point of the rotation axis (m); default the origin.

    Examples
    --------
    A tether clamped at the hub, spinning at 2 rad/s: the root tension of the steady state
    is ``rho A Omega^2 L^2 / 2 = 0.8 N``:

    >>> import skfem_cable as sc
    >>> sec = sc.Section(E=1e9, A=1e-4, I=1e-10, rho=1000.0)
    >>> cable = sc.Cable.straight([0, 0, 0], [2, 0, 0], 4, sec)
    >>> system = sc.System([cable]).clamp(cable.node(0)).add_centrifugal([0, 0, 2.0])
    >>> round(float(sc.solve_static(system).tension(cable, 0.0)), 4)
    0.8
    """

    def __init__(self, omega, center=(0.0, 0.0, 0.0)):
        self.omega = vector3(omega, "omega")
        self.center = vector3(center, "center")

    @property
    def frame_rate(self):
        """The angular velocity (rad/s) of the rotating frame whose inertia this load is:
        the property by which ``modes`` and ``solve_steady`` recognise a system already
        in a rotating frame."""
        return self.omega

    def bind(self, system):
        if system.deployments:
            raise ValueError("Centrifugal: the system has deploying cables, whose mass "
                             "changes with their length; build the cables at their free "
                             "length for a steady spinning state")
        C = spin_matrix(system, system.mass_matrix(), self.omega, 2).tocoo()
        matrix = C.tocsr()
        values = C.data
        u_c = system.rigid_motion_velocity(system.q0, (0, 0, 0), velocity=self.center)

        def add(ev, index):
            ev.f_ext -= matrix @ (ev.q - u_c)
            ev.add_tangent(index, -values, sign=-1.0)

        return Term(add=add, rows=C.row.astype(np.int64), cols=C.col.astype(np.int64),
                    name="centrifugal")


def spin_matrix(system, M, omega, power):
    """``M (I (x) W^power)`` with ``W = [omega]_x`` acting on every 3-vector of coordinates
    of ``system`` (``System.rotation_operator``; ``power = 1``: half the gyroscopic matrix;
    ``2``: minus the centrifugal stiffness)."""
    W = np.linalg.matrix_power(np.cross(omega, np.eye(3)).T, power)
    return (M @ system.rotation_operator(W)).tocsr()
