"""Numba kernel of the rigid body's internal constraints (paper Eqs. 45-49): the compiled
hook of a nonlinear constraint (``contract``, ``Constraint.kernel``)."""

from numba import njit


@njit(cache=True)
def constraint_kernel(pack, index, cev):
    """Quadratic constraints ``C_j = q^T H_j q / 2 - c_j`` of one body: write ``scale C``
    into the multiplier rows of ``r_c``, add ``C_q^T lam`` to ``f_con`` and, with ``data``
    not empty, ``scale C_q``, ``scale C_q^T`` and ``cK sum_j lam_j H_j`` (Eq. 47).

    Parameters
    ----------
    pack : tuple ``(H, c)``
        Constant Hessians (m, nd, nd) and offsets (m,).
    index : tuple ``(dofs, rows, jac, jacT, hess)``
        The body's coordinates (nd,), the constraints' multiplier rows (m,) and the
        positions of ``C_q`` (m * nd), ``C_q^T`` (nd * m) and the Hessian term (nd * nd)
        in ``data`` (row-major).
    cev : tuple ``(q, lam, s, r_c, f_con, data)``
        Coordinates, multipliers, ``s = [t, cK, scale]``, constraint residual, constraint
        forces and matrix values (size 0: no tangent).
    """
    H, c = pack
    dofs, rows, jac, jacT, hess = index
    q, lam, s, r_c, f_con, data = cev
    cK, scale = s[1], s[2]
    m, nd = rows.size, dofs.size
    for j in range(m):
        lam_j = lam[rows[j]]
        value = 0.0
        for a in range(nd):
            g = 0.0
            for b in range(nd):
                g += H[j, a, b] * q[dofs[b]]
            value += 0.5 * g * q[dofs[a]]
            f_con[dofs[a]] += g * lam_j
            if data.size:
                data[jac[j * nd + a]] += scale * g
                data[jacT[a * m + j]] += scale * g
        r_c[rows[j]] = scale * (value - c[j])
    if data.size:
        for a in range(nd):
            for b in range(nd):
                h = 0.0
                for j in range(m):
                    h += lam[rows[j]] * H[j, a, b]
                data[hess[a * nd + b]] += cK * h
