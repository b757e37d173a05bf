"""The fixed KKT sparsity pattern of a system, the positions of every term's tangent entries
in its CSR values, and the constant parts (mass, linear constraint Jacobians, constant
loads), all computed once when the system's layout is first needed, with the description
of the system they were computed for."""

import numpy as np
import scipy.sparse as sp

from ..core.contract import NO_DATA, NO_INDEX, merge_terms
from ..core.inputs import InputTable, system_inputs
from ..core.linalg import FastCSR
from ..space.reference import Reference
from .fingerprint import describe_system


class Pattern:
    """Collects blocks of (row, col) entries, then fixes the CSR pattern and the position
    of every entry of every block in its values."""

    def __init__(self):
        self.rows, self.cols, self.shapes = [], [], []

    def block(self, rows, cols):
        """Register the entries ``(rows, cols)`` (broadcast); returns the block's id."""
        r, c = np.broadcast_arrays(np.asarray(rows, dtype=np.int64),
                                   np.asarray(cols, dtype=np.int64))
        self.shapes.append(r.shape)
        self.rows.append(r.ravel())
        self.cols.append(c.ravel())
        return len(self.shapes) - 1

    def finish(self, N):
        """Fix the pattern of an ``N x N`` matrix (with its full diagonal)."""
        self.block(np.arange(N), np.arange(N))
        key = np.concatenate(self.rows) * N + np.concatenate(self.cols)
        # the distinct keys by a sort: np.unique hashes them first (numpy 2.4), 3.3 s for
        # the 2.9 million of a cable of 10 000 elements against 0.06 s
        ordered = np.sort(key)
        self.ukey = ordered[np.concatenate([[True], ordered[1:] != ordered[:-1]])]
        self.N = N
        self.indptr = np.searchsorted(self.ukey // N, np.arange(N + 1)).astype(np.int64)
        self.indices = (self.ukey % N).astype(np.int64)
        self.pos = np.searchsorted(self.ukey, key)
        self.start = np.concatenate([[0], np.cumsum([r.size for r in self.rows])])

    def index(self, b):
        """Positions in the CSR values of the entries of block ``b`` (its shape)."""
        if b is None:
            return None
        return np.ascontiguousarray(self.pos[self.start[b]: self.start[b + 1]]
                                    .reshape(self.shapes[b]))

    def positions(self, rows, cols):
        """Positions of existing entries ``(rows, cols)`` (1-D arrays)."""
        return np.searchsorted(self.ukey, np.asarray(rows, np.int64) * self.N + cols)


class Layout:
    """Fixed KKT pattern of a system and its constant parts.

    Attributes
    ----------
    body_terms, load_terms : list of (Term, index)
        Bound contributors with the positions of their tangent entries.
    own_terms : dict
        Each body's own term (before terms with equal keys are merged), by ``id(body)``:
        what ``System.energy_parts`` evaluates alone.
    f_const : ndarray
        Sum of the constant generalized forces (gravity, fixed loads).
    mass, mass_data, mass_diagonal
        The mass matrix (``FastCSR``), its values in the KKT pattern, its diagonal.
    linear_data
        The constant Jacobians of the linear constraints in the KKT pattern.
    cdofs, crows
        Coordinates and multiplier rows of each constraint.
    constrained : int ndarray
        The coordinates some constraint holds (the union of ``cdofs``, sorted): the only
        ones where ``C_q^T lambda`` can differ from zero.
    writes : frozenset of str
        The force accumulators some term writes (``Term.writes``): the compiled step
        clears, reads and books only these.
    border
        Unknowns of the hubs, ordered last by the linear solver (``_border``).
    junctions
        Coordinates where bodies other than hubs meet (``_junctions``): ordered last
        too where that narrows the band, before the hubs (two levels).
    description : dict
        ``io.fingerprint.describe_system`` of the system once bound: a later one that
        differs means the system was edited (``System.current_layout``).
    reference : Reference or None
        The reference of the runs on this binding, in orbit (``orbit.Reference``, made
        from ``System.orbit``; None otherwise): the terms that read ``R(t)``, ``V(t)``
        hold it (a load declaring ``reads_reference`` is bound with
        ``bind(system, reference)``), each run sets its rebases (``simulate``: none at a
        fresh start, the checkpoint's when resumed) and the rectification rebases it;
        the user's ``Orbit`` stays as given.
    inputs : inputs.InputTable
        The values of the system's declared inputs during the runs on this binding
        (``inputs.system_inputs``): a part declaring inputs (``inputs()``) is bound with
        ``bind(system, inputs=table)`` and its terms read them; each run starts them at
        their initial values, its controllers set them (``control.ControlLoop``); the
        user's ``Input`` objects keep their initial values.
    """

    def __init__(self, system):
        self.system = system
        n = system.n_dofs
        pattern = Pattern()
        orbit = getattr(system, "orbit", None)
        self.reference = None if orbit is None else Reference(orbit)
        self.inputs = InputTable(system_inputs(system))
        own = [self._bind(b, system) for b in system.bodies]
        self.own_terms = dict(zip(map(id, system.bodies), own))
        bodies = merge_terms([t for t in own if t])
        loads = [self._bind(load, system) for load in system.loads]
        body_blocks = [self._block(pattern, t) for t in bodies]
        load_blocks = [self._block(pattern, t) for t in loads]
        M = self._with_loads_mass(system.mass_matrix(), loads).tocoo()
        pattern.block(M.row, M.col)
        con_blocks = self._constraint_blocks(pattern, system, n)
        pattern.finish(n + self.n_c)
        self.pattern = pattern
        self.N, self.indptr, self.indices = pattern.N, pattern.indptr, pattern.indices
        self.nnz = len(pattern.indices)
        self.diagonal_index = pattern.positions(np.arange(self.N), np.arange(self.N))
        self.body_terms = [(t, pattern.index(b)) for t, b in zip(bodies, body_blocks)
                           if t.evaluates]
        self.load_terms = [(t, pattern.index(b)) for t, b in zip(loads, load_blocks)
                           if t.evaluates]
        self.jac_index, self.jacT_index, self.hess_index = (
            [pattern.index(b).ravel() if b is not None else None for b in blocks]
            for blocks in con_blocks)
        #: ``(dofs, rows, jac, jacT, hess)`` of each constraint: the ``index`` of a
        #: compiled constraint hook (``Constraint.kernel``, see ``contract``)
        self.cindex = [tuple(np.ascontiguousarray(a, dtype=np.int64) for a in (
            d, r, j, jt, NO_INDEX if h is None else h)) for d, r, j, jt, h in zip(
            self.cdofs, self.crows, self.jac_index, self.jacT_index, self.hess_index)]
        self.constrained = np.unique(np.concatenate([NO_INDEX, *self.cdofs]))
        self.writes = frozenset().union(*(t.writes for t, _ in self.body_terms
                                          + self.load_terms))
        self._mass(M)
        owner, count, hubs = self._hubs(system)
        self.border = self._border(system, owner, hubs)
        self.junctions = self._junctions(owner, count, hubs)
        self._linear_constraints(system)
        self.f_const = self._constant_force(system, loads)
        self._scales(system)
        self.description = describe_system(system)
        self._derived = {}

    def derived(self, key, make):
        """``make()``, made at the first call with ``key`` and then kept: what a solver
        derives from this layout alone (the band ordering of its iteration matrix, the
        types of its compiled step's arguments), made once for all its runs on the
        unchanged system (``System.current_layout``) instead of at every start."""
        if key not in self._derived:
            self._derived[key] = make()
        return self._derived[key]

    def _bind(self, part, system):
        """The term of ``part`` (a body or a load): one declaring ``reads_reference`` (it
        reads the reference point's motion ``R(t)``, ``V(t)``) is bound with the runs'
        ``reference``, one declaring inputs (an ``inputs()`` method) with the runs'
        ``inputs`` table (keywords of its ``bind``)."""
        context = {}
        if getattr(part, "reads_reference", False):
            context["reference"] = self.reference
        if callable(getattr(part, "inputs", None)):
            context["inputs"] = self.inputs
        return part.bind(system, **context)

    @staticmethod
    def _block(pattern, term):
        return pattern.block(term.rows, term.cols) if term.has_tangent else None

    def _constraint_blocks(self, pattern, system, n):
        """Rows of the multipliers, and the pattern blocks of ``C_q``, ``C_q^T`` and the
        Hessian term of every constraint."""
        self.cdofs, self.crows = [], []
        jac, jacT, hess = [], [], []
        row = 0
        for c in system.constraints:
            d = np.asarray(c.dofs(system), dtype=np.int64)
            rr = row + np.arange(c.n_eq)
            self.cdofs.append(d)
            self.crows.append(rr)
            jac.append(pattern.block(n + rr[:, None], d[None, :]))
            jacT.append(pattern.block(d[:, None], n + rr[None, :]))
            hess.append(None if c.linear else pattern.block(d[:, None], d[None, :]))
            row += c.n_eq
        self.n_c = row
        return jac, jacT, hess

    #: A body joined by constraints to at least this many other bodies, and to no fewer
    #: than any of them is, is a hub (the E-sail's tethers joined to the hub and to two
    #: auxiliary tethers are not: their partner the hub has more).
    HUB_PARTNERS = 3
    #: Coordinates coupled to more than this many unknowns (a reel's length, coupled to
    #: every coordinate of its cable) are ordered last too.
    DENSE_ROW = 64

    def _hubs(self, system):
        """The body owning each coordinate, each body's number of partners (bodies joined
        to it by a constraint) and the hubs: bodies joined to ``HUB_PARTNERS`` or more
        others, and to no fewer than any of them is (the E-sail's hub)."""
        owner = np.empty(system.n_dofs, dtype=np.int64)
        for b, body in enumerate(system.bodies):
            owner[system.dofs(body)] = b
        partners = [set() for _ in system.bodies]
        for d in self.cdofs:
            joined = set(owner[d].tolist())
            for b in joined:
                partners[b] |= joined - {b}
        count = [len(p) for p in partners]
        hubs = {b for b, p in enumerate(partners)
                if count[b] >= self.HUB_PARTNERS and all(count[o] <= count[b] for o in p)}
        return owner, count, hubs

    def _border(self, system, owner, hubs):
        """Unknowns of the ``hubs`` (``_hubs``) and coordinates with more than
        ``DENSE_ROW`` entries in their row (a reel's length; a rigid body whose surface a
        line touches, ``loads.contact_body``), with the multipliers of the constraints on
        those coordinates alone (a pivot-free elimination of the rest needs them last).
        Ordered last by the linear solver, they keep the band narrow
        (``linalg.PatternSolver``)."""
        counts = np.diff(self.indptr)[:system.n_dofs]
        parts = [system.dofs(system.bodies[b]) for b in sorted(hubs)]
        parts.append(np.flatnonzero(counts > self.DENSE_ROW))
        coordinates = np.unique(np.concatenate(parts))
        parts += [system.n_dofs + rows for d, rows in zip(self.cdofs, self.crows)
                  if d.size and np.isin(d, coordinates).all()]
        return np.unique(np.concatenate(parts)).astype(np.int64)

    def _junctions(self, owner, count, hubs):
        """Coordinates where bodies other than hubs meet, which would join their blocks
        of the band into one (the E-sail's ring joins every tether to its neighbours):
        on every constraint joining such bodies, the coordinates of the one joined to
        the most (the first of equals; a tether's tip, not its auxiliary tether's end);
        and the multipliers of the constraints on those coordinates alone (a rigid
        body's own, which would otherwise be a block of zeros).  Ordered last, with the
        hubs as their dense border, where that narrows the band (``linalg.PatternSolver``:
        two levels)."""
        parts = [np.zeros(0, dtype=np.int64)]
        for d in self.cdofs:
            bodies = sorted(set(owner[d].tolist()))
            if len(bodies) > 1 and not hubs.intersection(bodies):
                best = max(bodies, key=lambda b: count[b])
                parts.append(d[owner[d] == best])
        junctions = np.unique(np.concatenate(parts))
        parts += [owner.size + rows for d, rows in zip(self.cdofs, self.crows)
                  if d.size and np.isin(d, junctions).all()]
        return np.unique(np.concatenate(parts)).astype(np.int64)

    @staticmethod
    def _with_loads_mass(M, loads):
        """The mass the integrator sees: the system's (bodies and point masses, the mass
        gravity weighs) plus the constant mass of loads (``Term.mass``: the added mass of
        a fluid)."""
        parts = [t.mass for t in loads if t.mass is not None]
        if not parts:
            return M
        rows, cols, values = (np.concatenate(a) for a in zip(*parts))
        return M + sp.csr_matrix((values, (rows, cols)), shape=M.shape)

    def _mass(self, M):
        self.mass = FastCSR(M)
        self.mass_data = np.bincount(self.pattern.positions(M.row, M.col), weights=M.data,
                                     minlength=self.nnz)
        self.mass_diagonal = M.diagonal()

    def _linear_constraints(self, system):
        """Constraints with constant Jacobians: one sparse matrix ``C_lin`` and their
        constant KKT entries; driven ones keep their time-dependent offsets."""
        n = system.n_dofs
        linear = [k for k, c in enumerate(system.constraints) if c.linear]
        self.nonlinear = [k for k, c in enumerate(system.constraints) if not c.linear]
        self.linear_data = np.zeros(self.nnz)
        self.C_lin, self.lin_rows, self.driven = None, np.zeros(0, dtype=np.int64), []
        if not linear:
            return
        q0 = system.q0
        Jr, Jc, Jv, offsets = [], [], [], []
        start = 0
        for k in linear:
            c, d = system.constraints[k], self.cdofs[k]
            J = c.jacobian(q0[d], 0.0)
            Jr.append(np.repeat(np.arange(start, start + c.n_eq), J.shape[1]))
            Jc.append(np.tile(d, J.shape[0]))
            Jv.append(J.ravel())
            offsets.append(J @ q0[d] - c.value(q0[d], 0.0))
            if c.driven:
                self.driven.append((slice(start, start + c.n_eq), c))
            self.linear_data[self.jac_index[k]] += J.ravel()
            self.linear_data[self.jacT_index[k]] += J.T.ravel()
            start += c.n_eq
        self.lin_rows = np.concatenate([self.crows[k] for k in linear])
        C_lin = sp.csr_matrix((np.concatenate(Jv), (np.concatenate(Jr), np.concatenate(Jc))),
                              shape=(start, n))
        self.C_lin = FastCSR(C_lin)
        self.C_lin_T = FastCSR(C_lin.T)
        self.c_lin = np.concatenate(offsets)

    def linear_offsets(self, t):
        """``c(t)`` of ``C_lin q - c(t)``."""
        if not self.driven:
            return self.c_lin
        c = self.c_lin.copy()
        for rows, con in self.driven:
            c[rows] = con.offset(t)
        return c

    def constraints(self, q, t, lam, f_con, r_c, scale, data=None, cK=1.0):
        """Add ``C_q^T lam`` to ``f_con``, write ``scale C(q, t)`` into ``r_c`` and, with
        ``data``, the scaled Jacobians and ``cK`` times the Hessian terms."""
        constraints = self.system.constraints
        if self.C_lin is not None:
            r_c[self.lin_rows] = scale * (self.C_lin @ q - self.linear_offsets(t))
            f_con += self.C_lin_T @ lam[self.lin_rows]
        packed = (q, lam, np.array([t, cK, scale]), r_c, f_con,
                  NO_DATA if data is None else data)
        for k in self.nonlinear:
            kernel = getattr(constraints[k], "kernel", None)
            if kernel is not None:
                kernel[0](kernel[1], self.cindex[k], packed)
            else:
                self.python_constraint(k, q, t, lam, f_con, r_c, scale, data, cK)

    def python_constraint(self, k, q, t, lam, f_con, r_c, scale, data=None, cK=1.0):
        """``constraints`` for the nonlinear constraint ``k`` without compiled kernel,
        through its ``value``, ``jacobian`` and ``hessian``."""
        c, d, rows = self.system.constraints[k], self.cdofs[k], self.crows[k]
        qc = q[d]
        Jc = c.jacobian(qc, t)
        f_con[d] += Jc.T @ lam[rows]
        r_c[rows] = scale * c.value(qc, t)
        if data is not None:
            data[self.jac_index[k]] += scale * Jc.ravel()
            data[self.jacT_index[k]] += scale * Jc.T.ravel()
            H = c.hessian(qc, lam[rows], t)
            if H is not None:
                data[self.hess_index[k]] += cK * H.ravel()

    @staticmethod
    def _constant_force(system, terms):
        f = np.zeros(system.n_dofs)
        for term in terms:
            if term.force is not None:
                np.add.at(f, *term.force)
        return f

    def _scales(self, system):
        """Coordinate scales for convergence tests: system size for positions, 1 for
        slopes.  The size is the diameter of the position points about their centroid
        (the same in any frame), or 1 (m) where it is 0: a system of one point (a user's
        bead; a rigid body has its four base points) has no size of its own (it read
        1e-300, which scaled its residual by 1e300 and made Newton's tolerance one of
        exact zeros)."""
        is_position = np.concatenate([b.position_mask for b in system.bodies])
        points = system.q0[system.vectors[system.vector_is_position]]
        extent = 2 * np.linalg.norm(points - points.mean(axis=0), axis=1).max() \
            if points.size else 0.0
        self.length_scale = float(extent) if extent > 0 else 1.0
        self.coordinate_scale = np.where(is_position, self.length_scale, 1.0)

    def matrix(self, data):
        return sp.csr_matrix((data, self.indices, self.indptr), shape=(self.N, self.N))
