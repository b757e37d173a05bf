"""The ANCF cable body: a scikit-fem ``MeshLine`` over the reference arc length carrying the
3-D cubic-Hermite position field ``r(x)`` (paper Sect. 2.2)."""

import os

import numpy as np
from skfem import Basis, BilinearForm, ElementVector, LinearForm, MeshLine, asm
from skfem.helpers import dot
from skfem.quadrature import get_quadrature

from .contract import Term
from .element import ElementLineCableHermite, hermite
from .kernels import cable as cable_kernel
from .kernels import reference
from .kernels.density import SLOPE_FLOOR
from .section import Section

KINDS = ("cable", "truss")
_EMPTY = np.zeros(0)
_NO_SCATTER = np.zeros((0, 12, 12), dtype=np.int64)


class CableForces:
    """The compiled elastic and damping forces of the elements of one or more cables that
    share a law (section, bending stiffness, quadrature): the ``add`` hook of their
    ``Term`` (see ``contract``).  Cables with the same law are merged into one instance,
    so an E-sail's tethers are one kernel call.

    Parameters
    ----------
    edofs : int ndarray (ne, 12)
        Global coordinates of each element.
    tables : tuple ``(Sx, Sxx, weights, h)``
        Shape-function derivative tables, Gauss weights and element lengths.
    law : tuple ``(EA, EI, gamma_axial, gamma_bending)``
    """

    def __init__(self, edofs, tables, law):
        self.edofs = np.ascontiguousarray(edofs, dtype=np.int64)
        self.tables = tuple(np.ascontiguousarray(t) for t in tables)
        self.law = tuple(float(x) for x in law)
        self.static_law = self.law[:2] + (0.0, 0.0)

    def __call__(self, ev, index):
        """Add the forces (Eqs. 86-127) and, if wanted, ``cK K + cC C`` (numba kernel)."""
        want = ev.data is not None
        out = (ev.f, ev.f_damping, ev.data if want else _EMPTY,
               index if want else _NO_SCATTER, ev.energy, ev.power)
        cable_kernel.force_tangent((ev.q, ev.v), (self.edofs, *self.tables),
                                   self.law if ev.dynamic else self.static_law, out,
                                   (ev.cK, ev.cC))

    @staticmethod
    def merge(terms):
        """One term for the concatenated elements of ``terms`` (same law)."""
        parts = [t.add for t in terms]
        forces = CableForces(np.concatenate([p.edofs for p in parts]),
                             [np.concatenate(tabs) for tabs in zip(*(p.tables for p in parts))],
                             parts[0].law)
        return forces.term(terms[0].key, " + ".join(t.name for t in terms))

    def term(self, key, name):
        ed = self.edofs
        return Term(add=self, rows=ed[:, :, None], cols=ed[:, None, :], key=key,
                    merge=CableForces.merge, name=name)


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


#: Memory (bytes) per element to build a cable, its system layout and a time
#: integration (measured: 4.7 kB, 12 kB and 8 kB at 1e5 elements).
MEMORY_PER_ELEMENT = 25e3


def check_memory(n_elements):
    """Refuse a cable that cannot be built and simulated in this machine's memory."""
    try:
        total = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    except (AttributeError, ValueError, OSError):  # not a POSIX system: no estimate
        return
    need = MEMORY_PER_ELEMENT * n_elements
    if need > total:
        raise ValueError(f"n_elements = {n_elements}: a cable of that size needs about "
                         f"{need / 1e9:.3g} GB to build and simulate, and this machine has "
                         f"{total / 1e9:.3g} GB; at most about {int(total / MEMORY_PER_ELEMENT)}"
                         " elements fit")


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
        check_memory(n - 1)
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
        S, Sx, Sxx = hermite(X[0][None, :], self.h[:, None])
        self.S = np.ascontiguousarray(np.moveaxis(S, 0, -1))
        self.Sx = np.ascontiguousarray(np.moveaxis(Sx, 0, -1))
        self.Sxx = np.ascontiguousarray(np.moveaxis(Sxx, 0, -1))
        self.weights = np.ascontiguousarray(W[None, :] * self.h[:, None])
        self._mass = None

    @classmethod
    def straight(cls, start, end, n_elements, section, kind="cable", **kwargs):
        """A stress-free straight cable from ``start`` to ``end`` with ``n_elements`` elements."""
        if int(n_elements) != n_elements or n_elements < 1:
            raise ValueError(f"n_elements must be a positive integer, got {n_elements!r}")
        check_memory(int(n_elements))
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
    def position_mask(self):
        """True for position coordinates, False for slopes."""
        return np.tile(np.repeat([True, False], 3), self.n_nodes)

    def internal_constraints(self):
        """None: an ANCF cable's coordinates are all free."""
        return []

    def describe_dof(self, index):
        """Which node and component a local coordinate is, e.g. ``node 3 r_x[1]``."""
        node, k = divmod(int(index), 6)
        return f"node {node} {'r' if k < 3 else 'r_x'}[{k % 3}]"

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
        """Bending stiffness in use (0 for a truss)."""
        return self.section.EI if self.bending else 0.0

    def global_element_dofs(self, system):
        """Global coordinates of every element, int (ne, 12)."""
        return self.element_dofs + system.dofs(self)[0]

    def bind(self, system):
        """The term of the cable's elastic and damping forces (see ``contract``): the
        compiled kernel of ``CableForces``, shared by all cables with the same section,
        kind and quadrature.  A subclass with other physics overrides this hook."""
        sec = self.section
        law = (sec.EA, self.EI_active, sec.gamma_axial,
               sec.gamma_bending if self.bending else 0.0)
        forces = CableForces(self.global_element_dofs(system),
                             (self.Sx, self.Sxx, self.weights, self.h), law)
        return forces.term(("ancf-cable", law, self.Sx.shape[1]), self.name)

    def forces_reference(self, q, v=None):
        """Per-element energy, power, force and tangents ``(K, C)`` by the numpy path."""
        sec = self.section
        qe = q[self.element_dofs].reshape(-1, 4, 3)
        ve = np.zeros_like(qe) if v is None else v[self.element_dofs].reshape(-1, 4, 3)
        damping = (0.0, 0.0) if v is None else (sec.gamma_axial, sec.gamma_bending)
        return reference.element_forces(qe, ve, self.Sx, self.Sxx, self.weights, self.h,
                                        sec.EA, self.EI_active, *damping)

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
        """Axial force in the section (N): ``N = EA eps |r_x| - EI kappa^2 / |r_x|``.

        The first term is the force of the Green-strain law (``dW/d|r_x|`` of
        ``EA/2 eps^2``; ``EA eps`` alone, the second Piola-Kirchhoff force, differs by the
        factor ``|r_x| = 1 + O(eps)``); the second is the axial part of the section force
        ``n = W_a - (W_b)'`` coming from the bending energy, whose curvature is measured per
        current length (zero for a truss and negligible for taut tethers).
        """
        _, a, b = self.interpolate(q, s)
        p = np.maximum(np.einsum("...i,...i", a, a), SLOPE_FLOOR)
        lam = np.sqrt(p)
        N = self.section.EA * 0.5 * (p - 1.0) * lam
        if self.bending:
            N = N - self.section.EI * _kappa2(a, b, p) / lam
        return N

    def curvature(self, q, s):
        """Curvature ``kappa = |r_x x r_xx| / |r_x|^3`` (Eq. 24), 1/m."""
        _, a, b = self.interpolate(q, s)
        p = np.maximum(np.einsum("...i,...i", a, a), SLOPE_FLOOR)
        return np.sqrt(_kappa2(a, b, p))


def _kappa2(a, b, p):
    return np.einsum("...i,...i", np.cross(a, b), np.cross(a, b)) / p**3
