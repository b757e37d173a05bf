"""Clamps and pins between nodes, body points and the ground, and a body's slope guide
(``BodySlope``)."""

import numpy as np

from ..bodies.rigid import BodyPoint
from ..core.node import Node
from ..core.quadratic import QuadraticConstraints
from .linear import LinearConstraint, SlopeDirection, _unit, orthonormal_complement
from .prescribed import Motion
from .twist_tie import TwistTie


def clamp(node, direction=None, position=None, velocity=None, acceleration=None,
          slope="direction", twist=True):
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
    twist : bool or callable
        On a node with a twist (a rod's, ``Node.has_twist``): True (default) holds its
        twist angle at its initial value, False leaves it free, a callable ``twist(t)``
        (rad) drives it (one more equation, label ``T``: ``-lambda`` is the torque on
        the twist).  With a body point ``position``, True ties the twist to the body's
        rotation about the tangent (``TwistTie``: the clamp transmits torque), False
        leaves it free; a callable is refused.  Ignored on a node without twist.

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
    held = _twist(node, twist, position)
    return _clamp(node, direction, position, velocity, acceleration, slope) + held


def _twist(node, twist, position):
    """The twist equation of a clamp (``clamp``): none on a node without twist or with
    ``twist=False``; with a body point ``position``, the tie to the body (``TwistTie``)."""
    if not node.has_twist or twist is False:
        return []
    if isinstance(position, BodyPoint):
        if twist is not True:
            raise ValueError(f"twist: a clamp of {node!r} to a rigid body ties the twist "
                             f"to the body (True) or leaves it free (False), got {twist!r}")
        return [TwistTie(node, position.body)]
    return [hold_twist(node, twist)]


def hold_twist(node, twist=True):
    """The twist angle of a rod's node held at its initial value (``twist=True``) or
    driven, ``twist(t)`` (rad): one equation, label ``T`` (``-lambda`` is the torque on
    the twist, whose moment is semi-tangential, ``loads.TwistTorque``).  With ``pin``, a
    hinge that holds the twist (Greenhill's shaft, ``docs/rods.md``); ``clamp`` adds it.

    Parameters
    ----------
    node : Node
        A rod's node (``Node.has_twist``).
    twist : True or callable

    Returns
    -------
    LinearConstraint

    Examples
    --------
    >>> import skfem_cable as sc
    >>> from skfem_cable import constraints
    >>> rod = sc.Rod.straight([0, 0, 0], [1, 0, 0], 2, sc.Section.circular(1e-3, 2e11, 7850.0))
    >>> constraints.hold_twist(rod.node(0)).labels
    ['T']
    """
    if twist is not True and not callable(twist):
        raise ValueError(f"twist must be True, False or a callable twist(t) (rad), got "
                         f"{twist!r}")
    motion = Motion(lambda t: np.atleast_1d(twist(t)), name="twist", size=1) \
        if callable(twist) else node.body.q0[node.twist_dofs]
    return LinearConstraint(lambda s: s.dofs(node.body)[node.twist_dofs], np.eye(1), motion,
                            f"twist {node!r}", ["T"])


def _clamp(node, direction, position, velocity, acceleration, slope):
    """The position and slope equations of ``clamp``."""
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
    >>> from skfem_cable.constraints.joints import BodySlope
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
