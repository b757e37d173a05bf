"""What closed-loop control costs per step (``control``): the paper's 12-tether E-sail (5
elements per tether, 10 deg, dt = 0.1 s) with its tether voltages modulated by each
tether's rotation phase, ``V_k = V0 (1 + m cos(phase_k))``, three ways side by side:

* ``open loop``: the voltages as functions of time, the phases computed from the nominal
  spin (``V0 (1 + m cos(zeta_k + omega t))``);
* ``controller``: the voltages as one ``Input`` (a value per tether) set by a
  ``Controller`` sampling at every step, the phases measured by ``sensors.tether_phase``
  on the state;
* ``controller, 1 s``: the same controller sampling every 10 steps.

Each wall time is the minimum over the repeats after a short run that compiles.  Goal:
a controller sampling every step costs at most ``GOAL`` times the open-loop run per step.

    OPENBLAS_NUM_THREADS=1 .venv/bin/python benchmarks/control_cost.py [--quick]
"""

import time
from dataclasses import replace

import numpy as np

import skfem_cable as sc
from skfem_cable.cli.bench import arguments
from skfem_cable.scenes import esail

SETTINGS = {"full": {"t_end": 600.0, "repeats": 3}, "quick": {"t_end": 60.0, "repeats": 3}}

#: Goal of the ratio of the controlled run's wall time to the open-loop one's.
GOAL = 1.2

DT, ALPHA, ELEMENTS, DEPTH = 0.1, 10.0, 5, 0.3


class PhaseModulation(sc.Controller):
    """Each tether's voltage follows its measured rotation phase (one input holding the
    12 voltages)."""

    def __init__(self, scene, sample_time):
        super().__init__(sample_time)
        self.scene, self.v0 = scene, esail.BaselineConfig().voltage

    def update(self, t, state):
        phase = sc.sensors.tether_phase(state, self.scene.tethers, self.scene.hub)
        return {"voltages": self.v0 * (1.0 + DEPTH * np.cos(phase))}


def build(voltages):
    config = esail.BaselineConfig()
    return esail.build(replace(config, voltage=voltages(config)), ALPHA, ELEMENTS)


def open_loop(config):
    zeta = 2 * np.pi * np.arange(config.n_tethers) / config.n_tethers
    omega, v0 = config.spin_rate, config.voltage
    return [lambda t, z=z: v0 * (1.0 + DEPTH * np.cos(z + omega * t)) for z in zeta]


def inputs(config):
    return sc.Input("voltages", np.full(config.n_tethers, config.voltage))


def best(scene, controllers, t_end, repeats):
    run = dict(dt=DT, initial=scene.initial, rho_inf=0.25, every=int(round(60 / DT)))
    sc.simulate(scene.system, t_end=10 * DT, controllers=controllers, **run)
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        result = sc.simulate(scene.system, t_end=t_end, controllers=controllers, **run)
        times.append(time.perf_counter() - start)
    return min(times), result


def main(argv=None):
    """Parse the arguments (``--quick``), run and return the figures."""
    quick = arguments(__doc__, "60 s instead of 600 s", argv).quick
    s = SETTINGS["quick" if quick else "full"]
    cases = {"open loop": (build(open_loop), lambda scene: [])}
    scene = build(inputs)
    cases["controller"] = (scene, lambda scene: [PhaseModulation(scene, DT)])
    slow = build(inputs)
    cases["controller, 1 s"] = (slow, lambda scene: [PhaseModulation(scene, 10 * DT)])
    print(f"12 tethers x {ELEMENTS} elements, {s['t_end']:g} s at dt = {DT} s, minimum of "
          f"{s['repeats']}")
    print("| case | wall [s] | ms/step | path |\n|---|---|---|---|")
    walls = {}
    for name, (scene, controllers) in cases.items():
        wall, result = best(scene, controllers(scene), s["t_end"], s["repeats"])
        walls[name] = wall
        print(f"| {name} | {wall:.2f} | {1e3 * wall / result.stats['steps']:.3f} | "
              f"{result.stats['path']} |")
    ratio = walls["controller"] / walls["open loop"]
    print(f"ratio controller (every step) / open loop: {ratio:.2f} (goal <= {GOAL})")
    return {"ratio": ratio, **walls}


if __name__ == "__main__":
    main()
