"""The ``esail-rig`` scene: the full E-sail rig (``esail.FULL_RIG``: remote units and the
ring of auxiliary tethers) under on-off voltage modulation for one spin period."""

from dataclasses import replace

import numpy as np

from ..runner.drive import RunScene
from . import esail
from .esail.modulation import alternating_voltage, modulated


def scene(tethers=100, alpha=10.0, elements=4, ring=True, steps_per_spin=180, every=10):
    """``tethers`` tethers of ``esail.FULL_RIG`` (``elements`` each) at sailing angle
    ``alpha`` (deg), with the ring of auxiliary tethers or (``ring`` False) the remote
    units alone, from the state under the wind (``esail.settled``, one spin period of
    relaxation), run for one spin period with on-off modulation, neighbours in antiphase
    (``esail.modulation.alternating_voltage``), in steps of a ``steps_per_spin``-th of a
    period (rho_inf = 0.5), every ``every``-th saved.  Outputs: ``spacing_min_ratio``
    (the least distance of neighbouring units over the nominal spacing),
    ``auxiliary_tension_min_N`` and ``auxiliary_tension_max_N`` (over the ring and the
    saved steps; absent without the ring)."""
    config = replace(esail.FULL_SIZE, n_tethers=tethers)
    rig = replace(esail.FULL_RIG, config=config)
    built = rig.build(alpha, elements) if ring else \
        esail.build(config, alpha, elements, remote_units=rig.remote_units)
    start = esail.settled(built, spins=1.0)
    period = config.spin_period
    run = modulated(start, alternating_voltage(tethers, config.voltage, period))
    nominal = esail.tip_spacing(start, start.initial.q).mean()

    def outputs(result):
        numbers = {"spacing_min_ratio": float(esail.tip_spacing(start, result.q).min()
                                              / nominal)}
        if ring:
            tension = np.array([esail.auxiliary_tension(start, q) for q in result.q])
            numbers.update(auxiliary_tension_min_N=float(tension.min()),
                           auxiliary_tension_max_N=float(tension.max()))
        return numbers

    settings = {"t_end": period, "dt": period / steps_per_spin, "every": every,
                "rho_inf": 0.5}
    parameters = {"tethers": tethers, "alpha_deg": alpha, "elements_per_tether": elements,
                  "ring": ring, "auxiliary_tension_design_N": rig.auxiliary_tension,
                  "remote_unit_mass": rig.remote_units.mass}
    return RunScene("esail-rig", run.system, run.initial, settings, parameters,
                    outputs=outputs)


def run(options):
    """``skfem-cable run esail-rig`` (``--alpha``, ``--elements``)."""
    return scene(alpha=options.value("alpha", 10.0),
                 elements=options.value("elements", 4)).run(options)
