"""skfem_cable: tethers, cables and E-sails on scikit-fem.

Public API (``__all__``, documented on the API page of the docs; the packages by role
and what may import what: ``docs/architecture.md``):

* model: ``Section``, ``Cable`` (and its ``Node``; its element types ``ELEMENTS``,
  ``CableElement``, ``ElementLineCableHermite``, ``ElementLineCableHermite5``,
  ``ElementLineCableLinear``), ``Rod`` (a cable with twist and two principal bending
  stiffnesses, ``docs/rods.md``),
  ``RigidBody``, ``System``; the surfaces a system's lines touch (``System.contact``)
  ``Plane``, ``Sphere``, ``Cylinder``, ``Edge`` (``loads.surfaces``);
* loads (package ``loads``): ``Gravity``, ``PointLoad``, ``PointMoment``, ``LineLoad``,
  ``Centrifugal``, ``PointMass``, the solar wind ``SolarWind``, ``SolarWindForce``
  (``loads.coulomb``), drag in water and in a rarefied atmosphere ``MorisonDrag``,
  ``Buoyancy``, ``CurrentProfile``, ``FreeMolecularDrag`` (``loads.drag``), the
  co-rotating atmosphere's drag with a density model ``AtmosphericDrag``
  (``loads.atmosphere``),
  electrodynamic tethers ``ElectrodynamicForce``, ``MagneticDipole``
  (``loads.electrodynamic``); constraints: ``System.clamp``, ``System.pin`` (package
  ``constraints``); deploying and retrieving cables: ``System.deploy``
  (``constraints.deploy``), from a ``Reel`` with a torque law ``Brake``, ``Motor``,
  ``Servo`` (``bodies.reel``);
* orbits: ``Orbit`` (Keplerian reference orbits, the orbiting frame), ``Reference`` (a
  run's reference: the orbit and the rebases of its rectification), the constants
  ``MU_EARTH``, ``MU_SUN``, ``R_EARTH``, ``AU`` (package ``space``);
* element laws: ``cable_law``, ``CableLaw`` and the module ``laws``; their scikit-fem
  forms ``forms``;
* solvers: ``solve_static`` (``StaticConvergenceError``), ``solve_steady``, ``settle``,
  ``modes``, ``simulate`` (``SimulationError``); results: ``State``, ``Result``;
* the evaluation contract: ``Evaluation``, ``Term``, ``Observer`` (hooks into
  ``simulate``), and the I/O layer ``io`` (observers: run store, ParaView series,
  progress bar); ``export`` (ParaView files) and ``plot``;
* the E-sail scene ``esail``; the rod-chain tether ``RodChain``, ``RodChainResult``,
  ``RodChainDivergence``, ``circular_anchor`` (package ``rodchain``).

References
----------
1. G. Pacheco-Ramos, D. Garcia-Vallejo and R. Vazquez, "Formulation of a
   high-fidelity multibody dynamical model for an electric solar wind sail", Universidad
   de Sevilla, preprint (the copy followed names no journal or year).  "Eq. N", "Sect. N"
   and "Table N" in this package refer to it unless stated otherwise.
2. Ma Shuguang and Wang Tianshu, "An Efficient Model of Tethers for Tethered
   Satellite Systems", Advances in Astronautics Science and Technology (Springer), 2019,
   doi:10.1007/s42423-018-0025-1: the rod-chain tether (``rodchain``).

Examples
--------
>>> import skfem_cable as sc
>>> sec = sc.Section.circular(radius=0.01, E=7e10, rho=7800.0)       # SI units
>>> cable = sc.Cable.straight([0, 0, 0], [1.2, 0, 0], n_elements=16, section=sec)
>>> system = sc.System([cable]).pin(cable.node(0)).add_gravity([0, -9.81, 0])
>>> system.n_dofs, system.n_constraints
(102, 3)
"""

import importlib
import importlib.util

from . import _moved as _moved  # old module paths, one release (docs/architecture.md)

# isort: split
from . import kernels as kernels  # first: numba caches and reports the kernels defined after
from .util.lazy import exports as _exports

#: Where each public name lives: imported on first use (PEP 562 ``__getattr__``), so that
#: ``import skfem_cable`` costs numba alone and a command imports what it uses.
_PUBLIC = {
    "analysis.tangent_check": ("check_tangent",),
    "bodies.cable": ("Cable",),
    "bodies.formulation": ("FORMULATIONS",),
    "bodies.reel": ("Brake", "Motor", "Reel", "Servo"),
    "bodies.rigid": ("RigidBody",),
    "bodies.rod": ("Rod",),
    "bodies.section": ("Section",),
    "control.controller": ("ControlError", "Controller"),
    "core.contract": ("Evaluation", "Term"),
    "core.inputs": ("Input",),
    "core.node": ("Node",),
    "core.protocols": ("Observer",),
    "elements": ("ELEMENTS", "CableElement", "ElementLineCableHermite",
                 "ElementLineCableHermite5", "ElementLineCableLinear"),
    "environment": ("Cathode", "Epoch"),
    "laws": ("CableLaw", "cable_law"),
    "loads.atmosphere": ("AtmosphericDrag",),
    "loads.coulomb": ("SolarWind", "SolarWindForce"),
    "loads.drag": ("Buoyancy", "CurrentProfile", "FreeMolecularDrag", "MorisonDrag"),
    "loads.electrodynamic": ("ElectrodynamicForce", "MagneticDipole"),
    "loads.gravity": ("Centrifugal", "Gravity"),
    "loads.line": ("LineLoad",),
    "loads.point": ("PointLoad", "PointMass", "PointMoment"),
    "loads.surfaces": ("Cylinder", "Edge", "Plane", "Sphere"),
    "loads.twist": ("TwistTorque",),
    "model.state": ("State",),
    "model.system": ("System", "SystemChanged"),
    "results.result": ("Result",),
    "rodchain": ("RodChain", "RodChainDivergence", "RodChainResult", "circular_anchor"),
    "solvers.modal": ("modes",),
    "solvers.settle": ("settle",),
    "solvers.simulate": ("simulate",),
    "solvers.static": ("StaticConvergenceError", "solve_static"),
    "solvers.steady": ("solve_steady",),
    "solvers.step_control": ("SimulationError",),
    "space.constants": ("AU", "MU_EARTH", "MU_SUN", "R_EARTH"),
    "space.orbit": ("Orbit",),
    "space.reference": ("Reference",),
    "study": ("sweep",),  # parameter studies on Dask distributed
}

#: The public modules, by their full names: element laws, I/O observers (run store,
#: ParaView series, progress bar), the environment's models (IGRF, IRI, NRLMSIS, epochs,
#: OML current), renders and figures, scikit-fem forms of the laws, what a controller
#: measures, VTU files for ParaView, the E-sail scene.
_MODULES = {"environment": "environment", "io": "io", "laws": "laws", "plot": "plot",
            "forms": "bodies.forms", "sensors": "control.sensors", "export": "io.export",
            "esail": "scenes.esail"}

#: The public names: those of ``_PUBLIC`` and four of the modules.
__all__ = [name for names in _PUBLIC.values() for name in names] + [
    "environment", "esail", "io", "laws"]


_public, __dir__ = _exports(__name__, _PUBLIC, _MODULES)


def __getattr__(name):
    """A public name (``_PUBLIC``, ``_MODULES``), one of the package's submodules not
    imported yet (``scene_file``, ``validation``, ``runner``, ...) or an old module path
    (``_moved``), imported when first named: ``sc.System`` and ``sc.scene_file.load(path)``
    work without importing their modules."""
    found = _moved.attribute(name)
    if found is not None:
        return found
    if importlib.util.find_spec(f"{__name__}.{name}") is not None:
        return importlib.import_module(f"{__name__}.{name}")
    return _public(name)
