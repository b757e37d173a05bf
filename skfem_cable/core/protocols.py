"""The declared interfaces: what plugs into a system, what the solvers and ``io`` read of
a system, and what the time integration calls between steps, as ``typing.Protocol``s
(``docs/extending.md``, "Declared interfaces").

They are structural: a class need not inherit from them, only provide the members
(``members`` lists them); the tests check that the built-ins do and that the solvers and
``io`` read nothing of a system that ``IntegrableSystem`` and ``SystemView`` do not
declare (``tests/test_protocols.py``).

* What plugs in: ``Body`` (and ``Line``, a body with fields along an arc length),
  ``Load``, ``Constraint``, ``Observer``, and the ``Surface``s that line bodies touch.
  A ``System`` refuses a body that lacks a hook of ``Body``, naming it (``check_body``).
* What is read of a system: ``SystemView``, what a run store labels, fingerprints and
  reads back (``io``); ``IntegrableSystem``, what the solvers, the ``Result`` they return
  and the runner's summaries read.  ``System`` is both; the rod chain's
  ``rodchain.stored.ChainSystem`` is a ``SystemView``.
* What acts between steps: ``StepHook`` (Encke's rectification, the control loop), whose
  state is ``Checkpointed`` as the integrator's own instability guard's is.

The evaluation contract they refer to (``Evaluation``, ``Term``, ``Step``, ``Run``,
``Shape``) is ``contract``'s.
"""

from typing import Protocol, runtime_checkable

import numpy as np


def members(protocol):
    """The names ``protocol`` declares, its protocol bases' included: its annotated
    attributes and its public methods, in the order of declaration."""
    names = {}
    for cls in reversed(protocol.__mro__):
        if cls is Protocol or not getattr(cls, "_is_protocol", False):
            continue
        names.update(dict.fromkeys(vars(cls).get("__annotations__", {})))
        names.update(dict.fromkeys(name for name, value in vars(cls).items()
                                   if callable(value) and not name.startswith("_")))
    return tuple(names)


@runtime_checkable
class Body(Protocol):
    """A body of a ``System``: coordinates, mass, internal forces, and what it shows.

    ``name``, ``n_dofs``, ``q0`` (its initial coordinates), ``position_mask`` (True for
    coordinates that are lengths: scales for convergence tests) and ``energy_parts``
    (the names of the stored energy its term books in the two slots of
    ``Evaluation.energy``, e.g. a cable's ``("axial", "bending")``; ``()`` for a body that
    stores none: ``System.energy_parts`` reports them by these names); optionally
    ``vector_mask`` (True for coordinates that are parts of 3-vectors in space, which
    rigid motions move; all True by default).
    """

    name: str
    n_dofs: int
    q0: np.ndarray
    position_mask: np.ndarray
    energy_parts: tuple

    def describe_dof(self, index):
        """Which coordinate ``index`` (local) is, for messages: ``"node 3 r_x[1]"``."""

    def mass_matrix(self):
        """The constant mass matrix (scipy sparse, ``n_dofs`` square)."""

    def mass_points(self):
        """Where the mass is, for gravity fields that vary in space (an orbit's):
        ``(vectors (np, nf), coefficients (np, nf), mass (np,))``, point ``p`` at ``sum_j
        coefficients[p, j] q[vectors[p, j]: +3]`` of the body's coordinates ``q``, masses
        that reproduce the body's mass, centre of mass and second moments (empty arrays
        for a body without mass in space)."""

    def internal_constraints(self):
        """The body's own constraints (a list, maybe empty)."""

    def bind(self, system):
        """The ``Term`` of its internal forces in ``system``, or None."""

    def show(self, system, q, v, t, **detail):
        """What ParaView draws of it at the system's coordinates ``q`` and velocities ``v``
        and time ``t``: a ``Shape``, or None for a body with nothing in space (a reel).
        ``detail``: ``points_per_element`` (samples of a line per element), ``resolution``
        (segments around a surface); a body ignores what it does not use."""

    def outputs(self, system, q, t):
        """Its key numbers for a run's summary at ``q`` and ``t``: a dict of numbers and
        short arrays."""


#: What a ``Body`` provides (``check_body``): the protocol's attributes and hooks.
BODY_HOOKS = members(Body)


def check_body(body):
    """Refuse a body that lacks a hook of ``Body``, naming the hooks."""
    missing = [name for name in BODY_HOOKS if not hasattr(body, name)]
    if missing:
        raise TypeError(f"{body!r} is not a body: it lacks {', '.join(sorted(missing))} "
                        "(the hooks of skfem_cable.core.protocols.Body; docs/extending.md, "
                        "'A body')")


@runtime_checkable
class Line(Body, Protocol):
    """A body with fields along its arc length ``s`` (a cable): ``length``, and
    ``interpolate(q, s)`` (position, slope and second derivative), ``strain``,
    ``tension`` and ``curvature(q, s, stretch)`` of its own coordinates ``q``."""

    length: float

    def interpolate(self, q, s):
        """``r``, ``r_s``, ``r_ss`` at arc lengths ``s``."""

    def strain(self, q, s, stretch=1.0):
        """Axial (Green) strain at arc lengths ``s``."""

    def tension(self, q, s, stretch=1.0):
        """Axial force (N) at arc lengths ``s``."""

    def curvature(self, q, s, stretch=1.0):
        """Curvature (1/m) at arc lengths ``s``."""


@runtime_checkable
class LineBody(Body, Protocol):
    """A body that line loads reach (``Gravity`` and the orbit's differential gravity need
    only ``Body``): its points as linear combinations of its 3-vector coordinates, their
    slopes along the reference arc length and their weights (``lines.LinePoints``).  The
    gather, interpolation and scatter of every built-in line load are written once, on
    these tables (``kernels.line``); a cable, a rod or a user's element gets them all."""

    def line_points(self, system):
        """The body's ``lines.LinePoints`` with global coordinates in ``system``."""


@runtime_checkable
class Surface(Protocol):
    """A rigid surface that line bodies touch (``system.contact``, ``loads.contact``):
    ``surface_array()``, its description for the compiled contact
    (``kernels.contact``: kind, point, direction, radius), and ``distance(x)``, the
    signed distance of points ``x`` (n, 3) from it (negative inside)."""

    def surface_array(self):
        """The surface as ``kernels.contact`` reads it: ``[kind, point (3), direction
        (3), radius]``."""

    def distance(self, x):
        """Signed distance (m) of the points ``x`` (n, 3) from the surface."""


@runtime_checkable
class Load(Protocol):
    """A load: ``bind(system)`` returns its ``Term`` (forces through ``add`` or
    ``kernels``, constant ``force`` and ``mass``; see the module docstring); optionally
    ``show(system, q, v, t)``, a ``Shape`` that ParaView draws (``io.export``: the contact
    forces of ``loads.contact``).  A load of a
    system in orbit that reads the reference point's motion ``R(t)``, ``V(t)`` declares
    ``reads_reference = True`` and is bound with ``bind(system, reference)``: the run's
    ``orbit.Reference`` (the orbit and the rectification's rebases), not
    ``system.orbit``, whose single arc a rectified run leaves behind.  A load whose term
    gives per-step numbers (``Term.outputs``) declares their names in ``step_outputs`` (a
    tuple of str, unique in the system; ``load_outputs``): the run records them at every
    saved step (the store's ``output_<name>``, ``Result.outputs``).  Per-step arrays
    (a contact's forces per element) it declares in ``step_arrays(system)``, a dict of
    their names and shapes: recorded the same way, ``(n_saved, *shape)``."""

    def bind(self, system):
        """The load's ``Term`` in ``system``."""


@runtime_checkable
class Constraint(Protocol):
    """Equations ``C(q, t) = 0`` with multipliers: ``n_eq``, ``name``, ``labels`` (one
    per equation), ``linear`` (constant Jacobian), and the hooks below on the
    coordinates ``qc = q[dofs(system)]`` (module docstring; an optional compiled
    ``kernel``)."""

    n_eq: int
    name: str
    labels: list
    linear: bool

    def dofs(self, system):
        """The global coordinates it reads."""

    def value(self, qc, t=0.0):
        """``C`` (n_eq,)."""

    def jacobian(self, qc, t=0.0):
        """``C_q`` (n_eq, len(qc))."""

    def hessian(self, qc, lam, t=0.0):
        """``d(C_q^T lam)/dq`` (len(qc) square), or None if zero."""

    def velocity_term(self, qc, t=0.0):
        """``C_t``."""

    def accel_term(self, qc, vc, t=0.0):
        """``(C_q v)_q v + 2 C_qt v + C_tt``."""


class Observer(Protocol):
    """Observers of a time integration (``simulate(..., observers=[...])``): a protocol
    with default hooks, so a subclass overrides any of the three and a plain class with
    all three needs no base.

    ``start(run)``
        Once before the first step (also when a run is resumed).  ``run`` carries the
        ``system``, the ``integrator`` (its ``snapshot()`` is what a checkpoint needs), the
        run's ``settings`` and ``stats``.
    ``saved(run, step)``
        At the initial state, every saved step and the last step, with a ``Step``.
        Return a true value (e.g. a message string) to stop the run cleanly after this step.
    ``finish(run, error)``
        Once at the end, also when the run failed or was interrupted (``error`` is the
        exception, or None).
    """

    def start(self, run):
        pass

    def saved(self, run, step):
        return None

    def finish(self, run, error):
        pass




@runtime_checkable
class SystemView(Protocol):
    """What ``io`` reads of a system to label, fingerprint, write and read back a run
    store (``io.labels``, ``io.fingerprint``, ``io.schema``, ``io.writer``,
    ``io.reader``): a ``System``, and a rod chain's run (``rodchain.stored``).

    Attributes
    ----------
    n_dofs : int
        Number of coordinates ``q`` (the stored ``q``, ``v``, ``a`` have this width).
    n_constraints : int
        Number of constraint equations (the stored multipliers ``lam``).
    bodies : list of Body
        The bodies, in the order of their coordinates (labelled by ``name`` and
        ``describe_dof``; fingerprinted by class, ``name``, ``n_dofs``, ``q0``).
    constraints : list of Constraint
        The constraints, in the order of their multipliers.
    loads : list of Load
        The loads (fingerprinted by class and parameters).
    point_masses : list
        The point masses (fingerprinted by class and parameters).
    vectors : int ndarray (k, 3)
        Global coordinates of every 3-vector (positions, slopes, rod vectors).
    vector_is_position : bool ndarray (k,)
        True for the rows of ``vectors`` that are positions (labelled ``x y z``, stored
        as ``r``); the others are labelled ``dx dy dz``.
    orbit : orbit.Orbit or None
        The reference orbit of a system in orbit, whose run's rebases a store reads back
        (``orbit.Reference``); None otherwise.
    epoch : environment.Epoch or None
        The UTC instant of the run's ``t = 0`` (``System.add_orbit(epoch=)``), part of the
        fingerprint; None for a system without one.
    """

    n_dofs: int
    n_constraints: int
    bodies: list
    constraints: list
    loads: list
    point_masses: list
    vectors: np.ndarray
    vector_is_position: np.ndarray
    orbit: object
    epoch: object

    def dofs(self, item):
        """Global coordinates (int ndarray) of ``item``: a body, or a node of one."""
        ...

    def cables(self):
        """The bodies that are ``Line``s (their nodes' arc lengths are stored)."""
        ...

    def mass_matrix(self):
        """The constant mass matrix (scipy sparse, ``n_dofs`` square), fingerprinted."""
        ...


class IntegrableSystem(SystemView, Protocol):
    """What the solvers (``solvers``) read of a system, and what the ``Result`` they
    return (``result``) and the runner's summaries (``runner``) read of it: a
    ``SystemView`` and the members below.  A ``System`` is one.  (Not
    ``runtime_checkable``: ``isinstance`` would build the ``layout``.)

    Attributes
    ----------
    q0 : ndarray (n_dofs,)
        The bodies' initial coordinates.
    layout : layout.Layout
        The fixed pattern and constant parts of the equations, built on first use.
    deployments : dict
        The deploying cables' ``Deployment``s by ``id`` of the cable (``deploy``).
    orbit_gravity : orbit_gravity.DifferentialGravity or None
        The differential gravity of a system in orbit (``frame_change``); None otherwise.
    """

    q0: np.ndarray
    layout: object
    deployments: dict
    orbit_gravity: object

    def current_layout(self):
        """The ``layout`` of the system as it is now (built again after an edit)."""
        ...

    def check_unchanged(self, layout, during):
        """Raise ``system.SystemChanged`` if the system is no longer ``layout``'s."""
        ...

    def describe_dof(self, index):
        """Who owns global unknown ``index`` (coordinate, or multiplier past ``n_dofs``)."""
        ...

    def evaluate(self, q, v, t, lam, load_factor=1.0, cK=1.0, cC=0.0, scale=1.0,
                 data=None, reference_force=False, a=None, cM=0.0, layout=None):
        """Residual ``[f_int - f_ext + C_q^T lam, scale C]``, tangent into ``data``."""
        ...

    def constraint_values(self, q, t=0.0, layout=None):
        """``C(q, t)`` of every constraint (n_constraints,)."""
        ...

    def constraint_velocity_term(self, q, t=0.0, layout=None):
        """``C_t`` of every constraint (consistent velocities: ``C_q v = -C_t``)."""
        ...

    def constraint_accel_term(self, q, v, t=0.0, layout=None):
        """``(C_q v)_q v + 2 C_qt v + C_tt`` of every constraint (Eq. 2)."""
        ...

    def energy_rate(self, q, t):
        """Explicit time derivative (W) of the stored energy at fixed coordinates."""
        ...

    def energy_change(self, q0, q1, t0, t1):
        """Work (J) of the terms' data changing in time over a step."""
        ...

    def deployment(self, body):
        """The ``Deployment`` of ``body`` (``deploy``), or None."""
        ...

    def stretch(self, cable, t, q=None):
        """Mesh stretch of ``cable`` at times ``t`` (free over built length; else 1)."""
        ...

    def rigid_motion_velocity(self, q, omega, center=(0, 0, 0), velocity=(0, 0, 0)):
        """Velocities (n_dofs,) of a rigid motion of the whole system at ``q``."""
        ...

    def rotation_operator(self, W):
        """Sparse (n_dofs, n_dofs): ``W`` (3, 3) on every 3-vector, zero on scalars."""
        ...

    def rotate(self, q, R, center=(0, 0, 0)):
        """Coordinates ``q`` turned rigidly by the rotation matrix ``R`` about ``center``."""
        ...

    def centre_of_mass(self, x):
        """Centre of mass (3,) or (..., 3) of the coordinates ``x`` (..., n_dofs)."""
        ...

    def energy_parts(self, q, v, t=0.0):
        """Kinetic and stored energy (J) of each body at ``(q, v, t)``, by label."""
        ...


@runtime_checkable
class Checkpointed(Protocol):
    """State that a checkpoint holds, so that a continued run is bit for bit the
    uninterrupted one: the integrator's instability guard (``solvers.guard``) and every
    ``StepHook``.  ``GeneralizedAlpha.snapshot`` joins their ``snapshot()`` into its own
    at every checkpoint (a checkpoint is written after a saved step); a resumed run calls
    ``restore`` with that whole mapping, read back from the store."""

    def snapshot(self):
        """The state as a dict of numpy values (keys its own, unique in the checkpoint)."""
        ...

    def restore(self, snap):
        """Put back the state of ``snapshot()`` from the checkpoint mapping ``snap``."""
        ...


@runtime_checkable
class StepHook(Checkpointed, Protocol):
    """What acts between the steps of a time integration (``simulate``): Encke's
    rectification (``solvers.rectify.Rectification``) and the control loop
    (``control.ControlLoop``).  ``simulate`` calls these five members and nothing else,
    in this order: ``restore(snap)`` on resume (before the integrator's) or
    ``start(integrator)`` on a fresh start (after ``integrator.initialize``); then, after
    every step, ``after_step(integrator)``; with adaptive steps, before each,
    ``next_event(t)``; the integrator's ``snapshot()`` calls ``snapshot()``.  A hook
    that needs no action at one of them implements it as a no-op."""

    def start(self, integrator):
        """A fresh run starts at ``integrator.t`` (may ``initialize`` it again)."""
        ...

    def after_step(self, integrator):
        """A step was accepted: act on the integrator (``shift``, ``stats``) or not."""
        ...

    def next_event(self, t):
        """The next time after ``t`` that an adaptive step must end on (``inf``: none)."""
        ...


def load_output_shapes(system):
    """``{name: shape}`` of the per-step outputs the loads of ``system`` declare, in the
    loads' order: their numbers (``step_outputs``, shape ``()``) and arrays
    (``step_arrays(system)``, ``Load``); a name declared twice is an error."""
    pairs = []
    for load in system.loads:
        pairs += [(name, ()) for name in getattr(load, "step_outputs", ())]
        arrays = getattr(load, "step_arrays", None)
        pairs += [(name, tuple(shape)) for name, shape in
                  (arrays(system) if arrays is not None else {}).items()]
    names = [name for name, _ in pairs]
    twice = sorted({name for name in names if names.count(name) > 1})
    if twice:
        raise ValueError(f"two loads declare the step output {twice[0]!r}: give each its "
                         "own name")
    return dict(pairs)


def load_outputs(system):
    """The names of the per-step outputs (numbers and arrays) the loads of ``system``
    declare (``load_output_shapes``), in the loads' order."""
    return tuple(load_output_shapes(system))
