"""The cubic-Hermite element of the gradient-deficient ANCF cable (paper Eqs. 16-19): the
paper's element and the default.

Positions and slopes ``r_x`` at each node (C1 across nodes), ``r_x`` and ``r_xx`` for the
law.  The slope functions are scaled by the element length ``h``, so that the nodal
degrees of freedom are derivatives with respect to the *global* coordinate ``x``; nothing is
inverted and nothing is cached on the element, so the accuracy does not degrade with mesh
refinement (scikit-fem's ``ElementLineHermite`` inverts a power-basis Vandermonde matrix in
global coordinates per element).
"""

from .base import CableElement


class ElementLineCableHermite(CableElement):
    """Scalar cubic-Hermite line element with DOFs ``u`` and ``u_x`` at each node.

    Use ``ElementVector(ElementLineCableHermite(), dim=3)`` for the 3-D position field of an
    ANCF cable; scikit-fem then numbers the six DOFs of a node as ``r^1, r^2, r^3, r_x^1,
    r_x^2, r_x^3`` and consecutive nodes consecutively.

    Examples
    --------
    >>> import numpy as np
    >>> from skfem import Basis, MeshLine, ElementVector
    >>> basis = Basis(MeshLine(np.linspace(0, 1, 5)), ElementVector(ElementLineCableHermite(), 3))
    >>> basis.N
    30
    >>> ElementLineCableHermite().shape(0.5, 2.0)[0].tolist()   # Eq. 18 at the midpoint
    [0.5, 0.25, 0.5, -0.25]
    """

    name = "hermite3"
    orders = (0, 1)
    fields = ("r_x", "r_xx")
    #: ``formulation``: the assumed strain (the default), the paper's, Lobatto's.
    formulations = ("assumed-strain", "paper", "lobatto")
    #: 5 Gauss points: the Green axial energy (degree 8) exactly.
    intorder = 9
