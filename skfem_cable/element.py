"""The cubic-Hermite element of the gradient-deficient ANCF cable (paper Eqs. 16-19).

The four Hermite functions are evaluated on the reference line ``xi in [0, 1]`` and the two
slope functions are scaled by the element Jacobian ``h`` (the element length, signed), so
that the nodal degrees of freedom are the value and the derivative with respect to the
*global* coordinate ``x``.  Nothing is inverted, and nothing is cached on the element, so the
accuracy does not degrade with mesh refinement (scikit-fem's ``ElementLineHermite`` inverts a
power-basis Vandermonde matrix in global coordinates per element).
"""

import numpy as np
from skfem.element import Element
from skfem.element.discrete_field import DiscreteField
from skfem.refdom import RefLine


def hermite(xi, h):
    """Cubic Hermite functions and their first two ``x``-derivatives (paper Eq. 18).

    Parameters
    ----------
    xi : ndarray
        Reference coordinates in ``[0, 1]``, any shape.
    h : ndarray or float
        Element length (the Jacobian ``dx/dxi``), broadcastable against ``xi``.

    Returns
    -------
    s, s_x, s_xx : ndarray
        Arrays of shape ``(4,) + broadcast(xi, h).shape`` with the functions
        ``s1..s4`` of Eq. 18 and their derivatives with respect to ``x = h xi``.
    """
    xi = np.asarray(xi, dtype=float)
    h = np.asarray(h, dtype=float)
    xi2, xi3 = xi * xi, xi * xi * xi
    one = np.ones_like(xi * h)
    s = np.array([
        (1 - 3 * xi2 + 2 * xi3) * one,
        h * (xi - 2 * xi2 + xi3),
        (3 * xi2 - 2 * xi3) * one,
        h * (xi3 - xi2),
    ])
    s_x = np.array([
        (-6 * xi + 6 * xi2) / h,
        (1 - 4 * xi + 3 * xi2) * one,
        (6 * xi - 6 * xi2) / h,
        (3 * xi2 - 2 * xi) * one,
    ])
    s_xx = np.array([
        (-6 + 12 * xi) / h ** 2,
        (-4 + 6 * xi) / h,
        (6 - 12 * xi) / h ** 2,
        (6 * xi - 2) / h,
    ])
    return s, s_x, s_xx


class ElementLineCableHermite(Element):
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
    """

    nodal_dofs = 2
    maxdeg = 3
    dofnames = ["u", "u_x"]
    doflocs = np.array([[0.0], [0.0], [1.0], [1.0]])
    refdom = RefLine

    def gbasis(self, mapping, X, i, tind=None):
        if not 0 <= i < 4:
            self._index_error()
        if tind is None:
            tind = np.arange(mapping.mesh.t.shape[1])
        h = mapping.A[0, 0, tind]
        xi = X[0] if X.ndim == 2 else X[0]
        xi = np.broadcast_to(xi, (len(tind), xi.shape[-1]))
        s, s_x, s_xx = hermite(xi, h[:, None])
        return (DiscreteField(value=s[i], grad=s_x[i][None], hess=s_xx[i][None, None]),)
