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

# isort: split
from . import environment as environment  # IGRF, IRI, NRLMSIS, epochs, OML current
from . import io as io  # observers: run store, ParaView series, progress bar
from . import laws as laws  # element laws: energy densities -> compiled kernels
from . import plot as plot  # renders and figures
from .analysis.tangent_check import check_tangent
from .bodies import forms as forms  # scikit-fem forms of the element laws
from .bodies.cable import Cable
from .bodies.formulation import FORMULATIONS
from .bodies.reel import Brake, Motor, Reel, Servo
from .bodies.rigid import RigidBody
from .bodies.rod import Rod
from .bodies.section import Section
from .control import sensors as sensors  # what a controller measures
from .control.controller import ControlError, Controller
from .core.contract import Evaluation, Term
from .core.inputs import Input
from .core.node import Node
from .core.protocols import Observer
from .elements import (
    ELEMENTS,
    CableElement,
    ElementLineCableHermite,
    ElementLineCableHermite5,
    ElementLineCableLinear,
)
from .environment import Cathode, Epoch
from .io import export as export  # VTU files for ParaView
from .laws import CableLaw, cable_law
from .loads.atmosphere import AtmosphericDrag
from .loads.coulomb import SolarWind, SolarWindForce
from .loads.drag import Buoyancy, CurrentProfile, FreeMolecularDrag, MorisonDrag
from .loads.electrodynamic import ElectrodynamicForce, MagneticDipole
from .loads.gravity import Centrifugal, Gravity
from .loads.line import LineLoad
from .loads.point import PointLoad, PointMass, PointMoment
from .loads.surfaces import Cylinder, Edge, Plane, Sphere
from .loads.twist import TwistTorque
from .model.state import State
from .model.system import System, SystemChanged
from .results.result import Result
from .rodchain import RodChain, RodChainDivergence, RodChainResult, circular_anchor
from .scenes import esail as esail
from .solvers.modal import modes
from .solvers.settle import settle
from .solvers.simulate import simulate
from .solvers.static import StaticConvergenceError, solve_static
from .solvers.steady import solve_steady
from .solvers.step_control import SimulationError
from .space.constants import AU, MU_EARTH, MU_SUN, R_EARTH
from .space.orbit import Orbit
from .space.reference import Reference
from .study import sweep  # parameter studies on Dask distributed

__all__ = [
    "check_tangent",
    "AU",
    "MU_EARTH",
    "MU_SUN",
    "R_EARTH",
    "Orbit",
    "Reference",
    "AtmosphericDrag",
    "Rod",
    "Brake",
    "Buoyancy",
    "Cable",
    "CableLaw",
    "Cathode",
    "ControlError",
    "Controller",
    "Centrifugal",
    "CurrentProfile",
    "Cylinder",
    "Edge",
    "ElectrodynamicForce",
    "Epoch",
    "Evaluation",
    "FreeMolecularDrag",
    "Gravity",
    "Input",
    "LineLoad",
    "MagneticDipole",
    "MorisonDrag",
    "Motor",
    "Observer",
    "Plane",
    "PointLoad",
    "PointMass",
    "PointMoment",
    "TwistTorque",
    "Term",
    "ELEMENTS",
    "CableElement",
    "ElementLineCableHermite",
    "ElementLineCableHermite5",
    "ElementLineCableLinear",
    "FORMULATIONS",
    "Node",
    "Reel",
    "Result",
    "RigidBody",
    "RodChain",
    "RodChainDivergence",
    "RodChainResult",
    "Servo",
    "SimulationError",
    "Section",
    "Sphere",
    "SolarWind",
    "SolarWindForce",
    "State",
    "StaticConvergenceError",
    "System",
    "SystemChanged",
    "cable_law",
    "circular_anchor",
    "esail",
    "environment",
    "io",
    "laws",
    "modes",
    "simulate",
    "solve_static",
    "solve_steady",
    "settle",
    "sweep",
]


def __getattr__(name):
    """The package's submodules not imported above (``scene_file``, ``validation``,
    ``runner``, ...), imported when first named: ``sc.scene_file.load(path)`` works
    without ``import skfem_cable.scene_file``."""
    found = _moved.attribute(name)
    if found is not None:
        return found
    if importlib.util.find_spec(f"{__name__}.{name}") is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    return importlib.import_module(f"{__name__}.{name}")
