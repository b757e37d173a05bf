"""The point function of line-to-surface contact (``loads.contact``) for the one loop of
the line loads (``kernels.line.module``), and the surfaces it knows.

A surface is the array ``surface = [kind, o (3), d (3), R]`` (8 floats): a plane
through ``o`` of unit normal ``d`` (``PLANE``), a sphere of centre ``o`` and radius ``R``
(``SPHERE``), the outside of a cylinder of axis ``o + s d`` (``d`` unit) and radius ``R``
(``CYLINDER``).  ``distance`` gives the signed distance ``s(x)`` of a point from it, the
unit normal ``n = ds/dx`` and its derivative ``H = dn/dx`` (symmetric):

* plane: ``s = n . (x - o)``, ``H = 0``;
* sphere, cylinder: ``y = P (x - o)`` (``P = I``, or ``I - d d^T`` for the cylinder),
  ``s = |y| - R``, ``n = y / |y|``, ``H = (P - n n^T) / |y|``;
* edge (``EDGE``, a table top ending in a rounded edge): ``surface = [kind, o, d, R, e,
  c, a]`` (17 floats), the top through ``o`` of unit normal ``d``, ending along the line
  through ``o`` of direction ``a = d x e`` (``e`` unit, in the top, pointing off the
  table), rounded by the cylinder of axis ``c + s a``, ``c = o - R d``: the plane's
  distance where ``e . (x - c) <= 0``, the cylinder's beyond.  Both give ``s = 0`` and
  the normal ``d`` on the line where they meet (the force is continuous, ``H`` jumps from
  0 to the cylinder's curvature, as where any rope leaves a flat onto a drum).  It is the
  distance of the solid above the cylinder's axis and outside the cylinder (what a rope
  lying on the table and hanging over the edge meets); below the axis, the table's
  front face under the edge is not modelled.

At a point ``x`` of a line of cross-section radius ``r_c`` moving at ``xd`` the gap is
``g = s(x) - r_c``.  Where ``g < 0`` (penetration ``p = -g``) the force per unit reference
length on the line is

    f = N_e n + N_d n + f_t,   N_d = -c v_n r(p),   v_n = n . xd,

with the penalty ``N_e = k (p - p_0 / 2)`` beyond the onset ``p_0`` and
``N_e = k p^2 / (2 p_0)`` within it (force and tangent continuous at first touch: Newton
does not cycle on the points where a line leaves a surface tangentially), the damping
ramped in by ``r = 1 - (1 - p / p_0)^2`` within the onset and 1 beyond (its force
continuous at first touch, its tangent continuous at ``p_0``; the damping ratio of the
default ``c = 2 sqrt(k m)`` is ``2 sqrt(p / p_0) - (p / p_0)^1.5`` there, below 1: a
contact that works deep in its onset is under-damped, ``loads.surface_broad_phase``),
and Coulomb's friction on
the penalty's normal force ``N = N_e`` (the damping acts in impacts only, and its
velocity would make the friction's tangent jump where ``N_e + N_d`` changes sign),
regularised in the slip velocity ``v_t = xd - v_n n`` (the surface is fixed):

    f_t = -mu N v_t / sqrt(|v_t|^2 + eps^2).

Derivatives (``h = H xd``, ``k' = dN_e/dp``, ``D = I / sigma - v_t v_t^T / sigma^3``,
``sigma^2 = |v_t|^2 + eps^2``, ``P_n = I - n n^T``):

    d(N_e n)/dx = -k' n n^T + N_e H,
    dN_d/dx = -c r h^T + c v_n r' n^T,  dN_d/dxd = -c r n^T,
    dv_t/dx = -(n h^T + v_n H),  dv_t/dxd = P_n,
    df_t/dx = -mu (-k' phi n^T + N D dv_t/dx),  df_t/dxd = -mu N D P_n,

``phi = v_t / sigma``.  The force splits in two parts (``coef[PART]``): ``ELASTIC``, the
penalty ``N_e n`` (conservative: its work is booked as external work), and
``DISSIPATIVE``, the normal damping and the friction (booked as dissipation:
``LinePoints.hook(point, dissipative=True)``).
"""

import math

import numpy as np
from numba import njit

from .line import point_function

#: Kinds of surface (``surface[0]``).
PLANE, SPHERE, CYLINDER, EDGE = 0.0, 1.0, 2.0, 3.0
#: Positions in ``coef = [k, c, mu, eps, r_c, part, p_0]``.
STIFFNESS, DAMPING, FRICTION, SLIP, RADIUS, PART, ONSET = range(7)
#: The two parts of the force (``coef[PART]``).
ELASTIC, DISSIPATIVE = 0.0, 1.0
#: Where ``o`` starts in ``surface``, and the edge's cylinder axis point ``c``; int64, one
#: signature of ``rounded`` for both (a global int is typed as its literal value).
ORIGIN, EDGE_AXIS = np.int64(1), np.int64(11)

#: The surface's functions (``distance``, ``flat``, ``rounded``) are compiled once each
#: and inlined by LLVM into their callers (``forceinline``), not inlined by numba
#: (``inline="always"``), which types and lowers a function again at every call:
#: ``resolve``, two inlined ``contact_point`` each with ``distance``, itself with ``flat``
#: and ``rounded`` twice, took 9.8 s to compile (2.6 s now).  ``contact_point`` stays
#: ``inline="always"``: compiled apart, the capstan's step took 1.07 times as long.


@njit(cache=True, forceinline=True)
def flat(surface, at, x, n, H):
    """The signed distance of ``x`` from the plane through ``surface[at:at + 3]`` of unit
    normal ``surface[at + 3:at + 6]``; the normal into ``n``, ``H = 0``."""
    s = 0.0
    for i in range(3):
        n[i] = surface[at + 3 + i]
        s += n[i] * (x[i] - surface[at + i])
        for j in range(3):
            H[i, j] = 0.0
    return s


@njit(cache=True, forceinline=True)
def rounded(surface, at, cylinder, x, n, H):
    """The signed distance of ``x`` from the sphere (``cylinder = 0``) or the cylinder
    (``cylinder = 1``, axis ``surface[at + 3:at + 6]``) of centre ``surface[at:at + 3]``
    and radius ``surface[7]``; the normal into ``n``, ``dn/dx`` into ``H``."""
    axial = 0.0
    for i in range(3):
        n[i] = x[i] - surface[at + i]
        axial += n[i] * surface[at + 3 + i]
    for i in range(3):
        n[i] -= cylinder * axial * surface[at + 3 + i]
    r = math.sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2])
    inv = 1.0 / r if r > 0.0 else 0.0
    for i in range(3):
        n[i] *= inv
    for i in range(3):
        for j in range(3):
            d = 1.0 if i == j else 0.0
            H[i, j] = (d - cylinder * surface[at + 3 + i] * surface[at + 3 + j]
                       - n[i] * n[j]) * inv
    return r - surface[7]


@njit(cache=True, forceinline=True)
def distance(surface, x, n, H):
    """The signed distance of ``x`` from ``surface``; its unit normal into ``n`` (3,) and
    ``dn/dx`` into ``H`` (3, 3) (module notes)."""
    kind = surface[0]
    if kind == PLANE:
        return flat(surface, ORIGIN, x, n, H)
    if kind == EDGE:
        beyond = 0.0
        for i in range(3):
            beyond += surface[8 + i] * (x[i] - surface[11 + i])
        if beyond <= 0.0:
            return flat(surface, ORIGIN, x, n, H)
        return rounded(surface, EDGE_AXIS, 1.0, x, n, H)
    return rounded(surface, ORIGIN, 1.0 if kind == CYLINDER else 0.0, x, n, H)


@njit(cache=True, inline="always")
def contact_point(surface, coef, x, xd, want, f, Fx, Fv, work):
    """The part ``coef[PART]`` of the contact force per unit length ``f`` at the point
    ``x`` moving at ``xd`` and, if ``want``, ``Fx = df/dx``, ``Fv = df/dxd`` (module
    notes); ``work`` (8, 3, 3) is scratch, with the normal in ``work[0, 0]`` on return.
    The elastic part does not read ``xd``."""
    n, h, vt, phi = work[0, 0], work[0, 1], work[0, 2], work[1, 0]
    dNx, dNv = work[1, 1], work[1, 2]
    H, D, T = work[2], work[3], work[4]
    for i in range(3):
        f[i] = 0.0
        for j in range(3):
            Fx[i, j] = 0.0
            Fv[i, j] = 0.0
    p = coef[RADIUS] - distance(surface, x, n, H)
    if p <= 0.0:
        return
    k, onset = coef[STIFFNESS], coef[ONSET]
    if p < onset:   # N_e = k p^2 / (2 p_0), its slope kp = dN_e/dp, the ramp s and ds/dp
        u = 1.0 - p / onset
        Ne, kp, s, ds = 0.5 * k * p * p / onset, k * p / onset, 1.0 - u * u, 2.0 * u / onset
    else:
        Ne, kp, s, ds = k * (p - 0.5 * onset), k, 1.0, 0.0
    if coef[PART] == ELASTIC:
        for i in range(3):
            f[i] = Ne * n[i]
            for j in range(3 if want else 0):
                Fx[i, j] = -kp * n[i] * n[j] + Ne * H[i, j]
        return
    c, mu = coef[DAMPING], coef[FRICTION]
    vn = n[0] * xd[0] + n[1] * xd[1] + n[2] * xd[2]
    for i in range(3):
        h[i] = H[i, 0] * xd[0] + H[i, 1] * xd[1] + H[i, 2] * xd[2]
        vt[i] = xd[i] - vn * n[i]
    Nd = -c * vn * s
    for i in range(3):
        f[i] = Nd * n[i]
        dNx[i] = -c * s * h[i] + c * vn * ds * n[i]      # dN_d/dx
        dNv[i] = -c * s * n[i]                           # dN_d/dxd
    for i in range(3 if want else 0):
        for j in range(3):
            Fx[i, j] = n[i] * dNx[j] + Nd * H[i, j]
            Fv[i, j] = n[i] * dNv[j]
    N = Ne
    if mu == 0.0:
        return
    sigma = math.sqrt(vt[0] * vt[0] + vt[1] * vt[1] + vt[2] * vt[2]
                      + coef[SLIP] * coef[SLIP])
    for i in range(3):
        phi[i] = vt[i] / sigma
        f[i] -= mu * N * phi[i]
    if not want:
        return
    for i in range(3):
        dNx[i] = -kp * n[i]                                  # dN/dx
        dNv[i] = 0.0                                         # dN/dxd
        for j in range(3):
            D[i, j] = ((1.0 if i == j else 0.0) - phi[i] * phi[j]) / sigma
            T[i, j] = -(n[i] * h[j] + vn * H[i, j])           # dv_t/dx
    for i in range(3):
        for j in range(3):
            dx = 0.0
            dv = 0.0
            for m in range(3):
                dx += D[i, m] * T[m, j]
                dv += D[i, m] * ((1.0 if m == j else 0.0) - n[m] * n[j])
            Fx[i, j] -= mu * (phi[i] * dNx[j] + N * dx)
            Fv[i, j] -= mu * (phi[i] * dNv[j] + N * dv)


@point_function
def point(params, e, t, x, a, xd, want, f, Fx, Fa, Fv, work):
    """The contact's point function for the loop of ``kernels.line.module``:
    ``params = (surface, coef)`` (module notes); the force does not depend on the slope
    (``Fa = 0``)."""
    surface, coef = params
    contact_point(surface, coef, x, xd, want, f, Fx, Fv, work)
    for i in range(3 if want else 0):
        for j in range(3):
            Fa[i, j] = 0.0


@njit(cache=True)
def resolve(surface, coef, X, V, normal, tangential, resistance, gap):
    """At the points ``X`` moving at ``V`` (m, 3): the normal force per unit length
    ``normal`` (m,), the tangential force ``tangential`` (m, 3), the dissipative part of
    the force ``resistance`` (m, 3: normal damping and friction) and the gap ``gap`` (m,)
    (negative: penetration), for outputs (``loads.contact``)."""
    c = coef.copy()
    work = np.empty((8, 3, 3))
    f = np.empty(3)
    F = np.empty((3, 3))
    for m in range(X.shape[0]):
        c[PART] = DISSIPATIVE
        contact_point(surface, c, X[m], V[m], False, resistance[m], F, F, work)
        c[PART] = ELASTIC
        contact_point(surface, c, X[m], V[m], False, f, F, F, work)
        n = work[0, 0]
        gap[m] = distance(surface, X[m], n, work[2]) - coef[RADIUS]
        s = 0.0
        for i in range(3):
            f[i] += resistance[m, i]
            s += f[i] * n[i]
        normal[m] = s
        for i in range(3):
            tangential[m, i] = f[i] - s * n[i]


@njit(cache=True)
def distances(surface, X, out):
    """The signed distances ``out`` (m,) of the points ``X`` (m, 3) from ``surface``."""
    n = np.empty(3)
    H = np.empty((3, 3))
    for m in range(X.shape[0]):
        out[m] = distance(surface, X[m], n, H)


@njit(cache=True)
def normals(surface, X, out):
    """The unit normals ``out`` (m, 3) of ``surface`` at the points ``X`` (m, 3)."""
    H = np.empty((3, 3))
    for m in range(X.shape[0]):
        distance(surface, X[m], out[m], H)


@njit(cache=True)
def near(surface, X, V, radius, h, margin, scale):
    """The broad phase (``loads.surface_broad_phase``): ``scale[e] = 1`` for the elements
    of the points ``X`` moving at ``V`` (ne, nq, 3) that a step of ``h`` may bring into
    touch, 0 for the others (the line loop skips them); returns the smallest gap.  A point
    may touch if its gap ``s(x) - radius`` is at most ``margin + 3 h v_max``, with
    ``v_max`` the largest speed of the line's points: the signed distance of a plane, a
    sphere, a cylinder or an edge (above its axis) changes by at most the distance a
    point moves (it is 1-Lipschitz), and 3 covers a speed that grows threefold within
    the step."""
    n = np.empty(3)
    H = np.empty((3, 3))
    vmax = 0.0
    for e in range(X.shape[0]):
        for g in range(X.shape[1]):
            vmax = max(vmax, math.sqrt(V[e, g, 0] ** 2 + V[e, g, 1] ** 2 + V[e, g, 2] ** 2))
    reach = margin + 3.0 * h * vmax
    smallest = np.inf
    for e in range(X.shape[0]):
        scale[e] = 0.0
        for g in range(X.shape[1]):
            gap = distance(surface, X[e, g], n, H) - radius
            smallest = min(smallest, gap)
            if gap <= reach:
                scale[e] = 1.0
    return smallest
