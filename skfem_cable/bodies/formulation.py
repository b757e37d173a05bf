"""Formulations of a cable's element law: which rule integrates its axial part (the terms
without ``r_xx``) and its bending part, and how strain and tension are recovered from
them (``docs/locking.md`` measures the three).

``"assumed-strain"`` (the default)
    The axial part at the assumed Green strain (``kernels.assumed_strain``): on
    the cubic element the continuous piecewise quadratic with the strain's nodal values
    and element means, ``2 n + 1`` values for ``n`` elements; on the quintic the C1
    piecewise quintic with its nodal values and slopes, element means and first
    moments, ``4 n + 2``.
    No membrane locking, the full rule's accuracy on taut cables (exact axial and
    geometric stiffness about a uniformly stretched cable), tension recovered from the
    assumed strain.  The bending part on the Gauss rule of the assumed strain (3 points
    on the cubic element, 6 on the quintic).  Needs a law whose axial part depends on the
    stretch alone (``CableLaw.check_strain``).
``"paper"``
    The paper's formulation: every term on the Gauss rule of ``Cable.intorder`` (5
    points), or, with ``Cable.quadrature``, the axial and the bending part each on a
    Gauss rule of its own (Exudyn's 5 and 3 points).  Membrane locking in
    bending-dominated states: tension stripes of tens of times the load.
``"lobatto"``
    The axial part on the 3-point Gauss-Lobatto rule (``LOBATTO``: nodes and midpoint,
    Simpson's weights), the bending part on the 3-point Gauss rule; strain and tension
    recovered from the Lobatto points.  Locking-free, but fourth order on taut cables
    where the others reach sixth.

``"segment"`` (the linear element's)
    The law at the element midpoints, strain and tension recovered from them
    (``Segment``).

A formulation is a small object with three hooks: ``passes(cable)`` (the compiled kernel
calls of its elastic forces: a law or a part of it, the kind of its generated module,
``laws.codegen.TEMPLATES``, and the tables of its rule) and ``strain``/``tension(cable, q,
s, stretch)`` (the recovered fields at arc lengths ``s``).
"""

import functools

import numpy as np

from ..kernels import assumed_strain
from ..kernels.assumed_strain import gauss

#: Rule of the axial part of the law on a ``"lobatto"`` cable: 3-point Gauss-Lobatto
#: (Simpson: the nodes and the midpoint), reference coordinates and weights.
LOBATTO = (np.array([0.0, 0.5, 1.0]), np.array([1.0, 4.0, 1.0]) / 6.0)

#: Rule of the bending part of the law of the Lobatto formulation: the 3-point Gauss rule
#: on [0, 1] (exact for the linearised bending stiffness; as accurate as 5 points on the
#: elastica and a third cheaper), the one the assumed strain of the cubic element takes
#: the strain's means with (``kernels.assumed_strain.Rule``).
BENDING_RULE = (assumed_strain.GAUSS_XI, assumed_strain.GAUSS_W)


@functools.cache
def _points_map(orders, points):
    """``Rule.assumed_map`` of the element type with the nodal fields ``orders`` at the
    reference coordinates ``points`` (a tuple), computed once: the map integrates its
    moments in exact arithmetic (sympy, a third of a second), which every sampled step
    of a cable paid before."""
    return assumed_strain.rule(orders).assumed_map(points)


class Paper:
    """Every term of the law on the Gauss rule ``cable.intorder``, or, with
    ``cable.quadrature``, the axial and the bending part each on a Gauss rule of its own;
    fields where asked."""

    name = "paper"

    def passes(self, cable):
        if cable.quadrature is None:
            return [(cable.law, "gauss", (cable.Sx, cable.Sxx, cable.weights, cable.h))]
        return [(cable.law.part(k), "gauss", cable.tables_at(*gauss(cable.quadrature[part])))
                for k, part in enumerate(("axial", "bending"))]

    def strain(self, cable, q, s, stretch=1.0):
        return cable.green(q, *cable.locate(s), stretch)

    def tension(self, cable, q, s, stretch=1.0, t=0.0):
        return cable.section_force(q, *cable.locate(s), stretch, t=t)


def _element_values(value, n_elements):
    """``value(e, xi)`` at the start, the midpoint and the end of every element: three
    arrays (..., n_elements)."""
    e = np.arange(n_elements)
    return tuple(value(e, np.full(n_elements, xi)) for xi in (0.0, 0.5, 1.0))


def _nodal(start, end):
    """Nodal values (..., n_nodes) from the values at the start and the end of every
    element (..., n_elements): the two values at an interior node averaged."""
    return np.concatenate([start[..., :1], 0.5 * (start[..., 1:] + end[..., :-1]),
                           end[..., -1:]], axis=-1)


def _quadratic(cable, nodes, middles, s):
    """The continuous piecewise quadratic through ``nodes`` (..., n_nodes) and ``middles``
    (..., n_elements), at arc lengths ``s``."""
    e, xi = cable.locate(s)
    return (2 * (xi - 0.5) * (xi - 1) * nodes[..., e] - 4 * xi * (xi - 1) * middles[..., e]
            + 2 * xi * (xi - 0.5) * nodes[..., e + 1])


class _Recovered:
    """Strain and tension of the raw field, sampled and interpolated by the formulation's
    ``_recovered(cable, value, s)`` (``value(e, xi)``: the field in elements ``e`` at
    reference coordinates ``xi``)."""

    def strain(self, cable, q, s, stretch=1.0):
        return self._recovered(cable, lambda e, xi: cable.green(q, e, xi, stretch), s)

    def tension(self, cable, q, s, stretch=1.0, t=0.0):
        return self._recovered(
            cable, lambda e, xi: cable.section_force(q, e, xi, stretch, t=t), s)


class Lobatto(_Recovered):
    """The axial part on the Gauss-Lobatto rule, the bending part on the 3-point Gauss
    rule; fields recovered from the Lobatto points."""

    name = "lobatto"

    def passes(self, cable):
        return [(cable.law.part(0), "gauss", cable.tables_at(*LOBATTO)),
                (cable.law.part(1), "gauss", cable.tables_at(*BENDING_RULE))]

    @staticmethod
    def _recovered(cable, value, s):
        """``value(e, xi)`` sampled where the axial strain is defined, the nodes
        (averaged over the two elements that meet there) and the midpoints, and
        interpolated quadratically in between, at arc lengths ``s``: between those points
        the raw strain of the cubic field is not constrained by the energy."""
        left, middle, right = _element_values(value, cable.n_elements)
        return _quadratic(cable, _nodal(left, right), middle, s)


class AssumedStrain:
    """The axial part at the assumed strain (``kernels.assumed_strain``), the bending
    part on its Gauss rule; strain and tension recovered from the assumed strain
    (``recovered``)."""

    name = "assumed-strain"

    #: Reference coordinates of the element points the recovery reads.
    POINTS = (0.0, 0.5, 1.0)

    def passes(self, cable):
        """One pass: the axial part at the assumed strain and the bending part on the
        Gauss rule of the element's ``kernels.assumed_strain.Rule``."""
        assumed = assumed_strain.rule(cable.element.orders)
        Sx = cable.tables_at(assumed.samples, np.zeros(assumed.samples.size))[0]
        _, Sxx, w, h = cable.tables_at(*assumed.gauss)
        return [(cable.law, "assumed-strain", (Sx, Sxx, w, h))]

    def strain(self, cable, q, s, stretch=1.0):
        return self.recovered(cable, *self.assumed(cable, q, stretch), s)

    def tension(self, cable, q, s, stretch=1.0, t=0.0):
        e = np.arange(cable.n_elements)
        force = [self.axial_force(cable, eps, e, stretch, t)
                 for eps in self.assumed(cable, q, stretch)]
        bending = cable.law.part(1)
        if not bending.vanishes:  # at the three points in one call: (..., 3, n_elements)
            points = np.broadcast_to(e, (len(self.POINTS), e.size))
            xi = np.broadcast_to(np.array(self.POINTS)[:, None], points.shape)
            bent = cable.section_force(q, points, xi, stretch, bending, t)
            force = [f + part for f, part in zip(force, np.moveaxis(bent, -2, 0))]
        return self.recovered(cable, *force, s)

    def assumed(self, cable, q, stretch=1.0):
        """The assumed strain at the start, the midpoint and the end of every element
        (three arrays (..., n_elements)): the element's ``Rule.assumed_map``
        (``kernels.assumed_strain``) of the raw strains at its samples."""
        orders = cable.element.orders
        a = cable.slopes_at(q, assumed_strain.rule(orders).samples, stretch)
        raw = 0.5 * (np.einsum("...i,...i", a, a) - 1.0)
        return tuple(np.moveaxis(raw @ _points_map(orders, self.POINTS).T, -1, 0))

    @staticmethod
    def axial_force(cable, eps, e, stretch=1.0, t=0.0):
        """``W'(eps) sqrt(1 + 2 eps)``: the axial force ``t . W_a = W'(eps) |a|`` of the
        axial energy ``W(eps)`` of the law (``CableLaw.strain``) at the strains ``eps`` of
        elements ``e`` at time ``t``."""
        law = cable.law
        lam = np.reshape(stretch, np.shape(stretch) + (1,) * np.ndim(e))
        h = np.broadcast_to(cable.h[e] * lam, np.shape(eps))
        sigma = law.compiled("assumed-strain", cable.element.orders).numpy_strain(
            eps, law.values_at(cable.section, t, np.ndim(eps)), h)["s"]
        return sigma * np.sqrt(np.maximum(1 + 2 * eps, 0.0))

    @staticmethod
    def recovered(cable, left, middle, right, s):
        """A field quadratic in each element (the assumed strain, the tension from it),
        given at the start, the midpoint and the end of every element (..., n_elements),
        recovered at arc lengths ``s``.

        In each element the field is its mean ``M``, a linear part ``a1 (2 xi - 1)`` and a
        curvature part ``a2 (6 xi^2 - 6 xi + 1)``.  In bending the energy holds the nodal
        values and the means of the strain, and the curvature part (their difference)
        carries an oscillation from element to element of the size of the discretisation
        error (2.6 % of the load at the root of an elastica of 16 elements at ``k = 10``).
        The recovered field keeps each element's mean and linear part and takes its
        curvature part from the slopes ``2 a1 / h`` of the neighbouring elements,
        ``a2 = h^2 f'' / 12`` with ``f''`` their central difference (one-sided in the end
        elements; an element alone keeps its own), then is made continuous by averaging
        the two values at each node.  It is exact for fields quadratic along the cable
        (uniform and centrifugal tension: a spinning tether's tension to 1e-9) and
        removes the oscillation (5.5e-3 of the load on that elastica)."""
        mean = (left + 4 * middle + right) / 6
        a1 = (right - left) / 2
        a2 = (left + right) / 2 - mean
        if cable.n_elements > 1:
            x = cable.mesh.p[0]
            slope = 2 * a1 / cable.h
            bend = np.diff(slope, axis=-1) / np.diff(0.5 * (x[1:] + x[:-1]))
            bend = np.concatenate([bend[..., :1], 0.5 * (bend[..., 1:] + bend[..., :-1]),
                                   bend[..., -1:]], axis=-1)
            a2 = cable.h**2 * bend / 12
        return _quadratic(cable, _nodal(mean - a1 + a2, mean + a1 + a2), mean - a2 / 2, s)


class Segment(_Recovered):
    """The law at the midpoint of each element (exact for the constant strain of the
    linear element); strain and tension recovered from the midpoints, where the linear
    element's strain is superconvergent: the piecewise linear through them, extrapolated
    to the cable's ends (a uniform field in a cable of one element).  Exact for tension
    that is linear along the cable (a hanging cable's), where the raw, constant value of
    an element is off by half an element's weight."""

    name = "segment"

    #: The midpoint rule: reference coordinate and weight.
    MIDPOINT = (np.array([0.5]), np.array([1.0]))

    def passes(self, cable):
        return [(cable.law, "gauss", cable.tables_at(*self.MIDPOINT))]

    @staticmethod
    def _recovered(cable, value, s):
        """``value(e, xi)`` at the element midpoints, interpolated linearly in the arc
        length between them and extrapolated beyond the first and last, at ``s``."""
        e = np.arange(cable.n_elements)
        middle = value(e, np.full(e.size, 0.5))
        if cable.n_elements == 1:
            return np.broadcast_to(middle[..., :1], middle.shape[:-1] + np.shape(s))
        x = cable.mesh.p[0]
        centre = 0.5 * (x[1:] + x[:-1])
        k = np.clip(np.searchsorted(centre, s) - 1, 0, cable.n_elements - 2)
        w = (np.asarray(s) - centre[k]) / (centre[k + 1] - centre[k])
        return (1 - w) * middle[..., k] + w * middle[..., k + 1]


#: The formulations by name; the first is the default.
FORMULATIONS = {f.name: f for f in (AssumedStrain(), Paper(), Lobatto(), Segment())}
DEFAULT = next(iter(FORMULATIONS))
