"""Fixed rigid surfaces that line bodies touch (``system.contact``): a plane, a sphere,
the outside of a cylinder, a table top ending in a rounded edge.  Each declares the
``protocols.Surface`` hooks:
``surface_array()`` for the compiled contact (``kernels.contact``) and ``distance(x)``.

Examples
--------
>>> import skfem_cable as sc
>>> drum = sc.Cylinder([0, 0, 0], [0, 0, 1], radius=0.5)
>>> drum.distance([[1.0, 0, 3.0], [0, 0.25, 0]]).tolist()
[0.5, -0.25]
>>> sc.Plane([0, 0, -1], [0, 0, 2]).distance([[5.0, 1.0, 0.0]]).tolist()
[1.0]
"""

import numpy as np

from ..bodies.section import check_positive, unit, vector3
from ..kernels import contact as kernel


class Surface:
    """A fixed surface of kind ``kind`` (``kernels.contact``): the point ``origin``, the
    unit ``direction`` and the ``radius`` (0 for a plane)."""

    kind = None

    def __init__(self, origin, direction, radius):
        self.origin, self.direction, self.radius = origin, direction, radius

    def surface_array(self):
        """``[kind, origin, direction, radius]`` for ``kernels.contact``."""
        return np.array([self.kind, *self.origin, *self.direction, self.radius])

    def distance(self, x):
        """Signed distance (m) of the points ``x`` (n, 3) from the surface (negative
        inside), by the kernel's own ``distance``."""
        x = np.atleast_2d(np.asarray(x, dtype=float))
        out = np.empty(len(x))
        kernel.distances(self.surface_array(), np.ascontiguousarray(x), out)
        return out

    def __repr__(self):
        return (f"{type(self).__name__}({self.origin.tolist()}, {self.direction.tolist()}"
                f", {self.radius})")


class Plane(Surface):
    """The plane through ``point`` of normal ``normal`` (made unit); its outside is on the
    side the normal points to."""

    kind = kernel.PLANE

    def __init__(self, point, normal):
        super().__init__(vector3(point, "point"), unit(normal, "normal"), 0.0)


class Sphere(Surface):
    """The sphere of centre ``centre`` and radius ``radius`` (m, > 0)."""

    kind = kernel.SPHERE

    def __init__(self, centre, radius):
        super().__init__(vector3(centre, "centre"), np.zeros(3),
                         check_positive("radius", radius))


class Cylinder(Surface):
    """The outside of the infinite cylinder of axis through ``axis_point`` along ``axis``
    (made unit) and radius ``radius`` (m, > 0): a drum, a pulley, a guide."""

    kind = kernel.CYLINDER

    def __init__(self, axis_point, axis, radius):
        super().__init__(vector3(axis_point, "axis_point"), unit(axis, "axis"),
                         check_positive("radius", radius))


class Edge(Surface):
    """A table top ending in a rounded edge: the plane through ``point`` of normal
    ``normal`` (made unit) for the points behind the edge, the line through ``point``
    across ``outward`` (a direction in the plane pointing off the table, made unit),
    rounded by a cylinder of radius ``radius`` (m, > 0) whose top is that line
    (``kernels.contact``, ``EDGE``): a rope lying on a table and hanging over its edge.
    Its distance is that of the solid above the rounding cylinder's axis; the table's
    front face below the edge is not modelled (a hanging rope does not reach it)."""

    kind = kernel.EDGE

    def __init__(self, point, normal, outward, radius):
        normal = unit(normal, "normal")
        outward = unit(outward, "outward")
        if abs(float(normal @ outward)) > 1e-12:
            raise ValueError(f"outward must be perpendicular to normal, got outward "
                             f"{outward.tolist()} and normal {normal.tolist()}")
        super().__init__(vector3(point, "point"), normal, check_positive("radius", radius))
        self.outward = outward

    def surface_array(self):
        """``[kind, o, d, R, e, c, a]`` for ``kernels.contact`` (its ``EDGE``)."""
        centre = self.origin - self.radius * self.direction
        return np.concatenate([super().surface_array(), self.outward, centre,
                               np.cross(self.direction, self.outward)])

    def __repr__(self):
        return (f"Edge({self.origin.tolist()}, {self.direction.tolist()}, "
                f"{self.outward.tolist()}, {self.radius})")
