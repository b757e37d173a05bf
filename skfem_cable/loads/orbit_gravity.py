"""The central body's differential gravity on a system in orbit (``System.add_orbit``).

The system's coordinates are offsets from the reference point of an ``Orbit``, in axes
parallel to the inertial ones.  Every body says where its mass is through the hook
``mass_points()`` (see ``DifferentialGravity``); the load integrates the differential
gravity ``g(R + delta) - g(R)`` (``orbit.differential_gravity``, optional J2) over those
points in one compiled kernel (``kernels.central``), with its exact tangent.
"""

from dataclasses import dataclass, replace

import numpy as np

from ..core.contract import Term, combined
from ..kernels import central
from ..space.tidal import differential_gravity


@dataclass(frozen=True)
class MassPoints:
    """Where the mass of a system is: points at ``positions(q)``, with masses ``mass``.

    Attributes
    ----------
    vectors : int ndarray (np, k)
        Global index of the first coordinate of each 3-vector a point combines.
    coefficients : ndarray (np, k)
        ``position_p = sum_j coefficients[p, j] q[vectors[p, j] : vectors[p, j] + 3]``
        (ANCF positions and slopes, natural coordinates: the positions are such
        combinations); padding has coefficient 0.
    mass : ndarray (np,)
    groups : int ndarray (ng + 1,)
        Points ``groups[g]:groups[g + 1]`` share their vectors (a cable element's Gauss
        points): the kernel adds their tangents into one block.
    """

    vectors: np.ndarray
    coefficients: np.ndarray
    mass: np.ndarray
    groups: np.ndarray

    def positions(self, x):
        """The points' positions (np, 3) for coordinates ``x`` (or their velocities for
        velocities ``x``)."""
        blocks = np.asarray(x, dtype=float)[self.vectors[..., None] + np.arange(3)]
        return np.einsum("pk,pki->pi", self.coefficients, blocks)

    def group_dofs(self):
        """The coordinates of each group's tangent block, int (ng, 3 k)."""
        first = self.vectors[self.groups[:-1]]
        return (first[:, :, None] + np.arange(3)).reshape(len(first), -1)


def _point_mass_vectors(system, point_mass):
    """``(vectors (1, k), coefficients (1, k))`` of a point mass, from
    ``System.position_map``: its ``G`` must combine whole 3-vectors (``[c_1 I, c_2 I, ...]``:
    cable nodes and rigid-body points)."""
    dofs, G = system.position_map(point_mass.point)
    G = np.asarray(G, dtype=float)
    c = G[0, 0::3]
    if dofs.size % 3 or not np.array_equal(G, np.kron(c[None, :], np.eye(3))):
        raise TypeError(f"point mass at {point_mass.point!r}: its position is not a "
                        "combination of 3-vectors of coordinates; in orbit a point mass sits "
                        "at a cable node or a rigid-body point")
    return np.asarray(dofs)[0::3][None, :], c[None, :]


def _padded(vectors, coefficients, width):
    """Vectors and coefficients padded to ``width`` columns (repeating the first vector
    with coefficient 0)."""
    n = vectors.shape[1]
    if n == width:
        return vectors, coefficients
    return (np.concatenate([vectors, np.repeat(vectors[:, :1], width - n, axis=1)], axis=1),
            np.concatenate([coefficients, np.zeros((len(vectors), width - n))], axis=1))


def system_mass_points(system):
    """The ``MassPoints`` of every body and point mass of ``system``.

    Bodies provide ``mass_points()`` returning ``(vectors, coefficients, mass)`` in their
    own coordinates (``MassPoints``' first three attributes, ``vectors`` counted from the
    body's first coordinate); point masses are placed by ``System.position_map``.
    """
    parts = []
    for body in system.bodies:
        vectors, coefficients, mass = body.mass_points()
        parts.append((np.asarray(vectors) + system.dofs(body)[0],
                      np.asarray(coefficients, float), np.asarray(mass, float)))
    for point_mass in system.point_masses:
        parts.append((*_point_mass_vectors(system, point_mass), np.array([point_mass.mass])))
    width = max(p[0].shape[1] for p in parts)
    padded = [_padded(v, c, width) for v, c, _ in parts]
    vectors = np.ascontiguousarray(np.concatenate([p[0] for p in padded]), dtype=np.int64)
    change = np.any(vectors[1:] != vectors[:-1], axis=1)
    groups = np.append(np.flatnonzero(np.append(True, change)), len(vectors))
    return MassPoints(vectors, np.ascontiguousarray(np.concatenate([p[1] for p in padded])),
                      np.ascontiguousarray(np.concatenate([p[2] for p in parts])),
                      groups.astype(np.int64))


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
    Bodies provide ``mass_points() -> (vectors, coefficients, mass)`` (``MassPoints``):
    points whose positions combine 3-vectors of the body's coordinates and whose masses
    reproduce the body's mass, centre of mass and second moments (a cable: 4 Gauss
    points per element weighted by ``rho A``; a rigid body: six points on its principal
    axes).  The
    force on them is the differential gravity at the points, so the gravity-gradient
    torque on a rigid body is exact to second order in its size over the orbit radius.

    The term reads the reference point ``R(t)`` of the run's ``Reference``
    (``reads_reference``: the rectification's arcs), the orbit's ``mu`` and ``t0``.
    """

    #: Bound with the run's reference (``bind(system, reference)``, ``layout.Layout``).
    reads_reference = True

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

    def frame_change(self, old, new):
        """``g(new) - g(old)`` (m/s^2, (3,)): how much faster the reference point falls
        at the absolute position ``new`` than at ``old`` (Encke's rectification moves it,
        ``solvers.rectify``); the central term free of cancellation
        (``orbit.differential_gravity``), J2's by difference."""
        old, new = np.asarray(old, dtype=float), np.asarray(new, dtype=float)
        change = differential_gravity(self.orbit.mu, old, new - old)
        if self.j2 is not None:
            at_old, at_new = np.zeros(3), np.zeros(3)
            central.j2_acceleration(self.k, old, at_old)
            central.j2_acceleration(self.k, new, at_new)
            change += at_new - at_old
        return change

    def bind(self, system, reference=None):
        """The compiled term of the constant mass (``kernels.central``), combined with the
        Python terms of the mass each deployment moves (``DeployedMass``) if any, about
        the reference point of ``reference`` (a run's ``Reference``; None: the orbit as
        given)."""
        reference = self.orbit if reference is None else reference
        term = self._constant_mass(system, reference)
        deployed = [DeployedMass(self, d, system, reference).term()
                    for d in system.deployments.values()]
        if not deployed:
            return term
        return combined([replace(term, add=term.evaluate, kernels=()), *deployed],
                        "differential gravity")

    def field(self, t, delta, reference=None):
        """``(a, phi, T)``: the differential acceleration (np, 3), the potential energy per
        unit mass (np,) and the acceleration's tangent (np, 3, 3) at the offsets ``delta``
        (np, 3) at time ``t`` (``kernels.central.field``) from the reference point of
        ``reference`` (a run's ``Reference``; None: the orbit as given)."""
        reference = (self.orbit if reference is None else reference).position(t)
        base = np.zeros(3)
        if self.j2 is not None:
            central.j2_acceleration(self.k, reference, base)
        delta = np.ascontiguousarray(np.reshape(delta, (-1, 3)), dtype=float)
        a, phi, T = np.empty_like(delta), np.empty(len(delta)), np.empty((len(delta), 3, 3))
        central.field(self.orbit.mu, self.k, reference, base, delta, a, phi, T)
        return a, phi, T

    def _constant_mass(self, system, orbit):
        """The compiled term of the bodies' and point masses' constant mass, about the
        reference point of ``orbit`` (an ``Orbit`` or a run's ``Reference``)."""
        points = system_mass_points(system)
        dofs = points.group_dofs()
        reference = np.zeros(3)
        base = np.zeros(3)
        constants = np.array([self.orbit.mu, self.k, 0.0])

        def prepare(t):
            reference[:] = orbit.position(t)
            # a bound of the gradient's norm 3 mu / r^3 wherever r > |R| / 2 (J2's share
            # is below a tenth of it above the central body's surface)
            constants[2] = 24.0 * self.orbit.mu / float(reference @ reference) ** 1.5
            if constants[1] != 0.0:
                central.j2_acceleration(constants[1], reference, base)

        prepare(orbit.t0)
        pack = (points.vectors, points.coefficients, points.mass, points.groups, reference,
                base, constants)
        return Term(kernels=((central.kernel, pack),), rows=dofs[:, :, None],
                    cols=dofs[:, None, :], prepare=prepare, name="differential gravity")


class DeployedMass:
    """The differential gravity on the mass a deployment (``deploy.Deployment``) adds to
    the constant mass the compiled term sees, as ``Deployment.bind_weight`` does in a
    uniform field: the cable's mass points weigh ``lam m_p`` (the material length element
    ``lam dx``, ``lam = l / L0``) instead of ``m_p``, and the material still on the reel,
    ``m_s = mu (capacity - l)``, rides at the anchor.  With ``phi`` the potential energy
    per unit mass of the differential field (``DifferentialGravity.field``) the potential
    of this mass is

        V_d = (lam - 1) sum_p m_p phi(delta_p) + m_s phi(r_P),

    whose forces are ``(lam - 1) m_p a_p`` on the cable's points and ``m_s a_P`` at a body
    anchor.  When the length is a reel's coordinate, ``-dV_d/dl = -sum_p m_p phi_p / L0 +
    mu phi(r_P)`` acts on it: the difference of the potential along the tether and at the
    reel (the constant of ``phi`` drops out as the material only moves between them), and
    the derivatives in ``l`` enter the tangent symmetrically (a potential).

    Parameters
    ----------
    gravity : DifferentialGravity
    deployment : deploy.Deployment
    system : System
    reference : Orbit or Reference
        Whose reference point the offsets are taken from (the run's).
    """

    def __init__(self, gravity, deployment, system, reference):
        self.gravity, self.deployment, self.reference = gravity, deployment, reference
        cable = deployment.cable
        vectors, coefficients, mass = cable.mass_points()
        n, k = coefficients.shape
        vectors = np.asarray(vectors) + system.dofs(cable)[0]
        self.points = MassPoints(vectors, coefficients, mass, np.array([0, n]))
        self.dofs = (vectors[:, :, None] + np.arange(3)).reshape(n, 3 * k)
        self.stowed = deployment.stowed(system)
        self.anchor = None if self.stowed is None or self.stowed[2] is None else \
            (self.stowed[2], system.position_map(deployment.anchor)[1])
        self.reel = deployment.reel

    def entries(self):
        """``(rows, cols)`` of the tangent, 1-D, in the order ``add`` fills them: the
        cable's points, the anchor, then with a reel the column and the row of its
        length."""
        rows = [np.broadcast_to(self.dofs[:, :, None], self.dofs.shape + (self.dofs.shape[1],))]
        cols = [np.broadcast_to(self.dofs[:, None, :], rows[0].shape)]
        line = [self.dofs.ravel()]
        if self.anchor is not None:
            pdofs = self.anchor[0]
            r, c = np.meshgrid(pdofs, pdofs, indexing="ij")
            rows.append(r)
            cols.append(c)
            line.append(pdofs)
        if self.reel is not None:
            line = np.concatenate(line)
            rows += [line, np.full(line.size, self.reel)]
            cols += [np.full(line.size, self.reel), line]
        return (np.concatenate([r.ravel() for r in rows]),
                np.concatenate([c.ravel() for c in cols]))

    def term(self):
        rows, cols = self.entries()
        return Term(add=self.add, rows=rows, cols=cols,
                    name=f"differential gravity of {self.deployment.cable.name}'s deployment")

    def add(self, ev, index):
        d = self.deployment
        ell = d.state(ev.t, ev.q)[0]
        lam = ell / d.L0
        c, m = self.points.coefficients, self.points.mass
        n, k = c.shape
        where = [self.points.positions(ev.q)]
        if self.stowed is not None:  # the material on the reel, in the same evaluation
            where.append(d.exit_point if self.anchor is None else
                         self.anchor[1] @ ev.q[self.anchor[0]])
        a, phi, T = self.gravity.field(ev.t, np.vstack(where), self.reference)
        per_point = np.einsum("p,pk,pi->pki", m, c, a[:n]).reshape(n, 3 * k)
        np.add.at(ev.f_ext, self.dofs, (lam - 1.0) * per_point)
        values = [np.einsum("p,pj,pl,pab->pjalb", (lam - 1.0) * m, c, c, T[:n]).ravel()]
        column = [per_point.ravel() / d.L0]
        on_length = -(m @ phi[:n]) / d.L0
        if self.stowed is not None:
            mu, capacity = self.stowed[:2]
            on_length += mu * phi[n]
            if self.anchor is not None:
                pdofs, G = self.anchor
                ev.f_ext[pdofs] += mu * (capacity - ell) * (G.T @ a[n])
                values.append(mu * (capacity - ell) * (G.T @ T[n] @ G).ravel())
                column.append(-mu * (G.T @ a[n]))
        if self.reel is not None:
            ev.f_ext[self.reel] += on_length
            column = np.concatenate(column)
            values += [column, column]
        if ev.want_tangent:
            ev.add_tangent(index, np.concatenate(values), sign=-1.0)


def orbital_energy(system, q, v, t, reference=None):
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
    the gradient of the mass points' potential).  ``reference``: the run's
    (``Result.reference``: the orbit and its rebases); None: the orbit as given.
    """
    if system.orbit is None:
        raise ValueError("orbital_energy: the system is not in orbit (System.add_orbit)")
    if system.deployments:
        raise ValueError("orbital_energy: the system deploys a cable (System.deploy), "
                         "whose mass moves between the reel and the tether; its "
                         "gravity is booked as external work (Result.energy)")
    orbit = system.orbit if reference is None else reference
    points = system_mass_points(system)
    delta, speed = points.positions(q), points.positions(v)
    R, V = orbit.position(t), orbit.velocity(t)
    r2 = R @ R
    qp = np.sum(delta * (2.0 * R + delta), axis=-1) / r2
    root = np.sqrt(1.0 + qp)
    potential = orbit.mu / np.sqrt(r2) * qp / (root * (1.0 + root))
    kinetic = speed @ V + 0.5 * np.sum(speed * speed, axis=-1)
    return float(points.mass @ (kinetic + potential))
