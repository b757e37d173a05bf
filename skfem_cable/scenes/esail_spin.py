"""The E-sail's spin rate at a fixed sailing angle around the Sun, free and held by the
remote units' thrusters (``esail.SpinController``).

The sail's normal is held on a direction fixed in the orbiting frame by
``esail_attitude.AttitudeHold``; Toivanen and Janhunen (J. Propulsion and Power 29
(2013) 178-185) show that its spin then rises when it spirals outward and falls when it
spirals inward, at ``(1/omega) d omega/dt = Omega tan(alpha)`` for a rigid flat sail
(``docs/esail.md``, "Spin control").  A positive sailing angle here leans the thrust
forward along the orbit (outward), a negative one backward (inward).
"""

from dataclasses import replace

import numpy as np

from ..control import sensors
from ..core.inputs import Input
from ..solvers.simulate import simulate
from ..space.constants import AU, MU_SUN
from ..space.orbit import Orbit
from . import esail
from .esail_attitude import AttitudeHold


def spin_scene(alpha_deg, n_tethers=12, n_elements=2, radius=AU, thrust_max=1e-3):
    """The baseline sail with ``n_tethers`` on the circular orbit of ``radius`` (m) about
    the Sun at the sailing angle ``alpha_deg`` (deg; > 0: its thrust leans forward along
    the orbit), its voltages an input ``voltages`` and its remote units' thrusters
    (``esail.RemoteUnitThrust``, up to ``thrust_max`` N each) an input ``thrust``.

    Returns
    -------
    (esail.ESailScene, esail.RemoteUnitThrust)
    """
    config = esail.BaselineConfig(n_tethers=n_tethers)
    voltages = Input("voltages", np.full(n_tethers, config.voltage))
    # ``build`` leans the sail so that its thrust leans forward along the circular orbit
    # (turning counter-clockwise about +z) for alpha > 0
    scene = esail.build_orbit(replace(config, voltage=voltages), alpha_deg, n_elements,
                              orbit=Orbit(MU_SUN, radius))
    thrusters = esail.RemoteUnitThrust(esail.tip_points(scene), scene.hub,
                                       Input("thrust", np.zeros(n_tethers)), thrust_max)
    scene.system.add_load(thrusters)
    return esail.settled(scene), thrusters


def hold_spin(scene, thrusters, days=1.0, controlled=True, dt=1.0, time_constant=3600.0,
              sample_time=10.0, attitude_gain=3e-6, every=600, target=None):
    """Run the sail of ``spin_scene`` for ``days`` with its sailing angle held
    (``AttitudeHold``, gain ``attitude_gain`` 1/s, the normal held where it starts in the
    orbiting frame) and its spin rate free or held (``controlled``:
    ``esail.SpinController`` with ``time_constant`` s, on ``target``: default, the spin
    rate at the start).

    Returns
    -------
    dict
        ``t`` (days), ``spin_rate`` (rad/s, the sail's: ``sensors.sail_spin_rate``),
        ``target`` (rad/s, at the saved steps), ``sail_angle`` (deg), ``thrust`` (N, each
        unit's, held at the saved steps), ``result``.
    """
    state = scene.initial
    normal = sensors.sail_normal(state, scene.tethers, scene.hub)
    voltage = float(np.mean(scene.config.voltage.initial))
    controllers = [AttitudeHold(scene, voltage, scene.orbit.to_lvlh(0.0, normal),
                                attitude_gain, sample_time)]
    spin = esail.SpinController(scene, thrusters, target, time_constant=time_constant,
                                sample_time=sample_time)
    if controlled:
        controllers.append(spin)
    result = simulate(scene.system, days * 86400.0, dt, initial=state, rho_inf=0.25,
                      every=every, controllers=controllers)
    rate, angle = [], []
    for k in range(len(result)):
        s = result.state(k)
        rate.append(sensors.sail_spin_rate(s, scene.tethers, scene.hub))
        wind = scene.orbit.position(float(s.t))
        angle.append(np.degrees(sensors.sail_angle(s, scene.tethers, wind, scene.hub)))
    return {"t": result.t / 86400.0, "spin_rate": np.array(rate),
            "target": np.array([spin.target_at(float(t)) for t in result.t]),
            "sail_angle": np.array(angle), "thrust": result.inputs["thrust"][:, 0],
            "result": result}


def drift_rate(t_days, spin):
    """Relative spin-rate drift ``(1/omega) d omega/dt`` (1/s): the least-squares slope
    of ``ln(omega / omega_0)`` against time."""
    return float(np.polyfit(np.asarray(t_days) * 86400.0, np.log(spin / spin[0]), 1)[0])


def rigid_drift(alpha_deg, radius=AU):
    """The rigid flat sail's drift ``Omega tan(alpha)`` (1/s) on the circular orbit of
    ``radius`` (m): > 0 spiralling outward (alpha > 0), < 0 inward."""
    return float(np.sqrt(MU_SUN / radius**3) * np.tan(np.radians(alpha_deg)))
