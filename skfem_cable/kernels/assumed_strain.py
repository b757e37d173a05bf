"""Template of the compiled kernel of the assumed-strain cable (``formulation``): the axial
part of the law at the assumed strain and its bending part on the 3-point Gauss rule, in one
pass over the elements.

The Green strain ``eps = (|r_x|^2 - 1)/2`` of the C1 cubic field is continuous across the
nodes; in a bent element it is a quartic.  The assumed strain ``eps_bar`` replaces it by
the quadratic that takes its values at the element's two nodes and its mean over the
element:

``eps_bar(xi) = eps(0) (1 - xi) + eps(1) xi + 6 xi (1 - xi) (mean(eps) - (eps(0) + eps(1))/2)``

(``xi`` in [0, 1]; the mean is exact with the 3-point Gauss rule, the quartic being of
degree 4).  Over a mesh of ``n`` elements this is a continuous piecewise quadratic fixed by
``2 n + 1`` values, as many as the linearised strain of the cubic field has: no membrane
locking and no spurious zero-energy mode (``docs/locking.md``).  The law's axial energy
``W(eps)`` and dissipation ``D(eps, eps_dot)`` (``CableLaw.strain``) are integrated on
``eps_bar`` with the 3-point Gauss rule, exactly for the Green law.  Hence:

* a strain that is already a continuous quadratic (every state of a straight cable, to
  first order, and a straight cable under centrifugal or uniform tension) is its own
  assumed strain: the axial stiffness and such states are those of the exact integration
  of the paper's formulation;
* the element means are kept, so under uniform tension ``N`` the geometric stiffness
  ``N int d(r_x) . d(r_x) dx``, the second variation of ``N int eps dx``, is exact (the
  Lobatto rule integrates it with Simpson's rule: an error of fourth order in the element
  length, and the sixth-order frequencies of taut cables fall to fourth).

With the raw strains ``eps_j`` at the five sampling points ``j`` (``SAMPLES``: the nodes,
then the Gauss points) and the constant map ``MAP`` (3 x 5) from them to the assumed
strains at the Gauss points ``g``, ``eps_bar_g = MAP[g, j] eps_j``, the chain rule gives,
with ``beta_g = MAP[g, j] S_x,j^T a_j`` and ``gamma_g = MAP[g, j] S_x,j^T ad_j``
(12-vectors, ``S_x,j`` the slope table at ``j``), ``sigma = W' + D_ed``,
``k = d sigma/d eps`` and ``c = d sigma/d eps_dot``:

``f = sum_g w_g sigma_g beta_g``,
``K = sum_g w_g [(cK k_g + cC c_g) beta_g beta_g^T + cK c_g beta_g gamma_g^T]
+ cK sum_j n_j (S_x,j^T S_x,j) (x) I3``,  ``n_j = sum_g w_g sigma_g MAP[g, j]``.

The bending part (the law's terms with ``r_xx``) is integrated as ``kernels.cable`` does,
at the Gauss points (the samples 2 to 4).  ``span`` is compiled
in the assumed-strain module of each law (``laws.codegen``, kind ``"assumed-strain"``) next
to the law's ``strain_point`` functions and the ``point_*`` functions of its bending part,
as ``kernels.cable``'s template is in the law's Gauss module, with the element loop of
``kernels.chunks`` around ``span``.  The tables are those of
``kernels.cable`` with ``Sx`` at the five sampling points and ``Sxx`` at the Gauss points.
"""

import numpy as np

#: Gauss points and weights on [0, 1] (3 points): the mean of the raw strain and the rule
#: of the energy.
GAUSS_XI = 0.5 + 0.5 * np.polynomial.legendre.leggauss(3)[0]
GAUSS_W = 0.5 * np.polynomial.legendre.leggauss(3)[1]

#: Reference coordinates of the sampling points of the raw strain: the nodes, then the
#: Gauss points.
SAMPLES = np.concatenate([[0.0, 1.0], GAUSS_XI])


def assumed_map(xi):
    """The map (len(xi), 5) from the raw strains at ``SAMPLES`` to the assumed strain at
    the reference coordinates ``xi``: the nodal values, and the mean by the Gauss rule
    (module docstring)."""
    xi = np.atleast_1d(np.asarray(xi, dtype=float))
    bubble = 6 * xi * (1 - xi)
    out = np.empty((xi.size, 5))
    out[:, 0] = 1 - xi - bubble / 2
    out[:, 1] = xi - bubble / 2
    out[:, 2:] = bubble[:, None] * GAUSS_W[None, :]
    return out


#: Raw strains at ``SAMPLES`` -> assumed strains at the Gauss points.
MAP = assumed_map(GAUSS_XI)


def span(first, last, step, state, elements, law, out, coef, acc):
    """Add the elastic and damping forces of the elements ``range(first, last, step)`` of
    the assumed-strain cable to ``f`` and ``cK K + cC C`` into ``data``: the axial part at the
    assumed strain and the bending part on the 3-point Gauss rule (the element loop,
    ``kernels.chunks``, calls it for its chunks of elements).

    Parameters
    ----------
    first, last, step : int
        The elements ``range(first, last, step)``.
    state : tuple ``(q, v)``
    elements : tuple ``(edofs, Sx, Sxx, w, h)``
        Global DOF of each element coordinate, int (ne, 12); the slope table at the five
        ``SAMPLES`` (ne, 5, 4) (the nodes, then the Gauss points); the second-derivative
        table at the Gauss points (ne, 3, 4); the Gauss weights times the element lengths
        (ne, 3); element lengths (ne,).
    law, out, coef, acc
        As in ``kernels.cable.span``: the axial part's energy and power go to ``acc[0]``,
        ``acc[2]``, the bending part's to ``acc[1]``, ``acc[3]``.
    """
    q, v = state
    edofs, Sx, Sxx, w, h = elements
    prm, damped = law
    f, fd, data, scatter, energy, power = out
    cK, cC = coef
    ne = w.shape[0]
    want_matrix = scatter.shape[0] == ne
    damped = DAMPED and damped  # noqa: F821 (constants of the generated module)
    bending = BENDING  # noqa: F821
    qe = np.empty((4, 3))
    ve = np.zeros((4, 3))
    a = np.empty((5, 3))
    ad = np.zeros((5, 3))
    raw = np.empty(5)
    rate = np.zeros(5)
    n = np.empty(5)
    Bj = np.empty((5, 12))
    Bdj = np.zeros((5, 12))
    beta = np.empty((3, 12))
    gamma = np.zeros((3, 12))
    sb = np.empty((3, 12))
    x = np.empty(6)
    xd = np.zeros(6)
    G = np.zeros(6)
    H = np.zeros((6, 6))
    Gd = np.zeros(6)
    Hc = np.zeros((6, 6))
    T = np.empty((6, 12))
    S6 = np.empty((2, 4))
    fe = np.empty(12)
    fde = np.zeros(12)
    Ke = np.empty((12, 12))
    for e in range(first, last, step):
        for A in range(4):
            for i in range(3):
                qe[A, i] = q[edofs[e, 3 * A + i]]
                if damped:
                    ve[A, i] = v[edofs[e, 3 * A + i]]
        # the raw strains and their rates at the samples
        for j in range(5):
            sa = 0.0
            sr = 0.0
            for i in range(3):
                aj = 0.0
                adj = 0.0
                for A in range(4):
                    aj += Sx[e, j, A] * qe[A, i]
                    adj += Sx[e, j, A] * ve[A, i]
                a[j, i] = aj
                ad[j, i] = adj
                sa += aj * aj
                sr += aj * adj
            raw[j] = 0.5 * (sa - 1.0)
            rate[j] = sr
            for A in range(4):
                for i in range(3):
                    Bj[j, 3 * A + i] = Sx[e, j, A] * a[j, i]
                    if damped:
                        Bdj[j, 3 * A + i] = Sx[e, j, A] * ad[j, i]
        # the axial part at the assumed strain of the Gauss points
        n[:] = 0.0
        fde[:] = 0.0
        for g in range(3):
            eps = 0.0
            epsd = 0.0
            for j in range(5):
                eps += MAP[g, j] * raw[j]  # noqa: F821
                epsd += MAP[g, j] * rate[j]  # noqa: F821
            wg = w[e, g]
            for m in range(12):
                b = 0.0
                bd = 0.0
                for j in range(5):
                    b += MAP[g, j] * Bj[j, m]  # noqa: F821
                    if damped:
                        bd += MAP[g, j] * Bdj[j, m]  # noqa: F821
                beta[g, m] = b
                gamma[g, m] = bd
            if damped:
                W, P, sigma, k, c, sd = strain_point_d(eps, epsd, prm, h[e])  # noqa: F821
                acc[2] += wg * P
                for m in range(12):
                    sb[g, m] = wg * ((cK * k + cC * c) * beta[g, m] + cK * c * gamma[g, m])
                    fde[m] += wg * sd * beta[g, m]
            else:
                W, sigma, k = strain_point(eps, prm, h[e])  # noqa: F821
                for m in range(12):
                    sb[g, m] = wg * cK * k * beta[g, m]
            acc[0] += wg * W
            for j in range(5):
                n[j] += wg * sigma * MAP[g, j]  # noqa: F821
        for m in range(12):
            s = 0.0
            for j in range(5):
                s += n[j] * Bj[j, m]
            fe[m] = s
        if want_matrix:
            for r in range(12):
                for m in range(12):
                    Ke[r, m] = beta[0, r] * sb[0, m] + beta[1, r] * sb[1, m] + beta[2, r] * sb[2, m]
            for A in range(4):
                for B in range(4):
                    s = 0.0
                    for j in range(5):
                        s += n[j] * Sx[e, j, A] * Sx[e, j, B]
                    s *= cK
                    for i in range(3):
                        Ke[3 * A + i, 3 * B + i] += s
        # the bending part at the Gauss points (the samples 2..4), as kernels.cable adds a
        # point (written out in both templates: shared njit helpers measured 20 to 60 %
        # slower, numba optimising less across a call than within one function)
        if bending:
            for g in range(3):
                for A in range(4):
                    S6[0, A] = Sx[e, 2 + g, A]
                    S6[1, A] = Sxx[e, g, A]
                for i in range(3):
                    bx = 0.0
                    bxd = 0.0
                    for A in range(4):
                        bx += S6[1, A] * qe[A, i]
                        bxd += S6[1, A] * ve[A, i]
                    x[i] = a[2 + g, i]
                    x[3 + i] = bx
                    xd[i] = ad[2 + g, i]
                    xd[3 + i] = bxd
                wg = w[e, g]
                if damped:
                    if want_matrix:
                        ea, eb, pa, pb = point_ghd(x, xd, prm, h[e], G, H, Gd, Hc)  # noqa: F821
                    else:
                        ea, eb, pa, pb = point_gd(x, xd, prm, h[e], G, Gd)  # noqa: F821
                    acc[3] += wg * pb
                elif want_matrix:
                    ea, eb = point_gh(x, prm, h[e], G, H)  # noqa: F821
                else:
                    ea, eb = point_g(x, prm, h[e], G)  # noqa: F821
                acc[1] += wg * eb
                for A in range(4):
                    for i in range(3):
                        fe[3 * A + i] += wg * (S6[0, A] * G[i] + S6[1, A] * G[3 + i])
                        if damped:
                            fde[3 * A + i] += wg * (S6[0, A] * Gd[i] + S6[1, A] * Gd[3 + i])
                if want_matrix:
                    # Ke += B^T Hw B with B = S6 (x) I3: T = Hw B, then B^T T
                    for r in range(6):
                        for B in range(4):
                            for j in range(3):
                                h0 = cK * H[r, j]
                                h1 = cK * H[r, 3 + j]
                                if damped:
                                    h0 += cC * Hc[r, j]
                                    h1 += cC * Hc[r, 3 + j]
                                T[r, 3 * B + j] = wg * (h0 * S6[0, B] + h1 * S6[1, B])
                    for A in range(4):
                        for i in range(3):
                            for m in range(12):
                                Ke[3 * A + i, m] += S6[0, A] * T[i, m] + S6[1, A] * T[3 + i, m]
        for m in range(12):
            f[edofs[e, m]] += fe[m]
            if damped:
                fd[edofs[e, m]] += fde[m]
        if want_matrix:
            for r in range(12):
                for m in range(12):
                    data[scatter[e, r, m]] += Ke[r, m]
