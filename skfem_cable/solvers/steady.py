"""Relative equilibria of spinning systems: statics in a frame rotating at a constant rate
about a fixed axis, with the gauge conditions a free-floating system needs
(``docs/steady.md`` and the section "Steady spinning states" of ``docs/theory.md``).

In the frame rotating at ``omega`` about the axis through ``center`` a steady state is at
rest: the elastic forces balance the centrifugal forces ``-M (I (x) W^2)(q - u_c)``
(``loads.Centrifugal``) and the loads, all evaluated at the velocities of the rigid
rotation (``System.rigid_motion_velocity``), at which the Kelvin-Voigt damping of the
cables vanishes identically (the strain and curvature of a rigid motion do not change).

Two gauge freedoms of the rotating frame are removed with Lagrange multipliers when the
system has them (the constraints decide: a motion that leaves every constraint unchanged
is free); a supported system (a clamp, a pin off the axis) has none:

* translation along the axis: the axial position of the centre of mass is held at that of
  ``center``, ``U^T M q / m = n . center`` (``U`` the coordinates of a unit translation
  along the axis ``n``).  Its reaction ``M U lambda / m`` is the d'Alembert force of a
  uniform acceleration ``a = lambda / m`` of the frame along the axis, so a net axial
  load (the thrust of a solar-wind sail) is balanced by accelerating the frame: the state
  is the relative equilibrium in the rotating, uniformly accelerating frame, and
  ``stats["frame_acceleration"]`` is ``a n``.  Translations across the axis are no
  gauge freedom: the centrifugal force fixes the centre of mass there;
* the phase of the rotation about the axis: the mass-weighted mean rotation angle about
  the axis from the initial guess is zero.  Its multiplier is the torque about the axis
  that holds the phase (``stats["phase_torque"]``): zero at a relative equilibrium, which
  is checked.

A relative equilibrium exists only if the loads are the same in every rotated position
(loads constant in the rotating frame: along the axis, or axisymmetric); ``solve_steady``
checks that the residual turns with the system and refuses otherwise.
"""

import copy

import numpy as np
import scipy.sparse as sp
from scipy.spatial.transform import Rotation

from ..constraints.linear import LinearConstraint
from ..core.protocols import IntegrableSystem
from ..loads.gravity import Centrifugal
from ..loads.point import vector3
from ..model.state import State
from .static import StaticConvergenceError, equilibrium
from .static_states import constraint_jacobian

#: A motion is free when the constraints change by less than this, relative to the norms
#: of their Jacobian and of the motion.
FREE_MOTION_TOL = 1e-9

#: The residual of a system whose loads are constant in the rotating frame turns with it to
#: round-off; beyond this (relative to the largest force) the loads are refused.
EQUIVARIANCE_TOL = 1e-8

#: A phase torque above this, relative to the largest force times the system size, is a
#: net torque of the loads about the axis: the spin cannot be steady.
TORQUE_TOL = 1e-8


class RigidRotation:
    """Velocities of the rigid rotation at ``omega`` about the axis through ``center``:
    ``v(q) = omega x (q - u_c)`` on every 3-vector of coordinates (``velocity``) and
    their constant derivative ``dv/dq = I (x) [omega]_x`` (``operator``)."""

    def __init__(self, system, omega, center):
        self.system, self.omega, self.center = system, omega, center
        W = np.cross(omega, np.eye(3)).T
        self.operator = system.rotation_operator(W)

    def velocity(self, q):
        return self.system.rigid_motion_velocity(q, self.omega, self.center)


def free_motions(system, q, fields):
    """Orthonormal combinations (rows, k x m) of the motions ``fields`` (n_dofs x m) that
    leave every constraint unchanged to first order at ``q``."""
    fields = np.asarray(fields, dtype=float)
    if system.n_constraints == 0:
        return np.eye(fields.shape[1])
    J = constraint_jacobian(system, q)
    JU = J @ fields
    _, s, vt = np.linalg.svd(JU)
    bound = FREE_MOTION_TOL * sp.linalg.norm(J) * np.linalg.norm(fields, axis=0).max()
    rank = int(np.sum(s > bound))
    return vt[rank:]


def gauge_constraints(system, q, omega, center):
    """The gauge conditions the system needs in the frame rotating at ``omega`` about the
    axis through ``center`` (module docstring): a list of ``LinearConstraint``
    (``"axial centre of mass"``, ``"spin phase"``, each only if the constraints leave that
    motion free) and the total mass (kg)."""
    M = system.mass_matrix()
    axis = omega / np.linalg.norm(omega)
    U = system.rigid_motion_velocity(q, (0, 0, 0), velocity=axis)  # translation along axis
    mass = float(U @ (M @ U))
    gauges = []
    if len(free_motions(system, q, U[:, None])):
        gauges.append(_linear((M @ U)[None, :] / mass, [axis @ center],
                              "axial centre of mass", ["m a"]))
    R = system.rigid_motion_velocity(q, axis, center)  # rotation about the axis
    inertia = float(R @ (M @ R))
    if inertia > 0 and len(free_motions(system, q, R[:, None])):
        g = (M @ R) / inertia
        gauges.append(_linear(g[None, :], [g @ q], "spin phase", ["Mz"]))
    return gauges, mass


def _linear(rows, offset, name, labels):
    """A ``LinearConstraint`` ``rows @ q[dofs] = offset`` on the coordinates the rows
    involve."""
    dofs = np.flatnonzero(np.any(rows != 0, axis=0))
    return LinearConstraint(lambda s: dofs, rows[:, dofs], np.asarray(offset, dtype=float),
                            name, labels)


def rotated(system, q, axis, angle, center):
    """The coordinates of the system turned rigidly by ``angle`` about the axis through
    ``center``: positions ``c + R (r - c)``, slopes and other vectors ``R x``."""
    Rm = Rotation.from_rotvec(angle * axis).as_matrix()
    return system.rotate(q, Rm, center), Rm


def check_equivariance(frame, motion, q, axis, center, angle=1.0):
    """Raise ``ValueError`` unless the forces of ``frame`` (elastic, centrifugal and loads,
    at the rigid-rotation velocities) turn with the system: ``r(R q, t) = R r(q, 0)`` for
    a turn by ``angle`` about the axis, the time ``t = angle / |omega|`` later (a load
    that changes in time is not constant in the rotating frame either), to
    ``EQUIVARIANCE_TOL`` of the largest force, or of the round-off of the forces of a
    turned state (the tangent's largest diagonal entry times ``eps`` times the coordinates'
    size: a system in orbit far from its central body has loads far below its
    stiffness).  Returns the relative mismatch."""
    lam = np.zeros(frame.n_constraints)
    n = frame.n_dofs
    lay = frame.current_layout()
    data = np.array(lay.linear_data)
    r0, info = frame.evaluate(q, motion.velocity(q), 0.0, lam, reference_force=True,
                              data=data, layout=lay)
    q1, Rm = rotated(frame, q, axis, angle, center)
    r1, _ = frame.evaluate(q1, motion.velocity(q1), angle / np.linalg.norm(motion.omega), lam,
                           layout=lay)
    turned = frame.rotate(r0[:n], Rm)
    round_off = (np.abs(lay.matrix(data).diagonal()[:n]).max() * np.finfo(float).eps
                 * np.abs(q).max() / EQUIVARIANCE_TOL)
    mismatch = np.linalg.norm(r1[:n] - turned) / max(info["force_ref"], round_off, 1e-300)
    if mismatch > EQUIVARIANCE_TOL:
        raise ValueError(
            "solve_steady: the loads are not constant in the rotating frame (turning the "
            f"system by {angle} rad about the spin axis changes its forces by {mismatch:.3g} "
            "of the largest force, e.g. a load across the spin axis, such as a solar wind "
            "oblique to it): no relative equilibrium exists; simulate the system instead")
    return mismatch


def frame_rates(system):
    """The angular velocities (rad/s) of the rotating frames that the loads of ``system``
    model (the loads' declared ``frame_rate``: ``add_centrifugal``)."""
    return [np.asarray(load.frame_rate, dtype=float) for load in system.loads
            if getattr(load, "frame_rate", None) is not None]


def rotating_frame(system, omega, center=(0.0, 0.0, 0.0)):
    """A copy of ``system`` in the frame rotating at ``omega`` about the axis through
    ``center``: its loads and constraints lists copied, a ``Centrifugal`` load added
    (``system`` is left unchanged)."""
    frame = copy.copy(system)
    frame.loads, frame.constraints = list(system.loads), list(system.constraints)
    return frame.add_load(Centrifugal(omega, center))


def check_space_fixed(system, omega, t=0.0):
    """Raise ``ValueError`` naming the loads of ``system`` whose force is fixed in space
    (the loads' declared ``space_fixed_force(t)``: a constant point or line load, uniform
    gravity) and has a component across the spin axis of ``omega``: such a force does
    not turn with the rotating frame, so no relative equilibrium exists (a constant drag
    on an orbiting tether is one: it decelerates the orbit)."""
    axis = omega / np.linalg.norm(omega)
    across = []
    for load in system.loads:
        fixed = getattr(load, "space_fixed_force", None)
        if fixed is None:
            continue
        f = np.asarray(fixed(t), dtype=float)
        side = f - (f @ axis) * axis
        if np.linalg.norm(side) > EQUIVARIANCE_TOL * np.linalg.norm(f):
            across.append(f"{load!r} (across the axis: {side.tolist()})")
    if across:
        raise ValueError(
            f"solve_steady: the loads are not constant in the rotating frame: "
            f"{'; '.join(across)} fixed in space (constant in the inertial frame, so "
            f"turning in the frame rotating at omega = {omega.tolist()} rad/s) across the "
            "spin axis: no relative equilibrium exists; give them along the axis, or "
            "simulate the system")


def solve_steady(system: IntegrableSystem, omega, center=(0.0, 0.0, 0.0), initial=None,
                 load_steps=1, tol=1e-10, max_iter=30, method="auto"):
    """Relative equilibrium of ``system`` spinning at ``omega`` about the axis through
    ``center``: statics in the rotating frame (elastic, centrifugal and constant loads),
    with the gauge conditions of a system free to translate along or turn about the axis
    (module docstring; derivation in ``docs/theory.md``).

    Parameters
    ----------
    system : System
        Without a ``Centrifugal`` load (it is added here, in a copy of the system).
    omega : array_like (3,)
        Angular velocity (rad/s), non-zero.
    center : array_like (3,)
        A point of the spin axis (m); a system free to translate along the axis has its
        centre of mass held at the plane through ``center`` normal to the axis.
    initial : State, optional
        Starting guess (default: the bodies' initial coordinates); it also fixes the phase
        about the axis of a system free to turn about it.
    load_steps, tol, max_iter, method
        As in ``solve_static`` (the load factor scales the loads, centrifugal included).

    Returns
    -------
    State
        Coordinates, multipliers of ``system``'s constraints, and velocities ``v`` of the
        rigid rotation (a dynamic run started from it is at rest in the rotating frame).
        ``stats`` holds those of ``solve_static`` and ``gauges`` (names of the gauge
        conditions used), ``frame_acceleration`` (m/s^2, along the axis: the net axial
        load over the total mass, e.g. the thrust of a solar-wind sail),
        ``phase_torque`` (N m, the torque about the axis holding the phase: zero to
        round-off, else ``StaticConvergenceError``), ``equivariance`` (relative change of
        the forces under a turn about the axis: round-off for loads constant in the
        rotating frame).

    Raises
    ------
    ValueError
        Bad ``omega``/``center``, a system that already has a ``Centrifugal`` load, or
        loads that are not constant in the rotating frame (e.g. a wind across the axis;
        a load that declares a force fixed in space, ``space_fixed_force``, across the
        axis is named: a constant drag on an orbiting tether, gravity across the axis).
    StaticConvergenceError
        Newton did not converge, or the loads have a net torque about the axis.

    Examples
    --------
    A free tether with tip masses at both ends spinning about its centre: no support, so
    the axial position of the centre of mass and the phase are held by gauge conditions,
    whose multipliers vanish (no net force or torque).  The tension at the centre is
    ``m Omega^2 r + mu Omega^2 r^2 / 2 = 4.2 N`` (``r = 1 m``, stretched by 4e-5):

    >>> import numpy as np, skfem_cable as sc
    >>> sec = sc.Section(E=1e9, A=1e-4, I=1e-10, rho=1000.0)
    >>> cable = sc.Cable.straight([-1, 0, 0], [1, 0, 0], 4, sec)
    >>> system = sc.System([cable]).add_point_mass(cable.node(0), 1.0)
    >>> system = system.add_point_mass(cable.node(-1), 1.0)
    >>> state = sc.solve_steady(system, [0, 0, 2.0])
    >>> state.stats["gauges"], round(float(state.tension(cable, 1.0)), 3)
    (['axial centre of mass', 'spin phase'], 4.2)
    >>> bool(np.allclose(state.v[:3], [0, 2 * state.q[0], 0]))       # omega x r
    True
    """
    omega = vector3(omega, "omega")
    center = vector3(center, "center")
    if not np.linalg.norm(omega) > 0:
        raise ValueError("omega must be a non-zero angular velocity (rad/s); use "
                         "solve_static for a system at rest")
    if frame_rates(system):
        raise ValueError("system already has a Centrifugal load: solve_steady adds its own "
                         "(remove add_centrifugal, or use solve_static)")
    check_space_fixed(system, omega)
    system.current_layout()  # the system as it is now (gauge_constraints uses it)
    q0 = system.q0 if initial is None else np.asarray(initial.q, dtype=float)
    gauges, mass = gauge_constraints(system, q0, omega, center)
    frame = rotating_frame(system, omega, center)
    for gauge in gauges:
        frame.add_constraint(gauge)
    if gauges:
        # the gauge rows join every body, which would make each a hub of the bordered
        # band ordering (``Layout.border``): no band fits, the linear solver is SuperLU
        frame.layout.border = np.zeros(0, dtype=np.int64)
        frame.layout.junctions = np.zeros(0, dtype=np.int64)
    motion = RigidRotation(system, omega, center)
    axis = omega / np.linalg.norm(omega)
    equivariance = check_equivariance(frame, motion, q0, axis, center)
    n_c = system.n_constraints
    lam0 = np.zeros(frame.n_constraints)
    if initial is not None and len(initial.lam) == n_c:
        lam0[:n_c] = initial.lam
    state = equilibrium(frame, load_steps, tol, max_iter, State(frame, q0, lam0),
                        method=method, motion=motion)
    q, lam = state.q, state.lam
    mu = dict(zip([g.name for g in gauges], lam[n_c:]))
    stats = dict(state.stats, gauges=[g.name for g in gauges], equivariance=equivariance,
                 frame_acceleration=axis * mu.get("axial centre of mass", 0.0) / mass,
                 phase_torque=0.0)
    if "spin phase" in mu:
        phase = gauges[-1]
        R = system.rigid_motion_velocity(q, axis, center)[phase.dofs(system)]
        stats["phase_torque"] = float(mu["spin phase"] * (R @ phase.J[0]))
        _check_torque(frame, state, stats["phase_torque"])
    return State(system, q, lam[:n_c], stats, v=motion.velocity(q))


def _check_torque(frame, state, torque):
    """Raise ``StaticConvergenceError`` when the phase condition holds a torque about the
    axis (above ``TORQUE_TOL``): the loads turn the system, no steady spin exists."""
    _, info = frame.evaluate(state.q, None, 0.0, state.lam, reference_force=True)
    size = frame.layout.length_scale
    if abs(torque) > TORQUE_TOL * info["force_ref"] * size:
        raise StaticConvergenceError(
            f"solve_steady: the loads exert a net torque of {torque:.6g} N m about the spin "
            "axis (held by the phase condition): the spin rate cannot stay constant, no "
            "relative equilibrium exists; simulate the system instead", state)


def at_rest_in_orbit(free, system, orbit):
    """The relative equilibrium of ``free`` at rest in the frame orbiting with ``orbit``
    (``solve_steady`` at the orbit's rate, ``Orbit.angular_velocity``), as a ``State`` of
    ``system``: the same bodies, with the loads ``free`` leaves out (a Lorentz force, drag,
    a brake: no equilibrium with them), moving with the orbiting frame."""
    omega = orbit.angular_velocity(0.0)
    steady = solve_steady(free, omega=omega)
    return State(system, steady.q, steady.lam,
                 v=system.rigid_motion_velocity(steady.q, omega))
