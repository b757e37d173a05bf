"""Rigid motions, momenta and the centre of mass of a system: what its 3-vectors of
coordinates (``vectors``, positions or directions, from the bodies' ``vector_mask`` and
``position_mask``) give.  ``SystemMotion`` is the part of ``System`` that reads them; it
needs the system's ``vectors``, ``vector_is_position``, ``n_dofs``, ``q0``, ``layout``,
``current_layout``, ``mass_matrix`` and ``deployments``."""

import numpy as np
import scipy.sparse as sp

from ..core.contract import Evaluation
from ..loads.point import vector3 as _vector3


class SystemMotion:
    """Rigid motions and momenta of a system (module docstring)."""

    def rigid_motion_velocity(self, q, omega, center=(0, 0, 0), velocity=(0, 0, 0)):
        """Velocities of a rigid motion of the whole system: ``velocity + omega x (r - center)``
        for position coordinates, ``omega x r_x`` for slopes and other vectors (Eqs. 81-82)
        and zero for scalar coordinates (a reel's length)."""
        omega = _vector3(omega, "omega")
        pos = self.vector_is_position[:, None]
        blocks = np.asarray(q, dtype=float)[self.vectors]
        rel = np.where(pos, blocks - _vector3(center, "center"), blocks)
        v = np.zeros(self.n_dofs)
        v[self.vectors] = np.cross(omega, rel) + np.where(pos, _vector3(velocity, "velocity"), 0)
        return v

    def rotation_operator(self, W):
        """The sparse matrix (n_dofs, n_dofs) applying the 3 x 3 matrix ``W`` to every
        3-vector of coordinates (``vectors``) and zero to scalar ones."""
        rows = np.repeat(self.vectors, 3, axis=1).ravel()
        cols = np.tile(self.vectors, (1, 3)).ravel()
        values = np.tile(np.asarray(W, dtype=float).ravel(), len(self.vectors))
        return sp.csr_matrix((values, (rows, cols)), shape=(self.n_dofs, self.n_dofs))

    def rotate(self, q, R, center=(0, 0, 0)):
        """Coordinates turned rigidly by the rotation matrix ``R`` about ``center``:
        positions ``c + R (r - c)``, slopes and other vectors ``R x``, scalars unchanged."""
        out = np.array(q, dtype=float)
        blocks = out[self.vectors]
        c = np.where(self.vector_is_position[:, None], _vector3(center, "center"), 0.0)
        out[self.vectors] = (blocks - c) @ np.asarray(R, dtype=float).T + c
        return out

    def momentum(self, q, v, t=0.0):
        """Generalized momentum ``dT/dv`` (n_dofs): ``M v`` plus the part of deploying
        cables (``deploy``), whose mass changes with time."""
        p = self.layout.mass @ v
        for deployment in self.deployments.values():
            p += deployment.momentum(self, q, v, t)
        return p

    def energy_parts(self, q, v, t=0.0):
        """The energy (J) of each body at ``(q, v, t)``, keyed by its label
        (``io.labels.body_labels``): ``kinetic``, ``v_b^T M_b v_b / 2`` with its own mass
        matrix, and its stored energy under the names of its ``energy_parts``
        (``contract.Body``), its own term in this system evaluated alone (with the state
        its term holds here: a rod's reference frames of the last run or solve,
        ``docs/rods.md``); ``point masses``: their kinetic energy, when the system has
        any.  The kinetic parts add up to ``v^T M v / 2``, the stored ones to the run's
        books (``axial`` + ``bending``)."""
        from .labels import body_labels

        v = np.zeros(self.n_dofs) if v is None else np.asarray(v, dtype=float)
        q = np.asarray(q, dtype=float)
        own = self.current_layout().own_terms
        out, kinetic = {}, 0.0
        for label, body in zip(body_labels(self), self.bodies):
            d = self.dofs(body)
            parts = {"kinetic": 0.5 * float(v[d] @ (body.mass_matrix() @ v[d]))}
            kinetic += parts["kinetic"]
            if body.energy_parts:
                term, ev = own[id(body)], Evaluation(self, t, q, v, np.zeros(self.n_constraints))
                term.evaluate(ev, _no_tangent(term))
                parts.update(zip(body.energy_parts, map(float, ev.energy)))
            out[label] = parts
        if self.point_masses:
            out["point masses"] = {"kinetic": 0.5 * float(v @ (self.mass_matrix() @ v))
                                   - kinetic}
        return out

    def energy_rate(self, q, t):
        """Explicit time derivative (W) of the stored energy at fixed coordinates: the sum
        of the terms' ``energy_rate`` (``contract.Term``; 0 when no energy depends on
        time)."""
        return self._terms_sum("energy_rate", q, t)

    def energy_change(self, q0, q1, t0, t1):
        """The work (J) done over a step from ``(q0, t0)`` to ``(q1, t1)`` by the change of
        the terms' data in time: the sum of the terms' ``energy_change``
        (``contract.Term``; a law parameter that varies in time)."""
        return self._terms_sum("energy_change", q0, q1, t0, t1)

    def _terms_sum(self, hook, *args):
        """The sum of the terms' ``hook(*args)`` over the terms that have it."""
        lay = self.layout
        return float(sum(getattr(term, hook)(*args)
                         for term, _ in lay.body_terms + lay.load_terms
                         if getattr(term, hook) is not None))

    def centre_of_mass(self, x):
        """The centre of mass of the coordinates ``x`` (n_dofs,) or (..., n_dofs): ``U_i^T
        M x / m`` over the unit translations ``U_i`` (of velocities: its velocity), exact
        for ANCF cables, natural coordinates and point masses, whose positions are linear
        in the coordinates; shape (3,) or (..., 3)."""
        M = self.mass_matrix()
        x = np.asarray(x, dtype=float)
        weighted = (M @ x.reshape(-1, self.n_dofs).T).T[:, self.vectors]
        unit = self.rigid_motion_velocity(self.q0, (0, 0, 0), velocity=(1, 0, 0))
        total = weighted[:, self.vector_is_position].sum(axis=1) / (unit @ (M @ unit))
        return total.reshape(x.shape[:-1] + (3,))

    def linear_momentum(self, q, v, t=0.0):
        """Linear momentum (kg m/s): the sum of the momentum over the position blocks of
        the coordinates (positions are linear in the coordinates, slopes carry none)."""
        p = self.momentum(q, v, t)[self.vectors]
        return p[self.vector_is_position].sum(axis=0)

    def angular_momentum(self, q, v, center=(0, 0, 0), t=0.0):
        """Angular momentum about ``center``: ``sum_A e_A x p_A`` over the 3-vector blocks
        ``e_A`` of the coordinates (positions relative to ``center``) and of the momentum
        ``p = momentum(q, v, t)`` (``sum_AB M_AB e_A x e_B_dot`` for constant masses;
        exact for ANCF cables, natural coordinates and point masses, whose positions are
        linear in the coordinates; scalar coordinates such as a reel's carry none)."""
        blocks = np.asarray(q, dtype=float)[self.vectors]
        rel = np.where(self.vector_is_position[:, None], blocks - np.asarray(center, dtype=float),
                       blocks)
        p = self.momentum(q, v, t)[self.vectors]
        return np.cross(rel, p).sum(axis=0)


def vector_blocks(bodies):
    """The global coordinates of the 3-vectors in space, int (nb, 3), and whether each is a
    position (else a slope or another direction): from the bodies' ``vector_mask``
    (optional in the body contract; all True by default) and ``position_mask``."""
    vector = np.concatenate([getattr(b, "vector_mask", np.ones(b.n_dofs, dtype=bool))
                             for b in bodies])
    position = np.concatenate([b.position_mask for b in bodies])
    index = np.flatnonzero(vector)
    if index.size % 3:
        raise ValueError("the bodies' vector coordinates (vector_mask) must come in 3-vectors")
    blocks = index.reshape(-1, 3)
    return blocks, position[blocks[:, 0]]


def _no_tangent(term):
    """An index of the shape of ``term``'s tangent entries (``rows``, ``cols``) for an
    evaluation without tangent, which reads none of it (compiled kernels are typed by its
    shape)."""
    if not term.has_tangent:
        return None
    return np.zeros(np.broadcast_shapes(np.shape(term.rows), np.shape(term.cols)), np.int64)
