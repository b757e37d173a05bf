"""Spin-rate control with the remote units' thrusters (``SpinController``).

A sail held at a fixed sailing angle on its orbit spins up when it spirals outward and
down when it spirals inward (Toivanen and Janhunen, "Spin plane control and thrust
vectoring of electric solar wind sail", J. Propulsion and Power 29 (2013) 178-185): the
voltage modulation that turns the spin plane with the orbit also torques the spin, by
``tan(alpha)`` times the turning torque, so ``(1/omega) d omega/dt = Omega tan(alpha)``
for a rigid flat sail (``docs/esail.md``, "Spin control").  ``SpinController`` holds the
spin rate (or a profile ``omega*(t)``) against that drift with ``RemoteUnitThrust``.
"""

import numpy as np

from ...control import sensors
from ...control.controller import Controller


def spin_inertia(system, state, hub):
    """The moment of inertia (kg m^2) of ``system`` at ``state`` about the spin axis of
    ``hub`` (its first axis) through its centre of mass: ``u^T M u`` with ``u`` the
    velocities of a rigid turn about that axis at 1 rad/s."""
    d = state.q[system.dofs(hub)]
    axis = hub.rotation(d)[:, 0]
    centre = hub.positions(d, hub.center_of_mass)
    u = system.rigid_motion_velocity(state.q, axis, center=centre)
    return float(u @ (system.mass_matrix() @ u))


class SpinController(Controller):
    """Holds the sail's spin rate on ``target`` with the remote units' thrusters: a
    proportional-integral law on the spin-rate error ``e = omega* - omega``,

        tau = I (e + (1 / T_i) int e dt) / T_c,   T_j = tau / sum_j r_j,

    the same thrust at every unit, clipped to ``thrust_max`` (the integral is held while
    the thrust saturates and the error would drive it further).  The spin ``omega`` is the
    sail's (``sensors.sail_spin_rate``: the remote units' mean rate, without the hub's
    libration); the sail, ``I omega' = tau + tau_d``, closed by the law, has the
    characteristic equation ``s^2 + s / T_c + 1 / (T_c T_i) = 0``: the default ``T_i = 4
    T_c`` damps it critically, and a constant disturbing torque ``tau_d`` (the orbital
    drift) leaves no error.

    Parameters
    ----------
    scene : esail.ESailScene
        The sail (its tethers, whose tips are the remote units, and its hub).
    thrusters : RemoteUnitThrust
        The thrusters, whose thrust is an ``sc.Input`` of one value per unit (the
        controller's output).
    target : float or callable
        The spin rate to hold (rad/s, > 0), or a profile ``target(t)``; default: the
        sail's spin rate in ``scene.initial``.
    time_constant : float
        ``T_c`` (s), > 0: the error's rate of decay.
    integral_time : float, optional
        ``T_i`` (s), > 0 (default ``4 T_c``).
    sample_time : float
        Seconds between samples.
    delay : float
        Seconds from a sample to its thrust.
    """

    def __init__(self, scene, thrusters, target=None, time_constant=3600.0,
                 integral_time=None, sample_time=10.0, delay=0.0):
        super().__init__(sample_time, delay)
        inputs = thrusters.inputs()
        if len(inputs) != 1 or inputs[0].initial.shape != (len(thrusters.points),):
            raise ValueError("thrusters: their thrust must be one sc.Input of "
                             f"{len(thrusters.points)} values (one per unit), got {inputs!r}")
        self.input = inputs[0].name
        self.scene, self.thrust_max = scene, thrusters.thrust_max
        self.tips = list(scene.tethers)
        self.n_units = len(thrusters.points)
        for what, value in (("time_constant", time_constant),
                            ("integral_time", 4.0 * time_constant if integral_time is None
                             else integral_time)):
            if not (np.isfinite(value) and value > 0):
                raise ValueError(f"{what} must be a finite number of seconds > 0, got "
                                 f"{value!r}")
            setattr(self, what, float(value))
        system, state = scene.system, scene.initial
        self.target = (sensors.sail_spin_rate(state, self.tips, scene.hub)
                       if target is None else target)
        self.target_at(0.0)  # fail now, not in the middle of a run
        self.inertia = spin_inertia(system, state, scene.hub)
        self.levers = float(thrusters.levers(system, state.q).sum())
        self.memory["integral"] = 0.0

    def target_at(self, t):
        """The spin rate to hold at ``t`` (rad/s)."""
        value = float(self.target(t)) if callable(self.target) else float(self.target)
        if not (np.isfinite(value) and value > 0):
            raise ValueError(f"target must be a spin rate > 0 (rad/s), got {value!r} at "
                             f"t = {t!r} s")
        return value

    def update(self, t, state):
        error = self.target_at(t) - sensors.sail_spin_rate(state, self.tips, self.scene.hub)
        integral = self.memory["integral"]
        torque = self.inertia * (error + integral / self.integral_time) / self.time_constant
        thrust = torque / self.levers
        if abs(thrust) < self.thrust_max or error * thrust < 0:
            self.memory["integral"] = integral + error * self.sample_time
        thrust = float(np.clip(thrust, -self.thrust_max, self.thrust_max))
        return {self.input: np.full(self.n_units, thrust)}
