"""The ANCF cable body: a scikit-fem ``MeshLine`` over the reference arc length carrying the
3-D cubic-Hermite position field ``r(x)`` (paper Sect. 2.2)."""

import os

import numpy as np
from skfem import Basis, BilinearForm, ElementVector, LinearForm, MeshLine, asm
from skfem.helpers import dot
from skfem.quadrature import get_quadrature

from .contract import Term
from .element import ElementLineCableHermite, hermite
from .laws import BUILTIN, SLOPE_FLOOR, CableLaw
from .section import Section

_EMPTY = np.zeros(0)
_NO_SCATTER = np.zeros((0, 12, 12), dtype=np.int64)


class CableForces:
    """The compiled elastic and damping forces of the elements of one or more cables that
    share a law and its parameter values: the ``add`` hook of their ``Term`` (see
    ``contract``).  Cables with the same law are merged into one instance, so an E-sail's
    tethers are one kernel call.

    Parameters
    ----------
    kernel : module
        The law's generated module (``CableLaw.compiled()``).
    edofs : int ndarray (ne, 12)
        Global coordinates of each element.
    tables : tuple ``(Sx, Sxx, weights, h)``
        Shape-function derivative tables, Gauss weights and element lengths.
    values : tuple of float
        The law's parameter values.
    damped : bool
        Whether the law's dissipation density is active (not identically zero).
    """

    def __init__(self, kernel, edofs, tables, values, damped):
        self.kernel = kernel
        self.edofs = np.ascontiguousarray(edofs, dtype=np.int64)
        self.tables = tuple(np.ascontiguousarray(t) for t in tables)
        self.values = np.array(values, dtype=float)
        self.damped = bool(damped)

    def __call__(self, ev, index):
        """Add the forces (Eqs. 86-127 for the built-in law) and, if wanted,
        ``cK K + cC C`` (compiled kernel)."""
        want = ev.data is not None
        out = (ev.f, ev.f_damping, ev.data if want else _EMPTY,
               index if want else _NO_SCATTER, ev.energy, ev.power)
        self.kernel.force_tangent((ev.q, ev.v), (self.edofs, *self.tables),
                                  (self.values, self.damped and ev.dynamic), out,
                                  (ev.cK, ev.cC))

    @staticmethod
    def merge(terms):
        """One term for the concatenated elements of ``terms`` (same law and values)."""
        parts = [t.add for t in terms]
        first = parts[0]
        forces = CableForces(first.kernel, np.concatenate([p.edofs for p in parts]),
                             [np.concatenate(tabs) for tabs in zip(*(p.tables for p in parts))],
                             first.values, first.damped)
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
    law : CableLaw or str
        The element law (``laws``): an energy and dissipation density, or the name of a
        built-in one, ``"cable"`` (the paper's Green strain, squared curvature and
        Kelvin-Voigt damping, Eqs. 23-26 and 36-38) or ``"truss"`` (the same without
        bending, the paper's comparison model).  Parameters come from ``section`` by name.
    intorder : int
        Order of the Gauss rule of the elastic forces and of ``basis``; the default 9 (5
        points) integrates the Green axial energy exactly.  The mass matrix and the line
        loads are always integrated exactly.
    name : str
        Label used in diagnostics and outputs.
    """

    def __init__(self, mesh, section, positions, slopes, law="cable", intorder=9, name="cable"):
        if not isinstance(mesh, MeshLine):
            raise TypeError(f"mesh must be a skfem.MeshLine, got {type(mesh).__name__}")
        if not isinstance(section, Section):
            raise TypeError(f"section must be a skfem_cable.Section, got {type(section).__name__}")
        if isinstance(law, str):
            if law not in BUILTIN:
                raise ValueError(f"law must be a CableLaw or one of {tuple(BUILTIN)}, "
                                 f"got {law!r}")
            law = BUILTIN[law]
        if not isinstance(law, CableLaw):
            raise TypeError(f"law must be a CableLaw (see skfem_cable.cable_law) or a name, "
                            f"got {type(law).__name__}")
        law.parameter_values(section)  # every parameter has a value
        law.symbolic  # noqa: B018 (the law is well formed: errors now, not at the first step)
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
        self.law = law
        self.name = name
        element = ElementVector(ElementLineCableHermite(), 3)
        self.basis = Basis(mesh, element, intorder=intorder)
        self._exact = Basis(mesh, element, intorder=6)  # mass and line loads
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
    def straight(cls, start, end, n_elements, section, law="cable", **kwargs):
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
        return cls(MeshLine(s), section, positions, np.tile(t, (len(s), 1)), law=law, **kwargs)

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
        """True if the law has bending (involves ``r_xx``)."""
        return self.law.bending

    # --- constant matrices and loads (scikit-fem assembly, done once) --------------------
    def mass_matrix(self):
        """Constant mass matrix ``rho A int S^T S dx`` (Eq. 22), assembled once."""
        if self._mass is None:
            mu = self.section.mass_per_length
            self._mass = asm(BilinearForm(lambda u, v, w: mu * dot(u, v)), self._exact).tocsr()
        return self._mass

    def line_load(self, force_per_length):
        """Consistent generalized force ``int S^T f dx`` of a uniform line load (N/m)."""
        f = np.asarray(force_per_length, dtype=float)
        if f.shape != (3,) or not np.all(np.isfinite(f)):
            raise ValueError("force_per_length must be a finite 3-vector, "
                             f"got {force_per_length!r}")
        return asm(LinearForm(lambda v, w: f[0] * v[0] + f[1] * v[1] + f[2] * v[2]), self._exact)

    # --- elastic forces -------------------------------------------------------------------
    def global_element_dofs(self, system):
        """Global coordinates of every element, int (ne, 12)."""
        return self.element_dofs + system.dofs(self)[0]

    def bind(self, system):
        """The term of the cable's elastic and damping forces (see ``contract``): the
        law's compiled kernel (``CableForces``), shared by all cables with the same law,
        parameter values and quadrature."""
        law = self.law
        values = law.parameter_values(self.section)
        damped = law.damped and law.dissipates(values)
        forces = CableForces(law.compiled(), self.global_element_dofs(system),
                             (self.Sx, self.Sxx, self.weights, self.h), values, damped)
        return forces.term(("ancf-cable", law.key, values, damped, self.Sx.shape[1]),
                           self.name)

    def assemble(self, q, v=None, cK=1.0, cC=0.0):
        """Internal force ``f = dU/dq + dD/dv`` and tangent ``cK df/dq + cC df/dv`` (sparse,
        the cable's own coordinates), by the compiled kernel.  ``v = None``: statics (no
        dissipation)."""
        from .system import System
        system = System([self])
        data = np.zeros(system.layout.nnz)
        f, _ = system.evaluate(q, v, 0.0, np.zeros(0), cK=cK, cC=cC, data=data)
        n = self.n_dofs
        return f[:n], system.layout.matrix(data)[:n, :n].tocsr()

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
        """Axial force in the section (N): ``N = t . W_a + t' . W_b`` with ``t = r_x/|r_x|``.

        This is the axial component ``t . (W_a - (W_b)')`` of the section force of the law
        ``W(a, b)``, exact when ``W`` depends on ``b`` only through its part normal to ``a``
        (the curvature), as every law of the gallery does.  For the built-in law it is
        ``EA eps |r_x| - EI kappa^2 / |r_x|``: the Green-strain force (``dW/d|r_x|``; the
        second Piola-Kirchhoff force ``EA eps`` differs by the factor ``|r_x|``) and the
        axial part of the bending section force (zero for a truss and negligible for
        taut tethers).  The elastic part only (at rest).
        """
        e, xi = self.locate(s)
        _, a, b = self.interpolate(q, s)
        x = np.moveaxis(np.concatenate([a, b], axis=-1), -1, 0)
        h = np.broadcast_to(self.h[e], x.shape[1:])
        G = self.densities(x, np.zeros_like(x), h)["G"]
        p = np.maximum(np.einsum("...i,...i", a, a), SLOPE_FLOOR)
        lam = np.sqrt(p)[..., None]
        t = a / lam
        t_x = (b - np.einsum("...i,...i", t, b)[..., None] * t) / lam
        return (np.einsum("...i,i...->...", t, G[:3])
                + np.einsum("...i,i...->...", t_x, G[3:]))

    def densities(self, x, xd, h):
        """The law's densities at points ``x = (a, b)``, ``xd`` (6, ...) of elements of
        length ``h`` (...) (its generated ``numpy_point``): energy ``ea``/``eb`` and power
        ``pa``/``pb`` (axial, bending), ``G = W_x + D_xd`` and ``Gd = D_xd`` (6, ...),
        ``H = W_xx + D_xd,x`` and ``Hc = D_xd,xd`` (6, 6, ...)."""
        out = self.law.compiled().numpy_point(x, xd, self.law.parameter_values(self.section),
                                              h)
        out["G"] = np.stack([out.pop(f"G_{i}") for i in range(6)])
        out["Gd"] = np.stack([out.pop(f"Gd_{i}") for i in range(6)])
        for k in ("H", "Hc"):
            out[k] = np.stack([[out.pop(f"{k}_{i}_{j}") for j in range(6)] for i in range(6)])
        return out

    def curvature(self, q, s):
        """Curvature ``kappa = |r_x x r_xx| / |r_x|^3`` (Eq. 24), 1/m."""
        _, a, b = self.interpolate(q, s)
        p = np.maximum(np.einsum("...i,...i", a, a), SLOPE_FLOOR)
        return np.sqrt(_kappa2(a, b, p))


def _kappa2(a, b, p):
    return np.einsum("...i,...i", np.cross(a, b), np.cross(a, b)) / p**3
