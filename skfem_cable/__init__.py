"""skfem_cable: tethers, cables and E-sails on scikit-fem.

Public API: ``Section``, ``Cable``, ``System``, ``solve_static``, ``modes``, ``State``.
"""

from .cable import Cable, Node
from .element import ElementLineCableHermite
from .section import Section
from .solvers.modal import modes
from .solvers.static import StaticConvergenceError, solve_static
from .state import State
from .system import System

__all__ = [
    "Cable",
    "ElementLineCableHermite",
    "Node",
    "Section",
    "State",
    "StaticConvergenceError",
    "System",
    "modes",
    "solve_static",
]
