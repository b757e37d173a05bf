"""Surfaces carried by a rigid body (``body.plane``, ``body.sphere``, ``body.cylinder``):
given in the body's frame, they move with it.  A line body touching one
(``system.contact(cable, body.cylinder(...))``) is coupled with the body's coordinates
(``loads.contact_body``, ``kernels.contact_body``).

The body's natural coordinates ``d`` (``bodies.rigid``, Eqs. 39-41, 131-132) carry the
surface's point linearly, ``o = G(x_o) d``, and its direction, ``a = C_B^I a_0 =
sum_k b_k (r_{k+1} - r_A)`` with ``b = B0^-1 a_0``: ``[o; a] = B d``, ``B`` (6, 12)
constant (``maps``).

Examples
--------
>>> import skfem_cable as sc
>>> plate = sc.RigidBody.cylinder(radius=0.5, height=0.1, density=100.0, position=[0, 0, 1])
>>> top = plate.plane([0.05, 0, 0], [1, 0, 0])       # its face, in the body's frame
>>> top.surface_array().tolist()                      # where it is at the body's q0
[0.0, 0.05, 0.0, 1.0, 1.0, 0.0, 0.0, 0.0]
>>> top.distance([[1.0, 0.0, 1.0]]).tolist()
[0.95]
"""

import numpy as np

from ..kernels import contact as kernel
from .section import check_positive, unit, vector3


class BodySurface:
    """The surface of kind ``kind`` (``kernels.contact``: ``PLANE``, ``SPHERE``,
    ``CYLINDER``) through the body-frame point ``origin`` along the body-frame unit
    ``direction`` (zero for a sphere), of ``radius`` (0 for a plane), carried by the rigid
    body ``body``.

    It declares the ``protocols.Surface`` hooks at the body's coordinates (default its
    ``q0``) and ``body``, the body whose coordinates a contact with it couples
    (``model.contact``).
    """

    def __init__(self, body, kind, origin, direction, radius):
        self.body, self.kind = body, kind
        self.origin, self.direction, self.radius = origin, direction, radius

    def maps(self):
        """``B`` (6, 12): ``[o; a] = B d`` (module notes)."""
        B = np.zeros((6, 12))
        B[:3] = self.body.G(self.origin)
        b = self.body.B0inv @ self.direction
        for k in range(3):
            B[3:, :3] -= b[k] * np.eye(3)
            B[3:, 3 * (k + 1):3 * (k + 2)] += b[k] * np.eye(3)
        return B

    def surface_array(self, d=None):
        """``[kind, o, a, radius]`` (``kernels.contact``) where the body's coordinates
        ``d`` (12,; default its ``q0``) put the surface."""
        d = self.body.q0 if d is None else np.asarray(d, dtype=float)
        return np.concatenate([[self.kind], self.maps() @ d, [self.radius]])

    def distance(self, x, d=None):
        """Signed distance (m) of the points ``x`` (n, 3) from the surface where the
        body's coordinates ``d`` (default its ``q0``) put it (negative inside)."""
        x = np.atleast_2d(np.asarray(x, dtype=float))
        out = np.empty(len(x))
        kernel.distances(self.surface_array(d), np.ascontiguousarray(x), out)
        return out

    def __repr__(self):
        kind = {kernel.PLANE: "plane", kernel.SPHERE: "sphere",
                kernel.CYLINDER: "cylinder"}[self.kind]
        return (f"{self.body.name}.{kind}({self.origin.tolist()}, "
                f"{self.direction.tolist()}, {self.radius})")


def plane(body, point, normal):
    """The plane through the body-frame ``point`` of body-frame ``normal`` (made unit),
    carried by ``body``; its outside is on the side the normal points to."""
    return BodySurface(body, kernel.PLANE, vector3(point, "point"), unit(normal, "normal"),
                       0.0)


def sphere(body, centre, radius):
    """The sphere of body-frame ``centre`` and ``radius`` (m, > 0), carried by ``body``."""
    return BodySurface(body, kernel.SPHERE, vector3(centre, "centre"), np.zeros(3),
                       check_positive("radius", radius))


def cylinder(body, axis_point, axis, radius):
    """The outside of the infinite cylinder of body-frame axis through ``axis_point``
    along ``axis`` (made unit) and ``radius`` (m, > 0), carried by ``body``: a drum, a
    pulley's sheave."""
    return BodySurface(body, kernel.CYLINDER, vector3(axis_point, "axis_point"),
                       unit(axis, "axis"), check_positive("radius", radius))


class ClassOrInstance:
    """A method that is ``on_class`` when called on the class and ``on_instance`` on an
    instance: ``RigidBody.cylinder(radius, height, density)`` builds a body,
    ``body.cylinder(axis_point, axis, radius)`` a surface carried by it."""

    def __init__(self, on_class, on_instance):
        self.on_class, self.on_instance = on_class, on_instance
        self.__doc__ = on_class.__doc__

    def __get__(self, instance, owner):
        if instance is None:
            return self.on_class.__get__(owner, owner)
        return self.on_instance.__get__(instance, owner)
