"""What an element type of the cable is: a scalar scikit-fem element on the reference line
whose functions interpolate nodal derivatives, and what it gives the rest of the library.

An element type is a subclass of ``CableElement`` that states four things:

* ``orders``: the derivative orders of its nodal fields, ``(0,)`` for positions only,
  ``(0, 1)`` for positions and slopes ``r_x`` (the paper's cable, Eq. 17), ``(0, 1, 2)``
  with ``r_xx`` too.  Its functions are the Hermite interpolants of those nodal values on
  ``xi in [0, 1]`` (degree ``2 len(orders) - 1``), derived here once, exactly, for any
  ``orders``; the function of a derivative of order ``k`` is scaled by ``h^k`` (the element
  length), so that nodal values are derivatives in the *global* arc length ``x`` and
  nothing is inverted per element (as ``hermite3`` explains).
* ``fields``: what a law sees at a point, ``("r_x",)`` or ``("r_x", "r_xx")``; a law with
  bending (``r_xx``) is refused on an element without it.
* ``formulations``: the formulations it supports (``formulation``), the first the default.
* ``intorder``: the default Gauss order of the elastic forces.

Everything else follows and is written once against it: the nodal layout (``3
len(orders)`` coordinates per node, fields in ``orders``' order, scikit-fem's numbering of
``ElementVector(element, 3)``), the tables of the kernels, the mass and line loads, the
recovery of fields and the export.
"""

import functools
import math

import numpy as np
from skfem.element import Element
from skfem.element.discrete_field import DiscreteField
from skfem.refdom import RefLine

#: The name of a nodal field of each derivative order (``Cable.describe_dof``, DOF names).
FIELD_NAMES = ("r", "r_x", "r_xx")


def hermite_coefficients(orders):
    """Power-basis coefficients ``(n, n)`` on ``xi in [0, 1]`` of the Hermite functions of
    the nodal derivatives ``orders`` at ``xi = 0`` then ``xi = 1`` (``n = 2 len(orders)``):
    row ``i`` is the polynomial whose ``orders[k]``-th derivative is 1 at the end and
    degree of freedom ``i`` and whose other nodal derivatives vanish.  Exact (rational
    arithmetic), then rounded to floats once per ``orders`` (a read-only array)."""
    return _hermite_coefficients(tuple(orders))


@functools.cache
def _hermite_coefficients(orders):
    import sympy as sp  # here: sympy's exact inverse costs 0.2 s for the quintic

    n = 2 * len(orders)
    xi = sp.Symbol("xi")
    monomials = [xi**j for j in range(n)]
    V = sp.Matrix([[sp.diff(m, xi, k).subs(xi, end) for m in monomials]
                   for end in (0, 1) for k in orders])
    coefficients = np.array(V.inv().T.tolist(), dtype=float)
    coefficients.flags.writeable = False  # shared: one array per ``orders``
    return coefficients


@functools.cache
def _derivative_terms(element):
    """The tables of ``CableElement.shape`` for the element type ``element`` (a class),
    once per type: for the functions and their first two derivatives (``d = 0, 1, 2``), the
    factors ``j!/(j-d)! C[:, j]`` of ``xi^(j-d)`` (``j = d, ...``; ``C`` the
    ``hermite_coefficients``), the powers of ``h`` that scale each function up and down
    (its nodal derivative's order less ``d``, and the opposite, at least 0) and which
    functions scale up (that power at least 0).  ``shape`` takes the product or the
    quotient of those a derivative has alone, not both (the same numbers in a third of
    the time: 99 -> 39 us for 12 cubic elements at 4 points)."""
    coefficients, power = element.coefficients, element.scaling
    terms = []
    for d in range(3):
        factors = tuple(float(math.perm(j, d)) * coefficients[:, j]
                        for j in range(d, coefficients.shape[1]))
        terms.append((factors, np.maximum(power - d, 0), np.maximum(d - power, 0),
                      power - d >= 0))
    return tuple(terms)


class _Coefficients:
    """The class attribute ``coefficients`` of an element type: its
    ``hermite_coefficients(orders)``, derived when first read (not when the type is
    defined: importing the package defines them all)."""

    def __get__(self, element, cls):
        return hermite_coefficients(cls.orders)


class CableElement(Element):
    """A scalar line element of the cable on scikit-fem's reference line (module
    docstring): subclasses set ``name``, ``orders``, ``fields``, ``formulations`` and
    ``intorder``; the scikit-fem attributes and the Hermite functions follow from them.

    Use ``ElementVector(element, 3)`` for the 3-D position field; scikit-fem then numbers
    a node's coordinates field by field, ``r^1, r^2, r^3, r_x^1, ...``, and consecutive
    nodes consecutively.

    Attributes
    ----------
    n_functions : int
        Functions per element, ``2 len(orders)`` (the element has ``3 n_functions``
        coordinates).
    coefficients : ndarray (n_functions, n_functions)
        Their power-basis coefficients in ``xi`` (``hermite_coefficients``).
    scaling : int ndarray (n_functions,)
        The power of ``h`` each function is scaled by (its nodal derivative's order).
    bending : bool
        Whether a law may read ``r_xx``.
    """

    refdom = RefLine
    name = None
    orders = (0,)
    fields = ("r_x",)
    formulations = ("paper",)
    intorder = 1
    coefficients = _Coefficients()

    _last_shape = (None, None)  # (key, shape) of ``remembered_shape``

    def __init_subclass__(cls, **kwargs):
        super().__init_subclass__(**kwargs)
        cls.nodal_dofs = len(cls.orders)
        cls.dofnames = ["u" + "_x" * k for k in cls.orders]
        cls.doflocs = np.array([[0.0]] * cls.nodal_dofs + [[1.0]] * cls.nodal_dofs)
        cls.n_functions = 2 * cls.nodal_dofs
        cls.maxdeg = cls.n_functions - 1
        cls.scaling = np.tile(cls.orders, 2)
        cls.bending = "r_xx" in cls.fields

    @property
    def node_fields(self):
        """Names of the nodal fields, e.g. ``("r", "r_x")``."""
        return tuple(FIELD_NAMES[k] for k in self.orders)

    @property
    def mass_order(self):
        """The Gauss order that integrates the mass matrix exactly (degree ``2 maxdeg``),
        plus one: ``maxdeg + 1`` points."""
        return 2 * self.maxdeg + 1

    def shape(self, xi, h):
        """The functions and their first two ``x``-derivatives (``x = h xi``).

        Parameters
        ----------
        xi : ndarray
            Reference coordinates in ``[0, 1]``, any shape.
        h : ndarray or float
            Element length (the Jacobian ``dx/dxi``), broadcastable against ``xi``.

        Returns
        -------
        s, s_x, s_xx : ndarray
            Arrays of shape ``(n_functions,) + broadcast(xi, h).shape``.
        """
        xi = np.asarray(xi, dtype=float)
        h = np.asarray(h, dtype=float)
        full = np.broadcast_shapes(xi.shape, h.shape)
        lead = (-1,) + (1,) * len(full)
        powers = [np.ones_like(xi)]
        for _ in range(self.coefficients.shape[1] - 1):
            powers.append(powers[-1] * xi)
        out = []
        for factors, up, down, rises in _derivative_terms(type(self)):
            # sum_j j!/(j-d)! C[:, j] xi^(j-d), in ascending powers as written by hand
            value = np.zeros((self.n_functions,) + full)
            for k, factor in enumerate(factors):
                value = value + factor.reshape(lead) * powers[k]
            if rises.all():
                out.append(value * h ** up.reshape(lead))
            elif not rises.any():
                out.append(value / h ** down.reshape(lead))
            else:
                out.append(np.where(rises.reshape(lead), value * h ** up.reshape(lead),
                                    value / h ** down.reshape(lead)))
        return tuple(out)

    def gbasis(self, mapping, X, i, tind=None):
        if not 0 <= i < self.n_functions:
            self._index_error()
        if tind is None:
            tind = np.arange(mapping.mesh.t.shape[1])
        h = mapping.A[0, 0, tind][:, None]
        xi = np.broadcast_to(X[0], (len(tind), X.shape[-1]))
        s, s_x, s_xx = self.remembered_shape(xi, h)
        return (DiscreteField(value=s[i].copy(), grad=s_x[i][None].copy(),
                              hess=s_xx[i][None, None].copy()),)

    def remembered_shape(self, xi, h):
        """``shape(xi, h)``, remembered for the last ``xi`` and ``h`` (by value), shared:
        read-only arrays.  scikit-fem asks
        ``gbasis`` for the functions one at a time, each with the same points and lengths,
        and a cable's fields at a set of points (``CableFields.sample``: positions,
        velocities, strain, tension and curvature) read them there five times or more
        (and the cables of a sail have the same), while ``shape`` computes them all."""
        xi, h = np.asarray(xi, dtype=float), np.asarray(h, dtype=float)
        key = (xi.shape, h.shape, xi.tobytes(), h.tobytes())
        last = self._last_shape  # one read: another thread may remember its own meanwhile
        if last[0] != key:
            shape = self.shape(xi, h)
            for table in shape:
                table.flags.writeable = False  # shared
            last = self._last_shape = key, shape
        return last[1]

    def __repr__(self):
        return f"{type(self).__name__}()"
