"""A tethered satellite system built with the rod-chain model (``tss_chain``): two end
bodies on a tether along the local vertical, at rest in the orbiting frame."""

import numpy as np

from ..space.constants import MU_EARTH, R_EARTH
from ..space.orbit import Orbit
from .checks import positive, positive_int
from .model import RodChain
from .orbiting import OrbitingChain

STRETCH_PASSES = 3  # each pass shrinks the error of the stretched lengths by the strain


def vertical_tensions(model, x, tidal):
    """Rod forces (n,) of the relative equilibrium of joints at heights ``x`` (n + 1,)
    along the local vertical, in the radial field ``tidal * x`` (gravity gradient plus
    centrifugal, ``3 n^2 x`` in a circular orbit).

    With ``q'' = -omega^2 q`` of the steady rotation the consistent mass turns the
    centrifugal field into the same loads of Eq. 14 as the gravity gradient, so Eq. 18
    reads ``k_i q_i = Q_i``: the rod force is Eq. 16 with ``F_j = tidal m_j (x_{j-1} +
    x_j) / 2``, ``F*_i = tidal m_i (x_{i-1} / 2 + l_i / 3)`` and ``tidal m_b x_n`` of the
    upper end body.
    """
    m = model.chain.masses
    F = tidal * m * 0.5 * (x[:-1] + x[1:])
    Fs = tidal * m * (0.5 * x[:-1] + np.diff(x) / 3.0)
    beyond = np.concatenate([np.cumsum(F[::-1])[::-1][1:], [0.0]])
    return Fs + beyond + tidal * model.end_masses[1] * x[-1]


def vertical_heights(model, tidal):
    """Joint heights (n + 1,) of the relative equilibrium along the local vertical: rods
    stretched by their forces (``vertical_tensions``), the centre of mass on the reference
    point (the resultant of the linear field vanishes only there)."""
    chain = model.chain
    lengths = chain.lengths
    for _ in range(STRETCH_PASSES):
        x = np.concatenate([[0.0], np.cumsum(lengths)])
        first = model.end_masses @ x[[0, -1]] + chain.masses @ (0.5 * (x[:-1] + x[1:]))
        x -= first / model.total_mass
        lengths = chain.lengths * (1.0 + vertical_tensions(model, x, tidal) / chain.EA)
    return x


def tss_chain(n_rods=5, *, orbit=None, end_masses=(100.0, 100.0), length=20e3, radius=1e-3,
              E=1e11, density=1.0, pitch=0.0, roll=0.0, t0=0.0, quadrature=2):
    """A tethered satellite system on a rod chain: end bodies ``end_masses`` (kg) at ``O_0``
    (lower) and ``O_n`` (upper) on a tether of ``n_rods`` equal rods along the local
    vertical, at rest in the orbiting frame.

    Parameters
    ----------
    n_rods : int
        Number of rods (odd: one rod holds the tether's centre).
    orbit : Orbit or None
        Default: circular, 400 km above the Earth's equator.
    end_masses : (float, float)
        The lower and upper end bodies (kg).
    length, radius, E, density : float
        The tether's rest length (m), the radius of its solid circular section (m),
        Young's modulus (Pa) and density (kg/m^3); the defaults are those of the ANCF
        dumbbell of ``tests/test_orbit_system.py`` (a nearly massless 20 km tether).
    pitch, roll : float
        Offsets (rad) of the tether from the local vertical: turned by ``pitch`` about
        the orbit normal, then by ``roll`` about the along-track axis (as the ``tss``
        scene turns the ANCF dumbbell), its direction in the orbiting frame (radial,
        along-track, normal) is ``(cos pitch cos roll, sin pitch, -cos pitch sin roll)``.
    t0 : float
        Time (s) of the state on the orbit's clock.
    quadrature : int
        Gauss points per rod (``OrbitingChain``).

    Returns
    -------
    model : OrbitingChain
    x0, v0 : ndarray (n_rods + 1, 3)
        The state ``(r_0, q_1 .. q_n)``: the rods stretched to the relative equilibrium
        along the vertical in the field ``2 mu / |R|^3 + |omega|^2`` (``3 n^2`` in a
        circular orbit) with the centre of mass on the reference point, turned by
        ``pitch`` and ``roll`` about it; velocities ``omega x delta`` with ``omega =
        orbit.angular_velocity(t0)``.
    """
    orbit = Orbit(MU_EARTH, R_EARTH + 400e3) if orbit is None else orbit
    n_rods = positive_int("n_rods", n_rods)
    area = np.pi * positive("radius", radius) ** 2
    chain = RodChain.uniform(n_rods, density * area * length / n_rods, length / n_rods, E,
                             area)
    model = OrbitingChain(chain, orbit, end_masses, quadrature)
    omega = orbit.angular_velocity(t0)
    tidal = 2.0 * orbit.mu / np.linalg.norm(orbit.position(t0)) ** 3 + omega @ omega
    heights = vertical_heights(model, tidal)
    direction = np.array([np.cos(pitch) * np.cos(roll), np.sin(pitch),
                          -np.cos(pitch) * np.sin(roll)])
    joints = orbit.from_lvlh(t0, heights[:, None] * direction)
    x0 = np.concatenate([joints[:1], np.diff(joints, axis=0)])
    return model, x0, np.cross(omega, x0)
