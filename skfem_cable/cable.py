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

import numpy as np
from skfem import Basis, BilinearForm, ElementVector, LinearForm, MeshLine, asm
from skfem.helpers import dot
from skfem.quadrature import get_quadrature

from .contract import Term
from .elements import DEFAULT_ELEMENT, ELEMENTS, element_type
from .fields import CableFields
from .formulation import FORMULATIONS
from .laws import BUILTIN, CableLaw
from .linalg import thread_count
from .lines import LinePoints
from .node import Node
from .section import Section
from .stretched import Stretched
from .varying import Varying


def cable_term(edofs, passes, key, name):
    """The term of the elastic and damping forces of the elements of one or more cables
    that share a law, its parameter values and quadrature (see ``contract``): one
    compiled kernel call per pass.  Cables with the same ``key`` are merged
    (``merge_cable_terms``), so an E-sail's tethers are one call.

    Parameters
    ----------
    edofs : int ndarray (ne, 3 n_functions)
        Global coordinates of each element (``n_functions`` of its element type).
    passes : sequence of ``(function, tables, values, damped)``
        One kernel call each: a compiled hook of the generated module of a law (or of a
        part of it, ``CableLaw.part``), its tables ``(Sx, Sxx, weights, h)``
        (shape-function derivatives and weights of its own rule, element lengths), its
        parameter values and whether its dissipation is active (the assumed strain's
        tables end with its map, ``kernels.assumed_strain.Rule.map``, which no stretch changes).
        The formulation (``formulation``) decides the passes: the paper's and the assumed
        strain have one, the Lobatto formulation two (the axial and the bending part).
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


#: Memory (bytes) per element to build a cable, its system layout and a time
#: integration (measured: 4.7 kB, 12 kB and 8 kB at 1e5 elements).
MEMORY_PER_ELEMENT = 25e3


def check_memory(n_elements, what=None):
    """Refuse ``n_elements`` cable elements that cannot be built and simulated in this
    machine's memory: one cable's, or all the cables of a scene or system (``what`` says
    which, default ``"n_elements = N: a cable of that size"``)."""
    try:
        total = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    except (AttributeError, ValueError, OSError):  # not a POSIX system: no estimate
        return
    need = MEMORY_PER_ELEMENT * n_elements
    if need > total:
        what = what or f"n_elements = {n_elements}: a cable of that size"
        raise ValueError(f"{what} needs about {need / 1e9:.3g} GB to build and simulate, "
                         f"and this machine has {total / 1e9:.3g} GB; at most about "
                         f"{int(total / MEMORY_PER_ELEMENT)} elements fit")


def check_total_memory(counts):
    """``check_memory`` of the cables with the element ``counts`` together (a system's
    or a scene's; the guard of each cable alone lets 30 cables of 900,000 elements
    through on 24 GB)."""
    total = int(sum(counts))
    check_memory(total, f"a system of {len(counts)} cables with {total} elements in all")


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


class Cable(CableFields):
    """Gradient-deficient ANCF cable (Eqs. 16-26): nodal positions and slopes (and, on the
    quintic element, second derivatives), or positions only (the linear element).

    Parameters
    ----------
    mesh : skfem.MeshLine
        Mesh of the reference arc length ``x in [0, L]`` with sorted nodes.
    section : Section
        Material and cross-section.
    positions, slopes : array_like, shape (n_nodes, 3)
        Initial nodal positions ``r`` and slopes ``r_x``.  A stress-free straight cable has
        unit slopes along its axis.  ``slopes`` is not used by an element without slopes
        (``"linear"``) and may be None there.
    law : CableLaw or str, optional
        The element law (``laws``): an energy and dissipation density, or the name of a
        built-in one, ``"cable"`` (the paper's Green strain, squared curvature and
        Kelvin-Voigt damping, Eqs. 23-26 and 36-38) or ``"truss"`` (the same without
        bending, the paper's comparison model).  Parameters come from ``section`` by name.
        Default ``"cable"``, or ``"truss"`` on an element without ``r_xx``, which refuses
        a law with bending.
    intorder : int, optional
        Order of the Gauss rule of the elastic forces of the ``"paper"`` formulation, of
        ``basis`` and of the line loads' tables; the element's default (9, 5 points, on the
        cubic element) integrates the Green axial energy exactly.  The mass matrix and the
        constant line loads are always integrated exactly.
    name : str
        Label used in diagnostics and outputs.
    formulation : str
        How the law is integrated and its tension recovered (``formulation``,
        ``docs/locking.md``), among those the element supports (the first is the
        default): ``"assumed-strain"`` (the cubic element's default: the axial part at the
        assumed strain interpolated from the strain's nodal values and element means,
        no membrane locking and the paper's accuracy on taut cables), ``"paper"`` (the
        paper's formulation, every term on the Gauss rule ``intorder``: locks in bending,
        with tension stripes of tens of times the load) or ``"lobatto"`` (the axial part
        on the nodes and midpoints: locking-free, fourth order on taut cables).
    locking_free : bool, optional
        The earlier switch, kept as it was: False is ``formulation="paper"``, True is
        ``"lobatto"``.
    element : str or CableElement, optional
        The element type (``elements``): ``"hermite3"`` (default, the paper's cubic
        Hermite: positions and slopes at the nodes), ``"hermite5"`` (quintic Hermite: also
        ``r_xx``, C2 across nodes), ``"linear"`` (two-node, positions only, axial laws
        only), or an instance of a user's ``CableElement``.
    curvatures : array_like, shape (n_nodes, 3), optional
        Initial nodal second derivatives ``r_xx`` of an element that has them (not used
        by the others); by default those of the cubic Hermite interpolant of
        ``positions`` and ``slopes`` (the mean of its two one-sided values at an interior
        node; ``Cable.straight`` gives zeros).
    quadrature : dict, optional
        Gauss points per element for each part of the law, ``{"axial": na, "bending":
        nb}`` (either key may be left out: the rule of ``intorder`` then serves that
        part): the axial part (the law's terms without ``r_xx``) and the bending part on
        rules of their own, as Exudyn (5 and 3 points) and Chrono do.  A ``"paper"``
        formulation (the default when ``quadrature`` is given): the others choose their
        own rules.

    The initial coordinates need not be the reference configuration: the mesh's arc
    length is the unstretched length, and ``positions``/``slopes`` may stretch, bend or
    slacken the cable (``Cable.between``).

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
    element : CableElement
        The element type (``elements``).
    basis : skfem.Basis
        scikit-fem basis of the vector element (``ElementVector(element, 3)``) with the
        Gauss rule ``intorder``: the basis on which the forms of ``forms`` are assembled.
    q0 : ndarray (n_dofs,)
        Initial coordinates, node by node, field by field (``[r, r_x]``, six per node, on
        the cubic element); the reference configuration of ``System.q0``.
    n_dofs : int
        Number of coordinates, ``3 n_fields n_nodes``.
    n_nodes, n_elements : int
        Numbers of nodes and elements.
    length : float
        Reference (unstretched) length ``L`` (m).
    h : ndarray (n_elements,)
        Element lengths (m).
    element_dofs : int ndarray (n_elements, 3 n_functions)
        Local coordinates of each element (``n_functions`` 3-vectors: the element's).
    intorder : int
        Order of the Gauss rule of the elastic forces.
    quadrature : dict or None
        ``{"axial": na, "bending": nb}``, the Gauss points of the two parts of the law
        (both keys filled in), or None: one rule for the whole law.
    formulation : str
        The formulation's name (see above).
    xi : ndarray (n_points,)
        Reference coordinates of the Gauss points of ``intorder``.
    S, Sx, Sxx : ndarray (n_elements, n_points, n_functions)
        The element's shape functions and their first and second arc-length derivatives
        at the Gauss points of ``intorder``, used by kernels and loads (``LineLoad``,
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

    #: ``contract.Body.energy_parts``: the law's stretching and bending energy.
    energy_parts = ("axial", "bending")

    def __init__(self, mesh, section, positions, slopes=None, law=None, intorder=None,
                 name="cable", formulation=None, locking_free=None, element=DEFAULT_ELEMENT,
                 curvatures=None, quadrature=None):
        if not isinstance(mesh, MeshLine):
            raise TypeError(f"mesh must be a skfem.MeshLine, got {type(mesh).__name__}")
        if not isinstance(section, Section):
            raise TypeError(f"section must be a skfem_cable.Section, got {type(section).__name__}")
        element = element_type(element)
        law = _law(law, element)
        law.parameter_values(section)  # every parameter has a value
        law.symbolic  # noqa: B018 (the law is well formed: errors now, not at the first step)
        if quadrature is not None and formulation is None and locking_free is None:
            formulation = "paper"
        formulation = _formulation(formulation, locking_free, element)
        if formulation == "assumed-strain":
            law.check_strain()
        intorder = element.intorder if intorder is None else intorder
        if not _is_count(intorder):
            raise ValueError(f"intorder must be a positive integer, got {intorder!r}")
        x = mesh.p[0]
        if np.any(np.diff(x) <= 0) or np.any(mesh.t[1] != mesh.t[0] + 1):
            raise ValueError("mesh nodes must be sorted along the arc length "
                             "(use MeshLine(np.sort(x)))")
        check_memory(len(x) - 1)
        self.mesh = mesh
        self.section = section
        self.law = law
        self.name = name
        self.element = element
        self.h = np.diff(x)
        vector = ElementVector(element, 3)
        self.intorder = int(intorder)
        self.basis = Basis(mesh, vector, intorder=self.intorder)
        self._exact = Basis(mesh, vector, intorder=2 * element.maxdeg)  # mass, line loads
        self.q0 = np.stack(self._nodal_fields(positions, slopes, curvatures), axis=1).ravel()
        self.element_dofs = np.ascontiguousarray(self.basis.element_dofs.T, dtype=np.int64)
        X, W = get_quadrature(mesh.refdom, self.intorder)
        self.xi = X[0]
        self.S = self._shape(self.xi)[0]
        self.Sx, self.Sxx, self.weights, _ = self.tables_at(self.xi, W)
        self.quadrature = _quadrature(quadrature, formulation, len(self.xi))
        self.formulation = formulation
        self._mass = None

    def _nodal_fields(self, positions, slopes, curvatures):
        """The initial nodal fields of the element, in the order of its ``orders``, each
        (n_nodes, 3), checked; ``r_xx`` by default from the cubic interpolant."""
        n = self.mesh.p.shape[1]
        given = {0: ("positions", positions), 1: ("slopes", slopes),
                 2: ("curvatures", curvatures)}
        fields = {}
        for order in self.element.orders:
            label, value = given[order]
            if value is None and order == 2:
                value = self._cubic_second_derivatives(fields[0], fields[1])
            if value is None:
                raise ValueError(f"{label} are required by the element "
                                 f"{self.element.name!r}: an array of shape ({n}, 3)")
            arr = np.asarray(value, dtype=float)
            if arr.shape != (n, 3) or not np.all(np.isfinite(arr)):
                raise ValueError(f"{label} must be a finite array of shape ({n}, 3), "
                                 f"got {arr.shape}")
            fields[order] = arr
        return [fields[k] for k in self.element.orders]

    def _cubic_second_derivatives(self, positions, slopes):
        """``r_xx`` at the nodes of the cubic Hermite interpolant of ``positions`` and
        ``slopes``: the mean of its one-sided values at an interior node."""
        _, _, Sxx = ELEMENTS["hermite3"].shape(np.array([0.0, 1.0]), self.h[:, None])
        ends = np.stack([positions[:-1], slopes[:-1], positions[1:], slopes[1:]])
        start, end = np.einsum("Aex,Aei->xei", Sxx, ends)
        return np.concatenate([start[:1], 0.5 * (start[1:] + end[:-1]), end[-1:]])

    def _shape(self, xi):
        """The element's functions and their x-derivatives (ne, nq, n_functions) at the
        reference coordinates ``xi`` (nq,) of every element."""
        return tuple(np.ascontiguousarray(np.moveaxis(t, 0, -1)) for t in
                     self.element.shape(np.asarray(xi, float)[None, :], self.h[:, None]))

    def tables_at(self, xi, weights):
        """The kernel tables ``(Sx, Sxx, w, h)`` of a rule with reference coordinates
        ``xi`` (nq,) and weights ``weights`` (nq,) on [0, 1]: the element's functions'
        first and second x-derivatives (ne, nq, n_functions), the weights times the
        element lengths (ne, nq) and the element lengths (ne,)."""
        _, Sx, Sxx = self._shape(xi)
        return Sx, Sxx, np.ascontiguousarray(np.asarray(weights)[None, :] * self.h[:, None]), \
            self.h

    @classmethod
    def straight(cls, start, end, n_elements, section, law=None, **kwargs):
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
            The other parameters of ``Cable`` (``element``, ``intorder``, ``name``,
            ``formulation``, ``quadrature``).

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
        start, end = _point("start", start), _point("end", end)
        return cls.between(start, end, np.linalg.norm(end - start), n_elements, section,
                           law=law, **kwargs)

    @classmethod
    def between(cls, start, end, length, n_elements, section, sag=None, law=None, **kwargs):
        """A cable of unstretched ``length`` from ``start`` to ``end``, whatever their
        distance: stretched straight when ``length`` is at most the distance, else hanging
        as the inextensible catenary of that length through both points, sagging along
        ``sag`` (a start that ``solve_static`` converges from under the weight).

        Parameters
        ----------
        start, end : array_like (3,)
            End points (m), distinct.
        length : float
            Unstretched length (m), > 0: the mesh's arc length.
        n_elements : int
            Number of equal elements, >= 1.
        section : Section
        sag : array_like (3,), optional
            The direction the slack cable sags to (the direction of its weight), not
            parallel to ``end - start``; default ``(0, 0, -1)``.  Not used by a cable that
            is stretched straight.
        law : CableLaw or str
            See ``Cable``.
        **kwargs
            The other parameters of ``Cable`` (``element``, ``quadrature``, ``name``, ...).

        Returns
        -------
        Cable
            Nodes equally spaced in the unstretched arc length; straight: slopes
            ``(end - start) / length`` (``|r_x| >= 1``, the uniform stretch); slack: the
            catenary's unit tangents (and curvatures on an element that has them).

        Examples
        --------
        MoorDyn's pendulum line, 100.5 m long between points 100.499 m apart, and the
        same line stretched between points 101 m apart:

        >>> import numpy as np, skfem_cable as sc
        >>> sec = sc.Section.circular(0.05, 1e9 / (np.pi * 0.05**2), 1000.0)
        >>> slack = sc.Cable.between([0, 0, 0], [10, 0, -100], 100.5, 20, sec, sag=[0, 0, -1])
        >>> slack.length, bool(np.allclose(slack.q0[-6:-3], [10, 0, -100]))
        (100.5, True)
        >>> taut = sc.Cable.between([0, 0, 0], [0, 0, -101], 100.0, 4, sec)
        >>> taut.q0[3:6].tolist()
        [0.0, 0.0, -1.01]
        """
        if not _is_count(n_elements):
            raise ValueError(f"n_elements must be a positive integer, got {n_elements!r}")
        check_memory(int(n_elements))
        start, end = _point("start", start), _point("end", end)
        chord = end - start
        distance = np.linalg.norm(chord)
        if not distance > 0:
            raise ValueError(f"start and end must differ, got {start.tolist()} for both")
        try:
            length = float(length)
        except (TypeError, ValueError):
            length = np.nan
        if not (np.isfinite(length) and length > 0):
            raise ValueError(f"length must be a finite unstretched length > 0 (m), got "
                             f"{length!r}")
        s = np.linspace(0.0, length, int(n_elements) + 1)
        if length <= distance:
            slope = chord / length
            positions = start + s[:, None] * slope
            return cls(MeshLine(s), section, positions, np.tile(slope, (len(s), 1)),
                       law=law, curvatures=np.zeros_like(positions), **kwargs)
        fields = _catenary(chord, length, s, (0.0, 0.0, -1.0) if sag is None else sag)
        positions, slopes, curvatures = fields
        return cls(MeshLine(s), section, start + positions, slopes, law=law,
                   curvatures=curvatures, **kwargs)

    def hanging(self, start, end, sag):
        """Coordinates of this cable hanging from ``start`` to ``end`` as the inextensible
        catenary of its length sagging along ``sag``, the slack shape ``between`` builds
        (``solve_static`` starts from it a cable whose ends are held closer than its
        length); None when the ends are at least its length apart.

        Parameters
        ----------
        start, end : array_like (3,)
            End points (m).
        sag : array_like (3,)
            The direction the cable sags to, not parallel to ``end - start``.

        Returns
        -------
        ndarray (n_dofs,) or None
        """
        start, end = _point("start", start), _point("end", end)
        if not np.linalg.norm(end - start) < self.length:
            return None
        positions, slopes, curvatures = _catenary(end - start, self.length,
                                                  self.mesh.p[0] - self.mesh.p[0, 0], sag)
        fields = self._nodal_fields(start + positions, slopes, curvatures)
        return np.stack(fields, axis=1).ravel()

    # --- layout -------------------------------------------------------------------------
    @property
    def n_dofs(self):
        """Number of coordinates, ``3 n_fields n_nodes`` (``6 n_nodes`` on the cubic
        element)."""
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

    @property
    def has_slopes(self):
        """Whether the nodes carry a slope ``r_x`` (the element's fields include it; the
        ``Node`` contract)."""
        return 1 in self.element.orders

    def node_dofs(self, index):
        """Local coordinates of the node ``index`` (non-negative), field by field in the
        order of the element's ``orders`` (``[r, r_x]``, six, on the cubic element)."""
        k = 3 * self.element.nodal_dofs
        return k * index + np.arange(k)

    @property
    def position_mask(self):
        """True for position coordinates, False for slopes and second derivatives."""
        return np.tile(np.arange(3 * self.element.nodal_dofs) < 3, self.n_nodes)

    def internal_constraints(self):
        """None: an ANCF cable's coordinates are all free."""
        return []

    def describe_dof(self, index):
        """Which node and component a local coordinate is, e.g. ``node 3 r_x[1]``."""
        node, k = divmod(int(index), 3 * self.element.nodal_dofs)
        return f"node {node} {self.element.node_fields[k // 3]}[{k % 3}]"

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
        """Where the mass is (the hook ``orbit_gravity`` reads): the Gauss points of the
        element's ``mass_order`` in every element (4 on the cubic element), ``(vectors (np,
        nf), coefficients (np, nf), mass (np,))`` with ``nf`` the element's functions, a
        point at ``sum_A S_A q[vectors[A] : vectors[A] + 3]`` (the element's nodal
        3-vectors weighted by its functions) with mass ``rho A`` times the Gauss weight:
        the rule integrates the mass matrix exactly, so the points hold the cable's mass,
        centre of mass, second moments and kinetic energy."""
        X, w = get_quadrature(self.mesh.refdom, self.element.mass_order)
        S = self._shape(X[0])[0]
        ne, nq, nf = S.shape
        vectors = np.repeat(self.element_dofs[:, 0::3], nq, axis=0)
        return vectors, S.reshape(ne * nq, nf), \
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
        """Global coordinates of every element, int (ne, 3 n_functions)."""
        return self.element_dofs + system.dofs(self)[0]

    def line_points(self, system):
        """The cable's points for line loads (the line-body hook, ``lines``): the Gauss
        points of ``intorder`` in every element, with the tables ``S``, ``Sx`` and
        ``weights``."""
        return LinePoints(self.global_element_dofs(system), self.S, self.Sx, self.weights)

    def bind(self, system):
        """The term of the cable's elastic and damping forces (see ``contract``): the
        law's compiled kernels (``cable_term``), one per pass of the cable's formulation
        (``formulation``), shared by all cables with the same law, parameter values,
        formulation and quadrature; their element loops on threads when the system runs
        on more than one (``linalg.thread_count``, ``kernels.chunks``)."""
        values = self.law.parameter_values(self.section)
        deployment = system.deployment(self)
        if deployment is not None and self.law.varies:
            raise ValueError(f"cable {self.name!r} deploys and its law's parameters "
                             f"{', '.join(self.law.varies)} vary in time: a deploying "
                             "cable takes a law with constant parameters")
        passes, key = [], []
        threads = thread_count()
        for piece, kind, tables in FORMULATIONS[self.formulation].passes(self):
            if piece.vanishes:
                continue
            damped = piece.damped and (bool(self.law.varies) or piece.dissipates(values))
            if deployment is not None and damped:
                raise ValueError(
                    f"cable {self.name!r} deploys and its law dissipates (e.g. the "
                    "section's gamma_axial, gamma_bending > 0): on the stretching mesh its "
                    "damping would take the mesh's stretching l'/l for a strain rate, not "
                    "the material's; use an undamped law for a deploying cable")
            if deployment is not None:  # the term's own tables, rescaled in time
                tables = tuple(np.array(t) for t in tables)
            module = piece.compiled(kind, self.element.orders)
            passes.append((module.kernel_parallel if threads > 1 else module.kernel, tables,
                           values, damped))
            key.append((piece.key, kind, damped, tables[0].shape[1]))
        term = cable_term(self.global_element_dofs(system), passes,
                          ("ancf-cable", self.element.name, values, *key), self.name)
        if self.law.varies:
            return Varying(self.law, self.section, term).term(term)
        if deployment is None:
            return term
        return Stretched(deployment, term, passes).term(system, term)


def _catenary(chord, length, s, sag):
    """Positions (from the start), unit tangents and their arc-length derivatives at the
    arc lengths ``s`` of the inextensible catenary of ``length`` spanning ``chord`` and
    sagging along ``sag`` (``Cable.between``), each (len(s), 3)."""
    from .analytic import catenary_xz, solve_catenary

    down = _point("sag", sag)
    if not np.linalg.norm(down) > 0:
        raise ValueError(f"sag must be a non-zero direction, got {sag!r}")
    up = -down / np.linalg.norm(down)
    across = chord - (chord @ up) * up
    span = np.linalg.norm(across)
    if not span > 1e-9 * np.linalg.norm(chord):
        raise ValueError(f"sag {np.asarray(sag).tolist()} is parallel to end - start: a "
                         "slack cable needs a sag direction across the line between its "
                         "ends")
    across /= span
    H, VA, _ = solve_catenary(span, chord @ up, length, 1.0)
    xz = catenary_xz(s, H, VA, 1.0)
    V = s - VA
    T = np.hypot(H, V)
    tangent = np.column_stack([H / T, V / T])
    bend = np.column_stack([-H * V / T**3, H**2 / T**3])
    basis = np.stack([across, up])
    return xz @ basis, tangent @ basis, bend @ basis


def _law(law, element):
    """The ``CableLaw`` of ``Cable``'s ``law`` on ``element``: a built-in name resolved,
    the default ``"cable"`` (``"truss"`` on an element without ``r_xx``), a law with
    bending refused on such an element."""
    if law is None:
        law = "cable" if element.bending else "truss"
    if isinstance(law, str):
        if law not in BUILTIN:
            raise ValueError(f"law must be a CableLaw or one of {tuple(BUILTIN)}, "
                             f"got {law!r}")
        law = BUILTIN[law]
    if not isinstance(law, CableLaw):
        raise TypeError(f"law must be a CableLaw (see skfem_cable.cable_law) or a name, "
                        f"got {type(law).__name__}")
    if law.bending and not element.bending:
        raise ValueError(f"law {law.name!r} has bending (its energy reads r_xx), which the "
                         f"element {element.name!r} does not have (it sees "
                         f"{', '.join(element.fields)} only): use an axial law such as "
                         "law='truss', or an element with bending, e.g. element='hermite3'")
    return law


#: Most Gauss points a part of the law may take (``quadrature``).
MAX_GAUSS_POINTS = 20


def _quadrature(quadrature, formulation, default):
    """``Cable``'s ``quadrature`` checked and completed (``{"axial": na, "bending": nb}``,
    a missing key taking ``default`` points, those of the rule of ``intorder``), or
    None."""
    if quadrature is None:
        return None
    if not isinstance(quadrature, dict) or not quadrature \
            or set(quadrature) - {"axial", "bending"}:
        raise ValueError("quadrature must be a dict with the keys 'axial' and/or 'bending' "
                         f"(Gauss points per element), got {quadrature!r}")
    if formulation != "paper":
        raise ValueError(f"quadrature is for formulation='paper' (Gauss rules for the "
                         f"axial and the bending part); formulation {formulation!r} "
                         "chooses its own rules: leave one of the two out")
    rules = {}
    for part in ("axial", "bending"):
        n = quadrature.get(part, default)
        if not (_is_count(n) and n <= MAX_GAUSS_POINTS):
            raise ValueError(f"quadrature[{part!r}] must be a whole number of Gauss points "
                             f"in [1, {MAX_GAUSS_POINTS}], got {n!r}")
        rules[part] = int(n)
    return rules


def _formulation(formulation, locking_free, element):
    """The formulation's name from ``Cable``'s ``formulation`` and ``locking_free``, one
    that ``element`` supports (its first by default)."""
    if locking_free is not None:
        if not isinstance(locking_free, bool):
            raise TypeError(f"locking_free must be True or False, got {locking_free!r}")
        named = "lobatto" if locking_free else "paper"
        if formulation is not None and formulation != named:
            raise ValueError(f"locking_free={locking_free} means formulation={named!r}, "
                             f"which contradicts formulation={formulation!r}: give one")
        formulation = named
    if formulation is None:
        return element.formulations[0]
    if formulation not in FORMULATIONS:
        raise ValueError(f"formulation must be one of {tuple(FORMULATIONS)}, "
                         f"got {formulation!r}")
    if formulation not in element.formulations:
        raise ValueError(f"formulation {formulation!r} is not available on the element "
                         f"{element.name!r}: it supports {element.formulations}")
    return formulation
