"""Template of the compiled kernel of the assumed-strain axial part of a cable's law.

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

``strain_force_tangent`` and ``strain_kernel`` are compiled in each law's generated module
(``laws.codegen``) next to the law's ``strain_point`` functions, as ``kernels.cable``'s
template is.  The tables are those of ``kernels.cable`` with ``Sx`` at the five sampling
points and no ``Sxx`` (the axial part has no ``r_xx``).
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


def strain_force_tangent(state, elements, law, out, coef):
    """Add the assumed-strain axial forces to ``f`` and ``cK K + cC C`` into ``data``.

    Parameters
    ----------
    state : tuple ``(q, v)``
    elements : tuple ``(edofs, Sx, Sxx, w, h)``
        Global DOF of each element coordinate, int (ne, 12); the slope table at the five
        ``SAMPLES`` (ne, 5, 4); an unused ``Sxx`` (ne, 0, 4); the Gauss weights times
        the element lengths (ne, 3); element lengths (ne,).
    law, out, coef
        As in ``kernels.cable.force_tangent`` (only the axial energy and power are
        written).
    """
    q, v = state
    edofs, Sx, Sxx, w, h = elements
    prm, damped = law
    f, fd, data, scatter, energy, power = out
    cK, cC = coef
    ne = w.shape[0]
    want_matrix = scatter.shape[0] == ne
    damped = DAMPED and damped  # noqa: F821 (constant of the generated module)
    qe = np.empty((4, 3))
    ve = np.zeros((4, 3))
    a = np.empty((5, 3))
    ad = np.zeros((5, 3))
    raw = np.empty(5)
    rate = np.zeros(5)
    n = np.empty(5)
    beta = np.empty((3, 12))
    gamma = np.zeros((3, 12))
    Bj = np.empty((5, 12))
    Bdj = np.zeros((5, 12))
    stiff = np.empty(3)
    cross = np.zeros(3)
    sigma_d = np.zeros(3)
    fe = np.empty(12)
    fde = np.empty(12)
    Ke = np.empty((12, 12))
    for e in range(ne):
        for A in range(4):
            for i in range(3):
                qe[A, i] = q[edofs[e, 3 * A + i]]
                if damped:
                    ve[A, i] = v[edofs[e, 3 * A + i]]
        for j in range(5):
            sa = 0.0
            sr = 0.0
            for i in range(3):
                x = 0.0
                xd = 0.0
                for A in range(4):
                    x += Sx[e, j, A] * qe[A, i]
                    xd += Sx[e, j, A] * ve[A, i]
                a[j, i] = x
                ad[j, i] = xd
                sa += x * x
                sr += x * xd
            raw[j] = 0.5 * (sa - 1.0)
            rate[j] = sr
            for A in range(4):
                for i in range(3):
                    Bj[j, 3 * A + i] = Sx[e, j, A] * a[j, i]
                    if damped:
                        Bdj[j, 3 * A + i] = Sx[e, j, A] * ad[j, i]
        n[:] = 0.0
        fde[:] = 0.0
        for g in range(3):
            eps = 0.0
            epsd = 0.0
            for j in range(5):
                eps += MAP[g, j] * raw[j]  # noqa: F821
                epsd += MAP[g, j] * rate[j]  # noqa: F821
            wg = w[e, g]
            if damped:
                W, P, sigma, k, c, sd = strain_point_d(eps, epsd, prm, h[e])  # noqa: F821
                power[0] += wg * P
                cross[g] = wg * cK * c
                stiff[g] = wg * (cK * k + cC * c)
                sigma_d[g] = wg * sd
            else:
                W, sigma, k = strain_point(eps, prm, h[e])  # noqa: F821
                stiff[g] = wg * cK * k
            energy[0] += wg * W
            for j in range(5):
                n[j] += wg * sigma * MAP[g, j]  # noqa: F821
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
                for m in range(12):
                    fde[m] += sigma_d[g] * beta[g, m]
        for m in range(12):
            s = 0.0
            for j in range(5):
                s += n[j] * Bj[j, m]
            fe[m] = s
        for m in range(12):
            f[edofs[e, m]] += fe[m]
            if damped:
                fd[edofs[e, m]] += fde[m]
        if want_matrix:
            for r in range(12):
                for m in range(12):
                    s = 0.0
                    for g in range(3):
                        s += beta[g, r] * (stiff[g] * beta[g, m] + cross[g] * gamma[g, m])
                    Ke[r, m] = s
            for A in range(4):
                for B in range(4):
                    s = 0.0
                    for j in range(5):
                        s += n[j] * Sx[e, j, A] * Sx[e, j, B]
                    s *= cK
                    for i in range(3):
                        Ke[3 * A + i, 3 * B + i] += s
            for r in range(12):
                for m in range(12):
                    data[scatter[e, r, m]] += Ke[r, m]


def strain_kernel(pack, index, ev):
    """The compiled hook of the evaluation contract (``contract.Term.kernels``):
    ``strain_force_tangent`` on the packed evaluation ``ev``, as ``kernels.cable.kernel``."""
    q, v, s, f, f_ext, fd, data, energy, power = ev
    edofs, Sx, Sxx, w, h, prm, damped = pack
    scatter = index if data.size else index[:0]
    strain_force_tangent((q, v), (edofs, Sx, Sxx, w, h), (prm, damped and s[3] != 0.0),
                  (f, fd, data, scatter, energy, power), (s[1], s[2]))
