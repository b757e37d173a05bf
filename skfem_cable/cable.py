"""The ANCF cable body: a scikit-fem ``MeshLine`` over the reference arc length carrying the
3-D cubic-Hermite position field ``r(x)`` (paper Sect. 2.2)."""

import numpy as np
from skfem import Basis, BilinearForm, ElementVector, LinearForm, MeshLine, asm
from skfem.helpers import dot
from skfem.quadrature import get_quadrature

from .element import ElementLineCableHermite, hermite
from .kernels import cable as cable_kernel
from .kernels import reference
from .section import Section

KINDS = ("cable", "truss")


class Node:
    """A node of a body, as used by constraints and loads: ``cable.node(i)``."""

    def __init__(self, body, index):
        self.body = body
        self.index = index

    @property
    def position_dofs(self):
        return self.body.node_dofs(self.index)[:3]

    @property
    def slope_dofs(self):
        return self.body.node_dofs(self.index)[3:]

    def __repr__(self):
        return f"Node({self.body.name}, {self.index})"


class Cable:
    """Gradient-deficient ANCF cable (Eqs. 16-26): nodal positions and slopes.

    Parameters
    ----------
    mesh : skfem.MeshLine
        Mesh of the reference arc length ``x in [0, L]`` with sorted nodes.
    section : Section
        Material and cross-section.
    positions, slopes : array_like, shape (n_nodes, 3)
        Initial nodal positions ``r`` and slopes ``r_x``.  A stress-free straight cable has
        unit slopes along its axis.
    kind : {"cable", "truss"}
        ``"cable"``: axial and bending stiffness; ``"truss"``: axial only (the paper's
        comparison model).
    intorder : int
        Order of the Gauss rule of the elastic forces; the default 9 (5 points) integrates
        the axial energy exactly.  The mass matrix and the line loads are always integrated
        exactly.
    name : str
        Label used in diagnostics and outputs.
    """

    def __init__(self, mesh, section, positions, slopes, kind="cable", intorder=9, name="cable"):
        if not isinstance(mesh, MeshLine):
            raise TypeError(f"mesh must be a skfem.MeshLine, got {type(mesh).__name__}")
        if not isinstance(section, Section):
            raise TypeError(f"section must be a skfem_cable.Section, got {type(section).__name__}")
        if kind not in KINDS:
            raise ValueError(f"kind must be one of {KINDS}, got {kind!r}")
        x = mesh.p[0]
        if np.any(np.diff(x) <= 0) or np.any(mesh.t[1] != mesh.t[0] + 1):
            raise ValueError("mesh nodes must be sorted along the arc length "
                             "(use MeshLine(np.sort(x)))")
        n = len(x)
        positions = np.asarray(positions, dtype=float)
        slopes = np.asarray(slopes, dtype=float)
        for label, arr in (("positions", positions), ("slopes", slopes)):
            if arr.shape != (n, 3) or not np.all(np.isfinite(arr)):
                raise ValueError(f"{label} must be a finite array of shape ({n}, 3), "
                                 f"got {arr.shape}")
        self.mesh = mesh
        self.section = section
        self.kind = kind
        self.name = name
        self.basis = Basis(mesh, ElementVector(ElementLineCableHermite(), 3), intorder=6)
        self.q0 = np.column_stack([positions, slopes]).ravel()
        self.element_dofs = np.ascontiguousarray(self.basis.element_dofs.T, dtype=np.int64)
        self.h = np.diff(x)
        X, W = get_quadrature(mesh.refdom, intorder)
        _, Sx, Sxx = hermite(X[0][None, :], self.h[:, None])
        self.Sx = np.ascontiguousarray(np.moveaxis(Sx, 0, -1))
        self.Sxx = np.ascontiguousarray(np.moveaxis(Sxx, 0, -1))
        self.weights = np.ascontiguousarray(W[None, :] * self.h[:, None])
        self._mass = None

    @classmethod
    def straight(cls, start, end, n_elements, section, kind="cable", **kwargs):
        """A stress-free straight cable from ``start`` to ``end`` with ``n_elements`` elements."""
        if int(n_elements) != n_elements or n_elements < 1:
            raise ValueError(f"n_elements must be a positive integer, got {n_elements!r}")
        start, end = np.asarray(start, float), np.asarray(end, float)
        axis = end - start
        length = np.linalg.norm(axis)
        if not length > 0:
            raise ValueError("start and end must differ")
        s = np.linspace(0.0, length, int(n_elements) + 1)
        t = axis / length
        positions = start + s[:, None] * t
        return cls(MeshLine(s), section, positions, np.tile(t, (len(s), 1)), kind=kind, **kwargs)

    # --- layout -------------------------------------------------------------------------
    @property
    def n_dofs(self):
        return self.q0.size

    @property
    def n_nodes(self):
        return self.mesh.p.shape[1]

    @property
    def n_elements(self):
        return self.mesh.t.shape[1]

    @property
    def length(self):
        return float(self.mesh.p[0, -1] - self.mesh.p[0, 0])

    def node(self, index):
        """The node ``index`` (negative counts from the end)."""
        n = self.n_nodes
        if not -n <= index < n:
            raise IndexError(f"node index {index} out of range for {n} nodes")
        return Node(self, index % n)

    def node_dofs(self, index):
        return 6 * index + np.arange(6)

    @property
    def bending(self):
        return self.kind == "cable"

    # --- constant matrices and loads (scikit-fem assembly, done once) --------------------
    def mass_matrix(self):
        """Constant mass matrix ``rho A int S^T S dx`` (Eq. 22), assembled once."""
        if self._mass is None:
            mu = self.section.mass_per_length
            self._mass = asm(BilinearForm(lambda u, v, w: mu * dot(u, v)), self.basis).tocsr()
        return self._mass

    def line_load(self, force_per_length):
        """Consistent generalized force ``int S^T f dx`` of a uniform line load (N/m)."""
        f = np.asarray(force_per_length, dtype=float)
        if f.shape != (3,) or not np.all(np.isfinite(f)):
            raise ValueError("force_per_length must be a finite 3-vector, "
                             f"got {force_per_length!r}")
        return asm(LinearForm(lambda v, w: f[0] * v[0] + f[1] * v[1] + f[2] * v[2]), self.basis)

    # --- elastic forces -------------------------------------------------------------------
    @property
    def EI_active(self):
        return self.section.EI if self.bending else 0.0

    def elastic(self, q, f, data=None, scatter=None, cK=1.0, energy=None, edofs=None):
        """Add ``dU/dq`` to ``f`` and ``cK d2U/dq2`` into ``data`` through ``scatter`` (numba
        kernel); returns the energy ``[axial, bending]``.

        ``q`` and ``f`` are the cable's own coordinates, or global vectors when ``edofs`` (the
        global DOFs of every element, shape ``(ne, 12)``) is given.
        """
        if edofs is None:
            edofs = self.element_dofs
        if energy is None:
            energy = np.zeros(2)
        if scatter is None:
            scatter = np.zeros((0, 12, 12), dtype=np.int64)
            data = np.zeros(0)
        cable_kernel.force_tangent(q, edofs, self.Sx, self.Sxx, self.weights,
                                   self.section.EA, self.EI_active, f, data, scatter, cK, energy)
        return energy

    def elastic_reference(self, q):
        """Energy, force and dense-per-element tangent with the vectorised numpy path."""
        qe = q[self.element_dofs].reshape(-1, 4, 3)
        return reference.element_force_tangent(qe, self.Sx, self.Sxx, self.weights,
                                               self.section.EA, self.EI_active)

    # --- evaluation at arc length --------------------------------------------------------
    def locate(self, s):
        """Element index and reference coordinate of arc lengths ``s``."""
        s = np.asarray(s, dtype=float)
        x = self.mesh.p[0]
        if np.any(s < x[0] - 1e-12 * self.length) or np.any(s > x[-1] + 1e-12 * self.length):
            raise ValueError(f"arc length s must lie in [{x[0]}, {x[-1]}]")
        e = np.clip(np.searchsorted(x, s, side="right") - 1, 0, self.n_elements - 1)
        return e, (s - x[e]) / self.h[e]

    def interpolate(self, q, s):
        """Position ``r``, slope ``r_x`` and ``r_xx`` at arc lengths ``s``.

        ``q`` may carry leading dimensions (e.g. time): shape ``(..., n_dofs)``; results
        have shape ``(...,) + s.shape + (3,)``.
        """
        e, xi = self.locate(s)
        S = hermite(xi, self.h[e])
        q = np.asarray(q)
        qe = q[..., self.element_dofs[e]].reshape(q.shape[:-1] + np.shape(e) + (4, 3))
        return tuple(np.einsum("A...,...Ai->...i", Sk, qe) for Sk in S)

    def strain(self, q, s):
        """Green axial strain ``eps = (|r_x|^2 - 1)/2`` (Eq. 24)."""
        _, a, _ = self.interpolate(q, s)
        return 0.5 * (np.einsum("...i,...i", a, a) - 1.0)

    def tension(self, q, s):
        """Axial force ``N = EA eps |r_x|`` (N) carried by the cross-section.

        With the Green strain of Eq. 24 the energy ``EA/2 eps^2`` gives the force
        ``dW/d|r_x| = EA eps |r_x|``; ``EA eps`` alone (the second Piola-Kirchhoff force)
        differs from it by the factor ``|r_x| = 1 + O(eps)``.
        """
        _, a, _ = self.interpolate(q, s)
        p = np.einsum("...i,...i", a, a)
        return self.section.EA * 0.5 * (p - 1.0) * np.sqrt(p)

    def curvature(self, q, s):
        """Curvature ``kappa = |r_x x r_xx| / |r_x|^3`` (Eq. 24)."""
        _, a, b = self.interpolate(q, s)
        p = np.einsum("...i,...i", a, a)
        return np.linalg.norm(np.cross(a, b), axis=-1) / np.maximum(p, 1e-300) ** 1.5
