"""A line body that is not a ``Cable``: a string of Lagrange-quadratic elements (three nodes
each, positions only, no slopes) with Green-strain axial elasticity, written as a user
would (``docs/extending.md``, "A line body").  It declares its points through the
line-body hook ``line_points(system)`` (``skfem_cable.core.lines``) and its internal forces as
a compiled kernel that uses the one gather and interpolation of ``kernels.line``: every
built-in line load reaches it, and it runs on the compiled step."""

import numpy as np
import scipy.sparse as sps
from numba import njit

import skfem_cable as sc
from skfem_cable.core.lines import LinePoints
from skfem_cable.kernels.line import gather, interpolate

#: Gauss points per element: exact for the products of the quadratic functions.
POINTS = 4


def lagrange2(xi, h):
    """The three quadratic Lagrange functions on an element of length ``h`` (nodes at
    ``xi = 0, 1/2, 1``) and their derivatives with respect to the arc length, at ``xi``
    (nq,): two arrays (nq, 3)."""
    S = np.stack([2 * (xi - 0.5) * (xi - 1), -4 * xi * (xi - 1), 2 * xi * (xi - 0.5)], -1)
    dS = np.stack([4 * xi - 3, 4 - 8 * xi, 4 * xi - 1], -1) / h
    return S, dS


@njit(cache=True)
def axial_kernel(pack, index, ev):
    """The string's elastic force ``int EA eps S_x^T a ds`` (Green strain
    ``eps = (|a|^2 - 1) / 2``), its tangent ``cK EA (S_x^T S_x (eps I + a a^T))`` into
    ``data`` at ``index`` and its energy ``int EA eps^2 / 2 ds`` (``contract.Term.kernels``;
    ``pack = (edofs, S, Sx, w, EA)``)."""
    q, v, s, f, f_ext, fd, data, energy, power = ev
    edofs, S, Sx, w, EA = pack
    ne, nq, nf = S.shape
    want = data.size > 0
    cK = s[1]
    qe = np.empty((nf, 3))
    a = np.empty(3)
    for e in range(ne):
        gather(edofs, q, e, nf, qe)
        for g in range(nq):
            interpolate(Sx, e, g, qe, nf, a)
            eps = 0.5 * (a[0] * a[0] + a[1] * a[1] + a[2] * a[2] - 1.0)
            k = EA[0] * w[e, g]
            energy[0] += 0.5 * k * eps * eps
            for A in range(nf):
                for i in range(3):
                    f[edofs[e, 3 * A + i]] += k * eps * Sx[e, g, A] * a[i]
            if want:
                for A in range(nf):
                    for B in range(nf):
                        c = cK * k * Sx[e, g, A] * Sx[e, g, B]
                        for i in range(3):
                            for j in range(3):
                                d = eps if i == j else 0.0
                                data[index[e, 3 * A + i, 3 * B + j]] += c * (d + a[i] * a[j])


class QuadraticString:
    """A string of ``n`` quadratic elements from ``start`` to ``end`` (stress-free there)
    with axial stiffness ``EA`` (N) and mass per length ``rho_A`` (kg/m): coordinates are
    the ``2 n + 1`` node positions; the hooks of ``contract.Body`` and the line-body hook
    ``line_points``."""

    position_mask = None
    energy_parts = ("axial",)

    def __init__(self, start, end, n, EA, rho_A, name="string"):
        start, end = np.asarray(start, float), np.asarray(end, float)
        self.name, self.EA, self.rho_A = name, float(EA), float(rho_A)
        nodes = np.linspace(0.0, 1.0, 2 * n + 1)
        self.length = float(np.linalg.norm(end - start))
        self.q0 = (start + nodes[:, None] * (end - start)).ravel()
        self.n_dofs = self.q0.size
        self.position_mask = np.ones(self.n_dofs, dtype=bool)
        xi, wq = np.polynomial.legendre.leggauss(POINTS)
        xi, wq = 0.5 * (xi + 1), 0.5 * wq
        h = self.length / n
        S, Sx = lagrange2(xi, h)
        self.S = np.ascontiguousarray(np.broadcast_to(S, (n, POINTS, 3)))
        self.Sx = np.ascontiguousarray(np.broadcast_to(Sx, (n, POINTS, 3)))
        self.w = np.full((n, POINTS), h) * wq
        self.nodes = 2 * np.arange(n)[:, None] + np.arange(3)     # nodes of each element
        self.element_dofs = (3 * self.nodes[:, :, None] + np.arange(3)).reshape(n, 9)

    def line_points(self, system):
        """The line-body hook: the Gauss points of every element."""
        return LinePoints(self.element_dofs + system.dofs(self)[0], self.S, self.Sx, self.w)

    #: Its nodes have positions only (the ``Node`` contract).
    has_slopes = False

    def node(self, k):
        """Node ``k`` (negative counts from the end), for pins and point loads."""
        return sc.Node(self, k % (self.n_dofs // 3))

    def node_dofs(self, k):
        """The local coordinates of node ``k``: its position."""
        return 3 * k + np.arange(3)

    def describe_dof(self, i):
        return f"node {i // 3} r[{i % 3}]"

    def mass_matrix(self):
        """``rho_A int S_A S_B ds`` on every component."""
        M = np.einsum("eg,egA,egB->eAB", self.rho_A * self.w, self.S, self.S)
        I, J = np.broadcast_arrays(self.nodes[:, :, None], self.nodes[:, None, :])
        scalar = sps.coo_matrix((M.ravel(), (I.ravel(), J.ravel())),
                                shape=(self.n_dofs // 3,) * 2)
        return sps.kron(scalar, sps.identity(3)).tocsr()

    def mass_points(self):
        """The Gauss points with mass ``rho_A w``."""
        n, nq, nf = self.S.shape
        vectors = np.repeat(self.element_dofs[:, 0::3], nq, axis=0)
        return vectors, self.S.reshape(n * nq, nf), self.rho_A * self.w.ravel()

    def internal_constraints(self):
        return []

    def bind(self, system):
        points = self.line_points(system)
        rows, cols = points.tangent_pattern()
        pack = (points.edofs, points.S, points.Sx, points.w, np.array([self.EA]))
        return sc.Term(kernels=((axial_kernel, pack),), rows=rows, cols=cols,
                       name=f"string {self.name}")

    def show(self, system, q, v, t, **detail):
        d = system.dofs(self)
        points, velocity = q[d].reshape(-1, 3), v[d].reshape(-1, 3)
        cells = np.stack([np.arange(len(points) - 1), np.arange(1, len(points))], 1)
        return sc.core.contract.Shape(points, velocity, "line", cells, part=4)

    def outputs(self, system, q, t):
        return {"length": float(np.linalg.norm(np.diff(q[system.dofs(self)].reshape(-1, 3),
                                                         axis=0), axis=1).sum())}

