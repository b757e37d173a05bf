"""Studies of the rod-chain model (``docs/rodchain.md``, section 5): the paper's energy
experiment, small oscillations of the hanging chain against rigid links and the continuous
chain, convergence in the number of rods, and the comparison with the ANCF truss and cable
models of the same steel tether (``hanging_chain``)."""

import numpy as np
from scipy.special import jn_zeros

from ..rodchain import RodChain
from .hanging_chain import STEEL, free_end_trajectory
from .rigid_chain import rigid_chain_frequencies


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
    from ..bodies.cable import Cable
    from ..bodies.section import Section
    from ..model.system import System
    from ..solvers.simulate import simulate

    L = STEEL["length"]
    sec = Section.circular(radius=STEEL["radius"], E=STEEL["E"], rho=STEEL["density"])
    cable = Cable.straight([0, 0, 0], [L, 0, 0], n_elements, sec, law=kind)
    system = System([cable]).pin(cable.node(0)).add_gravity([0, -STEEL["g"], 0])
    res = simulate(system, t_end=t_end, dt=dt, rho_inf=rho_inf)
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
