"""Thrust vectoring of the E-sail by voltage modulation (``control``): the paper's
12-tether sail at a sailing angle, its tethers' voltages either constant or switched on
only over two arcs of each rotation.

Each tether element feels the wind's component perpendicular to it (Eqs. 29-32).  With
the sail normal ``n`` tilted by ``alpha`` from the wind ``u = cos(alpha) n - sin(alpha)
p`` (``p`` in the spin plane), a tether at azimuth ``phi`` from ``p`` is pushed along
``cos(alpha) n - sin(alpha) sin(phi)^2 p``: along the normal where the tether lies in the
plane of the wind and the normal (``phi = 0, pi``), along the wind where it is
perpendicular to that plane.  With constant voltages the spin averages ``sin^2`` to 1/2
and the thrust leans from the wind by about half the sailing angle (the paper's 4.96 deg at
10 deg).  The *on-off modulation* of Toivanen, Janhunen and Envall ("Electric sail control
mode for amplified transverse thrust", Acta Astronautica 106 (2015) 111-119,
doi:10.1016/j.actaastro.2014.10.031, the paper's Ref. 19) applies the full voltage only
over two thrusting arcs of the rotation, where most of the transverse thrust is produced
(here: within ``half_width`` of ``phi = 0`` and ``pi``), and the thrust then leans by about
the sailing angle.  (The E-sail paper calls the unmodulated operation "continuous
modulation": our constant voltages.)  Between the two, a *smooth modulation* weights each
tether's force by ``cos(phi)^2``, the continuous counterpart of the arcs: the spin then
averages ``sin^2`` under that weight to 1/4, and the thrust leans from the normal by
``atan(tan(alpha) / 4)`` (7.48 deg from the wind at 10 deg).

``PhaseModulation`` is the controller of such modulations (its hook ``weight(phi)``, the
fraction of the full force a tether at azimuth ``phi`` gets), sampling the tethers'
phases (``sensors``); ``OnOffModulation`` and ``SmoothModulation`` are the two above.
``thrust_vectoring`` runs the sail with one of them (or with constant voltages) and
returns the mean thrust over whole rotations.
"""

from dataclasses import replace

import numpy as np

from ..control import sensors
from ..control.controller import Controller
from ..core.inputs import Input
from ..solvers.simulate import simulate
from . import esail

#: Mode names of ``thrust_vectoring``.
MODES = ("constant", "smooth", "on-off")


class PhaseModulation(Controller):
    """Modulates each tether's voltage with its azimuth ``phi`` from the plane of the wind
    and the sail's normal, sampled from the state: the voltage giving the fraction
    ``weight(phi)`` in [0, 1] of the full force of ``voltage`` (the force grows linearly
    above the threshold ``V1``, Eq. 29: ``V1 + (voltage - V1) weight``), and none where
    the weight is 0.  Sets the input ``voltages``; subclasses give ``weight``.

    Parameters
    ----------
    scene : esail.ESailScene
        The sail (its hub, tethers and the Sun's position).
    voltage : float
        The voltage (V) of a tether at full force.
    sample_time : float
        Seconds between samples.
    """

    def __init__(self, scene, voltage, sample_time):
        super().__init__(sample_time)
        self.scene, self.voltage = scene, float(voltage)
        self.threshold = scene.wind_force.wind.V1

    def weight(self, phi):
        """The hook: the fraction of the full force (array like ``phi``, in [0, 1])."""
        raise NotImplementedError(f"{type(self).__name__} must define weight(phi)")

    def update(self, t, state):
        hub = self.scene.hub
        axes = hub.rotation(state.q[state.system.dofs(hub)])
        wind = -self.scene.wind_force.sun_at(t)  # from the Sun to the sail's origin
        in_plane = wind - (wind @ axes[:, 0]) * axes[:, 0]
        phase_p = np.arctan2(in_plane @ axes[:, 2], in_plane @ axes[:, 1])
        w = self.weight(sensors.tether_phase(state, self.scene.tethers, hub) - phase_p)
        return {"voltages": np.where(w > 0, self.threshold + (self.voltage - self.threshold) * w,
                                     0.0)}


class OnOffModulation(PhaseModulation):
    """Full voltage on the tethers within ``half_width`` (rad, in (0, pi / 2]) of the
    plane of the wind and the sail's normal, none on the others."""

    def __init__(self, scene, voltage, half_width, sample_time):
        super().__init__(scene, voltage, sample_time)
        if not 0.0 < half_width <= np.pi / 2:
            raise ValueError(f"half_width must lie in (0, pi/2] rad, got {half_width!r}")
        self.half_width = float(half_width)

    def weight(self, phi):
        return (np.abs(np.cos(phi)) >= np.cos(self.half_width)).astype(float)


class SmoothModulation(PhaseModulation):
    """The force of each tether weighted by ``cos(phi)^2``: full in the plane of the wind
    and the normal, none across it."""

    def weight(self, phi):
        return np.cos(phi) ** 2


def thrust_vectoring(alpha_deg, mode, half_width_deg=45.0, n_elements=2, dt=1.0,
                     rotations=3, settle=2):
    """The sail at sailing angle ``alpha_deg`` (deg) with its voltages ``mode``
    (``"constant"``: 20 kV on every tether; ``"smooth"``: ``SmoothModulation``;
    ``"on-off"``: ``OnOffModulation`` with arcs of half width ``half_width_deg``; both
    sampling every step) for ``settle + rotations`` spin periods.

    Returns
    -------
    dict
        ``thrust_angle_deg``: angle between the mean thrust over the last ``rotations``
        periods and the wind; ``thrust_N``: its magnitude; ``duty``: the mean voltage over
        the full one; ``result``: the run.
    """
    if mode not in MODES:
        raise ValueError(f"mode must be one of {MODES}, got {mode!r}")
    config = esail.BaselineConfig()
    voltages = Input("voltages", np.full(config.n_tethers, config.voltage))
    scene = esail.build(replace(config, voltage=voltages), alpha_deg, n_elements)
    controllers = []
    if mode == "smooth":
        controllers.append(SmoothModulation(scene, config.voltage, dt))
    elif mode == "on-off":
        controllers.append(OnOffModulation(scene, config.voltage,
                                           np.deg2rad(half_width_deg), dt))
    period = config.spin_period
    steps = int(np.ceil((settle + rotations) * period / dt))
    every = max(1, int(round(10.0 / dt)))
    steps = int(np.ceil(steps / every)) * every
    result = simulate(scene.system, steps * dt, dt, initial=scene.initial, rho_inf=0.25,
                      every=every, controllers=controllers)
    thrust_O = esail.outputs(scene, result)["thrust_O"]  # with the recorded voltages
    last = result.t >= result.t[-1] - rotations * period
    thrust = thrust_O[last].mean(axis=0)
    angle = np.degrees(np.arctan2(np.hypot(thrust[0], thrust[1]), thrust[2]))
    return {"thrust_angle_deg": float(angle), "thrust_N": float(np.linalg.norm(thrust)),
            "duty": float(result.inputs["voltages"][last].mean() / config.voltage),
            "result": result}
