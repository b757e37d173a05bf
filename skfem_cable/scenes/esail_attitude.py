"""Attitude hold of the E-sail around the Sun by voltage modulation (``control``).

A spinning sail keeps its spin axis fixed in inertial space, so on its orbit the sailing
angle drifts with the orbit's turn (about 1 deg per day at 1 AU).  Holding the angle takes
a torque that turns the angular momentum ``H = h n`` with the orbiting frame:
``dH/dt = h (omega_orbit x n* + k (n* - (n . n*) n))`` for the commanded normal ``n*``
(fixed in the orbiting frame) and a gain ``k`` (1/s) on the error.  A tether ``j`` at the
in-plane direction ``t_j`` whose voltage is raised by the fraction ``m_j`` adds the moment
``m_j F r (t_j x n)`` (its Coulomb force ``F`` along the normal at the arm ``r``); with
``m_j = g (t_j x n) . tau`` the twelve tethers give ``6 g F r tau`` (the in-plane
projector averages 1/2 over equally spaced tethers), so ``g = 1 / (6 F r)`` for the
torque ``tau``.  The voltages are modulated with each tether's rotation phase (sampled
from the state), the phase-synchronous modulation of Toivanen and Janhunen ("Spin plane
control and thrust vectoring of electric solar wind sail", J. Propulsion and Power 29
(2013) 178-185, the E-sail paper's Ref. 8).

``AttitudeHold`` is the controller; ``hold_sail_angle`` runs the sail with and without it.
"""

from dataclasses import replace

import numpy as np

from ..control import sensors
from ..control.controller import Controller
from ..core.inputs import Input
from ..solvers.simulate import simulate
from . import esail


class AttitudeHold(Controller):
    """Holds the sail's normal on ``target_lvlh`` (a unit vector in the orbiting frame) by
    modulating the input ``voltages`` around ``voltage``.

    Parameters
    ----------
    scene : esail.ESailScene
        The sail on its orbit.
    voltage : float
        The mean voltage (V).
    target_lvlh : array_like (3,)
        The commanded normal in the orbiting frame.
    gain : float
        ``k`` (1/s): the error's rate of decay.
    sample_time : float
        Seconds between samples.
    """

    def __init__(self, scene, voltage, target_lvlh, gain, sample_time):
        super().__init__(sample_time)
        self.scene, self.voltage, self.gain = scene, float(voltage), float(gain)
        self.target = np.asarray(target_lvlh, dtype=float) / np.linalg.norm(target_lvlh)
        config = scene.config
        arm = 0.5 * config.tether_length
        force = config.wind.force_per_length(self.voltage) * config.tether_length
        self.per_torque = 1.0 / (0.5 * config.n_tethers * force * arm)  # g of the docstring
        # the moment of inertia about the spin axis (kg m^2): remote units, and tethers as
        # straight rods from the hub's rim
        L, R = config.tether_length, config.hub_radius
        tether = config.section.mass_per_length * L
        self.inertia = config.n_tethers * (config.remote_mass * (R + L) ** 2
                                           + tether * (R**2 + R * L + L**2 / 3))

    def update(self, t, state):
        scene, hub, orbit = self.scene, self.scene.hub, self.scene.orbit
        normal = sensors.sail_normal(state, scene.tethers, hub)
        h = sensors.spin_rate(state, hub) * self.inertia
        target = orbit.from_lvlh(float(t), self.target)
        rate = orbit.angular_velocity(float(t))
        torque = h * (np.cross(rate, target) + self.gain * (target - (normal @ target) * normal))
        torque -= (torque @ normal) * normal  # in the spin plane
        radial = sensors.tether_arms(state, scene.tethers, hub)
        radial -= np.outer(radial @ normal, normal)
        radial /= np.linalg.norm(radial, axis=1, keepdims=True)
        fraction = self.per_torque * (np.cross(radial, normal) @ torque)
        return {"voltages": self.voltage * np.clip(1.0 + fraction, 0.0, 2.0)}


def hold_sail_angle(alpha_deg=30.0, days=5.0, controlled=True, n_elements=2, dt=1.0,
                    gain=3e-6, sample_time=10.0, every=600):
    """The sail on the circular orbit of 1 AU at sailing angle ``alpha_deg`` for ``days``,
    with ``AttitudeHold`` (``controlled``) or constant voltages.

    Returns
    -------
    dict
        ``t`` (days), ``sail_angle`` (deg), ``spin_rate`` (rad/s) at the saved steps,
        ``result``.
    """
    config = esail.BaselineConfig()
    voltages = Input("voltages", np.full(config.n_tethers, config.voltage))
    scene = esail.build_orbit(replace(config, voltage=voltages), alpha_deg, n_elements)
    controllers = []
    if controlled:
        state = scene.initial
        normal = sensors.sail_normal(state, scene.tethers, scene.hub)
        target = scene.orbit.to_lvlh(0.0, normal)
        controllers.append(AttitudeHold(scene, config.voltage, target, gain, sample_time))
    result = simulate(scene.system, days * 86400.0, dt, initial=scene.initial,
                      rho_inf=0.25, every=every, controllers=controllers)
    angle, spin = [], []
    for k in range(len(result)):
        state = result.state(k)
        wind = scene.orbit.position(float(state.t))
        angle.append(np.degrees(sensors.sail_angle(state, scene.tethers, wind, scene.hub)))
        spin.append(sensors.spin_rate(state, scene.hub))
    return {"t": result.t / 86400.0, "sail_angle": np.array(angle),
            "spin_rate": np.array(spin), "result": result}
