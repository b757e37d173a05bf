"""Swinging steel chain: a rod-chain tether released from horizontal under gravity.

Physics
-------
Eleven steel rods (density 7801 kg/m^3, radius 1 mm, rest length 0.1 m, E = 207 GPa: the
paper's second experiment) joined by frictionless spherical hinges hang from a fixed point
``O_0``.  At ``t = 0`` the chain lies straight and horizontal along ``+x``, at rest, and falls
under gravity ``g = 9.81 m/s^2`` along ``-y``.  (The paper's initial state, straight along
``-y`` and at rest with gravity along ``-y``, is an equilibrium and does not move; the
horizontal release is that geometry with gravity turned by 90 degrees.)  The chain swings
down like a pendulum whose lower links lag behind, then whips past the vertical: the free
end reaches about 12 m/s.  The rods are so stiff (``EA = 6.5e5 N``) that their strain stays
below 1e-5, and the chain moves like a chain of rigid links.

The rod chain (equations of motion 18-21 of the paper, O(n) mass solve) is integrated with
classical RK4.  Its step must stay below ``2 sqrt(2) / omega_max`` with ``omega_max =
sqrt(12 EA / (l0 m))`` the highest axial frequency: 1.6e-5 s here, not the paper's 1e-4 s.
The result is checked against an independent model, the planar pendulum of n rigid uniform
rods in joint angles with a dense mass matrix, integrated by DOP853 at tight tolerance, and
against RK4 with half the step.

The module also holds the paper's first experiment (20 soft rods falling while turning at
1 rad/s, a check of energy conservation) and the small oscillations of a hanging chain,
whose frequencies approach those of the continuous chain, ``(j_{0,k} / 2) sqrt(g / L)``
with ``j_{0,k}`` the zeros of Bessel ``J0``.

Run ``python demos/hanging_chain.py``; the flags ``--energy``, ``--oscillations``,
``--convergence`` (number of rods at fixed total length and mass) and ``--ancf`` (the same
tether as ANCF truss and cable elements) print those studies.
"""

import sys
import time

import numpy as np
from scipy.integrate import solve_ivp
from scipy.linalg import eigh
from scipy.special import jn_zeros

from skfem_cable.rodchain import RodChain

STEEL = {"density": 7801.0, "radius": 1e-3, "E": 207e9, "length": 1.1, "g": 9.81}


def steel_chain(n_rods=11):
    """The paper's steel tether (total length 1.1 m) cut into ``n_rods`` equal rods."""
    A = np.pi * STEEL["radius"] ** 2
    l0 = STEEL["length"] / n_rods
    return RodChain.uniform(n_rods, mass=STEEL["density"] * A * l0, length=l0, E=STEEL["E"], A=A)


def release_state(chain):
    """Straight along ``+x`` at rest: rod vectors ``(l_i0, 0, 0)``, zero velocities."""
    q0 = np.zeros((chain.n, 3))
    q0[:, 0] = chain.lengths
    return q0, np.zeros_like(q0)


def rk4_step(chain, output_dt, safety=0.7):
    """Largest step ``output_dt / k`` (integer ``k``) below ``safety * chain.stable_dt()``."""
    return output_dt / np.ceil(output_dt / (safety * chain.stable_dt()))


def free_end_trajectory(n_rods=11, t_end=1.0, dt=None, output_dt=1e-4, method="rk4", **kwargs):
    """Free-end trajectory of the released steel chain, for comparison with other models.

    Parameters
    ----------
    n_rods : int
        Number of rods over the 1.1 m tether.
    t_end, output_dt : float
        Duration and output spacing (s).
    dt : float, optional
        RK4 step (s); default ``rk4_step(chain, output_dt)`` (1.11e-5 s for 11 rods).
    method : str
        ``"rk4"`` or an adaptive method of ``RodChain.simulate``; ``kwargs`` go there.

    Returns
    -------
    t : ndarray (nt,)
    xyz : ndarray (nt, 3)
        ``O_n(t) - O_0`` (m); gravity along ``-y``, released along ``+x``.
    """
    chain = steel_chain(n_rods)
    step = rk4_step(chain, output_dt) if dt is None else dt
    if method != "rk4":
        step = output_dt
    every = int(round(output_dt / step))
    res = chain.simulate(*release_state(chain), t_end, step, gravity=(0.0, -STEEL["g"], 0.0),
                         method=method, output_every=every, **kwargs)
    return res.t, res.free_end


def rigid_chain_matrices(masses, lengths):
    """Kinematics of a planar chain of rigid uniform rods in joint angles ``theta_j`` from
    the downward vertical, written independently of the rod-chain code.

    Rod centroids are ``r_ci = sum_j J_ij e(theta_j)`` with ``e = (sin, -cos)`` and
    ``J_ij = l_j`` (``j < i``), ``l_i / 2`` (``j = i``), 0 otherwise.  The kinetic energy
    ``sum_i m_i |r_ci'|^2 / 2 + m_i l_i^2 theta_i'^2 / 24`` has the mass matrix
    ``H_jk cos(theta_j - theta_k) + I_j delta_jk`` with ``H = J^T diag(m) J`` and
    ``I_j = m_j l_j^2 / 12``; gravity gives ``dV/dtheta_j = g (J^T m)_j sin theta_j``.

    Returns ``H`` (n, n), ``I`` (n,) and ``J^T m`` (n,).
    """
    m, l = np.asarray(masses, float), np.asarray(lengths, float)
    J = np.tril(np.ones((m.size, m.size)), -1) * l + np.diag(l / 2)
    return J.T @ (m[:, None] * J), m * l * l / 12, J.T @ m


def rigid_chain_frequencies(masses, lengths, g=9.81):
    """Angular frequencies (rad/s, ascending) of small oscillations of the rigid chain
    hanging at rest: ``g diag(J^T m) phi = omega^2 (H + diag(I)) phi``."""
    H, inertia, moment = rigid_chain_matrices(masses, lengths)
    return np.sqrt(eigh(g * np.diag(moment), H + np.diag(inertia), eigvals_only=True))


def rigid_chain_trajectory(masses, lengths, t_end, output_dt, g=9.81, rtol=1e-11, atol=1e-12):
    """Free end of the planar rigid chain (``rigid_chain_matrices``) released at rest from
    horizontal (``theta = pi / 2``): the independent reference.  Lagrange's equations
    ``sum_k H_jk (cos(th_j - th_k) th_k'' + sin(th_j - th_k) th_k'^2) + I_j th_j''
    + g (J^T m)_j sin th_j = 0`` are solved densely with DOP853.

    Returns ``t`` (nt,) and the free-end position (nt, 3) relative to ``O_0``.
    """
    l = np.asarray(lengths, float)
    n = l.size
    H, inertia, moment = rigid_chain_matrices(masses, l)

    def rhs(t, y):
        th, w = y[:n], y[n:]
        d = th[:, None] - th[None, :]
        mass = H * np.cos(d) + np.diag(inertia)
        force = -(H * np.sin(d)) @ (w * w) - g * moment * np.sin(th)
        return np.concatenate([w, np.linalg.solve(mass, force)])

    t = output_dt * np.arange(int(round(t_end / output_dt)) + 1)
    sol = solve_ivp(rhs, (0.0, t[-1]), np.concatenate([np.full(n, np.pi / 2), np.zeros(n)]),
                    method="DOP853", t_eval=t, rtol=rtol, atol=atol)
    if sol.status != 0:
        raise RuntimeError(f"rigid-chain reference failed: {sol.message}")
    th = sol.y[:n]
    xyz = np.stack([l @ np.sin(th), -(l @ np.cos(th)), np.zeros(t.size)], axis=-1)
    return t, xyz


def main(n_rods=11, t_end=1.0, output_dt=1e-4):
    """Simulate the released steel chain and return its key numbers (lengths in m)."""
    chain = steel_chain(n_rods)
    g = STEEL["g"]
    dt = rk4_step(chain, output_dt)
    every = int(round(output_dt / dt))
    start = time.perf_counter()
    res = chain.simulate(*release_state(chain), t_end, dt, gravity=(0.0, -g, 0.0),
                         output_every=every)
    runtime = time.perf_counter() - start
    half = chain.simulate(*release_state(chain), t_end, dt / 2, gravity=(0.0, -g, 0.0),
                          output_every=2 * every)
    _, rigid = rigid_chain_trajectory(chain.masses, chain.lengths, t_end, output_dt, g)
    L = chain.rest_length
    dev = np.linalg.norm(res.free_end - rigid, axis=1)
    E = res.energy["total"]
    strain = res.tension / chain.EA
    return {
        "n_rods": n_rods,
        "rk4_dt": dt,
        "stable_dt": chain.stable_dt(),
        "rk4_runtime_s": runtime,
        "max_dev_rigid_rel": dev.max() / L,
        "max_dev_rigid_time": res.t[dev.argmax()],
        "max_dev_half_step_rel": np.abs(res.free_end - half.free_end).max() / L,
        "energy_drift_rel": np.abs(E - E[0]).max() / res.energy["kinetic"].max(),
        "max_strain": strain.max(),
        "min_strain": strain.min(),
        "max_tip_speed": np.linalg.norm(res.joint_velocities[:, -1], axis=1).max(),
        "lowest_tip_y": res.free_end[:, 1].min(),
        "final_tip": res.free_end[-1],
    }


def n_convergence(ns=(11, 22, 44, 88), t_end=1.0, output_dt=1e-4, windows=(0.25, 0.4, 1.0)):
    """Free-end distance of n-rod steel chains (fixed total length and mass) to the finest
    one, relative to the length: ``{n: (max over t <= w for w in windows)}``."""
    runs = {n: free_end_trajectory(n, t_end, output_dt=output_dt) for n in ns}
    t, ref = runs[ns[-1]]
    out = {}
    for n in ns[:-1]:
        d = np.linalg.norm(runs[n][1] - ref, axis=1) / STEEL["length"]
        out[n] = tuple(d[t <= w + 1e-12].max() for w in windows)
    return out


def ancf_free_end_trajectory(kind="truss", n_elements=11, t_end=1.0, dt=1e-4, rho_inf=0.8):
    """The same steel tether as ANCF ``kind`` elements ("truss": axial only, the like-for-like
    model of the hinged chain; "cable": with its bending stiffness), pinned at the origin and
    released horizontally, integrated by generalized-alpha.  Returns ``(t, O_n - O_0)``."""
    import skfem_cable as sc

    L = STEEL["length"]
    sec = sc.Section.circular(radius=STEEL["radius"], E=STEEL["E"], rho=STEEL["density"])
    cable = sc.Cable.straight([0, 0, 0], [L, 0, 0], n_elements, sec, kind=kind)
    system = sc.System([cable]).pin(cable.node(0)).add_gravity([0, -STEEL["g"], 0])
    res = sc.simulate(system, t_end=t_end, dt=dt, rho_inf=rho_inf)
    return res.t, res.position(cable, L)


def ancf_comparison(cases=(("truss", 11, 11), ("truss", 44, 44), ("cable", 44, 44)),
                    t_end=1.0, windows=(0.4, 1.0)):
    """Largest free-end distance between the ANCF model and the rod chain over
    ``t <= w`` (relative to the length): ``{(kind, elements, rods): (d_w for w in windows)}``.
    The rod chain's 1e-4 s output grid is the ANCF step, so the samples coincide."""
    out = {}
    chains = {}
    for kind, n_el, n_rods in cases:
        if n_rods not in chains:
            chains[n_rods] = free_end_trajectory(n_rods, t_end, output_dt=1e-4)
        t, rods = chains[n_rods]
        _, ancf = ancf_free_end_trajectory(kind, n_el, t_end)
        d = np.linalg.norm(ancf - rods, axis=1) / STEEL["length"]
        out[(kind, n_el, n_rods)] = tuple(d[t <= w + 1e-12].max() for w in windows)
    return out


def paper_chain(compression=True):
    """The paper's energy experiment: 20 rods of 0.1 kg, 1 m, 1 mm^2, E = 1 GPa."""
    return RodChain.uniform(20, mass=0.1, length=1.0, E=1e9, A=1e-6, compression=compression)


def paper_state(n=20):
    """Straight along -y, every rod vector turning at 1 rad/s about z: q' = (1, 0, 0) m/s."""
    return np.tile([0.0, -1.0, 0.0], (n, 1)), np.tile([1.0, 0.0, 0.0], (n, 1))


def energy_error(dt=1e-4, t_end=5.0, method="rk4", compression=True, **kwargs):
    """Largest relative total-energy error ``|E(t) - E(0)| / |E(0)|`` (Eq. 31) of the paper's
    energy experiment (potential zero at ``O_0``)."""
    res = paper_chain(compression).simulate(*paper_state(), t_end, dt,
                                            gravity=(0.0, -STEEL["g"], 0.0), method=method,
                                            **kwargs)
    E = res.energy["total"]
    return np.abs(E - E[0]).max() / abs(E[0])


def transverse_frequencies(chain, q_eq, gravity, h=1e-6):
    """Frequencies (rad/s, ascending) of the rod chain linearised about ``q_eq`` hanging
    along ``-y``: central differences of the x-accelerations for rotations of single rods
    about z, which keep the rod lengths (a length change would bring in the stiff axial
    force at O(h^2))."""
    n = chain.n
    J = np.empty((n, n))
    for j in range(n):
        acc = []
        for angle in (h, -h):
            c, s = np.cos(angle), np.sin(angle)
            q = q_eq.copy()
            q[j, :2] = [c * q_eq[j, 0] - s * q_eq[j, 1], s * q_eq[j, 0] + c * q_eq[j, 1]]
            acc.append(chain.acceleration(q, gravity=gravity)[:, 0])
        J[:, j] = (acc[0] - acc[1]) / (2 * np.linalg.norm(q_eq[j]) * np.sin(h))
    return np.sort(np.sqrt(np.linalg.eigvals(-J).real))


def oscillation_table(ns=(5, 10, 20, 40, 80), length=20.0, modes=3):
    """Small oscillations of a stiff hanging chain (1 kg, strain 1e-8): the linearised rod
    chain against the rigid-link chain and the continuous chain, ``omega_k = (j_{0,k} / 2)
    sqrt(g / L)`` with ``j_{0,k}`` the zeros of Bessel ``J0``.  Returns ``{n: (rod-chain /
    rigid - 1, rod-chain / continuous - 1)}``, arrays over the first ``modes`` modes."""
    g = np.array([0.0, -STEEL["g"], 0.0])
    w_cont = jn_zeros(0, modes) / 2 * np.sqrt(STEEL["g"] / length)
    out = {}
    for n in ns:
        chain = RodChain.uniform(n, mass=1.0 / n, length=length / n, E=1e9, A=1.0)
        q = chain.static_equilibrium(g)
        w = transverse_frequencies(chain, q, g)[:modes]
        w_rigid = rigid_chain_frequencies(chain.masses, np.linalg.norm(q, axis=1),
                                          STEEL["g"])[:modes]
        out[n] = (w / w_rigid - 1, w / w_cont - 1)
    return out


if __name__ == "__main__":
    for key, value in main().items():
        print(f"{key:>24s}: {value}")
    flags = sys.argv[1:]
    if "--energy" in flags:
        print("paper's energy experiment, max relative energy error (Eq. 31):")
        for dt in (8e-4, 4e-4, 2e-4, 1e-4, 5e-5):
            print(f"  rk4 dt = {dt:.0e}: {energy_error(dt, output_every=1):.3e}")
        for method, rtol in (("RK45", 1e-3), ("RK45", 1e-6), ("RK45", 1e-8), ("DOP853", 1e-8)):
            err = energy_error(1e-3, method=method, rtol=rtol, atol=1e-2 * rtol)
            print(f"  {method} rtol = {rtol:.0e}: {err:.3e}")
        print(f"  slack rods (compression=False), rk4 dt = 1e-4: "
              f"{energy_error(1e-4, compression=False):.3e}")
    if "--oscillations" in flags:
        print("hanging-chain frequencies: rod chain / rigid links - 1 | / continuous - 1:")
        for n, (rigid, cont) in oscillation_table().items():
            print(f"  n = {n:3d}: " + " ".join(f"{x:9.2e}" for x in rigid) + " | "
                  + " ".join(f"{x:9.2e}" for x in cont))
    if "--ancf" in flags:
        print("free end, ANCF vs rod chain, max distance / length (t <= 0.4 s, 1 s):")
        for (kind, n_el, n_rods), d in ancf_comparison().items():
            print(f"  {kind:5s} {n_el:3d} elements vs {n_rods:3d} rods: "
                  + "  ".join(f"{x:.3e}" for x in d))
    if "--convergence" in flags:
        print("free-end distance to the finest chain / length (t <= 0.25 s, 0.4 s, 1 s):")
        for n, d in n_convergence().items():
            print(f"  n = {n:3d}: " + "  ".join(f"{x:.3e}" for x in d))
