"""The scenes ``skfem-cable run`` knows by name.

An entry is a name, a one-line description and a runner ``fn(options) -> summary``: it
builds the scene, runs it into the run directory ``options.out`` (``runner.RunOptions``)
and returns the summary dict.  The runner may be given as a ``"module:function"`` string,
imported only when the scene runs, so that an entry can name a module that is slow to
import or needs optional pieces.  Adding a scene is one call::

    from skfem_cable.scenes import catalog
    catalog.register("my-scene", "mypackage.scenes:run", "what it shows")

``run_scene`` also accepts the path of a TOML scene file (``scene_file``).
"""

import importlib
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..analytic import elastica_tip_load
from ..runner import run_dynamic, run_static
from ..solvers.static import solve_static
from . import classics


@dataclass
class Entry:
    """A runnable scene: ``target`` is a callable or a ``"module:function"`` string."""

    name: str
    target: object
    help: str

    def runner(self):
        if callable(self.target):
            return self.target
        module, _, function = self.target.partition(":")
        return getattr(importlib.import_module(module), function)


SCENES = {}


def register(name, target, help):
    """Add (or replace) the scene ``name``; ``target(options) -> summary``."""
    SCENES[name] = Entry(name, target, help)


def run_scene(scene, options):
    """Run a registered scene by name, or a TOML scene file by path; returns the summary."""
    if scene in SCENES:
        return SCENES[scene].runner()(options)
    if scene.endswith(".toml") or Path(scene).is_file():
        from .. import scene_file

        return scene_file.run(scene, options)
    raise ValueError(f"unknown scene {scene!r}: use one of {', '.join(sorted(SCENES))} "
                     "or the path of a .toml scene file")


# --- built-in scenes -------------------------------------------------------------------------
def cantilever(options):
    """Static elastica: tip loads ``k = P L^2 / EI = 1, 2, 5, 10``, each solved from the
    straight cable (20 load steps) and compared with the exact elastica; the
    VTU series uses ``k`` as its time value, so ParaView steps through the loads.  The
    cable is locking-free unless ``--paper-formulation``: bending-dominated, it would
    otherwise report tension stripes tens of times the load."""
    options.reject("cantilever", "t_end", "dt", "every", "alpha")
    n = options.value("elements", 16)
    section = classics.ELASTICA_SECTION
    rows, steps = [], []
    for k in (1.0, 2.0, 5.0, 10.0):
        scene = classics.cantilever(n, k, locking_free=options.value("locking_free", True))
        system, cable = scene.system, scene.cable
        state = solve_static(system, load_steps=20)
        tip = state.position(cable, 1.0)
        u, w = 1.0 - tip[0], -tip[1]
        u_ref, w_ref = elastica_tip_load(k)
        rows.append({"k": k, "u": u, "u_exact": u_ref, "w": w, "w_exact": w_ref,
                     "rel_error": max(abs(u - u_ref) / u_ref, abs(w - w_ref) / w_ref)})
        steps.append((k, state))
    parameters = {"elements": n, "EA L^2/EI": section.EA / section.EI,
                  "locking_free": cable.locking_free}
    return run_static("cantilever", system, steps, options, parameters, {"elastica": rows},
                      title="cantilever, k = P L^2/EI = 10")


def pendulum(options):
    """Flexible pendulum released horizontally (``classics.pendulum``)."""
    options.reject("pendulum", "alpha")
    scene = classics.pendulum(n_elements=options.value("elements", 16),
                              locking_free=options.value("locking_free", False))
    return run_dynamic("pendulum", scene.system, scene.initial, options,
                       {"t_end": 1.0, "dt": 1e-3, "every": 10, "rho_inf": 0.8},
                       {"elements": scene.cable.n_elements, "length": scene.cable.length,
                        "locking_free": scene.cable.locking_free})[0]


def spinning_tether(options):
    """Tether with a tip mass spinning about z (``classics.spinning_tether``); the mean root
    tension is compared with the rigid rotating cable ``m W^2 L + rho A W^2 L^2 / 2``."""
    options.reject("spinning-tether", "alpha")
    spin, tip_mass = 2.0, 0.5
    scene = classics.spinning_tether(n_elements=options.value("elements", 10), spin=spin,
                                     tip_mass=tip_mass,
                                     locking_free=options.value("locking_free", False))
    cable = scene.cable
    L, mu = cable.length, cable.section.mass_per_length
    rigid = tip_mass * spin**2 * L + mu * spin**2 * L**2 / 2

    def outputs(result):
        mean = float(np.mean(result.tension(cable, 0.0)))
        return {"root_tension_mean": mean, "root_tension_rigid": rigid,
                "root_tension_rel_error": mean / rigid - 1}

    return run_dynamic("spinning-tether", scene.system, scene.initial, options,
                       {"t_end": 5.0, "dt": 5e-3, "every": 4, "rho_inf": 0.8},
                       {"elements": cable.n_elements, "spin": spin, "tip_mass": tip_mass,
                        "locking_free": cable.locking_free},
                       outputs)[0]


register("esail", "skfem_cable.scenes.esail:run",
         "E-sail baseline of the paper (12 tethers, 3 spin periods); --alpha sailing angle")
register("cantilever", cantilever,
         "static elastica under tip loads k = PL^2/EI = 1..10 against the exact solution")
register("pendulum", pendulum, "flexible pendulum released from horizontal under gravity")
register("spinning-tether", spinning_tether,
         "tether with a tip mass spinning at 2 rad/s, root tension against the rigid value")
register("hanging-chain", "skfem_cable.scenes.hanging_chain:run",
         "steel rod chain released from horizontal, against rigid links")
