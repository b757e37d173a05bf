"""A mooring line in a current: Morison drag, buoyancy, the settled shape and the transient.

A line of unstretched length ``L = 100 m`` (diameter 5 cm, 10 kg/m, ``EA = 1e7 N``, no
bending stiffness: the ``truss`` law) hangs in water (1025 kg/m^3) between two fixed points
at the same depth, 80 m apart.  Its submerged weight is
``w = (mu - rho pi d^2 / 4) g = 78.4 N/m`` (``Gravity`` plus ``Buoyancy``).  A uniform
current of 1 m/s along the span loads it with Morison drag per unit unstretched length

    f = rho d C_dn |u_n| u_n / 2 + rho pi d C_dt |u_t| u_t / 2,   u = U - r_dot

(``MorisonDrag``, ``C_dn = 1.2``, ``C_dt = 0.1``; MoorDyn's convention), 30.75 N/m on a
line across the flow: the line blows downstream, the downstream end takes more tension.

* ``settled``: the equilibrium in the current, by ``solve_static`` (the line is at rest,
  the current is a real load), started from the elastic catenary in still water;
* ``switched_on``: the current switched on at ``t = 0`` on the line resting in still
  water, integrated in time (generalized-alpha): the drag both drives and damps the
  motion, which settles on the static shape.

The settled state is checked against the cable equilibrium equations solved to 1e-10 by
``scipy.integrate.solve_bvp`` (``tests/test_drag.py``) and against MoorDyn
(``benchmarks/mooring_moordyn.py``).  Run ``python demos/mooring_current.py``.
"""

import numpy as np
from scipy.integrate import solve_bvp
from skfem import MeshLine

import skfem_cable as sc
from skfem_cable.analysis.analytic import elastic_catenary
from skfem_cable.bodies.catenary import green_stretch

#: The line, the water and the current (SI units); ``x`` along the span, ``z`` up.
LINE = {"length": 100.0, "span": 80.0, "diameter": 0.05, "mass_per_length": 10.0,
        "EA": 1e7, "rho_water": 1025.0, "g": 9.81, "cd_normal": 1.2, "cd_tangential": 0.1,
        "current": 1.0}


def submerged_weight(p=LINE):
    """Weight minus buoyancy per unit unstretched length (N/m)."""
    return (p["mass_per_length"] - p["rho_water"] * np.pi * p["diameter"] ** 2 / 4) * p["g"]


def section(p=LINE):
    """The line's section: area of the diameter, density and modulus giving ``mu, EA``."""
    area = np.pi * p["diameter"] ** 2 / 4
    return sc.Section(E=p["EA"] / area, A=area, I=area**2 / (4 * np.pi),
                      rho=p["mass_per_length"] / area)


def build(n_elements, current=None, p=LINE):
    """The line pinned at ``(0, 0, 0)`` and ``(span, 0, 0)``, in the elastic catenary of
    still water, with gravity, buoyancy and Morison drag in ``current`` (3,) (default
    ``(U, 0, 0)``): ``(system, cable)``."""
    current = [p["current"], 0.0, 0.0] if current is None else current
    s = np.linspace(0.0, p["length"], n_elements + 1)
    xz, T, H, VA = elastic_catenary(s, p["span"], 0.0, p["length"], submerged_weight(p),
                                    p["EA"])
    w = submerged_weight(p)
    force = np.column_stack([np.full_like(s, H), w * s - VA])  # along the tangent
    slopes = force / np.hypot(*force.T)[:, None]
    zero = np.zeros_like(s)
    cable = sc.Cable(MeshLine(s), section(p), np.column_stack([xz[:, 0], zero, xz[:, 1]]),
                     np.column_stack([slopes[:, 0], zero, slopes[:, 1]]), law="truss",
                     name="line")
    g = [0.0, 0.0, -p["g"]]
    system = sc.System([cable]).pin(cable.node(0)).pin(cable.node(-1)).add_gravity(g)
    system.add_load(sc.Buoyancy(cable, p["rho_water"], p["diameter"], g))
    system.add_load(sc.MorisonDrag(cable, p["rho_water"], p["diameter"], p["cd_normal"],
                                   p["cd_tangential"], current=current))
    return system, cable


def numbers(state, cable, p=LINE):
    """Tensions at both ends (N): the magnitudes of the pins' reactions, which balance the
    consistent nodal loads exactly (the strain recovered at an end node converges more
    slowly); sag below the supports (m) and the position of the line's midpoint
    ``s = L / 2`` (m; ``mid_x - span / 2`` is its downstream offset)."""
    s = np.linspace(0.0, cable.length, 8001)
    r = state.position(cable, s)
    mid = state.position(cable, cable.length / 2)
    a, b = (np.linalg.norm(lam) for lam in state.multipliers.values())
    return {"tension_a": float(a), "tension_b": float(b), "sag": float(-r[:, 2].min()),
            "mid_x": float(mid[0]), "mid_z": float(mid[2])}


def settled(n_elements=20):
    """The equilibrium in the current (``solve_static``): ``(State, cable)``."""
    system, cable = build(n_elements)
    return sc.solve_static(system), cable


def switched_on(n_elements=20, t_end=60.0, dt=0.1, every=1):
    """The current switched on at ``t = 0`` on the line at rest in still water (every
    ``every``-th step saved): ``(Result, cable)``."""
    still, cable = build(n_elements, current=[0.0, 0.0, 0.0])
    start = sc.solve_static(still)
    system, cable = build(n_elements)
    initial = (start.q, np.zeros_like(start.q))
    return sc.simulate(system, t_end=t_end, dt=dt, rho_inf=0.8, initial=initial,
                       every=every), cable


def equilibrium(p=LINE, tol=1e-10):
    """The settled line from the equilibrium equations of an extensible cable without
    bending, an independent reference: with ``F(s)`` the force in the line at unstretched
    arc length ``s`` (tension ``T = |F|`` along the tangent ``t = F / T``),

        r' = (1 + e(T)) t,    F' = w e_z - f_drag(t),    r(0) = 0,  r(L) = (span, 0, 0)

    (``e = green_stretch(T, EA)``, the truss law's stretch; ``f_drag`` the Morison drag of
    the current on the line at rest), solved by ``scipy.integrate.solve_bvp`` to the
    relative residual ``tol`` from the still-water catenary.  Returns the numbers of
    ``numbers`` (same keys) and the solution (``sol(s)`` gives ``[r, F]``)."""
    L, span, w, EA = p["length"], p["span"], submerged_weight(p), p["EA"]
    k = 0.5 * p["rho_water"] * p["diameter"]
    kn, kt = k * p["cd_normal"], np.pi * k * p["cd_tangential"]
    U = np.array([p["current"], 0.0, 0.0])

    def rhs(s, y):
        T = np.linalg.norm(y[3:], axis=0)
        t = y[3:] / T
        ut = (U @ t) * t
        un = U[:, None] - ut
        f = kn * np.linalg.norm(un, axis=0) * un + kt * np.linalg.norm(ut, axis=0) * ut
        f[2] -= w
        return np.vstack([(1 + green_stretch(T, EA)) * t, -f])

    def ends(ya, yb):
        return np.concatenate([ya[:3], yb[:3] - [span, 0.0, 0.0]])

    s = np.linspace(0.0, L, 201)
    xz, _, H, VA = elastic_catenary(s, span, 0.0, L, w, EA)
    zero = np.zeros_like(s)
    guess = np.vstack([xz[:, 0], zero, xz[:, 1], np.full_like(s, H), zero, w * s - VA])
    sol = solve_bvp(rhs, ends, s, guess, tol=tol, max_nodes=100_000)
    if not sol.success:
        raise RuntimeError(f"equilibrium: solve_bvp failed: {sol.message}")
    z = sol.sol(np.linspace(0.0, L, 100_001))[2]
    mid = sol.sol(L / 2)
    return {"tension_a": float(np.linalg.norm(sol.y[3:, 0])),
            "tension_b": float(np.linalg.norm(sol.y[3:, -1])), "sag": float(-z.min()),
            "mid_x": float(mid[0]), "mid_z": float(mid[2])}, sol


def main(n_elements=20, t_end=60.0, dt=0.1):
    """The settled numbers and the end of the transient (same keys, ``transient_*``)."""
    state, cable = settled(n_elements)
    out = numbers(state, cable)
    result, cable = switched_on(n_elements, t_end, dt)
    last = numbers(result.state(-1), cable)
    out.update({f"transient_{k}": v for k, v in last.items()})
    out["path"] = result.stats["path"]
    return out


def gallery_figure(path):
    """The gallery's picture (``scripts/gallery.py``) into ``path``: a 1 m/s current
    switched on, the shapes every 2 s and the end tensions against the equilibrium
    equations."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    result, cable = switched_on(20, 40.0, 0.05, every=10)
    s = np.linspace(0.0, cable.length, 201)
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(8.0, 3.0), layout="constrained")
    for i, t in enumerate(result.t):
        if i % 4 == 0:
            r = result.state(i).position(cable, s)
            ax.plot(r[:, 0], r[:, 2], "-", color=str(0.8 - 0.8 * t / result.t[-1]), lw=0.8)
    reference, solution = equilibrium()
    y = solution.sol(s)
    ax.plot(y[0], y[2], "C3--", lw=1, label="solve_bvp, settled")
    ax.set(xlabel="x [m]", ylabel="z [m]", aspect="equal", ylim=(-30, 2))
    ax.legend(fontsize=8, loc="upper center")
    ends = [numbers(result.state(i), cable) for i in range(len(result.t))]
    bx.plot(result.t, [m["tension_a"] for m in ends], label="upstream")
    bx.plot(result.t, [m["tension_b"] for m in ends], label="downstream")
    for key in ("tension_a", "tension_b"):
        bx.axhline(reference[key], color="k", lw=0.6, ls=":")
    bx.set(xlabel="t [s]", ylabel="end tension [N]")
    bx.legend(fontsize=8)
    ax.set_title("1 m/s current switched on: shapes every 2 s", fontsize=10)
    bx.set_title("dotted: equilibrium equations", fontsize=10)
    fig.savefig(path, dpi=90, bbox_inches="tight", pad_inches=0.05)
    plt.close(fig)


if __name__ == "__main__":
    for key, value in main().items():
        print(f"{key:>20s}: {value}")
