"""The central body's differential gravity on a system in orbit (``System.add_orbit``).

The system's coordinates are offsets from the reference point of an ``Orbit``, in axes
parallel to the inertial ones.  Every body says where its mass is through the hook
``mass_points()`` (see ``DifferentialGravity``); the load integrates the differential
gravity ``g(R + delta) - g(R)`` (``orbit.differential_gravity``, optional J2) over those
points in one compiled kernel (``kernels.central``), with its exact tangent.
"""

import numpy as np

from .contract import Term
from .kernels import central


def _padded(points, width):
    """``(dofs, G, mass)`` of mass points padded to ``width`` coordinates (zero columns of
    ``G`` on a repeated coordinate)."""
    dofs, G, mass = points
    n_points, n = dofs.shape
    if n == width:
        return dofs, G, mass
    pad = np.repeat(dofs[:, :1], width - n, axis=1)
    return (np.concatenate([dofs, pad], axis=1),
            np.concatenate([G, np.zeros((n_points, 3, width - n))], axis=2), mass)


def system_mass_points(system):
    """The mass points of every body and point mass of ``system``: ``dofs`` (np, n) global
    coordinates, ``G`` (np, 3, n) with ``position = G[p] @ q[dofs[p]]``, ``mass`` (np,).

    Bodies provide ``mass_points()`` returning the same triple in their own coordinates;
    point masses are placed by ``System.position_map``.
    """
    parts = []
    for body in system.bodies:
        hook = getattr(body, "mass_points", None)
        if hook is None:
            raise TypeError(
                f"body {body.name!r} ({type(body).__name__}) has no mass_points() hook: "
                "a system in orbit needs every body to say where its mass is (see "
                "docs/extending.md)")
        dofs, G, mass = hook()
        parts.append((np.asarray(dofs) + system.dofs(body)[0], np.asarray(G, float),
                      np.asarray(mass, float)))
    for point_mass in system.point_masses:
        dofs, G = system.position_map(point_mass.point)
        parts.append((np.asarray(dofs)[None, :], np.asarray(G, float)[None],
                      np.array([point_mass.mass])))
    width = max(p[0].shape[1] for p in parts)
    parts = [_padded(p, width) for p in parts]
    return (np.ascontiguousarray(np.concatenate([p[0] for p in parts]), dtype=np.int64),
            np.ascontiguousarray(np.concatenate([p[1] for p in parts])),
            np.ascontiguousarray(np.concatenate([p[2] for p in parts])))


class DifferentialGravity:
    """The differential gravity of the central body of ``orbit`` on every mass point of
    the system (added by ``System.add_orbit``).

    Parameters
    ----------
    orbit : Orbit
        The reference orbit: the system's coordinates are offsets from its point.
    j2 : float or None
        The central body's second zonal harmonic (e.g. 1.08263e-3 for the Earth), its
        axis along the system's ``z``; None: a point mass.
    body_radius : float or None
        Equatorial radius (m) of the central body, required with ``j2``.

    Notes
    -----
    Bodies provide ``mass_points() -> (dofs, G, mass)``: points whose positions are
    ``G[p] @ q_body[dofs[p]]`` and whose masses reproduce the body's mass, centre of mass
    and second moments (a cable: its Gauss points weighted by ``rho A``; a rigid body: six
    points on its principal axes).  The force on them is the differential gravity at the
    points, so the gravity-gradient torque on a rigid body is exact to second order in its
    size over the orbit radius.
    """

    def __init__(self, orbit, j2=None, body_radius=None):
        self.orbit = orbit
        if (j2 is None) != (body_radius is None):
            raise ValueError("add_orbit: give j2 and body_radius together (the J2 term "
                             "needs the central body's equatorial radius)")
        if j2 is not None and not (np.isfinite(j2) and np.isfinite(body_radius)
                                   and body_radius > 0):
            raise ValueError(f"add_orbit: j2 must be finite and body_radius > 0 (m), got "
                             f"j2={j2!r}, body_radius={body_radius!r}")
        self.j2 = None if j2 is None else float(j2)
        self.body_radius = None if body_radius is None else float(body_radius)

    @property
    def k(self):
        """``3/2 mu J2 R_e^2`` (0 without J2)."""
        if self.j2 is None:
            return 0.0
        return 1.5 * self.orbit.mu * self.j2 * self.body_radius**2

    def bind(self, system):
        if system.deployments:
            raise ValueError("add_orbit: deploying cables (System.deploy) are not "
                             "supported in orbit yet: their mass points move with the "
                             "free length")
        dofs, G, mass = system_mass_points(system)
        reference = np.zeros(3)
        base = np.zeros(3)
        constants = np.array([self.orbit.mu, self.k])

        def prepare(t):
            reference[:] = self.orbit.position(t)
            if constants[1] != 0.0:
                central.j2_acceleration(constants[1], reference, base)

        prepare(self.orbit.t0)
        return Term(kernels=((central.kernel, (dofs, G, mass, reference, base, constants)),),
                    rows=dofs[:, :, None], cols=dofs[:, None, :], prepare=prepare,
                    name="differential gravity")


def orbital_energy(system, q, v, t):
    """Kinetic plus potential energy (J) in the central field of the system in orbit at
    ``(q, v, t)``, less that of its mass moving with the reference point:
    ``sum_p m_p (|V + v_p|^2 / 2 - mu / |R + delta_p|) - m (|V|^2 / 2 - mu / |R|)``, with
    ``V, R`` the reference point's velocity and position and ``delta_p``, ``v_p`` the mass
    points' offsets and velocities (``system_mass_points``).

    Formed without cancellation (``V . v_p + |v_p|^2 / 2`` and ``mu / |R| q_p /
    (sqrt(1 + q_p) (1 + sqrt(1 + q_p)))`` with ``|R + delta_p|^2 = |R|^2 (1 + q_p)``), so that
    a tether's libration energy stays readable beside the orbit's.  The reference point's
    own energy is constant on its Keplerian orbit, so with the elastic energy added this is
    conserved by the equations of motion without other loads (the differential gravity is
    the gradient of the mass points' potential).
    """
    orbit = system.orbit
    if orbit is None:
        raise ValueError("orbital_energy: the system is not in orbit (System.add_orbit)")
    dofs, G, mass = system_mass_points(system)
    q, v = np.asarray(q, dtype=float), np.asarray(v, dtype=float)
    delta = np.einsum("pic,pc->pi", G, q[dofs])
    speed = np.einsum("pic,pc->pi", G, v[dofs])
    R, V = orbit.position(t), orbit.velocity(t)
    r2 = R @ R
    qp = np.sum(delta * (2.0 * R + delta), axis=-1) / r2
    root = np.sqrt(1.0 + qp)
    potential = orbit.mu / np.sqrt(r2) * qp / (root * (1.0 + root))
    kinetic = speed @ V + 0.5 * np.sum(speed * speed, axis=-1)
    return float(mass @ (kinetic + potential))
