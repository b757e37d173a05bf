"""The ANCF cable body: a scikit-fem ``MeshLine`` over the reference arc length carrying the
3-D cubic-Hermite position field ``r(x)`` (paper Sect. 2.2).

Examples
--------
>>> import skfem_cable as sc
>>> cable = sc.Cable.straight([0, 0, 0], [2, 0, 0], 4, sc.Section.circular(1e-3, 2e11, 7850.0))
>>> cable.n_elements, cable.n_nodes, cable.n_dofs, cable.length
(4, 5, 30, 2.0)
"""

import functools

import numpy as np
from skfem import Basis, BilinearForm, ElementVector, LinearForm, MeshLine, asm
from skfem.assembly import Dofs
from skfem.helpers import dot
from skfem.quadrature import get_quadrature

from ..core.linalg import thread_count
from ..core.lines import LinePoints
from ..core.node import Node
from ..elements import DEFAULT_ELEMENT, ELEMENTS, element_type
from .cable_options import check_strain_once, formulation_name, gauss_rules, is_count, resolve_law
from .cable_shapes import CableShapes
from .cable_term import cable_term
from .fields import CableFields
from .formulation import FORMULATIONS
from .memory import check_memory
from .section import Section
from .stretched import Stretched
from .varying import Varying

#: Most entries (nonzeros) of the mass matrices ``_kept_mass`` keeps.
MASS_KEPT = 2_000_000

_KEPT_MASSES = {}


def _kept_mass(key, assemble):
    """A copy of the mass matrix kept by ``key`` (what defines it: mesh, element, mass per
    length), else of ``assemble()``, kept then; the latest used are kept, up to
    ``MASS_KEPT`` entries in all (``Cable.mass_matrix``)."""
    M = _KEPT_MASSES.pop(key, None)
    if M is None:
        M = assemble()
    _KEPT_MASSES[key] = M  # the latest used last
    while sum(m.nnz for m in _KEPT_MASSES.values()) > MASS_KEPT:
        del _KEPT_MASSES[next(iter(_KEPT_MASSES))]
    return M.copy()


class Cable(CableFields, CableShapes):
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
        law = resolve_law(law, element)
        law.parameter_values(section)  # every parameter has a value
        law.symbolic  # noqa: B018 (the law is well formed: errors now, not at the first step)
        if quadrature is not None and formulation is None and locking_free is None:
            formulation = "paper"
        formulation = formulation_name(formulation, locking_free, element)
        if formulation == "assumed-strain":
            check_strain_once(law)
        intorder = element.intorder if intorder is None else intorder
        if not is_count(intorder):
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
        self.intorder = int(intorder)
        self.q0 = np.stack(self._nodal_fields(positions, slopes, curvatures), axis=1).ravel()
        self.element_dofs = np.ascontiguousarray(Dofs(mesh, self._vector).element_dofs.T,
                                                 dtype=np.int64)
        X, W = get_quadrature(mesh.refdom, self.intorder)
        self.xi = X[0]
        self.S, self.Sx, self.Sxx = self._shape(self.xi)
        self.weights = self._weighted(W)
        self.quadrature = gauss_rules(quadrature, formulation, len(self.xi))
        self.formulation = formulation
        self._mass = None

    @property
    def _vector(self):
        """The vector element of the cable's bases (``ElementVector(element, 3)``)."""
        return ElementVector(self.element, 3)

    @functools.cached_property
    def basis(self):
        """The scikit-fem basis on the Gauss rule ``intorder`` (``forms``), made at its
        first use: the kernels read tables of their own (``S``, ``Sx``, ``tables_at``)."""
        return Basis(self.mesh, self._vector, intorder=self.intorder)

    @functools.cached_property
    def _exact(self):
        """The scikit-fem basis on a rule exact for the mass matrix and line loads."""
        return Basis(self.mesh, self._vector, intorder=2 * self.element.maxdeg)

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
        return Sx, Sxx, self._weighted(weights), self.h

    def _weighted(self, weights):
        """The weights (nq,) of a rule on [0, 1] times the element lengths (ne, nq)."""
        return np.ascontiguousarray(np.asarray(weights)[None, :] * self.h[:, None])

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
        ``section`` (again when it is replaced), or a copy of the one of a recent cable
        with the same element, mesh and mass per length (``_kept_mass``: a scene built
        again, a sweep's cases, a test's fixtures)."""
        if self._mass is None or self._mass[0] is not self.section:
            mu = self.section.mass_per_length
            p, t = self.mesh.p, self.mesh.t
            key = (type(self.mesh), self.element, p.dtype.str, p.tobytes(), t.dtype.str,
                   t.tobytes(), float(mu).hex())
            self._mass = (self.section, _kept_mass(key, lambda: asm(
                BilinearForm(lambda u, v, w: mu * dot(u, v)), self._exact).tocsr()))
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
            function, span = piece.hook(kind, self.element.orders, threads)
            passes.append((function, tables, values, damped, span))
            key.append((piece.key, kind, damped, tables[0].shape[1]))
        term = cable_term(self.global_element_dofs(system), passes,
                          ("ancf-cable", self.element.name, values, *key), self.name)
        if self.law.varies:
            return Varying(self.law, self.section, term).term(term)
        if deployment is None:
            return term
        return Stretched(deployment, term, passes).term(system, term)


