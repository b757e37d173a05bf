"""The quintic-Hermite ANCF cable element: positions, slopes ``r_x`` and second derivatives
``r_xx`` at each node (C2 across nodes), ``r_x`` and ``r_xx`` for the law.

Every law of the cubic cable runs on it unchanged.  The curvature is continuous across the
nodes and the element reproduces quintics, so on smooth solutions its errors fall as
``h^6`` in the positions (``h^4`` for the cubic) for 9 coordinates per node instead of 6.
Its default formulation is the assumed strain (``kernels.assumed_strain.Rule``): the
axial part at the C1 piecewise quintic with the Green strain's nodal values and slopes
and its element means and first moments (``4 n + 2`` values), the bending part on 6
Gauss points; tension recovered from it.  It is free of membrane locking: on the
elastica of ``docs/elements.md`` (k = 5, 4 elements) its tip error is 1.3e-6 at
``EA L^2 / EI = 1e7`` and 1.6e-6 at 1e11, where the paper's formulation (every term on
the 9 Gauss points of ``intorder``, still available as ``formulation="paper"``) locks,
4.3e-6 and 1.3e-3; on bending-free and taut cables it is as accurate as the paper's
(``docs/locking.md``).  Its tension in bending carries stripes of the size of the load
(1.6 ``P`` on that elastica with 4 elements, 0.08 ``P`` with 16; the paper's: 10 and
0.1 ``P``), which the run summaries' tension guard reports; the support reactions (the
multipliers) are accurate.  For tensions in bending use the cubic element.
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
    #: ``formulation``: the assumed strain (the default: the quartic with the strain's
    #: nodal values and slopes and its element means), the paper's.
    formulations = ("assumed-strain", "paper")
    #: 9 Gauss points: the Green axial energy of the quintic field (degree 16) exactly.
    intorder = 17
