"""A multibody system: bodies stacked into one coordinate vector (Eq. 4), loads, point masses
and constraints with Lagrange multipliers; its residual and iteration matrix are evaluated
through the contract of ``contract`` on the fixed pattern of ``layout.Layout``.

The KKT (iteration) matrix of the unknowns ``(q, lambda')`` is

    [[cM M + cC D + cK (K + H(lambda) - dF_ext/dq) - cC dF_ext/dv,  s C_q^T],
     [s C_q,                                                         0      ]]

with ``K`` and ``D`` the stiffness and damping tangents of the bodies (Eqs. 13-15), ``H`` the
constraint Hessian term of Eq. 15 and ``s`` a constraint scaling (``lambda = s lambda'``)
chosen by the solvers for conditioning.

Examples
--------
>>> import skfem_cable as sc
>>> cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], 4, sc.Section.circular(1e-3, 2e11, 7850.0))
>>> system = sc.System([cable]).clamp(cable.node(0)).add_gravity([0, -9.81, 0])
>>> system.n_dofs, system.n_constraints, [c.name for c in system.constraints]
(30, 5, ['clamp Node(cable, 0)'])
"""

import numpy as np
import scipy.sparse as sp

from .. import constraints as cons
from ..bodies.memory import check_total_memory
from ..core.node import Node
from ..core.protocols import Line, check_body
from ..environment.epoch import epoch_or_none
from ..loads.gravity import Centrifugal, Gravity
from ..loads.line import UniformLineLoad
from ..loads.orbit_gravity import DifferentialGravity
from ..loads.point import PointLoad, PointMass, PointMoment
from .contact import contact
from .fingerprint import describe_system, differences
from .layout import Layout
from .motion import SystemMotion, vector_blocks
from .system_deploying import SystemDeploying
from .system_evaluation import SystemEvaluation


def _same_bytes(a, b):
    """True if the arrays ``a`` and ``b`` have the same type, shape and bytes."""
    return a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()


class SystemChanged(RuntimeError):
    """The system changed while a solver ran (an observer edited a load, a section, ...),
    or since a ``Result`` read from it was simulated: the message names what changed."""


class System(SystemMotion, SystemEvaluation, SystemDeploying):
    """Bodies, constraints, point masses and loads.

    Parameters
    ----------
    bodies : sequence of bodies
        Anything with the body contract (``contract``): ``Cable``, ``RigidBody`` or a
        user's body.

    Attributes
    ----------
    bodies : list
        The bodies, in the order of their coordinates.
    n_dofs : int
        Number of coordinates (all bodies).
    n_constraints : int
        Number of constraint equations (Lagrange multipliers).
    constraints : list
        The constraints: the bodies' internal ones (a rigid body's six) first, then those
        added (``clamp``, ``pin``, ``add_constraint``).
    loads, point_masses : list
        The contributors added by ``add_load`` (and the ``add_*`` shortcuts) and
        ``add_point_mass``.
    offsets : dict
        First global coordinate of each body, by ``id(body)``.
    q0 : ndarray (n_dofs,)
        The bodies' initial coordinates, stacked.
    vectors : int ndarray (nb, 3)
        The global coordinates of every 3-vector in space (positions, slopes, a rigid
        body's base points); scalar coordinates (a reel's length) are in none.
    vector_is_position : bool ndarray (nb,)
        Which of ``vectors`` are positions (the others are directions).

    Notes
    -----
    The building methods (``clamp``, ``pin``, ``add_*``) return the system, so that they
    chain.  The first solve fixes its sparsity pattern and constant parts (``layout``);
    every solver starts from the system as it is then (``current_layout``): a load, section
    or constraint edited between two solves is solved as edited, and so are ``evaluate``,
    ``assemble`` and the constraint terms called between solves.  A change while a solver
    runs (in an observer) cannot take effect and is refused (``SystemChanged``).

    Examples
    --------
    A cable pinned at one end under gravity, and a cable clamped at both ends:

    >>> import skfem_cable as sc
    >>> sec = sc.Section.circular(radius=0.01, E=7e10, rho=7800.0)
    >>> cable = sc.Cable.straight([0, 0, 0], [1.2, 0, 0], n_elements=16, section=sec)
    >>> pendulum = sc.System([cable]).pin(cable.node(0)).add_gravity([0, -9.81, 0])
    >>> pendulum.n_dofs, pendulum.n_constraints
    (102, 3)
    >>> beam = sc.System([cable]).clamp(cable.node(0)).clamp(cable.node(-1))
    >>> beam.n_constraints
    10
    >>> sc.System([cable]).dofs(cable.node(1)).tolist()
    [6, 7, 8, 9, 10, 11]
    """

    def __init__(self, bodies):
        self.bodies = list(bodies)
        if not self.bodies:
            raise ValueError("bodies must contain at least one body")
        for body in self.bodies:
            check_body(body)
        check_total_memory([b.n_elements for b in self.bodies if hasattr(b, "n_elements")])
        self.offsets = {}
        n = 0
        for body in self.bodies:
            if id(body) in self.offsets:
                raise ValueError(f"body {body.name!r} appears twice in bodies")
            self.offsets[id(body)] = n
            n += body.n_dofs
        self.n_dofs = n
        self.constraints = [c for body in self.bodies for c in body.internal_constraints()]
        self.vectors, self.vector_is_position = vector_blocks(self.bodies)
        self.loads = []
        self.point_masses = []
        self.deployments = {}
        self.orbit = self.orbit_gravity = None
        self.epoch = None
        self._layout = None
        self._mass_kept = None

    # --- building -------------------------------------------------------------------------
    def _offset(self, body):
        try:
            return self.offsets[id(body)]
        except KeyError:
            raise ValueError(f"{body!r} is not a body of this system") from None

    def dofs(self, item):
        """Global coordinates of a ``Node`` (6 for a cable node) or of a whole body."""
        if isinstance(item, Node):
            return self._offset(item.body) + item.body.node_dofs(item.index)
        return self._offset(item) + np.arange(item.n_dofs)

    def _changed(self):
        self._layout = None
        return self

    def add_constraint(self, constraint):
        """Add a constraint (see ``constraints``). Returns the system.

        Raises
        ------
        ValueError
            A linear constraint whose equations are dependent, or dependent on those of a
            constraint already added (a node pinned or clamped twice: the system's matrix
            would be singular); see ``constraints.check_independent``.
        """
        cons.check_independent(self, constraint)
        self.constraints.append(constraint)
        return self._changed()

    def clamp(self, node, direction=None, position=None, velocity=None, acceleration=None,
              slope="direction", twist=True):
        """Clamp a node: position and slope direction fixed, driven (callables of time), or
        carried by a rigid body (see ``constraints.clamp``). Returns the system.

        Five equations: the position (three) and the direction of the slope (two); the
        axial stretch at the clamp stays free.  ``slope="full"`` fixes the whole slope
        vector instead (six equations; Exudyn's ``[1, 1, 1, 1]`` node constraint).  With
        a body point ``position`` the node is pinned to it and its slope keeps a
        direction fixed in the body (``constraints.BodySlope``): a tether leaving a
        spinning hub through an exit guide.

        Parameters
        ----------
        node : Node
            ``cable.node(i)``.
        direction : array_like (3,) or callable, optional
            Slope direction (default: the node's initial one), or a callable ``f(t)`` of a
            driven clamp.  With a body point ``position``: a direction in the body frame
            (default: the node's initial slope in the body's initial frame).
        position : array_like (3,), callable or body point, optional
            Position (default: the node's initial one), a callable ``f(t)`` of a driven
            clamp, or a rigid-body point (``RigidBody.point``).
        velocity, acceleration : callable, optional
            Exact time derivatives of a driven ``position`` (None with a body point).
        slope : {"direction", "full"}
            Fix the slope's direction (default) or the whole slope vector (then
            ``direction`` is the slope vector, default the node's initial slope).
        twist : bool or callable
            A rod's node (``Node.has_twist``): hold its twist (True), leave it free
            (False) or drive it, ``twist(t)`` (rad); ignored on a cable's node.

        Returns
        -------
        System
            ``self``.

        Raises
        ------
        ValueError
            A zero ``direction``, or ``velocity``/``acceleration`` with a body point.

        Examples
        --------
        A tether clamped radially to the rim of a hub (axis along the body x axis): a pin
        to the rim point and the two slope equations of the exit guide.

        >>> import numpy as np, skfem_cable as sc
        >>> hub = sc.RigidBody.cylinder(radius=1.0, height=0.5, density=100.0)
        >>> tether = sc.Cable.straight([0, 1, 0], [0, 3, 0], 4,
        ...                            sc.Section.circular(1e-3, 7e10, 2700.0), name="tether")
        >>> system = sc.System([hub, tether]).clamp(tether.node(0), position=hub.point([0, 1, 0]))
        >>> [c.name for c in system.constraints[1:]]
        ['pin Node(tether, 0)-hub.point([0. 1. 0.])', 'body slope Node(tether, 0)-hub']
        >>> system.constraints[-1].direction
        array([0., 1., 0.])
        >>> float(np.abs(system.constraint_values(system.q0)).max())
        0.0
        """
        for c in cons.clamp(node, direction, position, velocity, acceleration, slope, twist):
            self.add_constraint(c)
        return self

    def pin(self, node, target=None, velocity=None, acceleration=None, directions=None):
        """Spherical joint of a node to ground (``target`` None, a point, or a callable
        ``target(t)`` with optional exact ``velocity(t)``, ``acceleration(t)``) or to
        another node/body point, in all directions or along the given ``directions``
        only (a node sliding on a plane or a line). Returns the system.

        Parameters
        ----------
        node : Node
            ``cable.node(i)``.
        target : None, array_like (3,), callable, Node or body point, optional
            Ground at the node's initial position (None), a ground point, a ground point
            moving on ``target(t)``, another cable's node, or a rigid-body point
            (``RigidBody.point``); see ``constraints.pin``.
        velocity, acceleration : callable, optional
            Exact derivatives of a callable ``target`` (else by differences).
        directions : array_like (k, 3), optional
            One direction (the node slides on the plane through the target normal to it)
            or two (on the line through the target along their normal); default all
            three.

        Returns
        -------
        System
            ``self``; three constraint equations (multipliers ``Fx, Fy, Fz``) are added,
            or one per direction (``F1``, ``F2``).

        Examples
        --------
        >>> import numpy as np, skfem_cable as sc
        >>> sec = sc.Section.circular(1e-3, 2e11, 7850.0)
        >>> a = sc.Cable.straight([0, 0, 0], [1, 0, 0], 2, sec, name="a")
        >>> b = sc.Cable.straight([1, 0, 0], [2, 0, 0], 2, sec, name="b")
        >>> shaker = lambda t: np.array([0.0, 0.01 * np.sin(10 * t), 0.0])
        >>> system = sc.System([a, b]).pin(a.node(0), shaker).pin(b.node(0), a.node(-1))
        >>> system.n_constraints, system.constraints[1].name
        (6, 'pin Node(b, 0)-Node(a, 2)')
        """
        return self.add_constraint(cons.pin(node, target, velocity, acceleration,
                                            directions))

    def add_load(self, load):
        """Add a contributor with ``bind(system) -> Term`` (loads, point masses, gravity,
        see ``loads`` and ``contract``). Returns the system."""
        if not callable(getattr(load, "bind", None)):
            raise TypeError(f"add_load expects an object with bind(system), got {load!r}")
        if self.orbit is not None and isinstance(load, Gravity):
            raise ValueError("add_gravity: the system is in orbit (add_orbit), where the "
                             "central body's differential gravity replaces uniform gravity")
        self.loads.append(load)
        return self._changed()

    def contact(self, first, second=None, friction=0.0, **options):
        """Contact of a line body with a surface (``sc.Plane``, ``sc.Sphere``,
        ``sc.Cylinder``), in either order, with Coulomb's ``friction`` (``mu >= 0``):
        ``loads.contact.LineSurfaceContact`` and its ``options`` (``radius``,
        ``stiffness``, ``tolerance``, ``damping``, ``slip_velocity``; ``docs/contact.md``).
        A surface carried by a rigid body (``body.cylinder(...)``, ``body.plane``,
        ``body.sphere``): ``loads.contact_body.LineBodyContact``, coupling the body.
        Two line bodies, or one twice (self-contact), or a sequence of line bodies alone
        (``system.contact(tethers)``: each with each, one broad phase):
        ``loads.contact_lines.LineLineContact`` (``model.contact``).  Its per-step outputs
        (``docs/contact.md``) are prefixed by its ``name`` (option; default
        ``contact_<line>``, numbered ``_2``, ... past the names of the system's loads).
        Returns the system; the contact is ``system.loads[-1]``."""
        taken = [getattr(load, "name", None) for load in self.loads]
        return self.add_load(contact(first, second, friction, taken, **options))

    def add_point_load(self, node, force):
        """Force (N) at a cable node or a rigid-body point (``RigidBody.point``): a 3-vector,
        or a callable ``force(t)`` (its work is booked as external work)."""
        return self.add_load(PointLoad(node, force))

    def add_point_moment(self, node, moment):
        """Moment (N m, fixed in space) at a cable node; see ``loads.PointMoment``."""
        return self.add_load(PointMoment(node, moment))

    def add_centrifugal(self, omega, center=(0.0, 0.0, 0.0)):
        """Centrifugal forces of a frame rotating at ``omega`` (rad/s) about the axis
        through ``center`` (m): for steady spinning states (``solve_static``; free-floating
        systems: ``solve_steady``) and their modes (``modes(..., spin=omega)``)."""
        return self.add_load(Centrifugal(omega, center))

    def add_gravity(self, g):
        """Uniform gravity (m/s^2) on every body and point mass (consistent nodal forces)."""
        return self.add_load(Gravity(g))

    def add_orbit(self, orbit, j2=None, body_radius=None, epoch=None):
        """Put the system in orbit: its coordinates become offsets from the reference
        point of ``orbit`` (an ``Orbit``), in axes parallel to the inertial ones, and every
        body and point mass feels the central body's differential gravity (optionally with
        J2 of a central body of equatorial radius ``body_radius``, its axis along ``z``);
        see ``orbit_gravity``.  Uniform gravity (``add_gravity``) and an orbit exclude each
        other.  An orbit whose periapsis lies inside the central body (``body_radius``,
        else the radius of ``orbit.central_body``) is refused (``Orbit.check_above``).

        ``epoch`` (an ``Epoch``, a ``datetime``, an astropy ``Time`` or an ISO 8601
        string; ``environment.as_epoch``) is the UTC instant of the run's ``t = 0``: the
        orbit's axes are then the GCRS axes at that instant, and the environment models
        of the loads (``environment.MSIS``, ``IGRF``, ``IRI``) made without an epoch of
        their own take it when bound (``environment.bound_model``); a model whose own
        epoch differs is refused by name.  The epoch is part of the run's fingerprint (a
        run resumed with another epoch is refused).  Returns the system."""
        if self.orbit is not None:
            raise ValueError("add_orbit: the system is already in orbit")
        body = orbit.central_body
        orbit.check_above(body_radius if body_radius is not None or body is None
                          else body.radius)
        if any(isinstance(load, Gravity) for load in self.loads):
            raise ValueError("add_orbit: the system has uniform gravity (add_gravity); in "
                             "orbit the central body's gravity replaces it")
        self.epoch = epoch_or_none(epoch)
        self.orbit = orbit
        self.orbit_gravity = DifferentialGravity(orbit, j2, body_radius)
        return self.add_load(self.orbit_gravity)

    def add_line_load(self, cable, force_per_length):
        """Uniform distributed load (N/m, fixed in space) along a cable; for loads that
        depend on position, velocity or time use ``add_load(LineLoad(...))``."""
        return self.add_load(UniformLineLoad(cable, force_per_length))

    def add_point_mass(self, node, mass):
        """Point mass (kg) at a node's position (e.g. a remote unit or a tip mass), or at a
        body point (a contributor whose ``Term`` has a constant ``mass``)."""
        self.point_masses.append(PointMass(node, mass))
        return self._changed()

    def position_map(self, point):
        """``(dofs, G)`` with ``position = G @ q[dofs]`` for a cable ``Node`` or a body
        point."""
        if isinstance(point, Node):
            return self.dofs(point)[:3], np.eye(3)
        return self.dofs(point.body), point.position_matrix

    # --- layout ---------------------------------------------------------------------------
    @property
    def q0(self):
        """The bodies' initial coordinates, stacked (n_dofs,)."""
        return np.concatenate([b.q0 for b in self.bodies])

    @property
    def n_constraints(self):
        """Number of constraint equations."""
        return sum(c.n_eq for c in self.constraints)

    @property
    def layout(self):
        """The fixed sparsity pattern of the KKT matrix and the constant parts
        (``layout.Layout``), built on first use and again after ``add_*``, ``clamp`` or
        ``pin``; a solver takes ``current_layout``."""
        if self._layout is None:
            self._check_deploying_loads()
            self._layout = Layout(self)
        return self._layout

    def current_layout(self):
        """The layout of the system as it is now: ``layout``, built again when the
        system's description (``io.fingerprint.describe_system``: bodies, sections, laws,
        masses, constraints, loads and their parameters) differs from the one at its
        build (``Layout.description``), as after ``load.g = ...`` or ``cable.section =
        ...``.  Every solver calls it once at its start, so that what it solves is what a
        run store fingerprints."""
        if self._layout is not None and describe_system(self) != self._layout.description:
            self._layout = None
        return self.layout

    def check_unchanged(self, layout, during):
        """Raise ``SystemChanged`` if the system is no longer the one ``layout`` (a
        solver's, from ``current_layout``) was built for, naming what changed ``during``
        the solve (e.g. "during the run"): an edit in an observer, which the running
        solver cannot take."""
        changed = differences(layout.description, describe_system(self))
        if changed:
            raise SystemChanged(
                f"the system changed {during}: {'; '.join(changed)}.  The solver had built "
                "its equations (constant forces, mass, constraints, load terms) at the "
                "start, so the steps after the change hold the old system or a mix of the "
                "old and the new one: edit the system between runs, not during one (a load "
                "that changes in time takes a callable of time; or stop the run and start "
                "another from its last state, initial=)")

    def _check_deploying_loads(self):
        """Refuse a load along a deploying cable (a load naming it in ``cables``) unless
        the load integrates over the material the reel pays out (``stretches = True``):
        it would act on the length as built, not on the free length."""
        for load in self.loads:
            for cable in getattr(load, "cables", ()):
                if self.deployment(cable) is not None and not getattr(load, "stretches", False):
                    raise ValueError(
                        f"{type(load).__name__} acts along {cable.name!r}, which deploys "
                        "(System.deploy): this load integrates over the cable as built, not "
                        "over its free length, and is not supported on a deploying cable "
                        "(gravity and SolarWindForce are; see docs/deploy.md)")

    def _solved(self, layout):
        """``layout`` (a solver's, from ``current_layout`` at its start), or when None the
        layout of the system as it is now (``current_layout``): what a public entry point
        evaluates, so that it sees the system as edited."""
        return self.current_layout() if layout is None else layout

    @property
    def f_const(self):
        """Constant generalized external force: fixed loads plus gravity (of the system
        as it is now)."""
        return self.current_layout().f_const

    def mass_matrix(self):
        """Global constant mass matrix (Eq. 11) including point masses: the bodies'
        blocks on the diagonal (the entries of ``scipy.sparse.block_diag``, in its order;
        a CSR block's read from its arrays, without scipy's conversions), then the point
        masses' ``m G^T G`` (``PointMass.entries``), summed where they meet.  Every
        description of the system (``describe_system``: at every solver's start and every
        public evaluation) asks for it: the summed matrix is kept with its entries and
        made again only when they differ, byte for byte (a copy is returned)."""
        entries, n = self._mass_entries()
        kept = self._mass_kept
        if kept is None or kept[1] != n or not all(map(_same_bytes, kept[0], entries)):
            M = sp.csr_matrix((entries[2], entries[:2]), shape=(n, n))
            self._mass_kept = kept = (entries, n, M)
        return kept[2].copy()

    def _mass_entries(self):
        """``(rows, cols, values)`` of the mass matrix before its entries are summed
        (``mass_matrix``), and its size."""
        rows, cols, vals, offset = [], [], [], 0
        for body in self.bodies:
            block = body.mass_matrix()
            if getattr(block, "format", None) != "csr":
                block = sp.coo_matrix(block)
                rows.append(block.row + offset)
                cols.append(block.col + offset)
            else:
                rows.append(np.repeat(np.arange(offset, offset + block.shape[0]),
                                      np.diff(block.indptr)))
                cols.append(block.indices + offset)
            vals.append(block.data)
            offset += block.shape[0]
        for point_mass in self.point_masses:
            r, c, m = point_mass.entries(self)
            rows.append(r)
            cols.append(c)
            vals.append(m)
        return (np.concatenate(rows), np.concatenate(cols), np.concatenate(vals)), offset

    def cables(self):
        """The bodies with fields along a line (``contract.Line``: ``interpolate``,
        ``tension``, ...): cables, their subclasses and a user's line bodies."""
        return [b for b in self.bodies if isinstance(b, Line)]

    def describe_dof(self, index):
        """Human-readable owner of a global unknown (body and node, or constraint)."""
        if index < self.n_dofs:
            for body in self.bodies:
                off = self._offset(body)
                if off <= index < off + body.n_dofs:
                    local = index - off
                    return f"{body.name} coordinate {local} ({body.describe_dof(local)})"
        k = index - self.n_dofs
        for c in self.constraints:
            if 0 <= k < c.n_eq:
                return f"constraint {c.name} equation {c.labels[k]}"
            k -= c.n_eq
        raise IndexError(f"unknown {index} out of range: the system has {self.n_dofs} "
                         f"coordinates and {self.n_constraints} constraint equations")
