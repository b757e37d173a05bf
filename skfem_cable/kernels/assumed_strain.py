"""Template of the compiled kernel of the assumed-strain cable (``formulation``): the axial
part of the law at the assumed strain and its bending part on a Gauss rule, in one pass
over the elements, for any element type (``Rule`` builds its tables).

The Green strain ``eps = (|r_x|^2 - 1)/2`` of the C1 cubic field is continuous across the
nodes; in a bent element it is a quartic.  The assumed strain ``eps_bar`` replaces it by
the quadratic that takes its values at the element's two nodes and its mean over the
element:

``eps_bar(xi) = eps(0) (1 - xi) + eps(1) xi + 6 xi (1 - xi) (mean(eps) - (eps(0) + eps(1))/2)``

(``xi`` in [0, 1]; the mean is exact with the 3-point Gauss rule, the quartic being of
degree 4).  Over a mesh of ``n`` elements this is a continuous piecewise quadratic fixed by
``2 n + 1`` values, as many as the linearised strain of the cubic field has: no membrane
locking and no spurious zero-energy mode (``docs/locking.md``).  The quintic element's is
the quintic with the strain's nodal values and slopes and its mean and first moment,
``4 n + 2`` values (``Rule``).  The law's axial energy ``W(eps)`` and dissipation
``D(eps, eps_dot)`` (``CableLaw.strain``) are integrated on ``eps_bar`` with the Gauss
rule (3 points on the cubic element, 6 on the quintic), exactly for the Green law.
Hence:

* a strain that is already a continuous quadratic (every state of a straight cable, to
  first order, and a straight cable under centrifugal or uniform tension) is its own
  assumed strain: the axial stiffness and such states are those of the exact integration
  of the paper's formulation;
* the element means are kept, so under uniform tension ``N`` the geometric stiffness
  ``N int d(r_x) . d(r_x) dx``, the second variation of ``N int eps dx``, is exact (the
  Lobatto rule integrates it with Simpson's rule: an error of fourth order in the element
  length, and the sixth-order frequencies of taut cables fall to fourth).

With the raw strains ``eps_j`` at the sampling points ``j`` (``Rule.samples``: the nodes,
the Gauss points, then the points that make the raw strain's nodal derivatives exact) and
the constant map ``MAP`` (``Rule.map``, 3 x 5 on the cubic element) from them to the
assumed strains at the Gauss points ``g``, ``eps_bar_g = MAP[g, j] eps_j``, the chain rule
gives, with ``beta_g = MAP[g, j] S_x,j^T a_j`` and ``gamma_g = MAP[g, j] S_x,j^T ad_j``
(``3 nf``-vectors, ``S_x,j`` the slope table at ``j``), ``sigma = W' + D_ed``,
``k = d sigma/d eps`` and ``c = d sigma/d eps_dot``:

``f = sum_g w_g sigma_g beta_g = sum_j n_j S_x,j^T a_j``,
``K = sum_g w_g [(cK k_g + cC c_g) beta_g beta_g^T + cK c_g beta_g gamma_g^T]
+ cK sum_j n_j (S_x,j^T S_x,j) (x) I3``,  ``n_j = sum_g w_g sigma_g MAP[g, j]``,

and the damping part of ``f`` likewise from ``sum_g w_g D_ed,g MAP[g, j]``: a residual
without tangent needs neither ``beta`` nor ``gamma``.

The bending part (the law's terms with ``r_xx``) is integrated as ``kernels.cable`` does,
at the Gauss points (the samples ``2 .. ng + 1``).  ``span`` is compiled
in the assumed-strain module of each law (``laws.codegen``, kind ``"assumed-strain"``) next
to the law's ``strain_point`` functions and the ``point_*`` functions of its bending part,
as ``kernels.cable``'s template is in the law's Gauss module; the element loop of
``kernels.chunks`` calls it at its address.  The tables are those of
``kernels.cable`` with ``Sx`` at the sampling points and ``Sxx`` at the Gauss points, and
``MAP``.
"""

import functools

import numpy as np

from ..elements.base import hermite_coefficients

#: Gauss points and weights on [0, 1] (3 points): the cubic element's rule of the mean of
#: the raw strain, of the energy at the assumed strain and of the bending part
#: (``Rule`` builds every element's).
GAUSS_XI = 0.5 + 0.5 * np.polynomial.legendre.leggauss(3)[0]
GAUSS_W = 0.5 * np.polynomial.legendre.leggauss(3)[1]


def gauss(points):
    """The Gauss-Legendre rule of ``points`` points on [0, 1]: coordinates and weights."""
    x, w = np.polynomial.legendre.leggauss(points)
    return (x + 1) / 2, w / 2


class Rule:
    """The assumed strain of an element type whose nodal fields are the derivatives
    ``orders`` (``CableElement.orders``, ``m = len(orders)``: the field is of degree
    ``2 m - 1``, its slope of degree ``2 m - 2``, its raw Green strain of degree
    ``4 m - 4``).

    In each element the assumed strain is the polynomial of degree ``3 m - 4`` that takes
    the raw strain's derivatives of orders ``0 .. m - 2`` at the element's two nodes and
    its moments of orders ``0 .. m - 2`` over the element (against the shifted Legendre
    polynomials ``L_k(xi) = P_k(2 xi - 1)``): the Hermite interpolant of the nodal data
    plus the bubbles ``xi^(m-1) (1 - xi)^(m-1) q(xi)`` dual to the moments, which restore
    them.  Over a mesh of ``n`` elements it is a ``C^(m-2)`` piecewise polynomial fixed by
    ``(m - 1)(2 n + 1)`` values.  The cubic element (``m = 2``): the continuous quadratic
    with the strain's nodal values and element means, ``2 n + 1`` values, the space of
    its linearised strain; the quintic (``m = 3``): the C1 quintic with the strain's nodal
    values and slopes and its element means and first moments, ``4 n + 2`` values.  Both
    leave the element about ``2 n`` inextensible modes in a plane, as many as a cubic
    element leaves: no membrane locking.  (A quartic with the means alone, ``3 n + 2``
    values, the space of the quintic's linearised strain, does not lock either and its
    tension is smooth in bending, but it loses the first moments and with them three
    orders on curved cables whose tension varies; the quintic's first moments carry an
    oscillation of the tension in bending instead: ``docs/locking.md``.)

    The raw strain is sampled at the two nodes, the ``3 m - 3`` points of the Gauss rule
    (exact for its moments, and for the energy of the Green law at the assumed strain),
    then the ``m - 2`` interior points of the ``m``-point Gauss-Lobatto rule (none on the
    cubic element, the midpoint on the quintic): ``4 m - 3`` points, which fix the raw
    strain, so that its nodal derivatives are exact combinations of the samples.

    Attributes
    ----------
    samples : ndarray (4 m - 3,)
        Reference coordinates of the samples of the raw strain.
    gauss : tuple of ndarray (3 m - 3,)
        The Gauss rule on [0, 1], coordinates and weights (the samples ``2 .. 3 m - 2``):
        the rule of the energy at the assumed strain and of the bending part.
    map : ndarray (3 m - 3, 4 m - 3)
        Raw strains at ``samples`` -> assumed strains at the Gauss points
        (``assumed_map``).
    """

    def __init__(self, orders):
        self.m = len(orders)
        self.gauss = gauss(3 * self.m - 3)
        lobatto = np.polynomial.legendre.Legendre.basis(self.m - 1).deriv().roots()
        self.samples = np.concatenate([[0.0, 1.0], self.gauss[0], (lobatto + 1) / 2])
        self.map = self.assumed_map(self.gauss[0])

    def nodal(self):
        """The map (2 (m - 1), n_samples) from the raw strains at ``samples`` to their
        derivatives in ``xi`` of orders ``0 .. m - 2`` at ``xi = 0``, then at ``xi = 1``:
        the values are samples, the derivatives those of the polynomial through them (in
        Legendre polynomials of ``t = 2 xi - 1``, well conditioned)."""
        legendre = np.polynomial.legendre
        n = self.samples.size
        through = np.linalg.inv(legendre.legvander(2 * self.samples - 1, n - 1))
        rows = []
        for end, sample in zip((-1.0, 1.0), np.eye(n)):
            rows.append(sample)
            for k in range(1, self.m - 1):
                derivative = 2.0**k * legendre.legval(end, legendre.legder(np.eye(n), k))
                rows.append(derivative @ through)
        return np.array(rows)

    def moments(self):
        """The map (m - 1, n_samples) from the raw strains at ``samples`` to their moments
        ``int eps L_k dxi``, ``k = 0 .. m - 2``, by the Gauss rule (exact)."""
        x, w = self.gauss
        out = np.zeros((self.m - 1, self.samples.size))
        out[:, 2:2 + x.size] = w * _legendre(self.m - 2, x)
        return out

    def assumed_map(self, xi):
        """The map (len(xi), n_samples) from the raw strains at ``samples`` to the assumed
        strain at the reference coordinates ``xi``: the Hermite interpolant of the nodal
        data (``nodal``), plus the bubbles times the raw strain's moments (``moments``)
        less the interpolant's (moments and bubbles in exact arithmetic)."""
        import sympy as sp  # here: importing sympy costs 0.3 s, and this runs once per element type

        xi = np.atleast_1d(np.asarray(xi, dtype=float))
        m = self.m
        hermite = hermite_coefficients(tuple(range(m - 1)))  # (2 m - 2 functions, powers)
        functions = np.polynomial.polynomial.polyval(xi, hermite.T)
        t = sp.Symbol("xi")
        legendre = [sp.legendre(k, 2 * t - 1) for k in range(m - 1)]
        power_moments = np.array([[float(sp.integrate(t**j * L, (t, 0, 1))) for L in legendre]
                                  for j in range(2 * m - 2)])
        bubble = t ** (m - 1) * (1 - t) ** (m - 1)
        gram = sp.Matrix(m - 1, m - 1, lambda i, j: sp.integrate(
            bubble * legendre[i] * legendre[j], (t, 0, 1)))
        dual = np.array(gram.inv().tolist(), dtype=float)
        bubbles = (dual @ _legendre(m - 2, xi)) * xi ** (m - 1) * (1 - xi) ** (m - 1)
        nodal = self.nodal()
        return (functions.T @ nodal - bubbles.T @ ((hermite @ power_moments).T @ nodal)
                + bubbles.T @ self.moments())


def _legendre(degree, xi):
    """The shifted Legendre polynomials ``P_k(2 xi - 1)``, ``k = 0 .. degree``, at ``xi``:
    (degree + 1, len(xi))."""
    return np.polynomial.legendre.legvander(2 * np.asarray(xi) - 1, degree).T


@functools.cache
def rule(orders):
    """The assumed strain (``Rule``) of the element type with the nodal fields
    ``orders``, built once."""
    return Rule(orders)


def constants(orders):
    """The constants of the generated module of the element type with the nodal fields
    ``orders`` (``laws.codegen``): its numbers of functions ``NF``, samples ``NS`` and
    Gauss points ``NG``, and its ``MAP`` (``Rule.map``), so that ``span``'s loops unroll
    (read from the tables they cost the cubic element a fifth more time per evaluation
    and the quintic a half).  Each element type compiles a module of its own, and only
    when a cable of that type takes the assumed strain."""
    assumed = rule(tuple(orders))
    return (f"ORDERS = {tuple(orders)!r}\nNF = {2 * len(orders)}\n"
            f"NS = {assumed.samples.size}\nNG = {assumed.gauss[0].size}\n"
            "MAP = rule(ORDERS).map")


def span(first, last, step, state, elements, law, out, coef, acc):
    """Add the elastic and damping forces of the elements ``range(first, last, step)`` of
    the assumed-strain cable to ``f`` and ``cK K + cC C`` into ``data``: the axial part at the
    assumed strain and the bending part on the Gauss rule (the element loop,
    ``kernels.chunks``, calls it for its chunks of elements).

    Parameters
    ----------
    first, last, step : int
        The elements ``range(first, last, step)``.
    state : tuple ``(q, v)``
    elements : tuple ``(edofs, Sx, Sxx, w, h)``
        Global DOF of each element coordinate, int (ne, 3 nf); the slope table at the
        ``ns`` sampling points (ne, ns, nf) (the nodes, the ``ng`` Gauss points, the
        others: ``Rule.samples``); the second-derivative table at the Gauss points (ne,
        ng, nf); the Gauss weights times the element lengths (ne, ng); element lengths
        (ne,).
    law, out, coef, acc
        As in ``kernels.cable.span``: the axial part's energy and power go to ``acc[0]``,
        ``acc[2]``, the bending part's to ``acc[1]``, ``acc[3]``.

    The numbers of functions ``nf``, samples ``ns`` and Gauss points ``ng`` and the map
    ``MAP`` (ng, ns) from the raw strains at the samples to the assumed strains at the
    Gauss points are constants of the generated module (``constants``).
    """
    q, v = state
    edofs, Sx, Sxx, w, h = elements
    nf, ns, ng, amap = NF, NS, NG, MAP  # noqa: F821 (constants of the generated module)
    prm, damped = law
    f, fd, data, scatter, energy, power = out
    cK, cC = coef
    ne = w.shape[0]
    nd = 3 * nf
    want_matrix = scatter.shape[0] == ne
    damped = DAMPED and damped  # noqa: F821 (constants of the generated module)
    bending = BENDING  # noqa: F821
    qe = np.empty((nf, 3))
    ve = np.zeros((nf, 3))
    a = np.empty((ns, 3))
    ad = np.zeros((ns, 3))
    raw = np.empty(ns)
    rate = np.zeros(ns)
    n = np.empty(ns)
    nsd = np.zeros(ns)
    Bj = np.empty((ns, nd))
    Bdj = np.zeros((ns, nd))
    beta = np.empty((ng, nd))
    gamma = np.zeros((ng, nd))
    sb = np.empty((ng, nd))
    x = np.empty(6)
    xd = np.zeros(6)
    G = np.zeros(6)
    H = np.zeros((6, 6))
    Gd = np.zeros(6)
    Hc = np.zeros((6, 6))
    T = np.empty((6, nd))
    S6 = np.empty((2, nf))
    fe = np.empty(nd)
    fde = np.zeros(nd)
    Ke = np.empty((nd, nd))
    for e in range(first, last, step):
        for A in range(nf):
            for i in range(3):
                qe[A, i] = q[edofs[e, 3 * A + i]]
                if damped:
                    ve[A, i] = v[edofs[e, 3 * A + i]]
        # the raw strains and their rates at the samples
        for j in range(ns):
            sa = 0.0
            sr = 0.0
            for i in range(3):
                aj = 0.0
                adj = 0.0
                for A in range(nf):
                    aj += Sx[e, j, A] * qe[A, i]
                    adj += Sx[e, j, A] * ve[A, i]
                a[j, i] = aj
                ad[j, i] = adj
                sa += aj * aj
                sr += aj * adj
            raw[j] = 0.5 * (sa - 1.0)
            rate[j] = sr
            for A in range(nf):
                for i in range(3):
                    Bj[j, 3 * A + i] = Sx[e, j, A] * a[j, i]
                    if damped and want_matrix:
                        Bdj[j, 3 * A + i] = Sx[e, j, A] * ad[j, i]
        # the axial part at the assumed strain of the Gauss points
        n[:] = 0.0
        nsd[:] = 0.0
        for g in range(ng):
            eps = 0.0
            epsd = 0.0
            for j in range(ns):
                eps += amap[g, j] * raw[j]
                epsd += amap[g, j] * rate[j]
            wg = w[e, g]
            # beta, gamma and sb serve the tangent alone (a residual without tangent skips
            # them: most evaluations of a modified Newton)
            if want_matrix:
                for m in range(nd):
                    b = 0.0
                    bd = 0.0
                    for j in range(ns):
                        b += amap[g, j] * Bj[j, m]
                        if damped:
                            bd += amap[g, j] * Bdj[j, m]
                    beta[g, m] = b
                    gamma[g, m] = bd
            if damped:
                W, P, sigma, k, c, sd = strain_point_d(eps, epsd, prm, h[e])  # noqa: F821
                acc[2] += wg * P
                for j in range(ns):
                    nsd[j] += wg * sd * amap[g, j]
                if want_matrix:
                    for m in range(nd):
                        sb[g, m] = wg * ((cK * k + cC * c) * beta[g, m] + cK * c * gamma[g, m])
            else:
                W, sigma, k = strain_point(eps, prm, h[e])  # noqa: F821
                if want_matrix:
                    for m in range(nd):
                        sb[g, m] = wg * cK * k * beta[g, m]
            acc[0] += wg * W
            for j in range(ns):
                n[j] += wg * sigma * amap[g, j]
        for m in range(nd):
            s = 0.0
            for j in range(ns):
                s += n[j] * Bj[j, m]
            fe[m] = s
            if damped:
                s = 0.0
                for j in range(ns):
                    s += nsd[j] * Bj[j, m]
                fde[m] = s
        if want_matrix:
            for r in range(nd):
                for m in range(nd):
                    s = 0.0
                    for g in range(ng):
                        s += beta[g, r] * sb[g, m]
                    Ke[r, m] = s
            for A in range(nf):
                for B in range(nf):
                    s = 0.0
                    for j in range(ns):
                        s += n[j] * Sx[e, j, A] * Sx[e, j, B]
                    s *= cK
                    for i in range(3):
                        Ke[3 * A + i, 3 * B + i] += s
        # the bending part at the Gauss points (the samples 2 .. ng + 1), as
        # kernels.cable adds a point (written out in both templates: shared njit helpers
        # measured 20 to 60 % slower, numba optimising less across a call than within one
        # function)
        if bending:
            for g in range(ng):
                for A in range(nf):
                    S6[0, A] = Sx[e, 2 + g, A]
                    S6[1, A] = Sxx[e, g, A]
                for i in range(3):
                    bx = 0.0
                    bxd = 0.0
                    for A in range(nf):
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
                for A in range(nf):
                    for i in range(3):
                        fe[3 * A + i] += wg * (S6[0, A] * G[i] + S6[1, A] * G[3 + i])
                        if damped:
                            fde[3 * A + i] += wg * (S6[0, A] * Gd[i] + S6[1, A] * Gd[3 + i])
                if want_matrix:
                    # Ke += B^T Hw B with B = S6 (x) I3: T = Hw B, then B^T T
                    for r in range(6):
                        for B in range(nf):
                            for j in range(3):
                                h0 = cK * H[r, j]
                                h1 = cK * H[r, 3 + j]
                                if damped:
                                    h0 += cC * Hc[r, j]
                                    h1 += cC * Hc[r, 3 + j]
                                T[r, 3 * B + j] = wg * (h0 * S6[0, B] + h1 * S6[1, B])
                    for A in range(nf):
                        for i in range(3):
                            for m in range(nd):
                                Ke[3 * A + i, m] += S6[0, A] * T[i, m] + S6[1, A] * T[3 + i, m]
        for m in range(nd):
            f[edofs[e, m]] += fe[m]
            if damped:
                fd[edofs[e, m]] += fde[m]
        if want_matrix:
            for r in range(nd):
                for m in range(nd):
                    data[scatter[e, r, m]] += Ke[r, m]
