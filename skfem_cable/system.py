"""A multibody system: bodies stacked into one coordinate vector (Eq. 4), constraints with
Lagrange multipliers, point masses and loads; residual and KKT matrix on a fixed pattern.

The KKT (iteration) matrix of the unknowns ``(q, lambda')`` is

    [[cM M + cC D + cK (K + H(lambda) - dF_ext/dq),  s C_q^T],
     [s C_q,                                          0      ]]

with ``K`` and ``D`` the stiffness and damping tangents of the bodies (Eqs. 13-15), ``H`` the
constraint Hessian term of Eq. 15 and ``s`` a constraint scaling (``lambda = s lambda'``)
chosen by the solvers for conditioning.  The constant part (mass and linear constraint
Jacobians) is precomputed as CSR data vectors (``Layout.mass_data``, ``Layout.linear_data``).
"""

import numpy as np
import scipy.sparse as sp

from . import constraints as cons
from .cable import Cable, Node, kernel_forces
from .linalg import FastCSR
from .loads import Centrifugal, PointMoment, TimeLoad, _vector3
from .section import check_positive


class System:
    """Bodies, constraints, point masses and loads.

    Parameters
    ----------
    bodies : sequence of bodies (``Cable``)
    """

    def __init__(self, bodies):
        self.bodies = list(bodies)
        if not self.bodies:
            raise ValueError("bodies must contain at least one body")
        self.offsets = {}
        n = 0
        for body in self.bodies:
            if id(body) in self.offsets:
                raise ValueError(f"body {body.name!r} appears twice in bodies")
            self.offsets[id(body)] = n
            n += body.n_dofs
        self.n_dofs = n
        self.constraints = [c for body in self.bodies
                            for c in getattr(body, "internal_constraints", list)()]
        self.loads = []
        self.point_masses = []
        self.gravity = np.zeros(3)
        self._f_fixed = np.zeros(n)
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

    def _changed(self):
        self._layout = None
        return self

    def add_constraint(self, constraint):
        self.constraints.append(constraint)
        return self._changed()

    def clamp(self, node, direction=None):
        """Clamp a node: position and slope direction fixed. Returns the system."""
        return self.add_constraint(cons.clamp(node, direction))

    def pin(self, node, target=None):
        """Spherical joint of a node to ground (``target`` None or a point) or to another
        node/body point. Returns the system."""
        return self.add_constraint(cons.pin(node, target))

    def add_point_load(self, node, force):
        """Force (N) at a cable node or a rigid-body point (``RigidBody.point``): a 3-vector,
        or a callable ``force(t)`` returning one (a time-dependent load, whose work is
        booked as external work)."""
        if callable(force):
            return self.add_load(TimeLoad(node, force))
        dofs, G = self.position_map(node)
        self._f_fixed[dofs] += G.T @ _vector3(force, "force")
        return self._changed()

    def add_load(self, load):
        """A configuration- or time-dependent load (see ``loads``); its work is booked as
        external work."""
        self.loads.append(load)
        return self._changed()

    def add_point_moment(self, node, moment):
        """Moment (N m, fixed in space) at a cable node; see ``loads.PointMoment``."""
        return self.add_load(PointMoment(node, moment))

    def add_centrifugal(self, omega):
        """Centrifugal forces of a frame rotating at ``omega`` (rad/s): for steady spinning
        states (``solve_static``) and their modes (``modes(..., spin=omega)``)."""
        return self.add_load(Centrifugal(omega))

    def add_gravity(self, g):
        """Uniform gravity (m/s^2) on every body and point mass (consistent nodal forces)."""
        self.gravity = self.gravity + _vector3(g, "g")
        return self._changed()

    def add_line_load(self, cable, force_per_length):
        """Uniform distributed load (N/m, fixed in space) along a cable."""
        self._f_fixed[self.dofs(cable)] += cable.line_load(force_per_length)
        return self._changed()

    def add_point_mass(self, node, mass):
        """Point mass (kg) at a node's position (e.g. a remote unit or a tip mass), or at a
        body point (anything with ``body`` and ``position_matrix``)."""
        dofs, G = self.position_map(node)
        self.point_masses.append((dofs, G, check_positive("mass", mass)))
        return self._changed()

    def position_map(self, point):
        """``(dofs, G)`` with ``position = G @ q[dofs]`` for a cable ``Node`` or a body
        point."""
        if isinstance(point, Node):
            return self.dofs(point)[:3], np.eye(3)
        return self.dofs(point.body), point.position_matrix

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

    @property
    def f_const(self):
        """Constant generalized external force: fixed loads plus gravity."""
        return self.layout.f_const

    def mass_matrix(self):
        """Global constant mass matrix (Eq. 11) including point masses."""
        M = sp.block_diag([b.mass_matrix() for b in self.bodies], format="csr")
        for dofs, G, m in self.point_masses:
            rows, cols = np.meshgrid(dofs, dofs, indexing="ij")
            M = M + sp.csr_matrix((m * (G.T @ G).ravel(), (rows.ravel(), cols.ravel())),
                                  shape=M.shape)
        return M.tocsr()

    def cables(self):
        return [b for b in self.bodies if isinstance(b, Cable)]

    def describe_dof(self, index):
        """Human-readable owner of a global unknown (body and node, or constraint)."""
        if index < self.n_dofs:
            for body in self.bodies:
                off = self._offset(body)
                if off <= index < off + body.n_dofs:
                    local = index - off
                    return f"{body.name} coordinate {local} ({body.describe_dof(local)})"
        k = index - self.n_dofs
        for c in self.constraints:
            if k < c.n_eq:
                return f"constraint {c.name} equation {c.labels[k]}"
            k -= c.n_eq
        return f"unknown {index}"

    def rigid_motion_velocity(self, q, omega, center=(0, 0, 0), velocity=(0, 0, 0)):
        """Velocities of a rigid motion of the whole system: ``velocity + omega x (r - center)``
        for position coordinates and ``omega x r_x`` for slopes (Eqs. 81-82)."""
        omega = _vector3(omega, "omega")
        blocks = np.asarray(q, dtype=float).reshape(-1, 3)
        is_position = np.concatenate([b.position_mask for b in self.bodies]).reshape(-1, 3)[:, 0]
        rel = np.where(is_position[:, None], blocks - _vector3(center, "center"), blocks)
        v = np.cross(omega, rel) + np.where(is_position[:, None], _vector3(velocity, "velocity"), 0)
        return v.ravel()

    def angular_momentum(self, q, v, center=(0, 0, 0)):
        """Angular momentum about ``center``: ``sum_AB M_AB e_A x e_B_dot`` over the 3-vector
        blocks of the coordinates (exact for ANCF cables, natural coordinates and point
        masses, whose positions are linear in the coordinates)."""
        is_position = np.concatenate([b.position_mask for b in self.bodies]).reshape(-1, 3)[:, 0]
        blocks = np.asarray(q, dtype=float).reshape(-1, 3)
        rel = np.where(is_position[:, None], blocks - np.asarray(center, dtype=float), blocks)
        p = (self.layout.mass @ v).reshape(-1, 3)
        return np.cross(rel, p).sum(axis=0)

    # --- evaluation -------------------------------------------------------------------------
    def constraint_values(self, q):
        r = np.zeros(self.layout.n_c)
        self._constraints(q, np.zeros(self.layout.n_c), np.zeros(self.n_dofs), r, 1.0)
        return r

    def constraint_accel_term(self, q, v):
        """``(C_q v)_q v`` of Eq. 2 for every constraint (zero for linear ones)."""
        out = np.zeros(self.layout.n_c)
        for k in self.layout.nonlinear:
            d = self.layout.cdofs[k]
            out[self.layout.crows[k]] = self.constraints[k].accel_term(q[d], v[d])
        return out

    def _constraints(self, q, lam, f_con, r_c, scale, data=None, cK=1.0):
        lay = self.layout
        if lay.C_lin is not None:
            r_c[lay.lin_rows] = scale * (lay.C_lin @ q - lay.c_lin)
            f_con += lay.C_lin_T @ lam[lay.lin_rows]
        for k in lay.nonlinear:
            c, d, rows = self.constraints[k], lay.cdofs[k], lay.crows[k]
            qc = q[d]
            Jc = c.jacobian(qc)
            f_con[d] += Jc.T @ lam[rows]
            r_c[rows] = scale * c.value(qc)
            if data is not None:
                data[lay.jac_index[k]] += scale * Jc.ravel()
                data[lay.jacT_index[k]] += scale * Jc.T.ravel()
                data[lay.hess_index[k]] += cK * c.hessian(qc, lam[rows]).ravel()

    def evaluate(self, q, v, t, lam, load_factor=1.0, cK=1.0, cC=0.0, scale=1.0, data=None,
                 reference_force=False):
        """Residual of the equations of motion without inertia, and tangents.

        ``r = [f_int(q, v) - load_factor f_ext(q, t) + C_q^T lambda, scale C(q)]`` with
        ``lambda = lam`` the true multipliers.  If ``data`` (CSR values of the KKT pattern,
        holding the caller's constant part ``Layout.mass_data``/``Layout.linear_data``) is
        given, ``cK`` times the stiffness and ``cC`` times the damping tangent are added.

        Returns
        -------
        r : ndarray (n_dofs + n_constraints,)
        info : dict
            ``energy`` (axial, bending), ``power`` (dissipated, axial and bending),
            ``f_damping`` (damping force, or None), ``f_nc`` (non-conservative external
            force: time-dependent loads and moments) and, with ``reference_force``,
            ``force_ref`` (largest norm of the internal, external and constraint forces: a
            scale for convergence tests).
        """
        lay = self.layout
        n = self.n_dofs
        f_int = np.zeros(n)
        f_damp = np.zeros(n) if (v is not None and lay.damped) else None
        energy = np.zeros(2)
        power = np.zeros(2)
        want = data is not None
        for group in lay.cable_groups:
            group.forces(q, v, f_int, data if want else None, cK, cC, energy, power, f_damp)
        for body, edofs, scatter in lay.other_forces:
            body.forces(q, v, f_int, data, scatter if want else None, cK, cC, energy, power,
                        edofs, f_damp)
        f_nc = np.zeros(n)
        for load, index in zip(self.loads, lay.load_index):
            load.apply(q, t, f_nc, data, index, -cK * load_factor)
        f_ext = load_factor * (lay.f_const + f_nc)
        f_con = np.zeros(n)
        r = np.empty(n + lay.n_c)
        self._constraints(q, lam, f_con, r[n:], scale, data, cK)
        r[:n] = f_int - f_ext + f_con
        info = {"energy": energy, "power": power, "f_damping": f_damp,
                "f_nc": load_factor * f_nc}
        if reference_force:
            info["force_ref"] = max(np.linalg.norm(f_int), np.linalg.norm(f_ext),
                                    np.linalg.norm(f_con))
        return r, info


class Layout:
    """Fixed KKT sparsity pattern of a system, the scatter maps into its CSR data, and the
    constant parts (mass, linear constraints, constant loads)."""

    def __init__(self, system):
        n = system.n_dofs
        rows, cols, shapes = [], [], []

        def block(r, c):
            r, c = np.broadcast_arrays(r, c)
            shapes.append(r.shape)
            rows.append(r.ravel())
            cols.append(c.ravel())
            return len(shapes) - 1

        self.body_edofs = [body.element_dofs + system.dofs(body)[0] for body in system.bodies]
        body_blocks = [block(ed[:, :, None], ed[:, None, :]) for ed in self.body_edofs]
        load_blocks = []
        for load in system.loads:
            rc = load.bind(system)
            load_blocks.append(None if rc is None else block(*rc))
        self.cdofs, self.crows = [], []
        row = 0
        jac_blocks, jacT_blocks, hess_blocks = [], [], []
        for c in system.constraints:
            d = np.asarray(c.dofs(system), dtype=np.int64)
            rr = row + np.arange(c.n_eq)
            self.cdofs.append(d)
            self.crows.append(rr)
            jac_blocks.append(block(n + rr[:, None], d[None, :]))
            jacT_blocks.append(block(d[:, None], n + rr[None, :]))
            hess_blocks.append(None if c.linear else block(d[:, None], d[None, :]))
            row += c.n_eq
        self.n_c = row
        N = n + row
        block(np.arange(N), np.arange(N))
        R = np.concatenate(rows).astype(np.int64)
        C = np.concatenate(cols).astype(np.int64)
        key = R * N + C
        ukey = np.unique(key)
        self.indptr = np.searchsorted(ukey // N, np.arange(N + 1)).astype(np.int64)
        self.indices = (ukey % N).astype(np.int64)
        self.nnz = len(ukey)
        self.N = N
        pos = np.searchsorted(ukey, key)
        start = np.concatenate([[0], np.cumsum([r.size for r in rows])])
        self.diagonal_index = np.searchsorted(ukey, np.arange(N) * (N + 1))

        def index(b):
            return pos[start[b]: start[b + 1]].reshape(shapes[b])

        body_scatter = [np.ascontiguousarray(index(b)) for b in body_blocks]
        self.cable_groups = CableGroup.collect(system.bodies, self.body_edofs, body_scatter)
        # bodies with forces of their own (e.g. user-defined element types)
        self.other_forces = [(b, ed, sc) for b, ed, sc in zip(system.bodies, self.body_edofs,
                                                              body_scatter)
                             if hasattr(b, "forces") and type(b) is not Cable]
        self.load_index = [None if b is None else index(b) for b in load_blocks]
        self.jac_index = [index(b).ravel() for b in jac_blocks]
        self.jacT_index = [index(b).ravel() for b in jacT_blocks]
        self.hess_index = [None if b is None else index(b).ravel() for b in hess_blocks]
        M = system.mass_matrix().tocoo()
        self.mass = FastCSR(M)
        mass_keys = M.row.astype(np.int64) * N + M.col
        self.mass_data = np.bincount(np.searchsorted(ukey, mass_keys), weights=M.data,
                                     minlength=self.nnz)
        self.mass_diagonal = M.diagonal()
        # linear constraints: one sparse matrix and their constant KKT entries
        linear = [k for k, c in enumerate(system.constraints) if c.linear]
        self.nonlinear = [k for k, c in enumerate(system.constraints) if not c.linear]
        self.linear_data = np.zeros(self.nnz)
        self.C_lin, self.lin_rows = None, np.zeros(0, dtype=np.int64)
        if linear:
            q0 = system.q0
            Jr, Jc, Jv, c_lin = [], [], [], []
            for k in linear:
                c, d = system.constraints[k], self.cdofs[k]
                J = c.jacobian(q0[d])
                Jr.append(np.repeat(self.crows[k], J.shape[1]))
                Jc.append(np.tile(d, J.shape[0]))
                Jv.append(J.ravel())
                c_lin.append(J @ q0[d] - c.value(q0[d]))
                self.linear_data[self.jac_index[k]] += J.ravel()
                self.linear_data[self.jacT_index[k]] += J.T.ravel()
            self.lin_rows = np.concatenate([self.crows[k] for k in linear])
            local = np.empty(row, dtype=np.int64)
            local[self.lin_rows] = np.arange(len(self.lin_rows))
            C_lin = sp.csr_matrix((np.concatenate(Jv), (local[np.concatenate(Jr)],
                                   np.concatenate(Jc))), shape=(len(self.lin_rows), n))
            self.C_lin = FastCSR(C_lin)
            self.c_lin = np.concatenate(c_lin)
            self.C_lin_T = FastCSR(C_lin.T)
        self.damped = any(getattr(b, "damped", False) for b in system.bodies)
        # constant generalized forces: fixed loads, gravity on bodies and point masses
        f = system._f_fixed.copy()
        if np.any(system.gravity):
            for body in system.bodies:
                f[system.dofs(body)] += body.gravity_load(system.gravity)
            for dofs, G, m in system.point_masses:
                f[dofs] += m * G.T @ system.gravity
        self.f_const = f
        # coordinate scales for convergence tests: system size for positions, 1 for slopes
        is_position = np.concatenate([b.position_mask for b in system.bodies])
        q0 = system.q0
        extent = np.ptp(q0[is_position].reshape(-1, 3), axis=0).max() if is_position.any() else 1
        self.length_scale = float(max(extent, 1e-300))
        self.coordinate_scale = np.where(is_position, self.length_scale, 1.0)

    def matrix(self, data):
        return sp.csr_matrix((data, self.indices, self.indptr), shape=(self.N, self.N))


class CableGroup:
    """Cables (exactly ``Cable``, not subclasses) with the same section, kind and quadrature,
    evaluated by one kernel call over the concatenation of their elements (an E-sail's
    tethers are one group)."""

    def __init__(self, cables, edofs, scatter):
        first = cables[0]
        self.section, self.EI = first.section, first.EI_active
        self.edofs = np.ascontiguousarray(np.concatenate(edofs))
        self.scatter = np.ascontiguousarray(np.concatenate(scatter))
        for name in ("Sx", "Sxx", "weights", "h"):
            setattr(self, name, np.ascontiguousarray(np.concatenate(
                [getattr(c, name) for c in cables])))

    @classmethod
    def collect(cls, bodies, edofs, scatter):
        groups = {}
        for body, ed, sc in zip(bodies, edofs, scatter):
            if type(body) is Cable:  # subclasses may override forces: called one by one
                key = (body.section, body.EI_active, body.Sx.shape[1])
                groups.setdefault(key, []).append((body, ed, sc))
        return [cls(*zip(*members)) for members in groups.values()]

    def forces(self, q, v, f, data, cK, cC, energy, power, f_damping):
        """As ``Cable.forces`` for all cables of the group (global vectors)."""
        kernel_forces(self, self.section, self.EI, self.edofs, self.scatter, q, v, f, data, cK,
                      cC, energy, power, f_damping)
