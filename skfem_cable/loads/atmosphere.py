"""Atmospheric drag in orbit with a density model: ``AtmosphericDrag`` on a cable (any line
body) or on a rigid body or a point (``PointDrag``); the density is sampled once per step
by ``sampling.DensitySampler``, shared with ``FreeMolecularDrag``.

The neutral atmosphere co-rotates with the Earth: the flow a body meets is
``v_r = V + v - omega_E x (R + x)`` at the absolute position ``R(t) + x`` (``drag.Flow``:
the reference point ``R``, ``V`` of a system in orbit and its offsets ``x``, ``v``).  A
density model (``environment.MSIS``, or any object with ``density(x, t)`` at absolute
positions, in kg/m^3) is evaluated once per time step at every point of the body,
never in the Newton iterations: the density is *frozen over the step*, at the positions
predicted for the step's end from the last accepted state (``x_n + h v_n``, a step hook of
the term: ``DensitySampler``), so the tangent with respect to the velocities is exact and
the one with respect to the positions omits ``d rho / dx`` (the density's scale height,
tens of km in low orbit, is far longer than a step's motion relative to the others).

References
----------
1. D. A. Vallado, "Fundamentals of Astrodynamics and Applications", 4th ed., Microcosm
   Press, 2013 (atmospheric drag, ``a = -(1/2) rho (C_D A / m) |v_r| v_r`` with the
   velocity relative to the rotating atmosphere).
2. M. L. Cosmo and E. C. Lorenzini (eds.), "Tethers in Space Handbook", 3rd ed., NASA
   Marshall Space Flight Center, 1997 (``C_D`` about 2.2 in free-molecular flow).
"""

import numpy as np

from ..bodies.section import check_positive
from ..core.contract import Term
from ..environment.epoch import bound_model
from ..kernels import drag as kernel
from .drag import Flow, FreeMolecularDrag
from .knots import spacing_or_none
from .sampling import DensitySampler, density_model, is_model


class PointDrag:
    """Drag ``f = -(1/2) rho C_D A |v_r| v_r`` at one point of a body (a rigid body's centre
    of mass, a point mass at a cable's node): ``v_r`` the velocity relative to the
    co-rotating atmosphere (module notes), ``rho`` a number or a density model.

    Parameters
    ----------
    point : Node or body point
        Where the drag acts (``System.position_map``).
    density : float or model
        Density (kg/m^3, > 0), or an object with ``density(x, t)`` (module notes).
    cd : float
        Drag coefficient (>= 0).
    area : float
        Cross-section area ``A`` (m^2, > 0) normal to the flow.
    omega : array_like (3,) or None
        Rotation rate of the atmosphere (rad/s); None: the central body's in orbit.
    sample_every : float or None
        A density model at every step (None) or at knots every ``h`` s (``sampling``).
    """

    #: Bound with the run's reference in orbit (``bind(system, reference)``).
    reads_reference = True

    def __init__(self, point, density, cd, area, omega=None, sample_every=None):
        self.point = point
        self.density = density_model(density)
        self.sample_every = spacing_or_none(sample_every)
        self.cd = check_positive("cd", cd, allow_zero=True)
        self.area = check_positive("area", area)
        self.flow = Flow(None, omega)

    def bind(self, system, reference=None):
        """The compiled term (``kernels.drag.body_drag``); the flow at ``R(t)`` relative
        to ``V(t)`` in orbit and the density model's value (``DensitySampler``) refreshed
        once per time step (``Term.prepare``)."""
        dofs, G = system.position_map(self.point)
        dofs = np.ascontiguousarray(dofs, dtype=np.int64)
        G = np.ascontiguousarray(G, dtype=float)
        orbit = system.orbit if reference is None else reference
        arrays = self.flow.arrays(orbit)
        hooks, rho = (), np.array([0.0])
        if is_model(self.density):
            model = bound_model(self.density, system.epoch, "density")
            at = DensitySampler(model, lambda q: (G @ q[dofs])[None, None, :],
                                np.ones((1, 1)), orbit, system.q0, self.sample_every)
            hooks, rho = (at,), at.out
        else:
            rho[0] = self.density

        def prepare(t):
            self.flow.refresh(arrays, t, orbit)
            for hook in hooks:
                hook.prepare(t)

        pack = (dofs, G, np.array([0.5 * self.cd * self.area]), rho, *arrays)
        still = self.flow.steady and orbit is None and not hooks
        return Term(kernels=((kernel.body_drag, pack),), rows=dofs[:, None],
                    cols=dofs[None, :], prepare=None if still else prepare, hooks=hooks,
                    name=f"atmospheric drag {self.point!r}")


class AtmosphericDrag:
    """Drag of the co-rotating atmosphere, with a density model, on a cable (any line
    body) or on a rigid body or a point.

    A line body (one with the hook ``line_points``) gets the free-molecular drag per unit
    length ``-(1/2) C_D rho d |v_r x t| v_r`` of ``FreeMolecularDrag`` with ``d = area``
    (the projected area per unit length: the diameter, a tape's width); a rigid body
    (one with ``point`` and ``center_of_mass``) the drag ``-(1/2) rho C_D A |v_r| v_r``
    at its centre of mass, ``A = area``; a point (``cable.node(i)``, ``body.point(x)``)
    the same drag there.

    Parameters
    ----------
    body_or_cable : line body, rigid body, Node or body point
    density : float or model
        Density (kg/m^3, > 0), or a model with ``density(x, t)`` at absolute positions,
        ``t`` s after the epoch (``environment.MSIS``; made without an epoch it takes the
        system's, ``System.add_orbit(orbit, epoch=...)``).
    cd : float
        Drag coefficient (>= 0), default 2.2 (free-molecular flow).
    area : float
        The area ``A`` (m^2, > 0) of a body or a point, the projected width ``d`` (m, > 0)
        of a line body.
    omega : array_like (3,) or None
        Rotation rate of the atmosphere (rad/s); None: the central body's in orbit.
    sample_every : float or None
        None (default): the density model at every point once per time step; ``h`` (s,
        > 0): the model at knots every ``h`` seconds along the reference point (blocks
        of knots in one call), its logarithm interpolated in time and carried to the
        points by its gradient (``loads.knots``; ``docs/environment.md``).

    Notes
    -----
    The density is evaluated once per time step at every point of the body (or
    interpolated from the knots) and frozen over the step (module notes): the tangent is
    exact in the velocities, without ``d rho / dx`` in the positions; on a line body the
    element's points share the weighted mean of their densities.

    Examples
    --------
    >>> import skfem_cable as sc
    >>> can = sc.RigidBody.cylinder(radius=0.5, height=1.0, density=100.0)
    >>> drag = sc.AtmosphericDrag(can, density=2e-11, cd=2.2, area=0.785)
    >>> type(drag.part).__name__
    'PointDrag'
    """

    #: Bound with the run's reference in orbit (``bind(system, reference)``).
    reads_reference = True

    def __init__(self, body_or_cable, density, cd=2.2, area=None, omega=None,
                 sample_every=None):
        if area is None:
            raise ValueError("area must be given: the area A (m^2, > 0) of a body or a "
                             "point, the projected width d (m, > 0) of a line body")
        target = body_or_cable
        if callable(getattr(target, "line_points", None)):
            self.part = FreeMolecularDrag(target, density, area, cd, omega=omega,
                                          sample_every=sample_every)
        else:
            if callable(getattr(target, "point", None)) and \
                    getattr(target, "center_of_mass", None) is not None:
                target = target.point(target.center_of_mass)
            self.part = PointDrag(target, density, cd, area, omega, sample_every)

    @property
    def cables(self):
        """The line body the drag acts along (none for a body or a point)."""
        return getattr(self.part, "cables", [])

    def bind(self, system, reference=None):
        """The term of the drag (``FreeMolecularDrag`` or ``PointDrag``)."""
        return self.part.bind(system, reference)
