"""Holonomic constraints ``C(q, t) = 0`` imposed with Lagrange multipliers (paper Sect. 2.4).

A constraint acts on a few global coordinates ``q[dofs]`` and provides (the contract of
``contract``):

* ``n_eq``, ``name``, ``labels`` (one per equation: names the multipliers);
* ``linear``: True when the Jacobian ``C_q`` is constant (it then lives in one constant
  sparse matrix; the value may still move in time through ``offset(t)``);
* ``dofs(system)``: the global coordinates involved;
* ``value(qc, t)``, ``jacobian(qc, t)``, ``hessian(qc, lam, t)`` (the term
  ``d(C_q^T lambda)/dq`` of Eq. 15, None when zero);
* ``velocity_term(qc, t)`` = ``C_t`` and ``accel_term(qc, vc, t)`` =
  ``(C_q v)_q v + 2 C_qt v + C_tt`` (Eq. 2), for consistent initial velocities and
  accelerations.

Driven joints take callables of time.  Their time derivatives are given by the user
(``velocity``, ``acceleration``) or computed by ``time_derivatives``.  A linear constraint
whose equations repeat those of another (a node pinned or clamped twice) is refused when
added (``check_independent``).

Examples
--------
``System.clamp`` and ``System.pin`` build them; ``System.add_constraint`` takes any object
with this contract:

>>> import skfem_cable as sc
>>> from skfem_cable import constraints
>>> cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], 2, sc.Section.circular(1e-3, 2e11, 7850.0))
>>> (joint,) = constraints.clamp(cable.node(0))
>>> joint.n_eq, joint.labels, joint.linear
(5, ['Fx', 'Fy', 'Fz', 'M1', 'M2'], True)
>>> joint.value(cable.q0[:6])               # satisfied by the initial coordinates
array([0., 0., 0., 0., 0.])
"""

import numpy as np
import scipy.sparse as sp

from .node import Node
from .quadratic import QuadraticConstraints
from .rigid import BodyPoint

#: Step of the time differences of driven joints, relative to ``max(1, |t|)`` seconds.
TIME_STEP = 1e-3


def time_derivatives(fn, t, order):
    """First (``order=1``) or second derivative of ``fn`` at ``t`` by central differences
    with Richardson extrapolation (fourth order; step ``TIME_STEP * max(1, |t|)``): relative
    error about ``(w h)^4 / 30`` for a motion of angular frequency ``w``, 1e-7 at
    ``w = 100 rad/s``.  Give the derivatives explicitly for faster motions.

    Examples
    --------
    >>> import numpy as np
    >>> from skfem_cable.constraints import time_derivatives
    >>> round(float(time_derivatives(np.sin, 0.0, 1)), 12)
    1.0
    >>> round(float(time_derivatives(np.cos, 0.0, 2)), 9)
    -1.0
    """
    h = TIME_STEP * max(1.0, abs(t))

    def central(step):
        if order == 1:
            return (np.asarray(fn(t + step)) - np.asarray(fn(t - step))) / (2 * step)
        return (np.asarray(fn(t + step)) - 2 * np.asarray(fn(t))
                + np.asarray(fn(t - step))) / step**2

    return (4 * central(0.5 * h) - central(h)) / 3


def _unit(v, name):
    v = np.asarray(v, dtype=float)
    n = np.linalg.norm(v)
    if v.shape != (3,) or not np.isfinite(n) or n == 0:
        raise ValueError(f"{name} must be a non-zero finite 3-vector, got {v!r}")
    return v / n


def _point(p, name, size=3):
    p = np.asarray(p, dtype=float)
    if p.shape != (size,) or not np.all(np.isfinite(p)):
        raise ValueError(f"{name} must be a finite vector of length {size}, got {p!r}")
    return p


def orthonormal_complement(d):
    """Two unit vectors spanning the plane orthogonal to the unit vector ``d``."""
    seed = np.eye(3)[np.argmin(np.abs(d))]
    n1 = np.cross(d, seed)
    n1 /= np.linalg.norm(n1)
    return n1, np.cross(d, n1)


class Motion:
    """A prescribed vector ``x(t)`` with its first two time derivatives.

    Parameters
    ----------
    fn : callable or array_like
        ``fn(t)`` (a constant vector is a motion at rest).
    velocity, acceleration : callable, optional
        Exact derivatives; else ``time_derivatives``.
    name : str
        Parameter name used in error messages.
    size : int
        Length of the vector.
    """

    def __init__(self, fn, velocity=None, acceleration=None, name="target", size=3):
        self.name, self.size = name, size
        if callable(fn):
            self.fn = fn
            self.driven = True
        else:
            value = _point(fn, name, size)
            self.fn = lambda t: value
            self.driven = False
        self.derivatives = (velocity, acceleration)
        for label, d in zip(("velocity", "acceleration"), self.derivatives):
            if d is not None and not callable(d):
                raise TypeError(f"{label} must be a callable of time, got {d!r}")
        self(0.0)

    def __call__(self, t, order=0):
        if order and not self.driven:
            return np.zeros(self.size)
        exact = self.derivatives[order - 1] if order else self.fn
        if exact is not None:
            label = f"{self.name} derivative {order}" if order else self.name
            return _point(exact(t), f"{label} at t={t!r}", self.size)
        return time_derivatives(
            lambda s: _point(self.fn(s), f"{self.name} at t={s!r}", self.size), t, order)


class LinearConstraint:
    """``C(q, t) = J q[dofs] - c(t)``: clamps and spherical joints between ANCF nodes, ground
    points (fixed or moving) and natural-coordinate bodies are all linear (Eqs. 53-55).

    Parameters
    ----------
    dofs : callable
        ``dofs(system) -> int ndarray``: the global coordinates involved.
    J : ndarray, shape (n_eq, len(dofs))
    c : ndarray (n_eq,) or Motion
        Constant offset, or a prescribed ``Motion`` (a driven joint).
    name : str
    labels : list of str
        One label per equation (names the multipliers, e.g. reaction components).
    """

    linear = True

    def __init__(self, dofs, J, c, name, labels):
        self._dofs = dofs
        self.J = np.atleast_2d(np.asarray(J, dtype=float))
        self.motion = c if isinstance(c, Motion) else None
        self.c = None if self.motion is not None else np.asarray(c, dtype=float)
        self.name = name
        self.labels = list(labels)

    @property
    def n_eq(self):
        return self.J.shape[0]

    @property
    def driven(self):
        return self.motion is not None and self.motion.driven

    def dofs(self, system):
        return self._dofs(system)

    def offset(self, t, order=0):
        """``c(t)`` (or its derivative of the given order)."""
        if self.motion is None:
            return self.c if order == 0 else np.zeros_like(self.c)
        return self.motion(t, order)

    def value(self, qc, t=0.0):
        return self.J @ qc - self.offset(t)

    def jacobian(self, qc, t=0.0):
        return self.J

    def hessian(self, qc, lam, t=0.0):
        return None

    def velocity_term(self, qc, t=0.0):
        return -self.offset(t, 1)

    def accel_term(self, qc, vc, t=0.0):
        return -self.offset(t, 2)


class SlopeDirection:
    """The slope of a node keeps the direction ``d(t)``: ``n_k(t) . r_x = 0`` for the two
    unit vectors ``n_k(t)`` orthogonal to ``d(t)``.

    ``n_k(t) = R(t) n_k0`` with ``R(t)`` the smallest rotation from ``d(t0)`` to ``d(t)``
    (continuous while ``d`` does not turn by 180 degrees).  The Jacobian depends on time
    only, so the constraint's Hessian is zero; its time derivatives come from
    ``time_derivatives`` of ``n_k(t)``.
    """

    linear = False
    n_eq = 2

    def __init__(self, node, direction, t0=0.0):
        self.node = node
        self.direction = direction
        self.d0 = _unit(direction(t0), "direction(t0)")
        self.n0 = np.array(orthonormal_complement(self.d0))
        self.name = f"slope direction {node!r}"
        self.labels = ["M1", "M2"]

    def normals(self, t):
        """``n_1(t), n_2(t)`` as rows (2, 3)."""
        d = _unit(self.direction(t), f"direction({t!r})")
        axis = np.cross(self.d0, d)
        s, c = np.linalg.norm(axis), self.d0 @ d
        if c <= -1 + 1e-12:
            raise ValueError(f"direction(t) turned by 180 degrees at t = {t}: the clamp "
                             "frame is undefined")
        K = np.cross(axis, np.eye(3)).T  # K @ x = axis x x
        R = np.eye(3) + K + K @ K / (1 + c) if s > 0 else np.eye(3)
        return self.n0 @ R.T

    def dofs(self, system):
        return system.dofs(self.node)[3:6]

    def value(self, qc, t=0.0):
        return self.normals(t) @ qc

    def jacobian(self, qc, t=0.0):
        return self.normals(t)

    def hessian(self, qc, lam, t=0.0):
        return None

    def velocity_term(self, qc, t=0.0):
        return time_derivatives(self.normals, t, 1) @ qc

    def accel_term(self, qc, vc, t=0.0):
        return (2 * time_derivatives(self.normals, t, 1) @ vc
                + time_derivatives(self.normals, t, 2) @ qc)


def clamp(node, direction=None, position=None, velocity=None, acceleration=None,
          slope="direction"):
    """Clamp ``node``: its position and the *direction* of its slope (or, with
    ``slope="full"``, the whole slope vector) are fixed, follow prescribed motions, or
    are carried by a rigid body.

    Fixing the slope's direction (two equations ``n_k . r_x = 0`` with ``n_k`` orthogonal to
    ``direction``) rather than the whole slope vector leaves the axial stretch at the root
    free.  Five equations: ``r - position = 0`` and the two slope-direction equations.
    ``slope="full"`` fixes the slope vector itself, ``r_x - direction = 0`` (Exudyn's
    node constraint ``[1, 1, 1, 1]``, a welded root whose stretch is held too): six
    equations.

    Parameters
    ----------
    node : Node
    direction : array_like (3,) or callable, optional
        Slope direction (default: the node's initial slope), or ``direction(t)`` (a driven
        clamp, see ``SlopeDirection``).  With a body point ``position``: a direction in the
        body frame (default: the node's initial slope in the body's initial frame).
    position : array_like (3,), callable or body point, optional
        Position (default: the node's initial position), ``position(t)``, or a rigid-body
        point (``RigidBody.point``): the clamp then moves with the body (an exit guide on a
        hub), see ``BodySlope``.
    velocity, acceleration : callable, optional
        Exact derivatives of a driven ``position`` (None with a body point).
    slope : {"direction", "full"}
        What of the slope is fixed: its direction (default) or the whole vector.  With
        ``"full"``, ``direction`` is the slope vector ``r_x`` itself (not normalized;
        default the node's initial slope) or a callable ``direction(t)`` (a driven slope,
        derivatives by ``time_derivatives``); a body point is refused.

    Returns
    -------
    list of constraints
        One ``LinearConstraint`` of five equations (labels ``Fx, Fy, Fz, M1, M2``); with a
        callable ``direction``, the position (three) and a ``SlopeDirection`` (two); with a
        body point, its ``pin`` (three) and a ``BodySlope`` (two); with ``slope="full"``,
        one ``LinearConstraint`` of six equations (``Fx, Fy, Fz, Mx, My, Mz``: ``-lambda``
        of the last three is the generalized force on the slope).

    Raises
    ------
    ValueError
        A zero ``direction``, ``velocity``/``acceleration`` given with a body point, a
        ``slope`` other than ``"direction"`` and ``"full"``, or ``"full"`` with a body point.

    See Also
    --------
    System.clamp : adds them to a system.

    Examples
    --------
    A clamp whose root follows a prescribed motion (exact derivatives given):

    >>> import numpy as np, skfem_cable as sc
    >>> from skfem_cable import constraints
    >>> cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], 2, sc.Section.circular(1e-3, 2e11, 7850.0))
    >>> root = lambda t: np.array([0.0, 0.1 * np.sin(t), 0.0])
    >>> (c,) = constraints.clamp(cable.node(0), position=root,
    ...                          velocity=lambda t: np.array([0.0, 0.1 * np.cos(t), 0.0]))
    >>> c.driven, c.offset(0.0, 1)
    (True, array([0. , 0.1, 0. , 0. , 0. ]))
    """
    if not isinstance(node, Node):
        raise TypeError(f"clamp expects a Node (cable.node(i)), got {type(node).__name__}")
    if slope not in ("direction", "full"):
        raise ValueError(f"slope must be 'direction' or 'full', got {slope!r}")
    q0 = node.body.q0[np.concatenate([node.position_dofs, node.slope_dofs])]
    if isinstance(position, BodyPoint):
        if slope == "full":
            raise ValueError("slope='full' clamps to ground or to prescribed motions; a "
                             "clamp to a body point fixes the slope's direction in the body")
        return _body_clamp(node, position, direction, velocity, acceleration)
    labels = ["Fx", "Fy", "Fz"]
    p = q0[:3] if position is None else position
    place = Motion(p, velocity, acceleration, "position")
    if slope == "full":
        r_x = Motion(q0[3:] if direction is None else direction, name="direction")
        return [LinearConstraint(lambda s: s.dofs(node)[:6], np.eye(6),
                                 _stacked(place, r_x), f"clamp {node!r}",
                                 labels + ["Mx", "My", "Mz"])]
    place = LinearConstraint(lambda s: s.dofs(node)[:3], np.eye(3), place,
                             f"clamp {node!r}", labels)
    if callable(direction):
        return [place, SlopeDirection(node, direction)]
    d = _unit(q0[3:] if direction is None else direction, "direction")
    n1, n2 = orthonormal_complement(d)
    J = np.zeros((5, 6))
    J[:3, :3] = np.eye(3)
    J[3, 3:] = n1
    J[4, 3:] = n2
    return [LinearConstraint(lambda s: s.dofs(node)[:6], J,
                             _stacked(place.motion, Motion(np.zeros(2), size=2)),
                             f"clamp {node!r}", labels + ["M1", "M2"])]


def _mapped(combine, size, *motions):
    """``combine`` (linear) of the values of ``motions``, order by order, as one
    ``Motion`` of ``size`` components (a constant vector when none is driven)."""
    if not any(m.driven for m in motions):
        return combine(*(m(0.0) for m in motions))
    return Motion(*(lambda t, k=k: combine(*(m(t, k) for m in motions)) for k in range(3)),
                  name=motions[0].name, size=size)


def _stacked(*motions):
    """The motions one after the other as one ``Motion`` (``_mapped``)."""
    return _mapped(lambda *x: np.concatenate(x), sum(m.size for m in motions), *motions)


def _projected(motion, D):
    """``D x(t)`` of the ``Motion`` ``x``: its components along the rows of ``D``
    (``_mapped``)."""
    return _mapped(lambda x: D @ x, D.shape[0], motion)


def _body_clamp(node, point, direction, velocity, acceleration):
    """The clamp of ``node`` to the body point ``point``: its ``pin`` and a ``BodySlope``
    (``clamp``)."""
    given = [name for name, value in (("velocity", velocity), ("acceleration", acceleration))
             if value is not None]
    if given:
        raise ValueError(f"a clamp to a body point moves with the body: {' and '.join(given)} "
                         "must be None")
    if direction is None:
        body = point.body
        slope = node.body.q0[node.slope_dofs]
        direction = body.rotation(body.q0).T @ slope
    return [pin(node, point), BodySlope(node, point.body, direction)]


class BodySlope(QuadraticConstraints):
    """The slope of a node keeps a direction fixed in a rigid body: ``n_k(d) . r_x = 0``
    for the two unit vectors ``n_k`` orthogonal to the body-frame ``direction``, carried by
    the body (the slope part of a clamp to a body point, ``clamp``).

    In natural coordinates a body-fixed vector is linear in the body's coordinates ``d``:
    ``n_k(d) = (G(x + n_k0) - G(x)) d = N_k d`` for any ``x`` (``G`` is affine in ``x``), so
    each equation is bilinear, ``C_k = r_x^T N_k d = z^T H_k z / 2`` in ``z = [r_x, d]``
    with the constant symmetric ``H_k = [[0, N_k], [N_k^T, 0]]``: the Hessian term is
    ``sum_k lam_k H_k`` and ``(C_q v)_q v = v^T H_k v``, and the compiled hook is the rigid
    body's (``quadratic.QuadraticConstraints`` with zero offsets).

    Parameters
    ----------
    node : Node
    body : RigidBody
    direction : array_like (3,)
        Slope direction in the body frame (non-zero; normalized).

    Attributes
    ----------
    direction : ndarray (3,)
        The unit body-frame direction.
    N : ndarray (2, 3, 12)
        ``N_k``: ``n_k(d) = N_k d``.
    H : ndarray (2, 15, 15)
        ``H_k`` in the coordinates ``[r_x, d]`` (``dofs``).

    Examples
    --------
    >>> import numpy as np, skfem_cable as sc
    >>> from skfem_cable.constraints import BodySlope
    >>> hub = sc.RigidBody.cylinder(radius=1.0, height=0.5, density=100.0)
    >>> tether = sc.Cable.straight([0, 1, 0], [0, 3, 0], 2, sc.Section.circular(1e-3, 7e10, 2700.0))
    >>> guide = BodySlope(tether.node(0), hub, [0, 1, 0])
    >>> guide.N @ hub.q0                    # the normals at the initial pose
    array([[ 0.,  0., -1.],
           [-1.,  0.,  0.]])
    >>> guide.value(np.concatenate([tether.q0[3:6], hub.q0]))
    array([0., 0.])
    """

    def __init__(self, node, body, direction):
        if callable(direction):
            raise TypeError("direction of a clamp to a body point is a body-frame 3-vector, "
                            "not a callable")
        self.node, self.body = node, body
        self.direction = _unit(direction, "direction")
        origin = body.coefficients(np.zeros(3))
        self.N = np.array([np.kron(body.coefficients(n) - origin, np.eye(3))
                           for n in orthonormal_complement(self.direction)])
        self.H = np.zeros((2, 15, 15))
        self.H[:, :3, 3:] = self.N
        self.H[:, 3:, :3] = self.N.transpose(0, 2, 1)
        self.c = np.zeros(2)
        self.name = f"body slope {node!r}-{body.name}"
        self.labels = ["M1", "M2"]

    def dofs(self, system):
        return np.concatenate([system.dofs(self.node)[3:6], system.dofs(self.body)])


def pin(node, target=None, velocity=None, acceleration=None, directions=None):
    """Spherical joint (Eq. 53): the position of ``node`` equals ``target`` (or, with
    ``directions``, equals it along those directions only).

    ``target`` is ``None`` (ground at the node's initial position), a 3-vector (a ground
    point), a callable ``target(t)`` (a ground point moving on a prescribed path, with
    optional exact ``velocity(t)`` and ``acceleration(t)``), another ``Node``, or a
    rigid-body point (``RigidBody.point``): all linear in the coordinates,
    ``C = r_node - G(x) d`` or ``C = r_node - target(t)``.  With ``directions`` (rows
    ``D``, orthonormalized) the equations are ``D C = 0``: one direction keeps the node
    on a plane through the target (normal to it), two on a line (a roller, a slider);
    the node moves freely in the others.

    Parameters
    ----------
    node : Node
    target : None, array_like (3,), callable, Node or body point, optional
    velocity, acceleration : callable, optional
        Exact derivatives of a callable ``target``.
    directions : array_like (k, 3) or (3,), optional
        ``k`` = 1 or 2 independent directions (fixed in space) along which the node is
        held; default all three.

    Returns
    -------
    LinearConstraint
        Three equations, labels ``Fx, Fy, Fz``: ``-lambda`` is the force of the joint on
        the node; with ``directions``, ``k`` equations (labels ``F1``, ``F2``): ``-lambda_j``
        is the force along the ``j``-th orthonormalized direction (``Gram-Schmidt`` of
        the rows, in order).

    Raises
    ------
    ValueError
        ``target`` is ``node`` itself (its equations would vanish), or not a finite point;
        ``directions`` not 1 or 2 independent finite 3-vectors.

    Examples
    --------
    >>> import skfem_cable as sc
    >>> from skfem_cable import constraints
    >>> cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], 2, sc.Section.circular(1e-3, 2e11, 7850.0))
    >>> joint = constraints.pin(cable.node(-1), [1.0, 0.0, 0.0])
    >>> joint.n_eq, joint.value(cable.q0[-6:-3])
    (3, array([0., 0., 0.]))
    """
    if not isinstance(node, Node):
        raise TypeError(f"pin expects a Node (cable.node(i)), got {type(node).__name__}")
    if isinstance(target, Node) and target.body is node.body and target.index == node.index:
        raise ValueError(f"pin {node!r}: target is the node itself; it must be another node "
                         "(of this or another cable), a rigid-body point, a ground point "
                         "(3-vector), a callable of time or None (the ground at the node's "
                         "initial position)")
    D = np.eye(3) if directions is None else _directions(directions)
    labels = ["Fx", "Fy", "Fz"] if directions is None else [f"F{k + 1}" for k in range(len(D))]
    kind = "pin" if directions is None else "sliding pin"
    if target is None or callable(target) or not hasattr(target, "body"):
        if target is None:
            target = node.body.q0[node.body.node_dofs(node.index)[:3]]
        elif not callable(target):
            target = np.asarray(target, dtype=float)
            if target.shape != (3,) or not np.all(np.isfinite(target)):
                raise ValueError("pin target must be a finite 3-vector, a callable of time, "
                                 f"a Node, a body point or None, got {target!r}")
        return LinearConstraint(lambda s: s.dofs(node)[:3], D,
                                _projected(Motion(target, velocity, acceleration, "target"), D),
                                f"{kind} {node!r}", labels)
    G = np.eye(3) if isinstance(target, Node) else target.position_matrix
    J = D @ np.hstack([np.eye(3), -G])

    def dofs(s):
        return np.concatenate([s.position_map(node)[0], s.position_map(target)[0]])

    return LinearConstraint(dofs, J, np.zeros(len(D)), f"{kind} {node!r}-{target!r}",
                            labels)


def _directions(directions):
    """``pin``'s ``directions`` as orthonormal rows (Gram-Schmidt, in order)."""
    D = np.atleast_2d(np.asarray(directions, dtype=float))
    if D.ndim != 2 or D.shape[1] != 3 or not 1 <= len(D) <= 2 or not np.all(np.isfinite(D)):
        raise ValueError("directions must be one or two finite 3-vectors (k, 3), k in [1, 2] "
                         f"(three directions: leave directions out), got {directions!r}")
    Q, R = np.linalg.qr(D.T)
    if np.min(np.abs(np.diag(R))) <= 1e-12 * np.max(np.abs(D)):
        raise ValueError(f"directions must be independent, got {D.tolist()}")
    return (Q * np.sign(np.diag(R))).T


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
    for other in system.constraints:
        if not other.linear:
            continue
        other_dofs, other_J = _distinct_jacobian(system, other, q0)
        if np.intersect1d(dofs, other_dofs).size and _dependent(dofs, J, other_dofs, other_J):
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


def _dependent(dofs, J, other_dofs, other_J):
    """True if the rows of ``J`` (on ``dofs``) and of ``other_J`` together have a smaller
    rank than ``other_J``'s plus the rows of ``J``."""
    union = np.union1d(dofs, other_dofs)
    stacked = np.zeros((len(J) + len(other_J), union.size))
    stacked[:len(J), np.searchsorted(union, dofs)] = J
    stacked[len(J):, np.searchsorted(union, other_dofs)] = other_J
    rank = np.linalg.matrix_rank
    return rank(stacked) < rank(other_J) + len(J)
