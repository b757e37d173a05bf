"""Compiled hooks of loads whose values change with time only: a point force
(``loads.PointLoad`` with a function of time, an ``Input``) and a reel's drive torque
(``reel.Reel``), so that a run whose inputs a controller sets (``control``) stays on the
compiled Newton step.  Their time-dependent values are refreshed once per step by the
term's ``prepare`` (``contract.Term``)."""

from numba import njit


@njit(cache=True)
def point_force(pack, index, ev):
    """``f_ext[dofs] += G^T force`` with ``pack = (dofs (nd,), G (3, nd), force (3,))``:
    a force at a point whose position is ``G q[dofs]``; no tangent."""
    dofs, G, force = pack
    f_ext = ev[4]
    for j in range(dofs.size):
        acc = 0.0
        for i in range(3):
            acc += G[i, j] * force[i]
        f_ext[dofs[j]] += acc


@njit(cache=True)
def reel_torque(pack, index, ev):
    """The drive of a reel of free length ``l = q[dof]``: the generalized force ``tau /
    R`` with ``tau = c0 + c1 l + c2 l'`` and its tangent ``-(cK c1 + cC c2) / R`` at
    ``index`` (1, 1); ``pack = (dof (1,), c (3,), inverse radius (1,))``."""
    dof, c, inverse = pack
    q, v, s, f, f_ext, fd, data, energy, power = ev
    i = dof[0]
    f_ext[i] += (c[0] + c[1] * q[i] + c[2] * v[i]) * inverse[0]
    if data.size > 0:
        data[index[0, 0]] -= (s[1] * c[1] + s[2] * c[2]) * inverse[0]
