"""Swinging steel chain: a rod-chain tether released from horizontal under gravity (the
``hanging-chain`` scene of ``skfem-cable run``).

Eleven steel rods (density 7801 kg/m^3, radius 1 mm, rest length 0.1 m, E = 207 GPa: the
paper's second experiment) joined by frictionless spherical hinges hang from a fixed point
``O_0``.  At ``t = 0`` the chain lies straight and horizontal along ``+x``, at rest, and
falls under gravity ``g = 9.81 m/s^2`` along ``-y``.  (The paper's initial state, straight
along ``-y`` and at rest with gravity along ``-y``, is an equilibrium and does not move;
the horizontal release is that geometry with gravity turned by 90 degrees.)  The chain
swings down like a pendulum whose lower links lag behind, then whips past the vertical:
the free end reaches about 12 m/s.  The rods are so stiff (``EA = 6.5e5 N``) that their
strain stays below 1e-5, and the chain moves like a chain of rigid links.

RK4 needs steps below ``2 sqrt(2) / omega_max`` (1.6e-5 s here, not the paper's 1e-4 s);
the run is checked against the independent rigid-link chain (``rigid_chain``) and against
RK4 with half the step.
"""

import numpy as np

from ..rodchain import RodChain, rk4_step
from .rigid_chain import rigid_chain_trajectory

STEEL = {"density": 7801.0, "radius": 1e-3, "E": 207e9, "length": 1.1, "g": 9.81}

#: Gravity of the scene (m/s^2), along -y.
GRAVITY = (0.0, -STEEL["g"], 0.0)

#: Time between two frames of the VTU series written by ``run`` (s).
SERIES_DT = 0.01


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


def simulate_release(n_rods=11, t_end=1.0, output_dt=1e-4, dt=None, method="rk4", **kwargs):
    """The released steel chain of ``n_rods`` rods, saved every ``output_dt`` (s).

    ``dt``: the RK4 step (default ``rk4_step(chain, output_dt)``, 1.11e-5 s for 11 rods);
    adaptive ``method``s use ``output_dt``; ``kwargs`` go to ``RodChain.simulate``
    (``observers``, ``rtol``, ...).  Returns the ``RodChainResult``.
    """
    chain = steel_chain(n_rods)
    step = rk4_step(chain, output_dt) if dt is None else dt
    if method != "rk4":
        step = output_dt
    every = int(round(output_dt / step))
    return chain.simulate(*release_state(chain), t_end, step, gravity=GRAVITY, method=method,
                          output_every=every, **kwargs)


def free_end_trajectory(n_rods=11, t_end=1.0, dt=None, output_dt=1e-4, method="rk4", **kwargs):
    """Free-end trajectory ``(t, O_n - O_0)`` of the released steel chain, for comparison
    with other models (``simulate_release``; gravity along ``-y``, released along ``+x``)."""
    res = simulate_release(n_rods, t_end, output_dt, dt, method, **kwargs)
    return res.t, res.free_end


def key_numbers(result, half_step=True):
    """Key numbers of a released steel chain run (``simulate_release``, RK4): the distance
    of the free end to the rigid-link reference and to RK4 with half the step (relative to
    the length), the energy drift relative to the largest kinetic energy, strains, the
    top speed and lowest point of the free end."""
    chain = result.chain
    t_end = float(result.t[-1])
    output_dt = float(result.t[1] - result.t[0])
    _, rigid = rigid_chain_trajectory(chain.masses, chain.lengths, t_end, output_dt,
                                      STEEL["g"])
    L = chain.rest_length
    dev = np.linalg.norm(result.free_end - rigid, axis=1)
    E = result.energy["total"]
    strain = result.tension / chain.EA
    out = {"n_rods": chain.n, "rk4_dt": result.stats["dt"], "stable_dt": chain.stable_dt(),
           "rk4_runtime_s": result.stats["wall_time"],
           "max_dev_rigid_rel": dev.max() / L,
           "max_dev_rigid_time": result.t[dev.argmax()]}
    if half_step:
        dt = result.stats["dt"]
        half = chain.simulate(*release_state(chain), t_end, dt / 2, gravity=GRAVITY,
                              output_every=2 * int(round(output_dt / dt)))
        out["max_dev_half_step_rel"] = np.abs(result.free_end - half.free_end).max() / L
    out.update({"energy_drift_rel": np.abs(E - E[0]).max() / result.energy["kinetic"].max(),
                "max_strain": strain.max(), "min_strain": strain.min(),
                "max_tip_speed": np.linalg.norm(result.joint_velocities[:, -1], axis=1).max(),
                "lowest_tip_y": result.free_end[:, 1].min(),
                "final_tip": result.free_end[-1]})
    return out


def main(n_rods=11, t_end=1.0, output_dt=1e-4):
    """Simulate the released steel chain and return its ``key_numbers`` (lengths in m)."""
    return key_numbers(simulate_release(n_rods, t_end, output_dt))


def run(options):
    """The ``hanging-chain`` scene of ``skfem-cable run``: the released steel chain into
    the run directory ``options.out`` (``rodchain.run.run_chain``: VTU series every
    ``SERIES_DT``, ``summary.json`` with ``key_numbers``, plots).  ``--elements`` is the
    number of rods (default 11), ``--dt`` the spacing of the saved steps (default 1e-4 s;
    the RK4 step follows from the stability limit), ``--t-end`` the duration (1 s)."""
    from ..rodchain.run import run_chain

    chain = steel_chain(options.value("elements", 11))
    dt = options.value("dt", 1e-4)
    defaults = {"t_end": 1.0, "dt": dt, "series_every": max(1, int(round(SERIES_DT / dt)))}
    parameters = {"n_rods": chain.n, "output_dt": dt, "material": STEEL,
                  "release": "straight along +x, at rest; gravity along -y"}
    return run_chain("hanging-chain", chain, release_state(chain), options, defaults,
                     loads={"gravity": GRAVITY}, parameters=parameters,
                     outputs=lambda result: {"reference": key_numbers(result)})[0]
