"""Template of the compiled cable kernel: forces and tangents of all elements in one pass.

``span`` is not compiled here: ``laws.codegen`` copies its source into the module it
generates for each element law (the element loop of ``kernels.chunks`` calls it at its
address), next to that law's point functions ``point_g``,
``point_gh``, ``point_gd``, ``point_ghd`` and the constants ``BENDING`` and ``DAMPED``,
and compiles it there with ``numba.njit(cache=True)`` (numba cannot cache a kernel that
receives its point function as an argument).  The mathematics is one chain rule: with
``x = (a, b) = (S_x e, S_xx e)`` at every Gauss point and the 2 x nf table ``S6 = [S_x;
S_xx]`` of the element's ``nf`` functions (``elements``; 4 on the paper's cubic element,
Eqs. 87, 96),

``f_A = sum_g w S6[U, A] G_U``,  ``K_AB = sum_g w S6[U, A] S6[V, B] (cK H + cC Hc)_UV``,

where the law supplies ``G = W_x + D_xd``, ``H = W_xx + D_xd,x`` and ``Hc = D_xd,xd``
at the point, and ``A, B`` run over the ``nf`` 3-vector blocks of the element coordinates
(Eq. 19).  This replaces the paper's explicit Eqs. 86-127; the element type enters only
through the tables' last dimension.
"""

import numpy as np


def span(first, last, step, state, elements, law, out, coef, acc):
    """Add the elastic and damping forces of the elements ``range(first, last, step)`` to
    ``f`` and ``cK K + cC C`` into ``data`` (the element loop, ``kernels.chunks``, calls
    it for its chunks of elements).

    Parameters
    ----------
    first, last, step : int
        The elements ``range(first, last, step)``.
    state : tuple ``(q, v)``
        Global coordinates and velocities, ndarray (n,) each.
    elements : tuple ``(edofs, Sx, Sxx, w, h)``
        Global DOF of each element coordinate, int (ne, 3 nf) (Eq. 8); shape-function
        derivative tables (ne, nq, nf) and weights (ne, nq); element lengths (ne,).
    law : tuple ``(prm, damped)``
        The law's parameter values (np,) and whether to add its dissipation.
    out : tuple ``(f, fd, data, scatter, energy, power)``
        Force accumulator ``dU/dq + dD/dv`` (n,); its damping part ``dD/dv`` alone (n,);
        CSR data accumulator and the index of each element-matrix entry in it, int
        (ne, 3 nf, 3 nf), or (0, 3 nf, 3 nf) to skip the tangents; axial and bending energy (2,)
        and dissipated power (2,) (the loop's totals: ``acc`` receives the span's).
    coef : tuple ``(cK, cC)``
        Factors of the stiffness ``df/dq`` and damping ``df/dv`` tangents.
    acc : ndarray (4,)
        Adds the elements' axial and bending energy and dissipated power.
    """
    q, v = state
    edofs, Sx, Sxx, w, h = elements
    prm, damped = law
    f, fd, data, scatter, energy, power = out
    cK, cC = coef
    ne, nq = w.shape
    nf = Sx.shape[2]
    m = 3 * nf
    want_matrix = scatter.shape[0] == ne
    damped = DAMPED and damped  # noqa: F821 (constant of the generated module)
    nu = 2 if BENDING else 1  # noqa: F821
    qe = np.empty((nf, 3))
    ve = np.zeros((nf, 3))
    x = np.zeros(6)
    xd = np.zeros(6)
    G = np.zeros(6)
    H = np.zeros((6, 6))
    Gd = np.zeros(6)
    Hc = np.zeros((6, 6))
    Hw = np.zeros((6, 6))
    T = np.zeros((6, m))
    fe = np.empty(m)
    fde = np.empty(m)
    Ke = np.empty((m, m))
    S6 = np.zeros((2, nf))
    for e in range(first, last, step):
        for A in range(nf):
            for i in range(3):
                qe[A, i] = q[edofs[e, 3 * A + i]]
                if damped:
                    ve[A, i] = v[edofs[e, 3 * A + i]]
        fe[:] = 0.0
        fde[:] = 0.0
        Ke[:] = 0.0
        for g in range(nq):
            for A in range(nf):
                S6[0, A] = Sx[e, g, A]
                S6[1, A] = Sxx[e, g, A]
            for U in range(nu):
                for i in range(3):
                    sx = 0.0
                    sv = 0.0
                    for A in range(nf):
                        sx += S6[U, A] * qe[A, i]
                        sv += S6[U, A] * ve[A, i]
                    x[3 * U + i] = sx
                    xd[3 * U + i] = sv
            wg = w[e, g]
            if damped:
                if want_matrix:
                    ea, eb, pa, pb = point_ghd(x, xd, prm, h[e], G, H, Gd, Hc)  # noqa: F821
                else:
                    ea, eb, pa, pb = point_gd(x, xd, prm, h[e], G, Gd)  # noqa: F821
                acc[2] += wg * pa
                acc[3] += wg * pb
            elif want_matrix:
                ea, eb = point_gh(x, prm, h[e], G, H)  # noqa: F821
            else:
                ea, eb = point_g(x, prm, h[e], G)  # noqa: F821
            acc[0] += wg * ea
            acc[1] += wg * eb
            for A in range(nf):
                for i in range(3):
                    fe[3 * A + i] += wg * (S6[0, A] * G[i] + S6[1, A] * G[3 + i])
                    if damped:
                        fde[3 * A + i] += wg * (S6[0, A] * Gd[i] + S6[1, A] * Gd[3 + i])
            if want_matrix:
                # Ke += B^T Hw B with B = S6 (x) I3, in two products: T = Hw B, B^T T (the
                # assumed-strain template, kernels.assumed_strain, adds its bending points so)
                for a in range(3 * nu):
                    for b in range(3 * nu):
                        hab = cK * H[a, b]
                        if damped:
                            hab += cC * Hc[a, b]
                        Hw[a, b] = wg * hab
                for a in range(3 * nu):
                    for B in range(nf):
                        for j in range(3):
                            t = 0.0
                            for V in range(nu):
                                t += Hw[a, 3 * V + j] * S6[V, B]
                            T[a, 3 * B + j] = t
                for A in range(nf):
                    for i in range(3):
                        for c in range(m):
                            k = 0.0
                            for U in range(nu):
                                k += S6[U, A] * T[3 * U + i, c]
                            Ke[3 * A + i, c] += k
        for k in range(m):
            f[edofs[e, k]] += fe[k]
            if damped:
                fd[edofs[e, k]] += fde[k]
        if want_matrix:
            for k in range(m):
                for c in range(m):
                    data[scatter[e, k, c]] += Ke[k, c]
