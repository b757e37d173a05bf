"""A multibody system: bodies stacked into one coordinate vector (Eq. 4), constraints with
Lagrange multipliers, and loads; assembly of residual and KKT matrix on a fixed pattern.

The KKT matrix of the unknowns ``(q, lambda')`` is

    [[cM M + cK (K + H(lambda) - dF_ext/dq),  s C_q^T],
     [s C_q,                                   0      ]]

with ``K`` the elastic tangent, ``H`` the constraint Hessian term of Eq. 15 and ``s`` a
constraint scaling (``lambda = s lambda'``) chosen by the solvers for conditioning.
"""

import numpy as np
import scipy.sparse as sp

from . import constraints as cons
from .cable import Cable, Node
from .loads import PointMoment, _vector3


class System:
    """Bodies, constraints and loads.

    Parameters
    ----------
    bodies : sequence of Cable
    """

    def __init__(self, bodies):
        self.bodies = list(bodies)
        if not self.bodies:
            raise ValueError("bodies must contain at least one body")
        self.offsets = {}
        n = 0
        for body in self.bodies:
            self.offsets[id(body)] = n
            n += body.n_dofs
        self.n_dofs = n
        self.constraints = []
        self.moments = []
        self.f_const = np.zeros(n)
        self.gravity = np.zeros(3)
        self._layout = None

    # --- building -------------------------------------------------------------------------
    def _offset(self, body):
        try:
            return self.offsets[id(body)]
        except KeyError:
            raise ValueError(f"{body!r} is not a body of this system") from None

    def dofs(self, item):
        """Global coordinates of a ``Node`` (6 for a cable node) or of a whole body."""
        if isinstance(item, Node):
            return self._offset(item.body) + item.body.node_dofs(item.index)
        return self._offset(item) + np.arange(item.n_dofs)

    def add_constraint(self, constraint):
        self.constraints.append(constraint)
        self._layout = None
        return self

    def clamp(self, node, direction=None):
        """Clamp a node: position and slope direction fixed. Returns the system."""
        return self.add_constraint(cons.clamp(node, direction))

    def pin(self, node, target=None):
        """Spherical joint of a node to ground (``target`` None or a point) or to another
        node/body point. Returns the system."""
        return self.add_constraint(cons.pin(node, target))

    def add_point_load(self, node, force):
        """Constant force (N) at a node's position."""
        self.f_const[self.dofs(node)[:3]] += _vector3(force, "force")
        return self

    def add_point_moment(self, node, moment):
        """Moment (N m, fixed in space) at a cable node; see ``loads.PointMoment``."""
        self.moments.append(PointMoment(node, moment))
        self._layout = None
        return self

    def add_gravity(self, g):
        """Uniform gravity (m/s^2) on every body: consistent nodal forces ``int S^T rho A g``."""
        g = _vector3(g, "g")
        self.gravity = self.gravity + g
        for body in self.bodies:
            self.f_const[self.dofs(body)] += body.line_load(body.section.mass_per_length * g)
        return self

    def add_line_load(self, cable, force_per_length):
        """Uniform distributed load (N/m, fixed in space) along a cable."""
        self.f_const[self.dofs(cable)] += cable.line_load(force_per_length)
        return self

    # --- layout ---------------------------------------------------------------------------
    @property
    def q0(self):
        return np.concatenate([b.q0 for b in self.bodies])

    @property
    def n_constraints(self):
        return sum(c.n_eq for c in self.constraints)

    @property
    def layout(self):
        if self._layout is None:
            self._layout = Layout(self)
        return self._layout

    def mass_matrix(self):
        """Global constant mass matrix (Eq. 11)."""
        return sp.block_diag([b.mass_matrix() for b in self.bodies], format="csr")

    def cables(self):
        return [b for b in self.bodies if isinstance(b, Cable)]

    # --- evaluation -------------------------------------------------------------------------
    def constraint_values(self, q):
        lay = self.layout
        return np.concatenate([c.value(q[d]) for c, d in zip(self.constraints, lay.cdofs)]) \
            if self.constraints else np.zeros(0)

    def elastic_energy(self, q):
        """``[axial, bending]`` elastic energy of all cables."""
        energy = np.zeros(2)
        for body in self.cables():
            body.elastic(q[self.dofs(body)], np.zeros(body.n_dofs), energy=energy)
        return energy

    def assemble(self, q, lam, load_factor=1.0, cK=1.0, scale=1.0, data=None):
        """Residual of the equilibrium equations without inertia and, if ``data`` is given,
        add the KKT matrix values (``cK`` times the stiffness blocks) to it.

        Returns
        -------
        r : ndarray
            ``[f_int - load_factor f_ext + C_q^T lambda, scale * C]`` with ``lambda = lam``
            the true multipliers.
        info : dict
            ``energy`` (``[axial, bending]``) and ``force_ref``, the largest norm of the
            internal, external and constraint forces (a scale for convergence tests).
        """
        lay = self.layout
        n = self.n_dofs
        f_int = np.zeros(n)
        energy = np.zeros(2)
        want = data is not None
        for body, edofs, scatter in zip(self.bodies, lay.body_edofs, lay.body_scatter):
            body.elastic(q, f_int, data, scatter if want else None, cK, energy, edofs)
        f_ext = load_factor * self.f_const
        for mom, d, idx in zip(self.moments, lay.mdofs, lay.moment_index):
            a = q[d]
            f_ext[d] += load_factor * mom.force(a)
            if want:
                np.add.at(data, idx, -cK * load_factor * mom.stiffness(a).ravel())
        f_con = np.zeros(n)
        r = np.empty(n + lay.n_c)
        for k, (c, d) in enumerate(zip(self.constraints, lay.cdofs)):
            rows = lay.crows[k]
            qc = q[d]
            Jc = c.jacobian(qc)
            f_con[d] += Jc.T @ lam[rows - n]
            r[rows] = scale * c.value(qc)
            if want:
                data[lay.jac_index[k]] += scale * Jc.ravel()
                data[lay.jacT_index[k]] += scale * Jc.T.ravel()
                H = c.hessian(qc, lam[rows - n])
                if H is not None:
                    data[lay.hess_index[k]] += cK * H.ravel()
        r[:n] = f_int - f_ext + f_con
        force_ref = max(np.linalg.norm(f_int), np.linalg.norm(f_ext), np.linalg.norm(f_con))
        return r, {"energy": energy, "force_ref": force_ref}


class Layout:
    """Fixed KKT sparsity pattern of a system and the scatter maps into its CSR data."""

    def __init__(self, system):
        n = system.n_dofs
        rows, cols = [], []
        blocks = []

        def block(r, c):
            r, c = np.broadcast_arrays(r, c)
            blocks.append(r.shape)
            rows.append(r.ravel())
            cols.append(c.ravel())
            return len(blocks) - 1

        self.body_edofs = [body.element_dofs + system.dofs(body)[0] for body in system.bodies]
        body_blocks = [block(ed[:, :, None], ed[:, None, :]) for ed in self.body_edofs]
        self.mdofs = [m.dofs(system) for m in system.moments]
        moment_blocks = [block(d[:, None], d[None, :]) for d in self.mdofs]
        self.cdofs, self.crows = [], []
        row = n
        jac_blocks, jacT_blocks, hess_blocks = [], [], []
        for c in system.constraints:
            d = np.asarray(c.dofs(system), dtype=np.int64)
            rr = row + np.arange(c.n_eq)
            self.cdofs.append(d)
            self.crows.append(rr)
            jac_blocks.append(block(rr[:, None], d[None, :]))
            jacT_blocks.append(block(d[:, None], rr[None, :]))
            hess_blocks.append(None if c.linear else block(d[:, None], d[None, :]))
            row += c.n_eq
        self.n_c = row - n
        N = row
        diag = np.arange(N)
        block(diag, diag)
        R = np.concatenate(rows)
        C = np.concatenate(cols)
        key = R * N + C
        ukey = np.unique(key)
        self.indptr = np.searchsorted(ukey // N, np.arange(N + 1)).astype(np.int64)
        self.indices = (ukey % N).astype(np.int64)
        self.nnz = len(ukey)
        self.N = N
        pos = np.searchsorted(ukey, key)

        start = np.concatenate([[0], np.cumsum([r.size for r in rows])])

        def index(b):
            return pos[start[b]: start[b + 1]].reshape(blocks[b])

        self.body_scatter = [np.ascontiguousarray(index(b)) for b in body_blocks]
        self.moment_index = [index(b).ravel() for b in moment_blocks]
        self.jac_index = [index(b).ravel() for b in jac_blocks]
        self.jacT_index = [index(b).ravel() for b in jacT_blocks]
        self.hess_index = [None if b is None else index(b).ravel() for b in hess_blocks]
        M = system.mass_matrix().tocoo()
        self.mass_data = np.bincount(np.searchsorted(ukey, M.row * N + M.col), weights=M.data,
                                     minlength=self.nnz)

    def matrix(self, data):
        return sp.csr_matrix((data, self.indices, self.indptr), shape=(self.N, self.N))
