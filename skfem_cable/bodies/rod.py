"""The rod: a Kirchhoff rod whose centreline is the ANCF cable's and whose cross-section
turns by a twist angle measured from nodal reference frames transported in time
(``docs/rods.md``).

Examples
--------
>>> import skfem_cable as sc
>>> tape = sc.Section.tape(0.02, 50e-6, E=7e10, rho=2700.0)
>>> rod = sc.Rod.straight([0, 0, 0], [1, 0, 0], 4, tape, normal=[0, 0, 1])
>>> rod.n_dofs, rod.node(-1).twist_dofs.tolist()
(40, [38])
"""

import numpy as np
import scipy.sparse as sp
from skfem.quadrature import get_quadrature

from ..core.contract import Term
from ..kernels import rod as kernel
from ..kernels.rod import smallest_rotation
from .cable import Cable
from .rod_frames import ReferenceFrames

#: Gauss order of the rod's own term (3 points): ``GJ phi'^2`` of the cubic twist exactly.
RULE = 5


class Rod(Cable):
    """A rod with torsion and two principal bending stiffnesses (``docs/rods.md``).

    Its coordinates are the cable's (``[r, r_x]`` per node, cubic Hermite) followed by
    the twist ``[phi, phi_x]`` per node (cubic Hermite too): ``phi`` is the angle of the
    section's ``normal`` axis (the director ``d1``) from the node's reference director,
    about the tangent.  Its energy is the cable's law with ``EI = EI_flat`` plus ``GJ
    kappa3^2 / 2 + (EI_edge - EI_flat) kappa1^2 / 2`` (``kernels.rod``); its mass the
    cable's plus ``rho I_p`` on the twist.  Every line load reaches its centreline
    unchanged (``line_points``, the cable's).

    Parameters
    ----------
    mesh, section, positions, slopes, **options
        As for ``Cable`` (the element must be the cubic ``"hermite3"``); ``section``
        gives ``GJ``, ``EI_flat``, ``EI_edge`` and ``polar_mass_moment``
        (``Section.tape``, ``Section.circular``).
    normal : array_like (3,) or (n_nodes, 3), optional
        The direction of the section's normal axis (a tape's thickness direction) at the
        nodes, made normal to the slopes; default a direction normal to the first slope.
    twist : array_like (n_nodes,), optional
        Initial twist angles (rad) from ``normal``; default zero.

    Attributes
    ----------
    n_centreline : int
        The number of centreline coordinates (``6 n_nodes``), which come first.
    directors : ndarray (n_nodes, 3)
        The initial unit directors (``normal`` made normal to the slopes).
    twist_element_dofs : int ndarray (n_elements, 4)
        Local twist coordinates of each element, in the order of its functions.
    """

    #: ``Body.energy_parts``: the cable's stretching; bending and twist together.
    energy_parts = ("axial", "bending and twist")
    #: Not part of a system's description (``fingerprint``): the frames of its bindings.
    caches = ("_frames",)

    def __init__(self, mesh, section, positions, slopes=None, normal=None, twist=None,
                 name="rod", **options):
        super().__init__(mesh, section, positions, slopes, name=name, **options)
        if self.element.orders != (0, 1):
            raise ValueError(f"element must be 'hermite3' for a rod (positions and slopes "
                             f"at the nodes), got {self.element.name!r}")
        n = self.n_nodes
        self.n_centreline = self.q0.size
        self.directors = _directors(normal, self.q0.reshape(n, 6)[:, 3:])
        phi = np.zeros(n) if twist is None else np.asarray(twist, float)
        if phi.shape != (n,) or not np.all(np.isfinite(phi)):
            raise ValueError(f"twist must be a finite array of shape ({n},), got {phi.shape}")
        self.q0 = np.concatenate([self.q0, np.stack([phi, np.zeros(n)], axis=1).ravel()])
        first = self.element_dofs[:, 0::3]
        node, order = first // 6, first % 6 // 3
        self.twist_element_dofs = self.n_centreline + 2 * node + order
        self._twist_mass = None
        self._frames = {}

    # --- layout -------------------------------------------------------------------------
    def twist_dofs(self, index):
        """Local coordinate (1,) of the twist angle of node ``index`` (``Node.twist_dofs``)."""
        return np.array([self.n_centreline + 2 * index])

    @property
    def position_mask(self):
        """True for position coordinates (not slopes, not twists)."""
        return np.concatenate([super().position_mask, np.zeros(2 * self.n_nodes, bool)])

    @property
    def vector_mask(self):
        """True for the centreline's 3-vectors, False for the twist coordinates."""
        return np.arange(self.n_dofs) < self.n_centreline

    def describe_dof(self, index):
        """Which node and field a local coordinate is, e.g. ``node 3 phi_x``."""
        if index < self.n_centreline:
            return super().describe_dof(index)
        node, k = divmod(int(index) - self.n_centreline, 2)
        return f"node {node} {('phi', 'phi_x')[k]}"

    def mass_matrix(self):
        """The cable's mass and ``rho I_p int S_A S_B ds`` on the twist (constant: the
        spin of the reference frames about the tangent is left out, ``docs/rods.md``)."""
        if self._twist_mass is None or self._twist_mass[0] is not self.section:
            X, W = get_quadrature(self.mesh.refdom, 6)
            S = self._shape(X[0])[0]
            M = np.einsum("q,e,eqA,eqB->eAB", W, self.h * self.section.polar_mass_moment,
                          S, S)
            d = self.twist_element_dofs - self.n_centreline
            rows = np.broadcast_to(d[:, :, None], M.shape).ravel()
            cols = np.broadcast_to(d[:, None, :], M.shape).ravel()
            size = 2 * self.n_nodes
            self._twist_mass = (self.section, sp.csr_matrix((M.ravel(), (rows, cols)),
                                                            shape=(size, size)))
        return sp.block_diag([super().mass_matrix(), self._twist_mass[1]], format="csr")

    # --- reference frames ---------------------------------------------------------------
    def initial_frames(self):
        """The nodal reference frames at ``q0``: unit slopes and ``directors``, copies."""
        slopes = self.q0[:self.n_centreline].reshape(-1, 6)[:, 3:]
        return slopes / np.linalg.norm(slopes, axis=1)[:, None], self.directors.copy()

    def frames_at(self, q):
        """The initial frames carried to the slopes of ``q`` (this rod's coordinates) by
        the smallest rotation: the reference of a static state (a run's own frames are
        transported step by step, ``rod_frames``)."""
        t0, d0 = self.initial_frames()
        slopes = np.ascontiguousarray(np.arange(self.n_centreline).reshape(-1, 6)[:, 3:])
        kernel.rebase(np.ascontiguousarray(q, dtype=float), slopes, t0, d0)
        return t0, d0

    def rigid_velocity(self, omega, center, q=None):
        """The velocities (this rod's coordinates) of the rod at ``q`` (default ``q0``)
        turning rigidly at ``omega`` (rad/s) about ``center``: ``omega x (r - center)`` on
        the positions, ``omega x r'`` on the slopes and the spin ``omega . t`` on the nodes'
        twist angles (their rates zero: exact for a straight rod, whose reference frames
        turn with it)."""
        q = self.q0 if q is None else np.asarray(q, float)
        omega, center = np.asarray(omega, float), np.asarray(center, float)
        vectors = q[:self.n_centreline].reshape(-1, 2, 3)
        v = np.zeros(self.n_dofs)
        v[:self.n_centreline] = np.cross(omega, vectors - [center, np.zeros(3)]).ravel()
        slopes = vectors[:, 1]
        v[self.n_centreline::2] = slopes @ omega / np.linalg.norm(slopes, axis=1)
        return v

    # --- internal forces -----------------------------------------------------------------
    def bind(self, system):
        """The cable's term (``Cable.bind``: axial and isotropic bending ``EI_flat``) with
        the rod's kernel (``kernels.rod``) in one term on the element blocks of the
        centreline and twist coordinates, and the reference frames as its step hook."""
        if system.deployment(self) is not None:
            raise ValueError(f"rod {self.name!r}: a rod does not deploy (System.deploy "
                             "takes cables)")
        cable = super().bind(system)
        offset = system.dofs(self)[0]
        edofs = np.concatenate([self.global_element_dofs(system),
                                self.twist_element_dofs + offset], axis=1)
        frames = ReferenceFrames(self, offset + np.arange(self.n_centreline).reshape(-1, 6)[:, 3:])
        self._frames[id(system)] = frames
        pack = self.kernel_pack(edofs, frames.t0, frames.d0)
        return Term(kernels=(*cable.kernels, (kernel.kernel, pack)), rows=edofs[:, :, None],
                    cols=edofs[:, None, :], name=self.name, prepare=cable.prepare,
                    energy_change=cable.energy_change, hooks=(frames,),
                    writes=cable.writes)  # the twist kernel writes f alone

    def reference_frames(self, system):
        """The nodal reference frames of this rod's term in ``system`` (its last binding
        there, ``bind``): what a constraint on its twist reads (``TwistTie``)."""
        if id(system) not in self._frames:
            raise ValueError(f"rod {self.name!r} is not bound in this system (bind it "
                             "first: a constraint on its twist reads its frames)")
        return self._frames[id(system)]

    def kernel_pack(self, edofs, t0, d0):
        """The pack of ``kernels.rod.kernel`` for the element coordinates ``edofs`` and
        the frames ``t0``, ``d0`` (see its module), on the 3-point Gauss rule
        (``RULE``: exact for ``GJ phi'^2`` of the cubic twist, as the cable's bending)."""
        X, W = get_quadrature(self.mesh.refdom, RULE)
        S, Sx, Sxx = self._shape(X[0])
        _, Sx1, _ = self._shape([1.0])
        nodes = np.stack([self.mesh.t[0], self.mesh.t[1]], axis=1).astype(np.int64)
        section = self.section
        prm = np.array([section.GJ, section.EI_edge - section.EI_flat])
        return (np.ascontiguousarray(edofs, dtype=np.int64), S, Sx, Sxx,
                np.ascontiguousarray(W[None, :] * self.h[:, None]), np.ascontiguousarray(X[0]),
                np.ascontiguousarray(self.h), np.ascontiguousarray(Sx1[:, 0, :]), nodes, t0,
                d0, prm)

    # --- fields ---------------------------------------------------------------------------
    def _section_state(self, q, s, frames=None):
        """At each arc length ``s``: the material angle, its rate, the reference twist
        rate and the material frame (rows ``d1, d2, t``); ``frames`` the nodal reference
        (default ``frames_at(q)``)."""
        q = np.asarray(q, float)
        t0, d0 = self.frames_at(q) if frames is None else frames
        e, xi = self.locate(np.atleast_1d(s))
        out = []
        for k, x in zip(e, xi):
            S, Sx, Sxx = (f[:, 0] for f in self.element.shape(np.array([x]), self.h[k]))
            u = q[np.concatenate([self.element_dofs[k], self.twist_element_dofs[k]])]
            alpha = self._mismatch(u, k, t0, d0)
            vectors = u[:12].reshape(4, 3)
            A, B = Sx @ vectors, Sxx @ vectors
            i = self.mesh.t[0, k]
            t = A / np.linalg.norm(A)
            theta = S @ u[12:] + x * alpha
            rate = Sx @ u[12:] + alpha / self.h[k]
            ref = -np.cross(t0[i], t) @ B / (np.linalg.norm(A) * (1 + t0[i] @ t))
            d = smallest_rotation(t0[i], t, d0[i])
            d1 = np.cos(theta) * d + np.sin(theta) * np.cross(t, d)
            out.append((theta, rate, ref, np.array([d1, np.cross(t, d1), t])))
        return out

    def _mismatch(self, u, k, t0, d0):
        """The mismatch angle of element ``k`` with coordinates ``u`` (``kernels.rod``)."""
        i, j = self.mesh.t[:, k]
        _, Sx1, _ = self._shape([1.0])
        return kernel.element_mismatch(u, Sx1[k, 0], t0[i], d0[i], t0[j], d0[j],
                                       np.zeros(12), kernel.workspace(), False)

    def twist(self, q, s, frames=None):
        """The twist angle (rad) of the section at arc lengths ``s``: the angle of its
        normal axis from the reference director, about the tangent."""
        return _shaped(s, [x[0] for x in self._section_state(q, s, frames)])

    def torque(self, q, s, frames=None):
        """The twisting moment ``GJ kappa3`` (N m) at arc lengths ``s``."""
        return _shaped(s, [self.section.GJ * (x[1] + x[2])
                           for x in self._section_state(q, s, frames)])

    def frame(self, q, s, frames=None):
        """The material frame at arc lengths ``s``: rows ``d1`` (the section's normal
        axis), ``d2`` (its width axis) and the unit tangent, shape ``s.shape + (3, 3)``."""
        return np.reshape([x[3] for x in self._section_state(q, s, frames)],
                          np.shape(s) + (3, 3))

    # --- output ---------------------------------------------------------------------------
    @property
    def width(self):
        """The width (m) of the rectangle with the section's area and principal moments,
        ``sqrt(A sqrt(I_edge / I))``: a tape's own width (``sqrt(A)`` for a round wire);
        the ribbon's width in ParaView (``io.export.ribbon``)."""
        section = self.section
        return float(np.sqrt(section.A * np.sqrt(section.EI_edge / section.EI_flat)))

    def show(self, system, q, v, t, points_per_element=8, **detail):
        """``Body.show``: the cable's line (``CableFields.show``) with the material frame
        (``frame``, the reference of ``frames_at``) as point data ``director`` (``d1``,
        the section's normal axis), ``width_direction`` (``d2``) and ``width``, from
        which ``io.export`` draws the ribbon."""
        shape = super().show(system, q, v, t, points_per_element, **detail)
        frame = self.frame(q[system.dofs(self)], shape.data["arc_length"])
        shape.data.update(director=frame[:, 0], width_direction=frame[:, 1],
                          width=np.full(len(frame), self.width))
        return shape


def _shaped(s, values):
    """``values`` (one per arc length) in the shape of ``s``."""
    return np.reshape(values, np.shape(s))


def _directors(normal, slopes):
    """Unit directors at the nodes: ``normal`` (one or one per node; default a direction
    normal to the first slope) made normal to the ``slopes``."""
    t = slopes / np.linalg.norm(slopes, axis=1)[:, None]
    if normal is None:
        k = np.argmin(np.abs(t[0]))
        normal = np.cross(t[0], np.eye(3)[k])
    n = np.broadcast_to(np.asarray(normal, float), t.shape)
    d = n - np.einsum("ij,ij->i", n, t)[:, None] * t
    size = np.linalg.norm(d, axis=1)
    if not np.all(np.isfinite(size)) or np.any(size < 1e-8 * np.linalg.norm(n, axis=1)):
        raise ValueError("normal must be a finite direction not along the rod's slopes, "
                         f"got {normal!r}")
    return d / size[:, None]
