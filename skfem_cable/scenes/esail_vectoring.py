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
the sailing angle.

``OnOffModulation`` is that controller, sampling the tethers' phases (``sensors``);
``thrust_vectoring`` runs the sail with it (or with constant voltages) and returns the
mean thrust over whole rotations.
"""

from dataclasses import replace

import numpy as np

from .. import sensors
from ..control import Controller
from ..inputs import Input
from ..solvers.simulate import simulate
from . import esail

#: Mode names of ``thrust_vectoring``.
MODES = ("constant", "on-off")


class OnOffModulation(Controller):
    """Full voltage ``voltage`` on the tethers within ``half_width`` (rad) of the plane of
    the wind and the sail's normal, none on the others; sets the input ``voltages``.

    Parameters
    ----------
    scene : esail.ESailScene
        The sail (its hub, tethers and the Sun's position).
    voltage : float
        The voltage (V) of a tether that is on.
    half_width : float
        Half width (rad) of each of the two thrusting arcs, in (0, pi / 2].
    sample_time : float
        Seconds between samples.
    """

    def __init__(self, scene, voltage, half_width, sample_time):
        super().__init__(sample_time)
        if not 0.0 < half_width <= np.pi / 2:
            raise ValueError(f"half_width must lie in (0, pi/2] rad, got {half_width!r}")
        self.scene, self.voltage, self.half_width = scene, float(voltage), float(half_width)

    def update(self, t, state):
        hub = self.scene.hub
        axes = hub.rotation(state.q[state.system.dofs(hub)])
        wind = -self.scene.wind_force.sun_at(t)  # from the Sun to the sail's origin
        in_plane = wind - (wind @ axes[:, 0]) * axes[:, 0]
        phase_p = np.arctan2(in_plane @ axes[:, 2], in_plane @ axes[:, 1])
        phi = sensors.tether_phase(state, self.scene.tethers, hub) - phase_p
        on = np.abs(np.cos(phi)) >= np.cos(self.half_width)
        return {"voltages": np.where(on, self.voltage, 0.0)}


def thrust_vectoring(alpha_deg, mode, half_width_deg=45.0, n_elements=2, dt=1.0,
                     rotations=3, settle=2):
    """The sail at sailing angle ``alpha_deg`` (deg) with its voltages ``mode``
    (``"constant"``: 20 kV on every tether; ``"on-off"``: ``OnOffModulation`` with arcs of
    half width ``half_width_deg``, sampling every step) for ``settle + rotations`` spin
    periods.

    Returns
    -------
    dict
        ``thrust_angle_deg``: angle between the mean thrust over the last ``rotations``
        periods and the wind; ``thrust_N``: its magnitude; ``duty``: the mean fraction of
        tethers on; ``result``: the run.
    """
    if mode not in MODES:
        raise ValueError(f"mode must be one of {MODES}, got {mode!r}")
    config = esail.BaselineConfig()
    voltages = Input("voltages", np.full(config.n_tethers, config.voltage))
    scene = esail.build(replace(config, voltage=voltages), alpha_deg, n_elements)
    controllers = []
    if mode == "on-off":
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
