"""The ANCF cable body: a scikit-fem ``MeshLine`` over the reference arc length carrying the
3-D cubic-Hermite position field ``r(x)`` (paper Sect. 2.2).

Examples
--------
>>> import skfem_cable as sc
>>> cable = sc.Cable.straight([0, 0, 0], [2, 0, 0], 4, sc.Section.circular(1e-3, 2e11, 7850.0))
>>> cable.n_elements, cable.n_nodes, cable.n_dofs, cable.length
(4, 5, 30, 2.0)
"""

import math
import os
from dataclasses import replace

import numpy as np
from skfem import Basis, BilinearForm, ElementVector, LinearForm, MeshLine, asm
from skfem.helpers import dot
from skfem.quadrature import get_quadrature

from .contract import NO_DATA, NO_INDEX, Term
from .element import ElementLineCableHermite, hermite
from .formulation import DEFAULT, FORMULATIONS
from .laws import BUILTIN, SLOPE_FLOOR, CableLaw
from .section import Section


def cable_term(edofs, passes, key, name):
    """The term of the elastic and damping forces of the elements of one or more cables
    that share a law, its parameter values and quadrature (see ``contract``): one
    compiled kernel call per pass.  Cables with the same ``key`` are merged
    (``merge_cable_terms``), so an E-sail's tethers are one call.

    Parameters
    ----------
    edofs : int ndarray (ne, 12)
        Global coordinates of each element.
    passes : sequence of ``(function, tables, values, damped)``
        One kernel call each: a compiled hook of the generated module of a law (or of a
        part of it, ``CableLaw.part``), its tables ``(Sx, Sxx, weights, h)``
        (shape-function derivatives and weights of its own rule, element lengths), its
        parameter values and whether its dissipation is active.  The formulation
        (``formulation``) decides the passes: the paper's and the assumed strain have one,
        the Lobatto formulation two (the axial and the bending part).
    key : hashable
    name : str
    """
    edofs = np.ascontiguousarray(edofs, dtype=np.int64)
    kernels = tuple((function, (edofs, *(np.ascontiguousarray(t) for t in tables),
                                np.array(values, dtype=float), bool(damped)))
                    for function, tables, values, damped in passes)
    return Term(kernels=kernels, rows=edofs[:, :, None], cols=edofs[:, None, :], key=key,
                merge=merge_cable_terms, name=name)


def merge_cable_terms(terms):
    """One term for the concatenated elements of ``terms`` (same key: same passes)."""
    kernels = []
    for k, (function, pack) in enumerate(terms[0].kernels):
        packs = [t.kernels[k][1] for t in terms]
        tables = tuple(np.concatenate(parts) for parts in zip(*(p[:5] for p in packs)))
        kernels.append((function, (*tables, *pack[5:])))
    edofs = kernels[0][1][0]
    return Term(kernels=tuple(kernels), rows=edofs[:, :, None], cols=edofs[:, None, :],
                key=terms[0].key, merge=merge_cable_terms,
                name=" + ".join(t.name for t in terms))


#: No tangent entries, as the cable kernels take them (int, 3-D).
NO_ELEMENT_INDEX = NO_INDEX.reshape(0, 12, 12)

#: Order of the Gauss rule of a cable's mass points (``Cable.mass_points``): 4 points,
#: exact for the mass matrix's degree 6.
MASS_ORDER = 7


class _Stretched:
    """The hooks of a deploying cable's term (``deploy``): its tables ``(Sx, Sxx, weights,
    h)`` rescaled to the material arc length of the mesh stretched by ``lam = l / L0``
    (``Sx / lam``, ``Sxx / lam^2``, ``lam weights``, ``lam h``).

    A prescribed length ``l(t)`` rescales them once per time (``Term.prepare``) and its
    elastic energy has the explicit time derivative ``energy_rate``.  A reel's length is a
    coordinate: the term evaluates the kernels at the stretch of the coordinates (a Python
    ``add``) and adds the derivatives of the elastic energy in the length, ``dU/dl`` to the
    reel's equation, ``d^2U/dq dl`` and ``d^2U/dl^2`` to the tangent (``derivatives``)."""

    #: Relative step in ``lam`` of the difference quotients in the length (fourth order).
    STEP = 1e-4

    def __init__(self, deployment, term, passes):
        self.deployment = deployment
        self.built = [tuple(np.array(t) for t in tables) for _, tables, _, _ in passes]
        self.kernels = term.kernels

    def term(self, system, term):
        """The deploying cable's term, from the plain ``term`` of its kernels."""
        if self.deployment.reel is None:
            return replace(term, key=None, prepare=self.prepare,
                           energy_rate=self.energy_rate)
        dofs, reel = system.dofs(self.deployment.cable), self.deployment.reel
        rows, cols = np.broadcast_arrays(term.rows, term.cols)
        self.n_element_entries = rows.size
        self.dofs = dofs
        line = np.full(dofs.size, reel)
        return Term(add=self.add, rows=np.concatenate([rows.ravel(), dofs, line, [reel]]),
                    cols=np.concatenate([cols.ravel(), line, dofs, [reel]]), name=term.name)

    def scaled(self, lam, out=None):
        """The tables of every pass for the stretch ``lam`` (into ``out`` if given)."""
        out = out or [tuple(np.empty_like(t) for t in tables) for tables in self.built]
        for (Sx0, Sxx0, w0, h0), (Sx, Sxx, w, h) in zip(self.built, out):
            np.divide(Sx0, lam, out=Sx)
            np.divide(Sxx0, lam * lam, out=Sxx)
            np.multiply(w0, lam, out=w)
            np.multiply(h0, lam, out=h)
        return out

    def prepare(self, t):
        """``Term.prepare``: the term's own tables at time ``t``."""
        self.scaled(self.deployment.stretch(t), [pack[1:5] for _, pack in self.kernels])

    def add(self, ev, index):
        """``Term.add`` of a reel's cable: the kernels at the stretch of ``ev.q``, and the
        coupling with the length."""
        deployment = self.deployment
        L0 = deployment.L0
        lam = deployment.stretch(ev.t, ev.q)
        self.scaled(lam, [pack[1:5] for _, pack in self.kernels])
        ne = self.n_element_entries // 144
        own = NO_ELEMENT_INDEX if index is None else \
            index[:self.n_element_entries].reshape(ne, 12, 12)
        packed = ev.packed()
        for function, pack in self.kernels:
            function(pack, own, packed)
        dU, g, d2U = self.derivatives(ev.q, lam)
        ev.f[deployment.reel] += dU / L0
        if index is not None:
            ev.add_tangent(index[self.n_element_entries:],
                           np.concatenate([g, g, [d2U / L0]]) / L0)

    def derivatives(self, q, lam):
        """``(dU/dlam, d f/dlam on the cable's coordinates, d^2U/dlam^2)`` of the elastic
        energy ``U`` and force ``f`` at ``q`` (all the system's coordinates), by fourth-order
        central differences of step ``STEP lam`` (five kernel evaluations)."""
        d = self.STEP * lam
        values = [self.elastic(q, lam + k * d) for k in (-2, -1, 0, 1, 2)]
        (Em2, fm2), (Em1, fm1), (E0, _), (E1, f1), (E2, f2) = values
        dU = (8 * (E1 - Em1) - (E2 - Em2)) / (12 * d)
        g = (8 * (f1 - fm1) - (f2 - fm2))[self.dofs] / (12 * d)
        d2U = (16 * (E1 + Em1) - (E2 + Em2) - 30 * E0) / (12 * d * d)
        return dU, g, d2U

    def elastic(self, q, lam):
        """The elastic energy and force (all the system's coordinates) of the coordinates
        ``q`` on the mesh stretched by ``lam``, by the law's kernels."""
        energy = np.zeros(2)
        f = np.zeros_like(q)
        zeros = np.zeros_like(q)
        ev = (q, zeros, np.zeros(4), f, zeros.copy(), zeros.copy(), NO_DATA, energy,
              np.zeros(2))
        for (function, pack), tables in zip(self.kernels, self.scaled(lam)):
            function((pack[0], *tables, *pack[5:]), NO_ELEMENT_INDEX, ev)
        return energy.sum(), f

    def energy(self, q, lam):
        """The elastic energy of the coordinates ``q`` (all the system's) on the mesh
        stretched by ``lam``."""
        return self.elastic(q, lam)[0]

    def energy_rate(self, q, t):
        """``Term.energy_rate``: ``dU/dt = (l' / L0) dU/dlam`` at fixed coordinates, the
        power the reel takes from the stored energy (``dU/dlam`` by central differences
        of relative step 1e-6)."""
        ell, rate, _ = self.deployment.state(t)
        lam = ell / self.deployment.L0
        d = 1e-6 * lam
        return rate / self.deployment.L0 * (self.energy(q, lam + d)
                                            - self.energy(q, lam - d)) / (2 * d)


class Node:
    """A node of a body, as used by constraints and loads: ``cable.node(i)``.

    Attributes
    ----------
    body : Cable
        The body the node belongs to.
    index : int
        Index of the node in the body (non-negative).
    position_dofs, slope_dofs : int ndarray (3,)
        The body's local coordinates of the node's position ``r`` and slope ``r_x``.

    Examples
    --------
    >>> import skfem_cable as sc
    >>> cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], 2, sc.Section.circular(1e-3, 2e11, 7850.0))
    >>> tip = cable.node(-1)
    >>> tip, tip.position_dofs.tolist(), tip.slope_dofs.tolist()
    (Node(cable, 2), [12, 13, 14], [15, 16, 17])
    """

    def __init__(self, body, index):
        self.body = body
        self.index = index

    @property
    def position_dofs(self):
        """Local coordinates of the node's position ``r`` in its body."""
        return self.body.node_dofs(self.index)[:3]

    @property
    def slope_dofs(self):
        """Local coordinates of the node's slope ``r_x`` in its body."""
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


def _is_count(value):
    """Whether ``value`` is a whole number >= 1 (an int, or a float without fraction)."""
    try:
        return math.isfinite(value) and int(value) == value and value >= 1
    except (TypeError, ValueError):
        return False


def _point(name, value):
    """``value`` as an array of 3 finite coordinates; ``ValueError`` naming ``name``
    otherwise."""
    try:
        x = np.asarray(value, float)
    except (TypeError, ValueError):
        x = None
    if x is None or x.shape != (3,) or not np.isfinite(x).all():
        raise ValueError(f"{name} must be 3 finite coordinates (m), got {value!r}")
    return x


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
        Order of the Gauss rule of the elastic forces of the ``"paper"`` formulation, of
        ``basis`` and of the line loads' tables; the default 9 (5 points) integrates the
        Green axial energy exactly.  The mass matrix and the constant line loads are
        always integrated exactly.
    name : str
        Label used in diagnostics and outputs.
    formulation : str
        How the law is integrated and its tension recovered (``formulation``,
        ``docs/locking.md``): ``"assumed-strain"`` (default: the axial part at the
        assumed strain interpolated from the strain's nodal values and element means,
        no membrane locking and the paper's accuracy on taut cables), ``"paper"`` (the
        paper's formulation, every term on the Gauss rule ``intorder``: locks in bending,
        with tension stripes of tens of times the load) or ``"lobatto"`` (the axial part
        on the nodes and midpoints: locking-free, fourth order on taut cables).
    locking_free : bool, optional
        The earlier switch, kept as it was: False is ``formulation="paper"``, True is
        ``"lobatto"``.

    Attributes
    ----------
    mesh : skfem.MeshLine
        The mesh of the reference arc length; ``mesh.p[0]`` are the nodes' arc lengths
        ``x`` (m).
    section : Section
        Material and cross-section (``section.EA``, ``section.mass_per_length``, ...).
    law : CableLaw
        The element law (a built-in name is resolved to its ``CableLaw``).
    name : str
        Label used in diagnostics, outputs and the names of constraints.
    basis : skfem.Basis
        scikit-fem basis of the vector cubic-Hermite element
        (``ElementVector(ElementLineCableHermite(), 3)``) with the Gauss rule ``intorder``:
        the basis on which the forms of ``forms`` are assembled.
    q0 : ndarray (n_dofs,)
        Initial coordinates, node by node ``[r, r_x]`` (six per node); the reference
        configuration of ``System.q0``.
    n_dofs : int
        Number of coordinates, ``6 n_nodes``.
    n_nodes, n_elements : int
        Numbers of nodes and elements.
    length : float
        Reference (unstretched) length ``L`` (m).
    h : ndarray (n_elements,)
        Element lengths (m).
    element_dofs : int ndarray (n_elements, 12)
        Local coordinates of each element.
    intorder : int
        Order of the Gauss rule of the elastic forces.
    formulation : str
        The formulation's name (see above).
    S, Sx, Sxx : ndarray (n_elements, n_points, 4)
        Hermite shape functions and their first and second arc-length derivatives at the
        Gauss points of ``intorder``, used by kernels and loads (``LineLoad``,
        ``SolarWindForce``).
    weights : ndarray (n_elements, n_points)
        The Gauss weights times the element lengths.
    position_mask : bool ndarray (n_dofs,)
        True for position coordinates, False for slopes.
    bending : bool
        True if the law has bending (involves ``r_xx``).

    See Also
    --------
    Section : the material and cross-section.
    System : a cable joined to other bodies, constraints and loads.
    State, Result : the fields of a solution at arc lengths ``s``.

    Examples
    --------
    A straight steel cable of 1.2 m in 16 elements, its nodes and fields:

    >>> import numpy as np
    >>> import skfem_cable as sc
    >>> sec = sc.Section.circular(radius=0.01, E=7e10, rho=7800.0)
    >>> cable = sc.Cable.straight([0, 0, 0], [1.2, 0, 0], n_elements=16, section=sec)
    >>> cable.n_dofs, cable.length, cable.node(-1)
    (102, 1.2, Node(cable, 16))
    >>> r, r_x, r_xx = cable.interpolate(cable.q0, 0.3)
    >>> r.tolist(), r_x.tolist()
    ([0.3, 0.0, 0.0], [1.0, 0.0, 0.0])
    >>> round(float(cable.tension(cable.q0, 0.6)), 6)   # stress-free
    0.0
    """

    def __init__(self, mesh, section, positions, slopes, law="cable", intorder=9, name="cable",
                 formulation=None, locking_free=None):
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
        formulation = _formulation(formulation, locking_free)
        if formulation == "assumed-strain":
            law.check_strain()
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
        self.intorder = int(intorder)
        X, W = get_quadrature(mesh.refdom, intorder)
        self.S = self._hermite(X[0])[0]
        self.Sx, self.Sxx, self.weights, _ = self.tables_at(X[0], W)
        self.formulation = formulation
        self._mass = None

    def _hermite(self, xi):
        """Hermite functions and their x-derivatives (ne, nq, 4) at the reference
        coordinates ``xi`` (nq,) of every element."""
        return tuple(np.ascontiguousarray(np.moveaxis(t, 0, -1))
                     for t in hermite(np.asarray(xi, float)[None, :], self.h[:, None]))

    def tables_at(self, xi, weights):
        """The kernel tables ``(Sx, Sxx, w, h)`` of a rule with reference coordinates
        ``xi`` (nq,) and weights ``weights`` (nq,) on [0, 1]: the Hermite functions' first
        and second x-derivatives (ne, nq, 4), the weights times the element lengths
        (ne, nq) and the element lengths (ne,)."""
        _, Sx, Sxx = self._hermite(xi)
        return Sx, Sxx, np.ascontiguousarray(np.asarray(weights)[None, :] * self.h[:, None]), \
            self.h

    @classmethod
    def straight(cls, start, end, n_elements, section, law="cable", **kwargs):
        """A stress-free straight cable from ``start`` to ``end`` with ``n_elements`` elements.

        Parameters
        ----------
        start, end : array_like (3,)
            End points (m); the reference length is their distance.
        n_elements : int
            Number of equal elements, >= 1.
        section : Section
        law : CableLaw or str
            See ``Cable``.
        **kwargs
            The other parameters of ``Cable`` (``intorder``, ``name``, ``locking_free``).

        Returns
        -------
        Cable
            Nodes equally spaced, unit slopes along ``end - start``.

        Examples
        --------
        >>> import skfem_cable as sc
        >>> sec = sc.Section.circular(1e-3, 2e11, 7850.0)
        >>> tether = sc.Cable.straight([0, 0, 0], [0, 10, 0], 5, sec, law="truss", name="t1")
        >>> tether.n_dofs, tether.q0[:6].tolist()
        (36, [0.0, 0.0, 0.0, 0.0, 1.0, 0.0])
        """
        if not _is_count(n_elements):
            raise ValueError(f"n_elements must be a positive integer, got {n_elements!r}")
        check_memory(int(n_elements))
        start, end = _point("start", start), _point("end", end)
        axis = end - start
        length = np.linalg.norm(axis)
        if not length > 0:
            raise ValueError(f"start and end must differ, got {start.tolist()} for both")
        s = np.linspace(0.0, length, int(n_elements) + 1)
        t = axis / length
        positions = start + s[:, None] * t
        return cls(MeshLine(s), section, positions, np.tile(t, (len(s), 1)), law=law, **kwargs)

    # --- layout -------------------------------------------------------------------------
    @property
    def n_dofs(self):
        """Number of coordinates, ``6 n_nodes``."""
        return self.q0.size

    @property
    def n_nodes(self):
        """Number of nodes."""
        return self.mesh.p.shape[1]

    @property
    def n_elements(self):
        """Number of elements."""
        return self.mesh.t.shape[1]

    @property
    def length(self):
        """Reference (unstretched) length ``L`` (m)."""
        return float(self.mesh.p[0, -1] - self.mesh.p[0, 0])

    def node(self, index):
        """The node ``index`` (negative counts from the end)."""
        n = self.n_nodes
        if not -n <= index < n:
            raise IndexError(f"node index {index} out of range for {n} nodes")
        return Node(self, index % n)

    def node_dofs(self, index):
        """Local coordinates ``[r, r_x]`` (six) of the node ``index`` (non-negative)."""
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
        """Constant mass matrix ``rho A int S^T S dx`` (Eq. 22), assembled once per
        ``section`` (again when it is replaced)."""
        if self._mass is None or self._mass[0] is not self.section:
            mu = self.section.mass_per_length
            self._mass = (self.section, asm(BilinearForm(lambda u, v, w: mu * dot(u, v)),
                                            self._exact).tocsr())
        return self._mass[1]

    def mass_points(self):
        """Where the mass is (the hook ``orbit_gravity`` reads): the 4 Gauss points of
        ``MASS_ORDER`` in every element, ``(vectors (np, 4), coefficients (np, 4), mass (np,))``, a
        point at ``sum_A S_A q[vectors[A] : vectors[A] + 3]`` (the element's positions and
        slopes weighted by its Hermite functions) with mass ``rho A`` times the Gauss
        weight: the rule integrates the mass matrix (degree 6) exactly, so the points hold
        the cable's mass, centre of mass, second moments and kinetic energy."""
        X, w = get_quadrature(self.mesh.refdom, MASS_ORDER)
        S = self._hermite(X[0])[0]
        ne, nq, _ = S.shape
        vectors = np.repeat(self.element_dofs[:, 0::3], nq, axis=0)
        return vectors, S.reshape(ne * nq, 4), \
            self.section.mass_per_length * (w[None, :] * self.h[:, None]).ravel()

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
        law's compiled kernels (``cable_term``), one per pass of the cable's formulation
        (``formulation``), shared by all cables with the same law, parameter values,
        formulation and quadrature."""
        values = self.law.parameter_values(self.section)
        deployment = system.deployment(self)
        passes, key = [], []
        for piece, kind, tables in FORMULATIONS[self.formulation].passes(self):
            if piece.vanishes:
                continue
            damped = piece.damped and piece.dissipates(values)
            if deployment is not None and damped:
                raise ValueError(
                    f"cable {self.name!r} deploys and its law dissipates (e.g. the "
                    "section's gamma_axial, gamma_bending > 0): on the stretching mesh its "
                    "damping would take the mesh's stretching l'/l for a strain rate, not "
                    "the material's; use an undamped law for a deploying cable")
            if deployment is not None:  # the term's own tables, rescaled in time
                tables = tuple(np.array(t) for t in tables)
            passes.append((piece.compiled(kind).kernel, tables, values, damped))
            key.append((piece.key, kind, damped, tables[0].shape[1]))
        term = cable_term(self.global_element_dofs(system), passes,
                          ("ancf-cable", values, *key), self.name)
        if deployment is None:
            return term
        return _Stretched(deployment, term, passes).term(system, term)

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
        return self._fields(q, *self.locate(s))

    def _fields(self, q, e, xi, stretch=1.0):
        """``r``, ``r_s``, ``r_ss`` in elements ``e`` at reference coordinates ``xi``:
        derivatives in the material arc length ``s = stretch x`` of a mesh stretched by
        ``stretch`` (scalar, or one value per leading index of ``q``; 1 unless the cable
        is deploying, see ``deploy``)."""
        S = hermite(xi, self.h[e])
        q = np.asarray(q)
        qe = q[..., self.element_dofs[e]].reshape(q.shape[:-1] + np.shape(e) + (4, 3))
        r, a, b = (np.einsum("A...,...Ai->...i", Sk, qe) for Sk in S)
        lam = np.reshape(stretch, np.shape(stretch) + (1,) * (np.ndim(e) + 1))
        return r, a / lam, b / lam**2

    def slopes_at(self, q, xi, stretch=1.0):
        """``r_s`` at the reference coordinates ``xi`` (nx,) of every element: (...,
        n_elements, nx, 3) for coordinates ``q`` (..., n_dofs) (``_fields``)."""
        Sx = self._hermite(xi)[1]
        q = np.asarray(q)
        qe = q[..., self.element_dofs].reshape(q.shape[:-1] + (self.n_elements, 4, 3))
        lam = np.reshape(stretch, np.shape(stretch) + (1, 1, 1))
        return np.einsum("eXA,...eAi->...eXi", Sx, qe) / lam

    def green(self, q, e, xi, stretch=1.0):
        """Green strain ``(|r_x|^2 - 1)/2`` of the cubic field in elements ``e`` at
        reference coordinates ``xi`` (``_fields``)."""
        a = self._fields(q, e, xi, stretch)[1]
        return 0.5 * (np.einsum("...i,...i", a, a) - 1.0)

    def strain(self, q, s, stretch=1.0):
        """Green axial strain ``eps = (|r_x|^2 - 1)/2`` (Eq. 24) at arc lengths ``s``, as
        the cable's formulation defines it (``formulation``): the assumed strain by
        default, recovered from the Lobatto points on a ``"lobatto"`` cable, the raw strain
        of the cubic field on a ``"paper"`` cable.  ``stretch``: the mesh stretch of a
        deploying cable (``_fields``)."""
        return FORMULATIONS[self.formulation].strain(self, q, s, stretch)

    def tension(self, q, s, stretch=1.0):
        """Axial force in the section (N) at arc lengths ``s``, the elastic part (at rest).

        The axial force of a law ``W(a, b)`` is ``N = t . W_a + t' . W_b`` with ``t =
        r_x/|r_x|`` (``section_force``), the axial component of its section force.  For
        the built-in law it is ``EA eps |r_x| - EI kappa^2 / |r_x|``: the Green-strain
        force (``dW/d|r_x|``; the second Piola-Kirchhoff force ``EA eps`` differs by the
        factor ``|r_x|``) and the axial part of the bending section force (zero for a
        truss and negligible for taut tethers).

        The axial part comes from the strain the formulation integrates (``formulation``):
        by default the assumed strain, a continuous field accurate to the discretisation
        (an elastica of 16 elements matches the exact ``P sin(theta)`` to better than 1 %
        of ``P``, root included); on a ``"lobatto"`` cable the values at the nodes and
        midpoints, interpolated; on a ``"paper"`` cable the raw strain of the cubic field,
        which membrane locking makes useless in bending (stripes of tens of times the
        load).  ``stretch``: the mesh stretch of a deploying cable (``_fields``).
        """
        return FORMULATIONS[self.formulation].tension(self, q, s, stretch)

    def section_force(self, q, e, xi, stretch=1.0, law=None):
        """``N = t . W_a + t' . W_b`` of ``law`` (default the cable's) evaluated on the
        cubic field in elements ``e`` at reference coordinates ``xi``: the axial component
        ``t . (W_a - (W_b)')`` of the law's section force, exact when ``W`` depends on
        ``b`` only through its part normal to ``a`` (the curvature), as every law of the
        gallery does."""
        _, a, b = self._fields(q, e, xi, stretch)
        x = np.moveaxis(np.concatenate([a, b], axis=-1), -1, 0)
        lam = np.reshape(stretch, np.shape(stretch) + (1,) * np.ndim(e))
        h = np.broadcast_to(self.h[e] * lam, x.shape[1:])
        G = self.densities(x, np.zeros_like(x), h, law)["G"]
        p = np.maximum(np.einsum("...i,...i", a, a), SLOPE_FLOOR)
        lam = np.sqrt(p)[..., None]
        t = a / lam
        t_x = (b - np.einsum("...i,...i", t, b)[..., None] * t) / lam
        return (np.einsum("...i,i...->...", t, G[:3])
                + np.einsum("...i,i...->...", t_x, G[3:]))

    def densities(self, x, xd, h, law=None):
        """The densities of ``law`` (default the cable's) at points ``x = (a, b)``, ``xd``
        (6, ...) of elements of length ``h`` (...) (its generated ``numpy_point``): energy
        ``ea``/``eb`` and power ``pa``/``pb`` (axial, bending), ``G = W_x + D_xd`` and
        ``Gd = D_xd`` (6, ...), ``H = W_xx + D_xd,x`` and ``Hc = D_xd,xd`` (6, 6, ...)."""
        law = self.law if law is None else law
        out = law.compiled().numpy_point(x, xd, law.parameter_values(self.section), h)
        out["G"] = np.stack([out.pop(f"G_{i}") for i in range(6)])
        out["Gd"] = np.stack([out.pop(f"Gd_{i}") for i in range(6)])
        for k in ("H", "Hc"):
            out[k] = np.stack([[out.pop(f"{k}_{i}_{j}") for j in range(6)] for i in range(6)])
        return out

    def curvature(self, q, s, stretch=1.0):
        """Curvature ``kappa = |r_x x r_xx| / |r_x|^3`` (Eq. 24), 1/m; ``stretch``: the
        mesh stretch of a deploying cable (``_fields``)."""
        _, a, b = self._fields(q, *self.locate(s), stretch)
        p = np.maximum(np.einsum("...i,...i", a, a), SLOPE_FLOOR)
        return np.sqrt(_kappa2(a, b, p))


def _formulation(formulation, locking_free):
    """The formulation's name from ``Cable``'s ``formulation`` and ``locking_free``."""
    if locking_free is not None:
        if not isinstance(locking_free, bool):
            raise TypeError(f"locking_free must be True or False, got {locking_free!r}")
        named = "lobatto" if locking_free else "paper"
        if formulation is not None and formulation != named:
            raise ValueError(f"locking_free={locking_free} means formulation={named!r}, "
                             f"which contradicts formulation={formulation!r}: give one")
        return named
    if formulation is None:
        return DEFAULT
    if formulation not in FORMULATIONS:
        raise ValueError(f"formulation must be one of {tuple(FORMULATIONS)}, "
                         f"got {formulation!r}")
    return formulation


def _kappa2(a, b, p):
    return np.einsum("...i,...i", np.cross(a, b), np.cross(a, b)) / p**3
