"""The two-node linear element: positions only, ``r_x`` constant in the element, no
bending (the segment model of lumped-mass codes such as MoorDyn).

For slack lines where bending does not matter (moorings, towed cables): an axial law only
(``"truss"``, the default on this element); a law with bending is refused.  The strain is
constant in an element, so its midpoint integrates an axial law exactly, and the tension is
recovered from the midpoints, where it is superconvergent (``formulation.Segment``).  The mass
matrix is the consistent one (``rho A h / 6 [[2, 1], [1, 2]]``), not the lumped one.
"""

from .base import CableElement


class ElementLineCableLinear(CableElement):
    """Scalar linear line element with the DOF ``u`` at each node (scikit-fem's
    ``ElementLineP1`` with the cable's conventions).

    Examples
    --------
    >>> ElementLineCableLinear().shape(0.25, 2.0)[1].tolist()   # d/dx of 1 - xi, xi
    [-0.5, 0.5]
    """

    name = "linear"
    orders = (0,)
    fields = ("r_x",)
    #: ``"segment"``: the law at the midpoint, tension recovered from the midpoints.
    formulations = ("segment",)
    #: The line loads' Gauss rule (two points: exact for a uniform load's consistent
    #: force); the elastic forces take the midpoint (``formulation.Segment``).
    intorder = 3
