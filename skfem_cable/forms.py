"""scikit-fem forms of a cable's element law: the same physics as the compiled kernel of a
cable in the paper's formulation (``formulation="paper"``: every term on the Gauss rule of
``cable.basis``), assembled by ``skfem.asm``.  The locking-free formulations integrate the
law's axial part on a rule of its own, which a form cannot express; they are refused.

With ``a = r_x``, ``b = r_xx`` interpolated from the state at the quadrature points and
``x = (a, b)``, the law's generated numpy code gives ``G = W_x + D_xd``, ``H = W_xx +
D_xd,x`` and ``Hc = D_xd,xd`` (``laws.codegen``), and

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

A reference path for checking and extending (it evaluates the law in numpy, once per
assembly); simulations use the compiled kernel.
"""

import numpy as np
from skfem import BilinearForm, LinearForm


def state(cable, q, v=None):
    """Keyword fields for ``skfem.asm`` at the cable's coordinates ``q`` and velocities
    ``v`` (``None``: at rest): ``r`` and ``rdot`` (interpolated fields) and ``h`` (element
    length at the quadrature points)."""
    q = np.asarray(q, dtype=float)
    v = np.zeros_like(q) if v is None else np.asarray(v, dtype=float)
    for name, arr in (("q", q), ("v", v)):
        if arr.shape != (cable.n_dofs,):
            raise ValueError(f"{name} must have shape ({cable.n_dofs},) (the cable's "
                             f"coordinates), got {arr.shape}")
    nq = cable.basis.X.shape[-1]
    return {"r": cable.basis.interpolate(q), "rdot": cable.basis.interpolate(v),
            "h": np.repeat(cable.h[:, None], nq, axis=1)}


def _six(field):
    """``(u_x, u_xx)`` of a vector field stacked to (6, ne, nq)."""
    return np.concatenate([field.grad[:, 0], field.hess[:, 0, 0]])


def _densities(cable):
    """``point(w)``: the law's densities at the quadrature points of the fields ``w``,
    evaluated once per assembly (the forms call it once per pair of basis functions)."""
    if cable.formulation != "paper":
        raise NotImplementedError(
            f"cable {cable.name!r} has the {cable.formulation!r} formulation: its axial part "
            "is integrated on a rule of its own (and the assumed strain couples the points "
            "of an element), which a form on cable.basis cannot express; the forms give "
            "the law of a cable built with formulation='paper' (the same law, every term "
            "on the Gauss rule of cable.basis)")
    memo = [None, None]

    def point(w):
        if memo[0] is not w:
            memo[0], memo[1] = w, cable.densities(_six(w["r"]), _six(w["rdot"]),
                                                   np.asarray(w["h"]))
        return memo[1]

    return point


def internal(cable):
    """The residual ``LinearForm`` and the tangent ``BilinearForm`` (``df/dq``) of the
    cable's law, to assemble with ``state(cable, q, v)`` on ``cable.basis``."""
    point = _densities(cable)

    @LinearForm
    def residual(v, w):
        return np.einsum("i...,i...->...", point(w)["G"], _six(v))

    @BilinearForm
    def tangent(u, v, w):
        return np.einsum("ij...,j...,i...->...", point(w)["H"], _six(u), _six(v))

    return residual, tangent


def damping(cable):
    """The damping tangent ``BilinearForm`` (``df/dv``) of the cable's law."""
    point = _densities(cable)

    @BilinearForm
    def tangent(u, v, w):
        return np.einsum("ij...,j...,i...->...", point(w)["Hc"], _six(u), _six(v))

    return tangent
