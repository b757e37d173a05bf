"""Rigid body in natural coordinates (paper Sect. 2.3 and Appendix B).

The coordinates are the global positions of four non-coplanar base points,
``d = [r_1, r_2, r_3, r_4]`` (Eq. 40).  Any body point with local coordinates ``x`` is the
affine combination ``r = G(x) d`` (Eqs. 39, 131-132), the mass matrix
``M = int rho G^T G dV`` (Eq. 52) is constant, and six quadratic internal constraints keep
the base points rigid (Eqs. 45-49).

Examples
--------
>>> import skfem_cable as sc
>>> hub = sc.RigidBody.cylinder(radius=1.0, height=2.0, density=884.0)
>>> hub.n_dofs, [c.n_eq for c in hub.internal_constraints()]
(12, [6])
"""

import numpy as np
import scipy.sparse as sp

from ..core.contract import PART_RIGID, Shape
from ..core.quadratic import QuadraticConstraints
from . import rigid_surfaces as surfaces
from .section import check_positive

#: Pairs of edge vectors ``(a, b)`` of the six internal constraints ``r_a . r_b = const``
#: with ``r_1 = r_B - r_A``, ``r_2 = r_C - r_A``, ``r_3 = r_D - r_A`` (Eq. 45 order).
CONSTRAINT_PAIRS = ((0, 0), (1, 1), (2, 2), (1, 0), (2, 0), (2, 1))


def _edge_operators():
    """``D_k`` (3 x 12) with ``r_k = D_k d`` for the three edges from base point A."""
    D = np.zeros((3, 3, 12))
    for k in range(3):
        D[k, :, :3] = -np.eye(3)
        D[k, :, 3 * (k + 1): 3 * (k + 2)] = np.eye(3)
    return D


EDGES = _edge_operators()


class BodyPoint:
    """A material point of a rigid body: ``position = position_matrix @ d``.

    Attributes
    ----------
    body : RigidBody
    x : ndarray (3,)
        Body-frame coordinates (m).
    position_matrix : ndarray (3, 12)
        ``G(x)``.
    """

    def __init__(self, body, x):
        self.body = body
        self.x = np.asarray(x, dtype=float)
        self.position_matrix = body.G(self.x)

    def __repr__(self):
        return f"{self.body.name}.point({np.array2string(self.x, precision=4)})"


class RigidBody:
    """Rigid body described by four base points (natural coordinates).

    Parameters
    ----------
    mass : float
        Mass (kg).
    center_of_mass : array_like (3,)
        Centre of mass in the body frame B (m).
    inertia : array_like (3, 3)
        Inertia tensor about the centre of mass, body axes (kg m^2).
    base_points : array_like (4, 3)
        Body-frame coordinates of the base points A, B, C, D (non-coplanar).
    position, rotation : array_like
        Initial position of the body-frame origin and rotation matrix ``C_B^I``
        (body to inertial, default identity), defining the initial coordinates.
    name : str

    Attributes
    ----------
    mass, center_of_mass, inertia, name
        As given.
    base_points : ndarray (4, 3)
        As given, read-only: they define the coordinates (``q0``), the internal
        constraints and the points made by ``point``, so that an edit after construction
        is refused (build another body).
    q0 : ndarray (12,)
        Initial coordinates ``d = [r_A, r_B, r_C, r_D]`` (inertial frame).
    n_dofs : int
        12.
    position_mask : bool ndarray (12,)
        All True: every coordinate is a position.
    radius, height : float
        Of a ``cylinder``.

    See Also
    --------
    System.pin : ``pin(cable.node(0), body.point(x))`` joins a cable to the body.
    plane, sphere, cylinder : surfaces in the body's frame that move with it, for
        ``system.contact(cable, body.cylinder(...))`` (``rigid_surfaces``).

    Examples
    --------
    The E-sail's hub with a tether pinned to its rim:

    >>> import numpy as np, skfem_cable as sc
    >>> hub = sc.RigidBody.cylinder(radius=1.0, height=2.0, density=884.0)
    >>> round(hub.mass, 1), hub.q0.reshape(4, 3)[:, 0].tolist()
    (5554.3, [-1.0, 1.0, 0.0, 0.0])
    >>> sec = sc.Section.circular(1e-3, 7e10, 2700.0)
    >>> tether = sc.Cable.straight([0, 1, 0], [0, 11, 0], 4, sec)
    >>> system = sc.System([hub, tether]).pin(tether.node(0), hub.point([0, 1, 0]))
    >>> system.n_dofs, system.n_constraints
    (42, 9)
    >>> hub.positions(hub.q0, np.array([0.0, 0.0, 1.0])), float(hub.rotation(hub.q0).trace())
    (array([0., 0., 1.]), 3.0)
    """

    #: ``contract.Body.energy_parts``: none (rigid).
    energy_parts = ()

    def __init__(self, mass, center_of_mass, inertia, base_points, position=(0, 0, 0),
                 rotation=None, name="body"):
        self.mass = check_positive("mass", mass)
        self.center_of_mass = np.asarray(center_of_mass, dtype=float)
        self.inertia = np.asarray(inertia, dtype=float)
        P = np.array(base_points, dtype=float)  # a copy: made read-only below
        if P.shape != (4, 3):
            raise ValueError(f"base_points must have shape (4, 3), got {P.shape}")
        B0 = (P[1:] - P[0]).T
        if abs(np.linalg.det(B0)) < 1e-12 * np.abs(B0).max() ** 3:
            raise ValueError("base_points must not be coplanar")
        if self.inertia.shape != (3, 3) or not np.allclose(self.inertia, self.inertia.T):
            raise ValueError("inertia must be a symmetric 3 x 3 matrix")
        second = 0.5 * np.trace(self.inertia) * np.eye(3) - self.inertia
        if np.any(np.linalg.eigvalsh(second) <= 0):
            raise ValueError("inertia must satisfy the strict triangle inequalities "
                             "I_a + I_b > I_c (a flat or slender body has a singular mass "
                             "matrix in natural coordinates)")
        self.name = name
        self._base_points = P
        P.flags.writeable = False
        self.B0inv = np.linalg.inv(B0)
        R = np.eye(3) if rotation is None else np.asarray(rotation, dtype=float)
        if not np.allclose(R.T @ R, np.eye(3), atol=1e-12) or np.linalg.det(R) < 0:
            raise ValueError("rotation must be a proper rotation matrix")
        self.q0 = (np.asarray(position, dtype=float) + P @ R.T).ravel()
        self.element_dofs = np.arange(12, dtype=np.int64)[None, :]
        self.radius = self.height = None  # a cylinder's (``cylinder``), for its surface
        self._mass = None

    def _cylinder_body(cls, radius, height, density, position=(0, 0, 0), rotation=None,
                       name="hub"):
        """Homogeneous cylinder with its axis along the body x axis, centred at the origin;
        base points ``A = (-h/2, 0, 0)``, ``B = (h/2, 0, 0)``, ``C = (0, R, 0)``,
        ``D = (0, 0, R)`` as in the paper (Sect. 4.1)."""
        R = check_positive("radius", radius)
        h = check_positive("height", height)
        m = check_positive("density", density) * np.pi * R**2 * h
        inertia = np.diag([m * R**2 / 2, m * (3 * R**2 + h**2) / 12, m * (3 * R**2 + h**2) / 12])
        P = np.array([[-h / 2, 0, 0], [h / 2, 0, 0], [0, R, 0], [0, 0, R]])
        body = cls(m, np.zeros(3), inertia, P, position, rotation, name)
        body.radius, body.height = R, h
        return body

    def _cylinder_surface(self, axis_point, axis, radius):
        """The outside of the cylinder of body-frame axis through ``axis_point`` along
        ``axis`` and ``radius`` (m, > 0), moving with the body: a drum, a pulley
        (``rigid_surfaces.cylinder``; ``system.contact(cable, body.cylinder(...))``)."""
        return surfaces.cylinder(self, axis_point, axis, radius)

    #: ``RigidBody.cylinder(radius, height, density, ...)``: a homogeneous cylinder body;
    #: ``body.cylinder(axis_point, axis, radius)``: a cylindrical surface carried by
    #: ``body`` (``rigid_surfaces.ClassOrInstance``).
    cylinder = surfaces.ClassOrInstance(classmethod(_cylinder_body), _cylinder_surface)

    def sphere(self, centre, radius):
        """The sphere of body-frame ``centre`` and ``radius`` (m, > 0), moving with the
        body (``rigid_surfaces.sphere``)."""
        return surfaces.sphere(self, centre, radius)

    def plane(self, point, normal):
        """The plane through the body-frame ``point`` of body-frame ``normal``, moving
        with the body: a plate, a deck (``rigid_surfaces.plane``)."""
        return surfaces.plane(self, point, normal)

    @property
    def base_points(self):
        """Body-frame coordinates of the base points A, B, C, D (4, 3), read-only."""
        return self._base_points

    @base_points.setter
    def base_points(self, value):
        raise AttributeError(
            f"base_points of the rigid body {self.name!r} cannot change after construction: "
            "they define its coordinates (q0), its internal constraints and the points "
            "made by point() for joints and loads, which would keep the old ones; build "
            "another RigidBody with base_points=... (an array (4, 3) of non-coplanar "
            "points)")

    # --- layout -------------------------------------------------------------------------
    n_dofs = 12

    @property
    def position_mask(self):
        """All True: every coordinate is a position."""
        return np.ones(12, dtype=bool)

    def describe_dof(self, index):
        return f"base point {'ABCD'[index // 3]} component {index % 3}"

    def internal_constraints(self):
        return [RigidConstraints(self)]

    # --- kinematics (Eqs. 39, 41, 64, 128-134) -----------------------------------------
    def coefficients(self, x):
        """``g_1 .. g_4`` of Eq. 132 at body-frame points ``x`` (..., 3)."""
        c = (np.asarray(x, dtype=float) - self.base_points[0]) @ self.B0inv.T
        return np.concatenate([1.0 - c.sum(axis=-1, keepdims=True), c], axis=-1)

    def G(self, x):
        """``G(x) = [g_1 I, g_2 I, g_3 I, g_4 I]`` (Eq. 131), shape (3, 12)."""
        return np.kron(self.coefficients(x)[None, :], np.eye(3))

    def point(self, x):
        """The body point with body-frame coordinates ``x`` (for joints and loads)."""
        return BodyPoint(self, x)

    def positions(self, d, x):
        """Global positions of body-frame points ``x`` (..., 3) for coordinates ``d``
        (..., 12) (leading axes of ``d``: e.g. time)."""
        g = self.coefficients(x)
        return np.einsum("...k,tki->t...i", g, np.asarray(d).reshape(-1, 4, 3)).reshape(
            np.shape(d)[:-1] + np.shape(x))

    def rotation(self, d):
        """``C_B^I`` (body to inertial, Eq. 41): ``[r_AB r_AC r_AD] B0^-1``; (..., 3, 3)."""
        d = np.asarray(d).reshape(np.shape(d)[:-1] + (4, 3))
        edges = np.swapaxes(d[..., 1:, :] - d[..., :1, :], -1, -2)
        return edges @ self.B0inv

    def angular_velocity(self, d, v):
        """Body-frame angular velocity ``omega^B`` (Eq. 64), (..., 3)."""
        R = self.rotation(d)
        W = np.swapaxes(R, -1, -2) @ self.rotation(v)
        return 0.5 * np.stack([W[..., 2, 1] - W[..., 1, 2], W[..., 0, 2] - W[..., 2, 0],
                               W[..., 1, 0] - W[..., 0, 1]], axis=-1)

    # --- inertia and loads (Eq. 52) --------------------------------------------------------
    def affine_map(self):
        """``A`` with ``g(x) = A [1, x]``."""
        A = np.zeros((4, 4))
        c0 = self.B0inv @ self.base_points[0]
        A[1:, 0] = -c0
        A[1:, 1:] = self.B0inv
        A[0, 0] = 1 + c0.sum()
        A[0, 1:] = -self.B0inv.sum(axis=0)
        return A

    def mass_matrix(self):
        """``M = int rho G^T G dV = (A Phi A^T) (x) I_3`` with the body's zeroth, first and
        second mass moments ``Phi`` (exact for any mass distribution); computed again when
        ``mass``, ``center_of_mass``, ``inertia`` or ``base_points`` changed."""
        key = (float(self.mass), *(np.asarray(x, dtype=float).tobytes() for x in (
            self.center_of_mass, self.inertia, self.base_points)))
        if self._mass is None or self._mass[0] != key:
            m, c = self.mass, self.center_of_mass
            second = (0.5 * np.trace(self.inertia) * np.eye(3) - self.inertia
                      + m * np.outer(c, c))
            Phi = np.block([[np.array([[m]]), m * c[None, :]], [m * c[:, None], second]])
            A = self.affine_map()
            self._mass = (key, sp.csr_matrix(np.kron(A @ Phi @ A.T, np.eye(3))))
        return self._mass[1]

    def mass_points(self):
        """Where the mass is (the hook ``orbit_gravity`` reads): six points of mass
        ``m / 6`` at ``c +- sqrt(3 s_k / m) e_k`` on the principal axes ``e_k`` of the
        second moment ``S = tr(J) / 2 I - J = sum_k s_k e_k e_k^T``; they have the body's
        mass, centre of mass and second moments.  Returns ``(vectors (6, 4), coefficients
        (6, 4), mass (6,))``: a point at ``sum_j g_j(x) r_j`` over the base points (Eq.
        132)."""
        second = 0.5 * np.trace(self.inertia) * np.eye(3) - self.inertia
        s, axes = np.linalg.eigh(0.5 * (second + second.T))
        arms = axes * np.sqrt(3.0 * np.clip(s, 0.0, None) / self.mass)
        x = self.center_of_mass + np.concatenate([arms.T, -arms.T])
        return np.tile(np.arange(0, 12, 3), (6, 1)), self.coefficients(x), \
            np.full(6, self.mass / 6)

    def bind(self, system):
        """No internal forces: a rigid body's coordinates are held by its
        ``internal_constraints``."""
        return None

    # --- what it shows (contract.Body) ------------------------------------------------------
    def surface(self, resolution=32):
        """Body-frame surface: the cylinder of ``RigidBody.cylinder`` (``resolution``
        segments around), or else the tetrahedron of the base points, as ``points``
        (n, 3) and outward-oriented ``triangles``."""
        if self.radius is not None:
            return cylinder_surface(self.radius, self.height, resolution)
        points = self.base_points
        faces = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
        centre = points.mean(axis=0)
        for f in faces:
            a, b, c = points[f]
            if np.cross(b - a, c - a) @ (a - centre) < 0:
                f[[1, 2]] = f[[2, 1]]
        return points, faces

    def show(self, system, q, v, t, resolution=32, **detail):
        """``Body.show``: its ``surface`` moving with it (``triangle`` cells)."""
        dofs = system.dofs(self)
        x, triangles = self.surface(resolution)
        return Shape(self.positions(q[dofs], x), self.positions(v[dofs], x), "triangle",
                     triangles, PART_RIGID)

    def outputs(self, system, q, t):
        """``Body.outputs``: the position of the centre of mass (m) and the rotation
        matrix (body to inertial)."""
        d = q[system.dofs(self)]
        return {"center_of_mass": self.positions(d, self.center_of_mass),
                "rotation": self.rotation(d)}


def cylinder_surface(radius, height, resolution=32):
    """Closed triangulated cylinder with its axis along ``x``, centred at the origin.

    Returns ``points`` (2 resolution + 2, 3) and outward-oriented ``triangles``
    (4 resolution, 3): the side wall and two caps fanned from their centres.
    """
    n = int(resolution)
    if n != resolution or n < 3:
        raise ValueError(f"resolution must be an integer >= 3, got {resolution!r}")
    th = 2 * np.pi * np.arange(n) / n
    ring = np.column_stack([np.zeros(n), radius * np.cos(th), radius * np.sin(th)])
    bottom, top = ring - [height / 2, 0, 0], ring + [height / 2, 0, 0]
    points = np.vstack([bottom, top, [[-height / 2, 0, 0], [height / 2, 0, 0]]])
    k, k1 = np.arange(n), (np.arange(n) + 1) % n
    cb, ct = np.full(n, 2 * n), np.full(n, 2 * n + 1)
    return points, np.vstack([np.column_stack([k, k1, n + k1]),
                              np.column_stack([k, n + k1, n + k]),
                              np.column_stack([cb, k1, k]),
                              np.column_stack([ct, n + k, n + k1])])


class RigidConstraints(QuadraticConstraints):
    """The six internal constraints of Eq. 45, each divided by a reference length so that
    its residual is in metres: ``C_j = (r_a . r_b - r_a0 . r_b0) / s_j`` with
    ``s_j = sqrt(|r_a0| |r_b0|)``.  Quadratic: constant Hessians ``H_j`` give the
    ``d(C_q^T lambda)/dq`` term (Eqs. 47-49) and the ``(C_q v)_q v`` term of Eq. 2
    (``quadratic.QuadraticConstraints``)."""

    def __init__(self, body):
        self.body = body
        self.name = f"rigid {body.name}"
        self.labels = ["AB.AB", "AC.AC", "AD.AD", "AC.AB", "AD.AB", "AD.AC"]
        d0 = body.q0
        edges0 = EDGES @ d0
        self.H = np.zeros((6, 12, 12))
        self.c = np.zeros(6)
        for j, (a, b) in enumerate(CONSTRAINT_PAIRS):
            s = np.sqrt(np.linalg.norm(edges0[a]) * np.linalg.norm(edges0[b]))
            self.H[j] = (EDGES[a].T @ EDGES[b] + EDGES[b].T @ EDGES[a]) / s
            self.c[j] = 0.5 * d0 @ self.H[j] @ d0

    def dofs(self, system):
        return system.dofs(self.body)
