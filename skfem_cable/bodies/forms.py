"""scikit-fem forms of a cable's element law, assembled by ``skfem.asm``: the same physics
as the compiled kernel, for the paper's formulation (``internal``, ``damping``) and for the
default, assumed-strain formulation (``AssumedStrain``).  The Lobatto and segment
formulations are refused.

**The paper's formulation** (``formulation="paper"``: every term on the Gauss rule of
``cable.basis``).  With ``a = r_x``, ``b = r_xx`` interpolated from the state at the
quadrature points and ``x = (a, b)``, the law's generated numpy code gives ``G = W_x +
D_xd``, ``H = W_xx + D_xd,x`` and ``Hc = D_xd,xd`` (``laws.codegen``), and

* ``internal(cable)``: the residual ``L(v) = int G . (v_x, v_xx) dx`` and the tangent
  ``a(u, v) = int (v_x, v_xx) . H (u_x, u_xx) dx`` (``df/dq``);
* ``damping(cable)``: ``c(u, v) = int (v_x, v_xx) . Hc (u_x, u_xx) dx`` (``df/dv``);
* ``state(cable, q, v)``: the fields these forms read, to pass to ``skfem.asm``.

>>> import numpy as np, skfem, skfem_cable as sc
>>> cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], 4, sc.Section(E=1e9, A=1e-4, I=1e-10,
...                           rho=1e3), formulation="paper")
>>> q = cable.q0 * 1.01
>>> L, a = sc.forms.internal(cable)
>>> f = skfem.asm(L, cable.basis, **sc.forms.state(cable, q))
>>> bool(np.allclose(f, sc.System([cable]).assemble(q)[0], rtol=1e-12, atol=1e-9))
True

**The assumed strain** (the default, ``AssumedStrain``) is a mixed form.  The assumed
strain ``eps_bar`` lives in the element-wise quadratics ``Q`` (``ElementDG(ElementLineP2)``)
and is tied to the Green strain ``eps = (|r_x|^2 - 1)/2`` of the cable's field by a
multiplier ``lam`` in ``T``: element-wise linears (``ElementDG(ElementLineP1)``) paired on
the nodal rule (the trapezoidal rule at the element's two nodes), and element-wise
constants (``ElementLineP0``) paired on the 3-point Gauss rule,

``Pi(r, eps_bar, lam) = int W(eps_bar) dx + <lam, eps(r) - eps_bar> + bending``.

Stationarity in ``lam`` is ``eps_bar = eps`` at the nodes and ``int eps_bar = int eps``
over each element: the kernel's assumed strain (``kernels.assumed_strain``).  The pairing
``M`` of ``T`` and ``Q`` couples the three values of an element only, so ``eps_bar = M^-1
b(r)`` and ``lam = M^-T s`` (``s = int W'(eps_bar) phi``) are solved element by element
(static condensation) and give the force and the tangents:

* ``f = <lam, d eps>`` (+ the bending part),
* ``df/dq = G^T D_k G + G^T D_c G_d + <lam, du_x . dv_x>`` (+ the bending part),
* ``df/dv = G^T D_c G`` (+ the bending part),

with ``G = M^-1 B``, ``B`` the pairing of ``T`` with ``d eps = r_x . u_x``, ``G_d`` the same
of the strain rate ``d(r_x . v_x)/dq = v_x . u_x``, and ``D_k``, ``D_c`` the masses of ``Q``
weighted by ``k = ds/de`` and ``c = ds/d(e_dot)`` of the law's axial part in the strain
(``CableLaw.strain``).  The bending part is the law's terms with ``r_xx`` on the 3-point
Gauss rule, the forms of the paper's formulation.

>>> cable = sc.Cable.between([0, 0, 0], [1.5, 0, 0], 2.0, 8, sc.Section(E=1e9, A=1e-4,
...                           I=1e-10, rho=1e3), sag=[0, 0, -1])   # the default formulation
>>> q = cable.q0 + 1e-3 * np.random.default_rng(0).standard_normal(cable.n_dofs)
>>> f, K = sc.forms.AssumedStrain(cable).internal(q)      # force and df/dq
>>> f0, K0 = sc.System([cable]).assemble(q)                # the compiled kernel
>>> bool(abs(f - f0).max() < 1e-12 * abs(f0).max()), bool(abs(K - K0).max() < 1e-12 * abs(K0).max())
(True, True)

A reference path for checking and extending (it evaluates the law in numpy, once per
assembly); simulations use the compiled kernel.
"""

import numpy as np
from scipy import sparse
from skfem import (
    Basis,
    BilinearForm,
    ElementDG,
    ElementLineP0,
    ElementLineP1,
    ElementLineP2,
    LinearForm,
    asm,
)
from skfem.helpers import dot

#: The nodal rule on the reference element [0, 1]: the trapezoidal rule, whose points are
#: the element's nodes (the assumed strain takes the raw strain's values there).
NODAL_RULE = (np.array([[0.0, 1.0]]), np.array([0.5, 0.5]))

#: scikit-fem's integration order of the 3-point Gauss rule: the rule of the assumed
#: strain's mean, of its energy and of the bending part.
GAUSS_ORDER = 5


def state(cable, q, v=None, basis=None):
    """Keyword fields for ``skfem.asm`` at the cable's coordinates ``q`` and velocities
    ``v`` (``None``: at rest) on ``basis`` (default ``cable.basis``): ``r`` and ``rdot``
    (interpolated fields) and ``h`` (element length at the quadrature points)."""
    basis = cable.basis if basis is None else basis
    q = np.asarray(q, dtype=float)
    v = np.zeros_like(q) if v is None else np.asarray(v, dtype=float)
    for name, arr in (("q", q), ("v", v)):
        if arr.shape != (cable.n_dofs,):
            raise ValueError(f"{name} must have shape ({cable.n_dofs},) (the cable's "
                             f"coordinates), got {arr.shape}")
    nq = basis.X.shape[-1]
    return {"r": basis.interpolate(q), "rdot": basis.interpolate(v),
            "h": np.repeat(cable.h[:, None], nq, axis=1)}


def _six(field):
    """``(u_x, u_xx)`` of a vector field stacked to (6, ne, nq)."""
    return np.concatenate([field.grad[:, 0], field.hess[:, 0, 0]])


def _refuse(cable, formulation):
    """Refuse a cable whose formulation is not ``formulation``, naming the forms of each."""
    if cable.formulation != formulation:
        raise NotImplementedError(
            f"cable {cable.name!r} has the {cable.formulation!r} formulation, not "
            f"{formulation!r}: sc.forms.internal and sc.forms.damping give the law of a "
            "cable built with formulation='paper' (every term on the Gauss rule of "
            "cable.basis), sc.forms.AssumedStrain that of formulation='assumed-strain' "
            "(the default; a mixed form); the 'lobatto' and 'segment' formulations, which "
            "integrate the law's axial part on rules of their own, have no forms")


def _point(cable, law):
    """``point(w)``: the densities of ``law`` (the cable's law or a part of it) at the
    quadrature points of the fields ``w``, evaluated once per assembly (the forms call it
    once per pair of basis functions)."""
    memo = [None, None]

    def point(w):
        if memo[0] is not w:
            memo[0], memo[1] = w, cable.densities(_six(w["r"]), _six(w["rdot"]),
                                                   np.asarray(w["h"]), law)
        return memo[1]

    return point


def _law_forms(point):
    """The residual, tangent (``df/dq``) and damping (``df/dv``) forms of the densities
    ``point(w)``."""

    @LinearForm
    def residual(v, w):
        return np.einsum("i...,i...->...", point(w)["G"], _six(v))

    def matrix(key):
        @BilinearForm
        def tangent(u, v, w):
            return np.einsum("ij...,j...,i...->...", point(w)[key], _six(u), _six(v))
        return tangent

    return residual, matrix("H"), matrix("Hc")


def _paper(cable):
    """The forms of the law of a cable of the paper's formulation on one rule, that of
    ``cable.basis``; a cable with a rule per part (``Cable.quadrature``) is refused."""
    _refuse(cable, "paper")
    if cable.quadrature is not None:
        raise NotImplementedError(
            f"cable {cable.name!r} integrates the axial and the bending part of its law on "
            f"Gauss rules of their own (quadrature={cable.quadrature}), which a form on "
            "cable.basis (one rule) cannot express: the forms give the law of a cable "
            "without quadrature (every term on the rule of intorder)")
    return _law_forms(_point(cable, cable.law))


def internal(cable):
    """The residual ``LinearForm`` and the tangent ``BilinearForm`` (``df/dq``) of the
    law of a cable of the paper's formulation, to assemble with ``state(cable, q, v)`` on
    ``cable.basis`` (``AssumedStrain``: the default formulation)."""
    return _paper(cable)[:2]


def damping(cable):
    """The damping tangent ``BilinearForm`` (``df/dv``) of the law of a cable of the
    paper's formulation."""
    return _paper(cable)[2]


def _slope(w):
    """``r_x`` at the quadrature points (3, ne, nq)."""
    return w["r"].grad[:, 0]


@BilinearForm
def _mass(u, v, w):
    return u * v


@BilinearForm
def _weighted_mass(u, v, w):
    return w["weight"] * u * v


@LinearForm
def _green(psi, w):
    """The Green strain ``(|r_x|^2 - 1)/2`` against ``psi``."""
    a = _slope(w)
    return psi * 0.5 * (dot(a, a) - 1.0)


@LinearForm
def _green_rate(psi, w):
    """The strain rate ``r_x . v_x`` against ``psi``."""
    return psi * dot(_slope(w), w["rdot"].grad[:, 0])


@BilinearForm
def _variation(u, psi, w):
    """The strain's variation ``r_x . u_x`` against ``psi``."""
    return psi * dot(_slope(w), u.grad[:, 0])


@BilinearForm
def _rate_variation(u, psi, w):
    """The strain rate's variation with ``q``, ``v_x . u_x``, against ``psi``."""
    return psi * dot(w["rdot"].grad[:, 0], u.grad[:, 0])


@LinearForm
def _moment(phi, w):
    """The stress ``s`` against ``phi``."""
    return w["s"] * phi


@LinearForm
def _stress_work(v, w):
    """The multiplier ``lam`` against the strain's variation ``r_x . v_x``."""
    return w["lam"] * dot(_slope(w), v.grad[:, 0])


@BilinearForm
def _geometric(u, v, w):
    """The multiplier ``lam`` against the strain's second variation ``u_x . v_x``."""
    return w["lam"] * dot(u.grad[:, 0], v.grad[:, 0])


def _local_inverse(M, rows, cols):
    """The inverse of a matrix ``M`` (test x trial) whose element ``e`` couples the test
    DOFs ``rows[e]`` with the trial DOFs ``cols[e]`` only (both (ne, k)): the ``k x k``
    blocks inverted element by element, as a sparse matrix (trial x test)."""
    ne, k = rows.shape
    r = np.broadcast_to(rows[:, :, None], (ne, k, k))
    c = np.broadcast_to(cols[:, None, :], (ne, k, k))
    blocks = np.asarray(M.tocsr()[r.ravel(), c.ravel()]).reshape(ne, k, k)
    inverse = np.linalg.inv(blocks)
    return sparse.csr_matrix((inverse.ravel(), (np.swapaxes(c, 1, 2).ravel(),
                                                np.swapaxes(r, 1, 2).ravel())),
                             shape=M.shape[::-1])


class AssumedStrain:
    """The law of a cable of the assumed-strain formulation (the default) as a mixed
    scikit-fem form (module docstring), assembled by ``skfem.asm`` on bases of the cable's
    element and of the strain spaces on ``cable.mesh``.

    Parameters
    ----------
    cable : Cable
        A cable with ``formulation="assumed-strain"`` on the cubic Hermite element
        (``"hermite3"``).

    Attributes
    ----------
    nodal, gauss : skfem.Basis
        The cable's element on the nodal rule (``NODAL_RULE``) and on the 3-point Gauss
        rule.
    strain : skfem.Basis
        The assumed strain's space ``Q`` (``ElementDG(ElementLineP2)``) on the Gauss rule.
    tests : tuple of skfem.Basis
        The multiplier's space ``T``: ``ElementDG(ElementLineP1)`` on the nodal rule and
        ``ElementLineP0`` on the Gauss rule.
    """

    def __init__(self, cable):
        _refuse(cable, "assumed-strain")
        if tuple(cable.element.orders) != (0, 1):
            raise NotImplementedError(
                "sc.forms.AssumedStrain gives the assumed strain of the cubic element's "
                "strain space (positions and slopes at the nodes: 'hermite3'); cable "
                f"{cable.name!r} has the element {cable.element.name!r} (nodal derivatives "
                f"of orders {tuple(cable.element.orders)})")
        mesh, element = cable.mesh, cable.basis.elem
        self.cable = cable
        self.nodal = Basis(mesh, element, quadrature=NODAL_RULE)
        self.gauss = Basis(mesh, element, intorder=GAUSS_ORDER)
        self.strain = Basis(mesh, ElementDG(ElementLineP2()), intorder=GAUSS_ORDER)
        self.tests = (Basis(mesh, ElementDG(ElementLineP1()), quadrature=NODAL_RULE),
                      Basis(mesh, ElementLineP0(), intorder=GAUSS_ORDER))
        nodal_strain = Basis(mesh, self.strain.elem, quadrature=NODAL_RULE)
        M = sparse.vstack([asm(_mass, nodal_strain, self.tests[0]),
                           asm(_mass, self.strain, self.tests[1])])
        rows = np.concatenate([self.tests[0].element_dofs,
                               self.tests[1].element_dofs + self.tests[0].N]).T
        self._inverse = _local_inverse(M, rows, self.strain.element_dofs.T)
        self._bending = None if cable.law.part(1).vanishes else \
            _law_forms(_point(cable, cable.law.part(1)))
        module = cable.law.compiled("assumed-strain", cable.element.orders)
        values = cable.law.parameter_values(cable.section)
        self._axial = np.vectorize(lambda e, ed, h: module.strain_point_d(e, ed, values, h),
                                   otypes=[float] * 6)

    def _paired(self, form, fields):
        """``<psi, form>`` of a ``LinearForm`` for the multiplier's test functions ``psi``
        (``tests``): a vector over ``T``; ``fields``: those of ``state`` on ``nodal`` and
        ``gauss``."""
        return np.concatenate([asm(form, t, **w) for t, w in zip(self.tests, fields)])

    def _paired_matrix(self, form, fields):
        """``<psi, form(u)>`` of a ``BilinearForm`` in the cable's functions ``u``: a sparse
        matrix (``T`` x the cable's coordinates)."""
        return sparse.vstack([asm(form, b, t, **w) for b, t, w in
                              zip((self.nodal, self.gauss), self.tests, fields)])

    def _fields(self, q, v):
        """The fields of ``state`` on ``nodal`` and ``gauss``."""
        return [state(self.cable, q, v, basis) for basis in (self.nodal, self.gauss)]

    def _assumed(self, fields):
        """The assumed strain and its rate: coefficients in ``strain``."""
        return tuple(self._inverse @ self._paired(form, fields)
                     for form in (_green, _green_rate))

    def assumed(self, q, v=None):
        """The assumed strain and its rate at the coordinates ``q`` and velocities ``v``
        (``None``: at rest): two vectors of coefficients in ``strain`` (``Q``), to
        interpolate with ``strain.interpolate`` or a basis of ``strain.elem`` on other
        points."""
        return self._assumed(self._fields(q, v))

    def _terms(self, q, v):
        """The pieces of the condensed law at ``(q, v)``: the fields on ``nodal`` and
        ``gauss``, the multiplier's fields, ``G``, ``G_d``, ``D_k`` and ``D_c``."""
        fields = self._fields(q, v)
        eps, rate = (np.asarray(self.strain.interpolate(x)) for x in self._assumed(fields))
        _, _, s, k, c, _ = self._axial(eps, rate, fields[1]["h"])
        lam = self._inverse.T @ asm(_moment, self.strain, s=s)
        n = self.tests[0].N
        lam = [t.interpolate(part) for t, part in zip(self.tests, (lam[:n], lam[n:]))]
        G, Gd = (self._inverse @ self._paired_matrix(form, fields)
                 for form in (_variation, _rate_variation))
        Dk, Dc = (asm(_weighted_mass, self.strain, weight=x) for x in (k, c))
        return fields, lam, G, Gd, Dk, Dc

    def internal(self, q, v=None):
        """The force ``f`` (n_dofs,) and the tangent ``df/dq`` (sparse) at the
        coordinates ``q`` and velocities ``v`` (``None``: at rest)."""
        fields, lam, G, Gd, Dk, Dc = self._terms(q, v)
        bases = (self.nodal, self.gauss)
        f = sum(asm(_stress_work, b, lam=m, **w) for b, m, w in zip(bases, lam, fields))
        K = G.T @ Dk @ G + G.T @ Dc @ Gd + sum(
            asm(_geometric, b, lam=m, **w) for b, m, w in zip(bases, lam, fields))
        if self._bending is not None:
            f = f + asm(self._bending[0], self.gauss, **fields[1])
            K = K + asm(self._bending[1], self.gauss, **fields[1])
        return f, K.tocsr()

    def damping(self, q, v=None):
        """The damping tangent ``df/dv`` (sparse) at ``(q, v)``."""
        fields, _, G, _, _, Dc = self._terms(q, v)
        C = G.T @ Dc @ G
        if self._bending is not None:
            C = C + asm(self._bending[2], self.gauss, **fields[1])
        return C.tocsr()
