"""Crossings of line-to-line contact (``loads.contact_crossing``): whether two segments of
the lines' sampled centrelines passed through each other between an accepted state and a
converged candidate state, over the candidate pairs of the step's broad phase.

A penalty on an unsigned gap releases two lines once their centrelines have crossed (the
closest-point vector, and with it the force, has flipped), so a step that carries one line
through the other converges quietly on the wrong side.  The check is the continuous
(swept) edge-edge test of cloth simulation (Provot, *Collision and self-collision handling
in cloth model dedicated to design garments*, 1997; Bridson, Fedkiw & Anderson, *Robust
treatment of collisions, contact and friction for cloth animation*, 2002): between the
two states the segments' ends ``P_j`` move on straight lines,
``P_j(tau) = P_j^n + tau (P_j^(n+1) - P_j^n)``, ``tau`` in ``[0, 1]``.  Two segments
``P0 P1`` and ``P2 P3`` can only meet where their four ends are coplanar,

    V(tau) = (u x w) . r = 0,    u = P1 - P0,  w = P3 - P2,  r = P2 - P0,

a cubic in ``tau`` (the triple product is trilinear: ``V = sum_k c_k tau^k`` with
``c_0 = [u, w, r]``, ``c_1 = [du, w, r] + [u, dw, r] + [u, w, dr]``,
``c_2 = [du, dw, r] + [du, w, dr] + [u, dw, dr]``, ``c_3 = [du, dw, dr]``, ``[.]`` the
determinant of the state ``n`` vectors and their changes ``d.``).  ``V / |u x w|`` is the
signed distance of the two lines along their common normal: its sign is the side one
line is on.  The cubic is split at the roots of ``V'`` into monotone pieces; on each piece
whose ends have opposite signs the root is bisected, and the segments cross there when
their closest points (``contact_lines.closest``, clamped to the segments) are within
``gap`` of each other (the lines' intersection lies on both segments; at a root it is 0
up to round-off where it does).

Not detected: a crossing the straight-line motion of the ends does not show (the true
path between the states is not known); a crossing of two lines that move in one plane
(``V`` vanishes identically: Ericson's caveat of the method, *Coplanarity is the evil*,
realtimecollisiondetection.net, 2007); a pair the broad phase
did not give (it covers the motion its reach predicts from the state ``n``'s velocities).
"""

import math

import numpy as np
from numba import njit

from .contact_lines import closest, gather_pair

#: Bisections of a root of ``V`` (the interval ``[0, 1]`` halved to 2^-60).
BISECTIONS = 60
#: Columns of ``found``: the pair's row in ``pairs``, the crossing's time in the step
#: (``tau``) and the closest points' parameters ``s``, ``t`` on the two segments there.
PAIR, TAU, ON_A, ON_B = range(4)


@njit(cache=True, inline="always")
def _det(a, b, c):
    """The triple product ``(a x b) . c``."""
    return (c[0] * (a[1] * b[2] - a[2] * b[1]) + c[1] * (a[2] * b[0] - a[0] * b[2])
            + c[2] * (a[0] * b[1] - a[1] * b[0]))


@njit(cache=True)
def coplanarity(P0, P1, c):
    """The coefficients ``c`` (4,) of the cubic ``V(tau)`` of the segments whose ends
    ``P0`` (4, 3) at ``tau = 0`` move to ``P1`` at ``tau = 1`` (module notes)."""
    u, w, r = P0[1] - P0[0], P0[3] - P0[2], P0[2] - P0[0]
    du, dw, dr = P1[1] - P1[0] - u, P1[3] - P1[2] - w, P1[2] - P1[0] - r
    c[0] = _det(u, w, r)
    c[1] = _det(du, w, r) + _det(u, dw, r) + _det(u, w, dr)
    c[2] = _det(du, dw, r) + _det(du, w, dr) + _det(u, dw, dr)
    c[3] = _det(du, dw, dr)


@njit(cache=True, inline="always")
def _cubic(c, x):
    return ((c[3] * x + c[2]) * x + c[1]) * x + c[0]


@njit(cache=True)
def pieces(c, cuts):
    """The ends of the monotone pieces of the cubic ``c`` on ``[0, 1]`` into ``cuts``
    (4,): 0, the roots of ``V'`` inside, 1; returns how many ends."""
    a, b, e = 3.0 * c[3], 2.0 * c[2], c[1]
    r0 = r1 = -1.0                     # outside: no cut
    if a == 0.0:
        if b != 0.0:
            r0 = -e / b
    else:
        disc = b * b - 4.0 * a * e
        if disc > 0.0:
            h = -0.5 * (b + math.copysign(math.sqrt(disc), b))
            r0 = h / a
            if h != 0.0:
                r1 = e / h
    cuts[0], m = 0.0, 1
    for x in (min(r0, r1), max(r0, r1)):
        if 0.0 < x < 1.0:
            cuts[m], m = x, m + 1
    cuts[m] = 1.0
    return m + 1


@njit(cache=True)
def _root(c, lo, hi):
    """A root of the cubic ``c`` between ``lo`` and ``hi`` (opposite signs), bisected."""
    flo = _cubic(c, lo)
    for _ in range(BISECTIONS):
        mid = 0.5 * (lo + hi)
        fm = _cubic(c, mid)
        if (fm < 0.0) == (flo < 0.0):
            lo, flo = mid, fm
        else:
            hi = mid
    return 0.5 * (lo + hi)


@njit(cache=True)
def crossing_time(P0, P1, gap, P, c, cuts):
    """The first time ``tau`` in ``[0, 1]`` at which the segments moving from ``P0`` to
    ``P1`` (4, 3) pass through each other (module notes), or -1; the interpolated ends
    at ``tau`` are left in ``P`` (4, 3).  ``c`` (4,) and ``cuts`` (4,) are scratch."""
    coplanarity(P0, P1, c)
    ends = pieces(c, cuts)
    for k in range(ends - 1):
        lo, hi = cuts[k], cuts[k + 1]
        if not _cubic(c, lo) * _cubic(c, hi) < 0.0:
            continue
        tau = _root(c, lo, hi)
        for j in range(4):
            for i in range(3):
                P[j, i] = P0[j, i] + tau * (P1[j, i] - P0[j, i])
        s, t = closest(P)
        d = 0.0
        for i in range(3):
            d += (P[0, i] + s * (P[1, i] - P[0, i]) - P[2, i] - t * (P[3, i] - P[2, i])) ** 2
        if math.sqrt(d) <= gap:
            return tau
    return -1.0


@njit(cache=True)
def crossed(edofs, S, segments, pairs, count, gap, q0, q1, found):
    """How many of the candidate pairs ``pairs[:count[0]]`` of rows of ``segments``
    (``contact_lines``) crossed between the states ``q0`` and ``q1``
    (``crossing_time``, within ``gap``); the first's ``[pair, tau, s, t]`` go into
    ``found`` (4,) (``PAIR, TAU, ON_A, ON_B``)."""
    P0, P1, P = np.empty((4, 3)), np.empty((4, 3)), np.empty((4, 3))
    c, cuts = np.empty(4), np.empty(4)
    n = 0
    for m in range(count[0]):
        sa, sb = segments[pairs[m, 0]], segments[pairs[m, 1]]
        gather_pair(edofs, S, sa, sb, q0, P0)
        gather_pair(edofs, S, sa, sb, q1, P1)
        tau = crossing_time(P0, P1, gap, P, c, cuts)
        if tau < 0.0:
            continue
        if n == 0:
            s, t = closest(P)
            found[PAIR], found[TAU], found[ON_A], found[ON_B] = m, tau, s, t
        n += 1
    return n
