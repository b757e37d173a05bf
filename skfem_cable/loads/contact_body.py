"""Contact of a line body with a surface carried by a rigid body (``body.plane``,
``body.sphere``, ``body.cylinder``; ``bodies.rigid_surfaces``): the line's and the body's
coordinates are coupled (``kernels.contact_body``: the method and its exact tangents).

* The penalty is a potential ``Pi(x, o(d), a(d))`` of the line's points and the body's
  natural coordinates ``d``: the force on the line is ``-dPi/dx``, on the body
  ``-dPi/dd``, equal and opposite with its moment for every rigid motion; the tangent is
  symmetric over the line's and the body's coordinates; the books hold ``Pi`` as stored
  energy (an internal force of the two bodies, ``contract.AXIAL``).
* The normal damping and the friction act on the velocity of the line relative to the
  body's material point at ``x``; the force on the body is minus the one on the line, at
  that point; its work is booked as dissipation.
* Stiffness, onset, damping, regularisation, tolerance and the broad phase are those of
  ``loads.contact`` (its ``LineSurfaceContact``); the broad phase reads the surface where
  the body is at the last accepted state, and the points' speeds relative to the body.
* The tangent pattern is the block of each element's coordinates and the body's 12.
"""

import numpy as np

from ..core.contract import Term
from ..core.lines import line_points
from ..kernels import contact as surface_kernel
from ..kernels import contact_body as kernel
from .contact import LineSurfaceContact
from .surface_broad_phase import BroadPhase


class LineBodyContact(LineSurfaceContact):
    """Contact of the line body ``line`` with ``surface``, a surface carried by a rigid
    body (``surface.body``), with Coulomb friction (module notes); the parameters are
    those of ``LineSurfaceContact``.  ``forces`` and ``resolve`` give the forces of the
    surface on the line's elements (the body gets their opposites)."""

    def __init__(self, line, surface, friction=0.0, **options):
        super().__init__(line, surface, friction, **options)
        self.body = surface.body

    def tables(self, system):
        """``(points, udofs, bdofs)``: the line's points, each element's coordinates with
        the body's after them (ne, nd) and the body's (12,)."""
        points = line_points(self.cable, system)
        bdofs = np.asarray(system.dofs(self.body), dtype=np.int64)
        ne = points.shape[0]
        udofs = np.hstack([points.edofs, np.broadcast_to(bdofs, (ne, 12))])
        return points, np.ascontiguousarray(udofs), bdofs

    def bind(self, system):
        """The compiled term (``kernels.contact_body.kernel``) on the blocks of the
        elements' and the body's coordinates, with the broad phase of
        ``loads.surface_broad_phase`` at the body's accepted state."""
        points, udofs, bdofs = self.tables(system)
        broad = BroadPhase(points, None, self.radius, self.tolerance * 2.0 * self.radius,
                           self.onset, self.cable.name,
                           seen=lambda q, v, X, V: self.seen(system, q, v, X, V))
        scale = broad.scale if self.broad_phase else np.ones(points.shape[0])
        coef = np.append(self.coefficients(surface_kernel.ELASTIC), self.surface.radius)
        pack = (udofs, points.S, points.w, scale, self.surface.maps(),
                float(self.surface.kind), coef)
        self.broad = broad
        return Term(kernels=((kernel.kernel, pack),), rows=udofs[:, :, None],
                    cols=udofs[:, None, :], name=f"contact {self.cable.name}",
                    prepare=broad.prepare, hooks=(broad,),
                    outputs=lambda: self.step_values(system, points, broad.q, broad.v))

    def seen(self, system, q, v, X, V):
        """``(surface, V)``: the surface where the body's coordinates in ``q`` put it, and
        the velocities ``V`` (m, 3) of the points ``X`` relative to the body's material
        points there (``kernels.contact_body.relative_velocities``)."""
        bdofs = system.dofs(self.body)
        d = np.ascontiguousarray(q[bdofs], dtype=float)
        dd = np.zeros(12) if v is None else np.ascontiguousarray(v[bdofs], dtype=float)
        relative = np.empty_like(V)
        kernel.relative_velocities(d, dd, np.ascontiguousarray(X), np.ascontiguousarray(V),
                                   relative)
        return self.surface.surface_array(d), relative
