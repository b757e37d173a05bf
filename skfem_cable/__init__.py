"""skfem_cable: tethers, cables and E-sails on scikit-fem.

Public API: ``Section``, ``Cable``, ``System``, ``solve_static``, ``modes``, ``simulate``,
``State``, ``Result``.
"""

from .cable import Cable, Node
from .element import ElementLineCableHermite
from .result import Result
from .section import Section
from .solvers.galpha import SimulationError, simulate
from .solvers.modal import modes
from .solvers.static import StaticConvergenceError, solve_static
from .state import State
from .system import System

__all__ = [
    "Cable",
    "ElementLineCableHermite",
    "Node",
    "Result",
    "SimulationError",
    "Section",
    "State",
    "StaticConvergenceError",
    "System",
    "modes",
    "simulate",
    "solve_static",
]
