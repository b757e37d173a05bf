"""skfem_cable: tethers, cables and E-sails on scikit-fem.

Public API: ``Section``, ``Cable``, ``RigidBody``, ``System``, ``solve_static``,
``modes``, ``simulate``, ``State``, ``Result``, ``SolarWind``, ``SolarWindForce``,
``RodChain``; the E-sail scene ``esail``; ``Observer`` (hooks into ``simulate``) and the
I/O layer ``io`` (observers: run store, ParaView series, progress bar); ``export``
(ParaView files) and ``plot``.
"""

from . import export as export  # VTU files for ParaView
from . import forms as forms  # scikit-fem forms of the element laws
from . import io as io  # observers: run store, ParaView series, progress bar
from . import laws as laws  # element laws: energy densities -> compiled kernels
from . import plot as plot  # renders and figures
from .cable import Cable, Node
from .contract import Evaluation, Observer, Term
from .coulomb import SolarWind, SolarWindForce
from .element import ElementLineCableHermite
from .laws import CableLaw, cable_law
from .loads import Centrifugal, Gravity, LineLoad, PointLoad, PointMass, PointMoment
from .result import Result
from .rigid import RigidBody
from .rodchain import RodChain, RodChainDivergence, RodChainResult, circular_anchor
from .scenes import esail as esail
from .section import Section
from .solvers.modal import modes
from .solvers.simulate import SimulationError, simulate
from .solvers.static import StaticConvergenceError, solve_static
from .state import State
from .system import System

__all__ = [
    "Cable",
    "CableLaw",
    "Centrifugal",
    "Evaluation",
    "Gravity",
    "LineLoad",
    "Observer",
    "PointLoad",
    "PointMass",
    "PointMoment",
    "Term",
    "ElementLineCableHermite",
    "Node",
    "Result",
    "RigidBody",
    "RodChain",
    "RodChainDivergence",
    "RodChainResult",
    "SimulationError",
    "Section",
    "SolarWind",
    "SolarWindForce",
    "State",
    "StaticConvergenceError",
    "System",
    "cable_law",
    "circular_anchor",
    "esail",
    "io",
    "laws",
    "modes",
    "simulate",
    "solve_static",
]
