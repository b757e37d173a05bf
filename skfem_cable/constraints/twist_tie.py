"""The twist of a rod's node tied to a rigid body's rotation about the rod's tangent: the
twist part of a clamp to a body point (``clamp``, ``docs/rods.md``)."""

import numpy as np

from ..kernels.rod import through_unit, unit_map

#: The Levi-Civita symbol ``EPS[k, i, m]``: ``(x cross y)_k = EPS[k, i, m] x_i y_m``.
EPS = np.zeros((3, 3, 3))
EPS[0, 1, 2] = EPS[1, 2, 0] = EPS[2, 0, 1] = 1.0
EPS[0, 2, 1] = EPS[2, 1, 0] = EPS[1, 0, 2] = -1.0


def width_axis(t, phi, a, d):
    """The rod's width axis ``d2 = cos(phi) t x e - sin(phi) e`` at a node, ``e = R(a ->
    t) d = d - (d . t) (a + t) / (1 + a . t)`` (the smallest rotation of the reference
    director ``d``, normal to ``a``), with its derivatives in ``(t, phi)``: ``g`` (3,),
    ``g_t`` (3, 3), ``g_phi`` (3,), ``g_tt`` (3, 3, 3), ``g_tphi`` (3, 3)."""
    c = 1.0 + a @ t
    beta = (d @ t) / c
    b1 = d / c - (d @ t) * a / c**2                                   # d beta / dt
    b2 = -(np.outer(d, a) + np.outer(a, d)) / c**2 + 2 * (d @ t) * np.outer(a, a) / c**3
    at = a + t
    e = d - beta * at
    e_t = -np.outer(at, b1) - beta * np.eye(3)                        # [k, i]
    e_tt = (-at[:, None, None] * b2[None] - np.eye(3)[:, None, :] * b1[None, :, None]
            - np.eye(3)[:, :, None] * b1[None, None, :])              # [k, i, j]
    w = np.cross(t, e)
    w_t = np.einsum("kim,m->ki", EPS, e) + np.einsum("klm,l,mi->ki", EPS, t, e_t)
    w_tt = (np.einsum("kim,mj->kij", EPS, e_t) + np.einsum("kjm,mi->kij", EPS, e_t)
            + np.einsum("klm,l,mij->kij", EPS, t, e_tt))
    cs, sn = np.cos(phi), np.sin(phi)
    return (cs * w - sn * e, cs * w_t - sn * e_t, -sn * w - cs * e, cs * w_tt - sn * e_tt,
            -sn * w_t - cs * e_t)


class TwistTie:
    """The twist of a rod's node follows a rigid body: ``C = b(x) . d2 = 0``, with ``b =
    N x`` a director carried by the body (linear in its natural coordinates ``x``, as
    ``BodySlope``'s normals) and ``d2`` the rod's width axis at the node (``width_axis``,
    from the node's reference frame of the run, ``Rod.reference_frames``): the section's
    normal axis ``d1`` stays on ``b``.  One equation, label ``T``; near alignment ``C`` is
    the angle of ``d1`` from ``b`` about the tangent, and ``-lambda`` the torque the body
    applies to the rod's twist (the rod's on the body: ``lambda``).  Its Jacobian and
    Hessian are exact (``width_axis`` and ``kernels.rod.through_unit``).

    Parameters
    ----------
    node : Node
        A rod's node (``Node.has_twist``), clamped to ``body`` (its slope held along a
        body direction, ``BodySlope``).
    body : RigidBody
    director : array_like (3,), optional
        The body-frame direction ``d1`` keeps (default: the node's initial director in
        the body's initial frame).
    """

    linear = False
    n_eq = 1
    #: Not part of a system's description (``fingerprint``): the rod's frames it reads.
    caches = ("frames",)

    def __init__(self, node, body, director=None):
        rod = node.body
        if director is None:
            director = body.rotation(body.q0).T @ rod.directors[node.index]
        origin = body.coefficients(np.zeros(3))
        self.N = np.kron(body.coefficients(np.asarray(director, float)) - origin, np.eye(3))
        self.node, self.body = node, body
        self.frames = None
        self.name = f"twist tie {node!r}-{body.name}"
        self.labels = ["T"]

    def dofs(self, system):
        """``[r_x, phi, x]``; reads the rod's reference frames in ``system``."""
        self.frames = self.node.body.reference_frames(system)
        d = system.dofs(self.node)
        twist = system.dofs(self.node.body)[self.node.twist_dofs]
        return np.concatenate([d[3:6], twist, system.dofs(self.body)])

    def _parts(self, qc, want):
        """The value, gradient (16,) and, if ``want``, Hessian (16, 16)."""
        i = self.node.index
        J, HJ = np.zeros((4, 3)), np.zeros((4, 3))
        A = np.ascontiguousarray(qc[:3])
        s = unit_map(A, J)
        g, g_t, g_phi, g_tt, g_tphi = width_axis(A / s, qc[3], self.frames.t0[i],
                                                 self.frames.d0[i])
        b = self.N @ qc[4:]
        gy, Hy = np.zeros(4), np.zeros((4, 4))
        gy[:3], Hy[:3, :3] = b @ g_t, np.einsum("k,kij->ij", b, g_tt)
        gA, HAA = np.zeros(3), np.zeros((3, 3))
        through_unit(gy, Hy, J, s, 3, gA, HAA, HJ, want)
        grad = np.concatenate([gA, [b @ g_phi], self.N.T @ g])
        if not want:
            return b @ g, grad, None
        H = np.zeros((16, 16))
        H[:3, :3] = HAA
        H[:3, 3] = H[3, :3] = J[:3].T @ (b @ g_tphi)
        H[3, 3] = -b @ g
        H[4:, :3] = self.N.T @ g_t @ J[:3]
        H[4:, 3] = self.N.T @ g_phi
        H[:4, 4:] = H[4:, :4].T
        return b @ g, grad, H

    def value(self, qc, t=0.0):
        return np.array([self._parts(qc, False)[0]])

    def jacobian(self, qc, t=0.0):
        return self._parts(qc, False)[1][None, :]

    def hessian(self, qc, lam, t=0.0):
        return lam[0] * self._parts(qc, True)[2]

    def velocity_term(self, qc, t=0.0):
        return np.zeros(1)

    def accel_term(self, qc, vc, t=0.0):
        return np.array([vc @ self._parts(qc, True)[2] @ vc])
