"""Speed of the rod-chain tether: the O(n) mass solve against dense and sparse solvers, and
the cost of one RK4 step versus the number of rods.

Run ``python benchmarks/rodchain_speed.py [--quick]`` (``--quick``: n = 10, 10^3 and
10^4, a tenth of the RK4 steps per timed run).  Times are the best of several repeats of
averaged loops (seconds per call), right-hand sides of shape (n, 3) as in the equations of
motion.

Solvers of ``M x = b`` compared:

* ``O(n)``: ``RodChain.solve_mass`` (Eqs. 28-30, numba);
* ``LU``: ``numpy.linalg.solve`` on the dense ``M`` (LAPACK gesv, factorises every call,
  as a generic ODE code would for a non-constant mass matrix);
* ``chol``: ``scipy.linalg.cho_solve`` with ``M`` factorised once (LAPACK potrs, the best a
  dense method can do for a constant ``M``);
* ``splu``: the factored form ``x = Phi^{-1} G^{-1} Phi^{-T} b`` with the tridiagonal ``G``
  (Eq. 25) factorised once by SuperLU (``scipy.sparse.linalg.splu``);
* ``spsolve``: the same with ``scipy.sparse.linalg.spsolve`` (factorises every call).

Dense solvers run up to ``DENSE_MAX`` (M takes 8 n^2 bytes; LU costs O(n^3)).
"""

import time

import numpy as np
import scipy.sparse as sp
from scipy.linalg import cho_factor, cho_solve
from scipy.sparse.linalg import splu, spsolve

from skfem_cable.cli.bench import arguments
from skfem_cable.rodchain import RodChain

DENSE_MAX = 4000

#: Sizes of the two tables and the work (rods x steps) of one timed RK4 run.
SETTINGS = {
    "full": {"solve": (10, 20, 50, 100, 200, 500, 1000, 2000, 4000, 10_000, 30_000, 100_000),
             "rk4": (10, 30, 100, 300, 1000, 3000, 10_000, 30_000, 100_000), "work": 4e6},
    "quick": {"solve": (10, 1000, 10_000), "rk4": (10, 1000, 10_000), "work": 4e5},
}


def best_time(fn, budget=0.2, repeats=5):
    """Best over ``repeats`` of the mean time of a loop lasting about ``budget / repeats``."""
    fn()
    start = time.perf_counter()
    fn()
    once = max(time.perf_counter() - start, 1e-7)
    loops = max(1, int(budget / repeats / once))
    best = np.inf
    for _ in range(repeats):
        start = time.perf_counter()
        for _ in range(loops):
            fn()
        best = min(best, (time.perf_counter() - start) / loops)
    return best


def g_matrix(masses):
    """Tridiagonal ``G`` of Eq. 25 (sparse CSC)."""
    diag = masses / 3.0
    diag[:-1] += masses[1:] / 3.0
    off = masses[1:] / 6.0
    return sp.diags([off, diag, off], [-1, 0, 1], format="csc")


def factored_solve(solve_g, b):
    """``Phi^{-1} G^{-1} Phi^{-T} b`` with ``Phi^{-1} = I - eps`` (Eqs. 22, 28)."""
    y = b.copy()
    y[:-1] -= b[1:]
    z = solve_g(y)
    z[1:] -= z[:-1].copy()
    return z


def exponent(ns, ts, n_min):
    """Fitted log-log slope over the sizes ``>= n_min`` (the larger half if none is)."""
    n_min = min(n_min, sorted(ns)[len(ns) // 2])
    sel = [i for i, n in enumerate(ns) if n >= n_min and np.isfinite(ts[i])]
    return np.polyfit(np.log([ns[i] for i in sel]), np.log([ts[i] for i in sel]), 1)[0]


def solve_table(ns, budget=1.0):
    """Print the table of the solvers of ``M x = b``, each timed over ``budget`` times
    its share of the timing loops' seconds (0: each solve run once per repeat, for the
    figures other than the times).

    Returns
    -------
    dict
        ``rows`` (per ``n``: seconds per solve of each solver, ``None`` where not run, and
        ``diff_to_lu``) and ``growth_exponent`` of the O(n) solve for ``n >= 1000``.
    """
    rng = np.random.default_rng(0)
    print("M x = b, b of shape (n, 3): seconds per solve and ratios to the O(n) solve")
    head = ["n", "O(n)", "us/rod", "LU", "chol", "splu", "spsolve", "LU/O(n)", "chol/O(n)",
            "splu/O(n)", "diff to LU"]
    print(("{:>8s}" + "{:>11s}" * (len(head) - 1)).format(*head))
    rows = []
    for n in ns:
        chain = RodChain(rng.uniform(0.5, 2.0, n), np.ones(n), np.ones(n))
        b = rng.standard_normal((n, 3))
        t_fast = best_time(lambda chain=chain, b=b: chain.solve_mass(b), budget * 0.2)
        G = g_matrix(chain.masses)
        lu_g = splu(G)
        t_splu = best_time(lambda lu_g=lu_g, b=b: factored_solve(lu_g.solve, b), budget * 0.2)
        t_spsolve = best_time(lambda G=G, b=b: factored_solve(lambda y: spsolve(G, y), b),
                              budget=budget * 0.1, repeats=3)
        x_ref = factored_solve(lu_g.solve, b)
        assert np.allclose(chain.solve_mass(b), x_ref, rtol=1e-9, atol=1e-12 * np.abs(x_ref).max())
        t_lu = t_chol = diff = np.nan
        if n <= DENSE_MAX:
            M = chain.mass_matrix()
            x_lu = np.linalg.solve(M, b)
            diff = np.linalg.norm(chain.solve_mass(b) - x_lu) / np.linalg.norm(x_lu)
            t_lu = best_time(lambda M=M, b=b: np.linalg.solve(M, b), budget=budget * 0.3,
                             repeats=3)
            cf = cho_factor(M)
            t_chol = best_time(lambda cf=cf, b=b: cho_solve(cf, b), budget=budget * 0.2,
                               repeats=3)
        rows.append({"n": n, "o_n": t_fast, "lu": t_lu, "chol": t_chol, "splu": t_splu,
                     "spsolve": t_spsolve, "diff_to_lu": diff})
        row = [t_fast, 1e6 * t_fast / n, t_lu, t_chol, t_splu, t_spsolve,
               t_lu / t_fast, t_chol / t_fast, t_splu / t_fast, diff]
        print(f"{n:8d}" + "".join(f"{x:11.3g}" if np.isfinite(x) else f"{'-':>11s}" for x in row))
    slope = exponent(ns, [r["o_n"] for r in rows], 1000)
    print(f"growth exponent of the O(n) solve for n >= 1000: {slope:.2f}")
    print("(diff to LU: |x - x_LU| / |x_LU|, dominated by LU's own error ~ cond(M) eps ~ n^2 eps)")
    return {"rows": rows, "growth_exponent": slope}


def rk4_table(ns, work=4e6):
    """Print the table of the RK4 step; one timed run takes ``min(work / 200, work / n)``
    steps (at least 4).

    Returns
    -------
    dict
        ``rows`` (per ``n``: ``steps``, seconds per step ``s_per_step`` and, with a callable
        line load, ``callable_s_per_step``, ``None`` where not run) and ``growth_exponent``
        for ``n >= 1000``.
    """
    print("\nOne RK4 step (4 right-hand sides incl. the O(n) solve), hanging chain")
    head = ["n", "steps", "s/step", "us/rod", "callable s/step", "callable/plain"]
    print(("{:>8s}" + "{:>16s}" * (len(head) - 1)).format(*head))
    g = np.array([0.0, -9.81, 0.0])
    rows = []
    for n in ns:
        chain = RodChain.uniform(n, mass=1e-3, length=1.0, E=1e11, A=1e-6)  # strain < 1 %
        q0 = chain.static_equilibrium(g)
        q0[:, 0] += 0.01  # a little transverse offset so that everything moves
        v0 = np.zeros_like(q0)
        dt = 0.5 * chain.stable_dt()
        steps = int(max(4, min(work / 200, work / n)))

        def run(steps=steps, chain=chain, q0=q0, v0=v0, dt=dt, **kw):
            chain.simulate(q0, v0, steps * dt, dt, gravity=g, output_every=steps, **kw)

        t_step = best_time(run, budget=0.5, repeats=3) / steps
        t_py = np.nan
        if n <= 10_000:  # a callable line load: Python RK4 loop and Gauss quadrature
            py_steps = max(4, steps // 20)

            def run_py(steps=py_steps, run=run):
                run(steps=steps, line_load=lambda t, r, v: np.zeros_like(r))

            t_py = best_time(run_py, budget=0.5, repeats=3) / py_steps
        rows.append({"n": n, "steps": steps, "s_per_step": t_step,
                     "callable_s_per_step": t_py})
        row = [t_step, 1e6 * t_step / n, t_py, t_py / t_step]
        print(f"{n:8d}{steps:16d}" + "".join(f"{x:16.3g}" if np.isfinite(x) else f"{'-':>16s}"
                                               for x in row))
    slope = exponent(ns, [r["s_per_step"] for r in rows], 1000)
    print(f"growth exponent of the RK4 step for n >= 1000: {slope:.2f}")
    return {"rows": rows, "growth_exponent": slope}


def main(argv=None):
    """Parse the arguments (``--quick``), print both tables and return their figures."""
    args = arguments(__doc__, "up to n = 10^4, fewer steps", argv)
    settings = SETTINGS["quick" if args.quick else "full"]
    return {"solve": solve_table(settings["solve"]),
            "rk4": rk4_table(settings["rk4"], settings["work"])}


if __name__ == "__main__":
    main()
