"""The quintic-Hermite ANCF cable element: positions, slopes ``r_x`` and second derivatives
``r_xx`` at each node (C2 across nodes), ``r_x`` and ``r_xx`` for the law.

Every law of the cubic cable runs on it unchanged.  The curvature is continuous across the
nodes and the element reproduces quintics, so on smooth solutions its errors fall as
``h^6`` in the positions (``h^4`` for the cubic) for 9 coordinates per node instead of 6.
Its elastic forces are integrated on the Gauss rule of ``intorder`` (the ``"paper"``
formulation: the assumed strain of ``formulation`` is built for the cubic's strain space).
Its positions converge fast, but it is not locking-free: in bending, its tension
(``Cable.tension``, the raw strain of the quintic field) carries stripes (0.1 of the load
on an elastica of 16 elements, tens of loads on 4), which the run summaries' tension guard
reports, and very slender cables on coarse meshes lock (``docs/elements.md`` measures
both); the support reactions (the multipliers) are accurate.  For tensions in bending use
the cubic element's default formulation.
"""

from .base import CableElement


class ElementLineCableHermite5(CableElement):
    """Scalar quintic-Hermite line element with DOFs ``u``, ``u_x`` and ``u_xx`` at each
    node.

    Examples
    --------
    >>> import numpy as np
    >>> from skfem import Basis, MeshLine, ElementVector
    >>> basis = Basis(MeshLine(np.linspace(0, 1, 5)), ElementVector(ElementLineCableHermite5(), 3))
    >>> basis.N                       # 9 coordinates per node
    45
    >>> ElementLineCableHermite5().maxdeg
    5
    """

    name = "hermite5"
    orders = (0, 1, 2)
    fields = ("r_x", "r_xx")
    formulations = ("paper",)
    #: 9 Gauss points: the Green axial energy of the quintic field (degree 16) exactly.
    intorder = 17
