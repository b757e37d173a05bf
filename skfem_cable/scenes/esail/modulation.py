"""On-off voltage modulation of the rig's tethers and how close neighbouring remote units
come under it (issue 51, item 2)."""

from dataclasses import replace

import numpy as np

from ...solvers.simulate import simulate
from .rig import _build
from .ring import tip_spacing


def alternating_voltage(n_tethers, voltage, period):
    """On-off modulation with neighbours in antiphase, the hardest on the rig's spacing:
    one callable returning every tether's voltage at ``t``: even tethers at ``voltage``
    in the first half of each ``period`` and off in the second, odd tethers the
    reverse."""
    even = np.arange(n_tethers) % 2 == 0

    def voltages(t):
        first = (t % period) < period / 2
        return np.where(even == first, float(voltage), 0.0)

    return voltages


def modulated(scene, voltage):
    """``scene`` with the tethers' ``voltage`` replaced (a value, a sequence or callables,
    as ``BaselineConfig.voltage``), its ring and start kept."""
    rebuilt = _build(replace(scene.config, voltage=voltage), np.degrees(scene.alpha),
                     **scene.options)
    return replace(rebuilt, initial=scene.initial)


def spacing_under_modulation(scene, spins=1.0, steps_per_spin=90, rho_inf=0.5):
    """Run ``scene`` (from its ``initial`` state, e.g. ``settled``) for ``spins`` spin
    periods with ``alternating_voltage`` at the config's voltage (steps of a
    ``steps_per_spin``-th of a period) and return the distances between neighbouring
    remote units over the run divided by their nominal spacing (the chord between tips at
    the start), (n_saved, p), and the ``Result``."""
    cfg = scene.config
    period = cfg.spin_period
    on = modulated(scene, alternating_voltage(cfg.n_tethers, cfg.voltage, period))
    t0 = scene.initial.t
    result = simulate(on.system, t0 + spins * period, period / steps_per_spin,
                      rho_inf=rho_inf, initial=on.initial, t_start=t0)
    nominal = tip_spacing(scene, scene.initial.q).mean()
    return tip_spacing(scene, result.q) / nominal, result
