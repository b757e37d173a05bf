"""External loads, point masses and gravity, each a contributor of the evaluation contract
(``contract``): ``bind(system)`` returns a ``Term`` and leaves the load unchanged.

Constant loads (fixed point and line loads, gravity) become constant generalized forces
(``Term.force``) whose potential is booked as potential energy; loads that depend on time,
position or velocity add to ``Evaluation.f_ext`` at every evaluation, with the tangent
blocks ``dF/dq`` and ``dF/dv``, and their work is booked as external work.

Examples
--------
``System.add_gravity``, ``add_point_load``, ``add_point_moment``, ``add_line_load``,
``add_centrifugal`` and ``add_point_mass`` build them; ``System.add_load`` takes any of
them (or a user's contributor), and ``TwistTorque``, a torque on a rod's twist:

>>> import numpy as np, skfem_cable as sc
>>> cable = sc.Cable.straight([0, 0, 0], [2, 0, 0], 4, sc.Section.circular(1e-3, 2e11, 7850.0))
>>> drag = sc.LineLoad(cable, lambda x, v, t: -0.5 * v)           # N/m, velocity-dependent
>>> system = sc.System([cable]).pin(cable.node(0)).add_load(drag).add_gravity([0, -9.81, 0])
>>> [type(load).__name__ for load in system.loads]
['LineLoad', 'Gravity']
"""

from .gravity import Centrifugal, Gravity, spin_matrix
from .line import AlongCable, LineLoad, UniformLineLoad
from .point import PointLoad, PointMass, PointMoment, vector3
from .twist import TwistTorque

__all__ = [
    "AlongCable",
    "Centrifugal",
    "Gravity",
    "LineLoad",
    "PointLoad",
    "PointMass",
    "PointMoment",
    "TwistTorque",
    "UniformLineLoad",
    "spin_matrix",
    "vector3",
]
