"""The scenes ``skfem-cable run`` knows by name.

An entry is a name, a one-line description and a runner ``fn(options) -> summary``: it
builds the scene, runs it into the run directory ``options.out`` (``runner.RunOptions``)
and returns the summary dict.  The runner may be given as a ``"module:function"`` string,
imported only when the scene runs, so that an entry can name a module that is slow to
import or needs optional pieces.  Adding a scene is one call::

    from skfem_cable.scenes import catalog
    catalog.register("my-scene", "mypackage.scenes:run", "what it shows")

An entry that also names a ``build`` function (``build(**params) -> runner.RunScene``, a
module-level function, also as a ``"module:function"`` string) can be swept over its
parameters: ``skfem-cable sweep NAME --param NAME=V1,V2`` (``skfem_cable.study``).

``run_scene`` also accepts the path of a TOML scene file (``scene_file``).
"""

import importlib
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..runner.options import OPT_IN


def _resolve(target):
    """``target`` itself when callable, else the function a ``"module:function"`` string
    names (imported now)."""
    if callable(target):
        return target
    module, _, function = target.partition(":")
    return getattr(importlib.import_module(module), function)


@dataclass
class Entry:
    """A runnable scene: ``target`` (the runner) and ``build`` (the scene builder of
    sweeps, or None) are callables or ``"module:function"`` strings."""

    name: str
    target: object
    help: str
    build: object = None
    #: The opt-in options (``runner.options.OPT_IN``) the scene takes, e.g. ``("model",)``.
    takes: tuple = ()

    def runner(self):
        return _resolve(self.target)

    def builder(self):
        """The scene's ``build(**params) -> RunScene``; ``ValueError`` when it has none."""
        if self.build is None:
            sweepable = ", ".join(sorted(n for n, e in SCENES.items() if e.build is not None))
            raise ValueError(f"scene {self.name!r} cannot be swept (it has no build "
                             f"function): sweep one of {sweepable}")
        return _resolve(self.build)


SCENES = {}

def register(name, target, help, build=None, takes=()):
    """Add (or replace) the scene ``name``; ``target(options) -> summary``; ``build``:
    ``build(**params) -> RunScene`` for sweeps (optional); ``takes``: the options of
    ``runner.options.OPT_IN`` it accepts."""
    SCENES[name] = Entry(name, target, help, build, tuple(takes))


def builder(scene):
    """The build function of the registered scene ``scene`` (for ``sweep``)."""
    if scene not in SCENES:
        raise ValueError(f"unknown scene {scene!r}: use one of {', '.join(sorted(SCENES))}")
    return SCENES[scene].builder()


#: The opt-in options a scene file takes: ``--epoch`` (its ``[environment]`` epoch).
SCENE_FILES_TAKE = ("epoch",)


def run_scene(scene, options):
    """Run a registered scene by name, or a TOML scene file by path; returns the summary."""
    if scene in SCENES:
        entry = SCENES[scene]
        options.reject(scene, *(n for n in OPT_IN if n not in entry.takes))
        return entry.runner()(options)
    options.reject(scene, *(n for n in OPT_IN if n not in SCENE_FILES_TAKE))
    if scene.endswith(".toml") or Path(scene).is_file():
        from .. import scene_file

        return scene_file.run(scene, options)
    raise ValueError(f"unknown scene {scene!r}: use one of {', '.join(sorted(SCENES))} "
                     "or the path of a .toml scene file")


# --- built-in scenes -------------------------------------------------------------------------
# Each imports the model, the solvers and the runner itself: the catalog alone (the scenes'
# names for ``skfem-cable --help``) does without them.
def elastica_row(cable, k, state):
    """Tip displacements ``u`` (along the cable), ``w`` (along the load) of the cantilever
    ``cable`` (``classics.cantilever``, unit length) at ``state``, against the exact
    elastica of the load parameter ``k``, and their largest relative error."""
    from ..analysis.analytic import elastica_tip_load  # here: scipy.integrate costs 0.2 s

    tip = state.position(cable, 1.0)
    u, w = 1.0 - tip[0], -tip[1]
    u_ref, w_ref = elastica_tip_load(k)
    return {"k": k, "u": u, "u_exact": u_ref, "w": w, "w_exact": w_ref,
            "rel_error": max(abs(u - u_ref) / u_ref, abs(w - w_ref) / w_ref)}


def cantilever(options):
    """Static elastica: tip loads ``k = P L^2 / EI = 1, 2, 5, 10``, each solved from the
    straight cable (20 load steps) and compared with the exact elastica; the
    VTU series uses ``k`` as its time value, so ParaView steps through the loads
    (``--formulation paper`` shows the tension stripes of membrane locking)."""
    from ..runner.drive import run_static
    from ..solvers.static import solve_static
    from . import classics

    options.reject("cantilever", "t_end", "dt", "every")
    n = options.value("elements", 16)
    section = classics.ELASTICA_SECTION
    rows, steps = [], []
    for k in (1.0, 2.0, 5.0, 10.0):
        scene = classics.cantilever(n, k, formulation=options.formulation,
                                    element=options.element)
        state = solve_static(scene.system, load_steps=20)
        rows.append(elastica_row(scene.cable, k, state))
        steps.append((k, state))
    parameters = {"elements": n, "EA L^2/EI": section.EA / section.EI,
                  "formulation": scene.cable.formulation,
                  "element": scene.cable.element.name}
    return run_static("cantilever", scene.system, steps, options, parameters,
                      {"elastica": rows}, title="cantilever, k = P L^2/EI = 10")


def cantilever_point(elements=16, k=5.0, formulation=None, load_steps=20, element=None):
    """One point of the cantilever convergence study (``benchmarks/
    cantilever_convergence.py``) as a sweep's scene: ``elements`` elements, tip load
    ``k = P L^2 / EI``, solved in ``load_steps`` steps; run it with
    ``run_cantilever_point``."""
    from ..runner.drive import RunScene
    from . import classics

    scene = classics.cantilever(elements, k, formulation=formulation, element=element)
    return RunScene("cantilever", scene.system, scene.initial, {"load_steps": load_steps},
                    {"elements": elements, "k": k, "formulation": scene.cable.formulation,
                     "element": scene.cable.element.name})


def run_cantilever_point(scene, options):
    """Solve the ``cantilever_point`` scene and write its run directory (``run_static``);
    its outputs are ``elastica_row``'s: ``rel_error`` against the exact elastica."""
    from ..runner.drive import run_static
    from ..solvers.static import solve_static

    k = scene.parameters["k"]
    state = solve_static(scene.system, load_steps=scene.settings["load_steps"])
    row = elastica_row(scene.system.cables()[0], k, state)
    return run_static("cantilever", scene.system, [(k, state)], options, scene.parameters,
                      row, title=f"cantilever, k = {k:g}")


def pendulum_scene(elements=16, formulation=None, t_end=1.0, dt=1e-3, every=10,
                   element=None):
    """The ``pendulum`` scene (``classics.pendulum``) with ``elements`` cable elements of
    the type ``element`` (the default: None), run to ``t_end`` with step ``dt``, every
    ``every``-th step saved."""
    from ..runner.drive import RunScene
    from . import classics

    scene = classics.pendulum(n_elements=elements, formulation=formulation, element=element)
    return RunScene("pendulum", scene.system, scene.initial,
                    {"t_end": t_end, "dt": dt, "every": every, "rho_inf": 0.8},
                    {"elements": scene.cable.n_elements, "length": scene.cable.length,
                     "formulation": scene.cable.formulation,
                     "element": scene.cable.element.name})


def pendulum(options):
    """Flexible pendulum released horizontally (``classics.pendulum``)."""
    return pendulum_scene(options.value("elements", 16), options.formulation,
                          element=options.element).run(options)


def spinning_tether_scene(elements=10, formulation=None, spin=2.0, tip_mass=0.5, t_end=5.0,
                          dt=5e-3, every=4, element=None):
    """Tether with a tip mass spinning about z (``classics.spinning_tether``); its
    outputs compare the mean root tension with the rigid rotating cable
    ``m W^2 L + rho A W^2 L^2 / 2``."""
    from ..runner.drive import RunScene
    from . import classics

    scene = classics.spinning_tether(n_elements=elements, spin=spin, tip_mass=tip_mass,
                                     formulation=formulation, element=element)
    cable = scene.cable
    L, mu = cable.length, cable.section.mass_per_length
    rigid = tip_mass * spin**2 * L + mu * spin**2 * L**2 / 2

    def outputs(result):
        mean = float(np.mean(result.tension(cable, 0.0)))
        return {"root_tension_mean": mean, "root_tension_rigid": rigid,
                "root_tension_rel_error": mean / rigid - 1}

    return RunScene("spinning-tether", scene.system, scene.initial,
                    {"t_end": t_end, "dt": dt, "every": every, "rho_inf": 0.8},
                    {"elements": cable.n_elements, "spin": spin, "tip_mass": tip_mass,
                     "formulation": cable.formulation, "element": cable.element.name},
                    outputs)


def spinning_tether(options):
    """``spinning_tether_scene`` (2 rad/s, 0.5 kg tip mass) run by ``skfem-cable run``."""
    return spinning_tether_scene(options.value("elements", 10), options.formulation,
                                 element=options.element).run(options)


def esail_scene(alpha=10.0, voltage=20e3, elements=5, formulation=None, t_end=None, dt=0.1,
                every=50):
    """The baseline E-sail (``esail.build``, 12 tethers of ``elements`` cable elements) at
    sailing angle ``alpha`` (deg) and tether voltage ``voltage`` (V), run to ``t_end``
    (default three spin periods) with step ``dt`` (rho_inf = 0.25), every ``every``-th
    step saved: the scene ``skfem-cable sweep esail`` sweeps.  Its outputs
    (``esail_numbers``): mean thrust vector and magnitude, thrust angle, coning and
    lagging amplitudes, peak tether tension."""
    from ..runner.drive import RunScene
    from . import esail

    cfg = esail.BaselineConfig(voltage=voltage)
    scene = esail.build(cfg, alpha, elements, formulation=formulation)
    settings = {"t_end": 3 * cfg.spin_period if t_end is None else t_end, "dt": dt,
                "every": every, "rho_inf": 0.25, "series_every": 12}
    parameters = {"alpha_deg": alpha, "voltage": voltage, "elements_per_tether": elements,
                  "tethers": cfg.n_tethers, "formulation": scene.tethers[0].formulation}
    return RunScene("esail", scene.system, scene.initial, settings, parameters,
                    lambda result: esail_numbers(scene, result))


def esail_orbit_scene(alpha=10.0, voltage=20e3, elements=5, formulation=None,
                      t_end=86400.0, dt=1.0, every=600):
    """The baseline E-sail on the circular heliocentric orbit of 1 AU (``esail.build_orbit``:
    the Sun's differential gravity, the solar wind at each point's heliocentric position)
    at sailing angle ``alpha`` (deg) and tether voltage ``voltage`` (V), run to ``t_end``
    (default a day) with step ``dt`` (rho_inf = 0.25), every ``every``-th step saved; its
    outputs are ``esail_numbers``', the summary adds the orbit (``runner.orbit_summary``)."""
    from ..runner.drive import RunScene
    from . import esail

    cfg = esail.BaselineConfig(voltage=voltage)
    scene = esail.build_orbit(cfg, alpha, elements, formulation=formulation)
    settings = {"t_end": t_end, "dt": dt, "every": every, "rho_inf": 0.25, "series_every": 6}
    parameters = {"alpha_deg": alpha, "voltage": voltage, "elements_per_tether": elements,
                  "tethers": cfg.n_tethers, "formulation": scene.tethers[0].formulation}
    return RunScene("esail-orbit", scene.system, scene.initial, settings, parameters,
                    lambda result: esail_numbers(scene, result))


def esail_orbit(options):
    """``esail_orbit_scene`` run by ``skfem-cable run esail-orbit`` (``--alpha``,
    ``--elements``, ``--formulation``)."""
    return esail_orbit_scene(options.value("alpha", 10.0), elements=options.value("elements", 5),
                             formulation=options.formulation).run(options)


def esail_full_scene(alpha=10.0, elements=10, t_end=None, rtol=None, every=50,
                     settled=True):
    """The full-size E-sail (``esail.FULL_SIZE``: 100 tethers of 20 km, ``elements`` each)
    on the circular heliocentric orbit of 1 AU at sailing angle ``alpha`` (deg), run to
    ``t_end`` (default one spin period, 87 min) with adaptive steps of relative tolerance
    ``rtol`` (default ``esail.MISSION_RTOL``; ``atol`` 1e-3 m, first step 1 s, rho_inf =
    0.25), every ``every``-th step saved; outputs ``esail_numbers``'.  It starts from
    the sail's state under the wind (``esail.settled``: its equilibrium and 4.4 h of
    relaxation before t = 0, some 9 s on one thread), or from the windless spin if not
    ``settled``."""
    from ..runner.drive import RunScene
    from . import esail

    cfg = esail.FULL_SIZE
    scene = esail.build_orbit(cfg, alpha, elements)
    if settled:
        scene = esail.settled(scene)
    settings = {"t_end": cfg.spin_period if t_end is None else t_end, "dt": 1.0,
                "rtol": esail.MISSION_RTOL if rtol is None else rtol, "atol": 1e-3,
                "every": every, "rho_inf": 0.25, "series_every": 10}
    parameters = {"alpha_deg": alpha, "elements_per_tether": elements,
                  "tethers": cfg.n_tethers, "tether_length": cfg.tether_length,
                  "spin_rate": cfg.spin_rate, "centrifugal_ratio": cfg.centrifugal_ratio}
    return RunScene("esail-full", scene.system, scene.initial, settings, parameters,
                    lambda result: esail_numbers(scene, result))


def esail_full(options):
    """``esail_full_scene`` run by ``skfem-cable run esail-full`` (``--alpha``,
    ``--elements``, ``--t-end 30d``)."""
    return esail_full_scene(options.value("alpha", 10.0),
                            options.value("elements", 10)).run(options)


def esail_numbers(scene, result):
    """Key numbers of an E-sail run (``esail.outputs`` averaged over the saved steps):
    ``thrust_mean_O`` (the mean thrust vector in the orbit frame, N), ``thrust_mean_N``
    (mean magnitude), ``thrust_angle_mean_deg`` (from the Sun line), ``coning_max_deg``,
    ``lagging_max_deg`` (largest over tethers and time), ``tension_max_N`` (largest tether
    tension at the nodes over the run)."""
    from . import esail

    out = esail.outputs(scene, result)
    tension = max(result.tension(c, c.mesh.p[0]).max() for c in scene.tethers)
    return {"thrust_mean_O": out["thrust_O"].mean(axis=0),
            "thrust_mean_N": np.linalg.norm(out["thrust"], axis=1).mean(),
            "thrust_angle_mean_deg": np.rad2deg(out["thrust_angle"]).mean(),
            "coning_max_deg": np.rad2deg(np.abs(out["coning"])).max(),
            "lagging_max_deg": np.rad2deg(np.abs(out["lagging"])).max(),
            "tension_max_N": tension}


register("esail", "skfem_cable.scenes.esail:run",
         "E-sail baseline of the paper (12 tethers, 3 spin periods); --alpha sailing angle",
         build=esail_scene, takes=("alpha",))
register("cantilever", cantilever,
         "static elastica under tip loads k = PL^2/EI = 1..10 against the exact solution",
         takes=("element",))
register("pendulum", pendulum, "flexible pendulum released from horizontal under gravity",
         build=pendulum_scene, takes=("element",))
register("spinning-tether", spinning_tether,
         "tether with a tip mass spinning at 2 rad/s, root tension against the rigid value",
         build=spinning_tether_scene, takes=("element",))
register("hanging-chain", "skfem_cable.scenes.hanging_chain:run",
         "steel rod chain released from horizontal, against rigid links")
register("esail-orbit", esail_orbit,
         "E-sail baseline on the circular orbit of 1 AU for a day; --alpha sailing angle",
         build=esail_orbit_scene, takes=("alpha",))
register("esail-full", esail_full,
         "full-size E-sail (100 tethers of 20 km) at 1 AU, adaptive steps; --alpha, "
         "--t-end 30d", build=esail_full_scene, takes=("alpha",))
register("esail-rig", "skfem_cable.scenes.esail_rig:run",
         "full E-sail rig (100 tethers, remote units, the ring of auxiliary tethers) under "
         "on-off modulation for a spin period; --alpha, --elements",
         build="skfem_cable.scenes.esail_rig:scene", takes=("alpha",))
register("capstan", "skfem_cable.scenes.capstan:run",
         "rope sliding over a fixed drum (wrap pi, mu = 0.3): T2 / T1 against exp(mu pi)",
         build="skfem_cable.scenes.capstan:scene")
register("tss", "skfem_cable.scenes.tss:run",
         "tethered satellites, 20 km tether in a 400 km orbit, pitch and roll librations; "
         "--model ancf (default) or rodchain",
         build="skfem_cable.scenes.tss:scene", takes=("model",))
register("tape-tether", "skfem_cable.scenes.tape_tether:run",
         "5 km aluminium tape (sc.Rod) in a 400 km orbit, librating, one turn of twist: "
         "torsional period against 2L/c", build="skfem_cable.scenes.tape_tether:scene")
register("ed-deorbit", "skfem_cable.scenes.ed_deorbit:run",
         "bare 5 km tape deorbiting, OML current from IRI in IGRF, MSIS drag, one orbit; "
         "--epoch (default 2026-01-01)", takes=("epoch",))
register("plasma-brake", "skfem_cable.scenes.plasma_brake:run",
         "5 km plasma-brake tether at -1 kV lowering 260 kg from 800 km in IRI, one orbit; "
         "--epoch (default 2026-01-01)", takes=("epoch",))
