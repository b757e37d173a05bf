"""Cost of element laws written as energy densities: generated kernels against the
hand-written one, a user law, the scikit-fem forms path and (``--jax``) JAX.

Method.  One free cable ``Cable.straight([0, 0, 0], [L, 0, 0], n, section)`` with a damped
section (``gamma_axial = gamma_bending = 0.01 s``) is evaluated at a random perturbation
``q`` of ``q0`` and random velocities ``v`` (the same in every process: the seed is
``n``).  One evaluation is the force and the tangent ``cK K + cC C`` (``cK = 1``,
``cC = 0.5``), ``system.evaluate(q, v, 0.0, np.zeros(0), cK=1.0, cC=0.5, data=data)``,
for

(a) the built-in law, generated and compiled by ``laws.codegen`` (this working tree);
(b) the hand-written numba kernel of ``--base`` (default ``93f5041``, the last commit
    before the laws), checked out with ``git worktree add`` into a temporary folder and
    imported through ``PYTHONPATH`` (as ``benchmarks/commit_compare.py`` does);
(c) user laws: the Biot law ``EA (|a| - 1)^2 / 2 + EI kappa^2 / 2``, undamped, and the
    same with the power-law dissipation ``c EA |e_dot|^3 / 3`` of ``demos/law_gallery.py``;
(d) the scikit-fem forms of the built-in law, ``skfem.asm(L, cable.basis, **state)`` and
    ``skfem.asm(a, cable.basis, **state)`` with ``L, a = forms.internal(cable)`` and
    ``state = forms.state(cable, q, v)`` (and, in a second row, also the damping form
    ``forms.damping(cable)``, which the kernel's ``cC C`` corresponds to).

Every case runs in a fresh Python process per size and repeat (alternating the cases); a
process makes one untimed call (compilation or cache load), times one call to choose the
number of calls filling ``--seconds``, and reports the mean over these calls; the table
gives the minimum over ``--repeats`` processes, in ms per evaluation, and the ratio to
(a).  The forces and tangents of the first repeat are compared with (a) (maximum
difference relative to the largest entry).

One-off costs: in a process with empty, temporary ``SKFEM_CABLE_CACHE`` and
``NUMBA_CACHE_DIR``, the time to import ``skfem_cable``, to build the law's sympy
expressions, to derive, generate and import its module (``law.compiled()``) and to compile
its kernel (the first evaluation of a 60-element cable less a second: the law's ``span``,
the one element loop of the laws and the system's terms module, ``laws.codegen``; for the
hand-written kernel of the base tree its ``force_tangent``); then the same in a second
process with the same (now filled) folders: the load time of a cached law.

``--jax``: the alternative route, JAX computing the gradient and Hessian of the Green
law's density ``W = EA eps^2 / 2 + EI kappa^2 / 2`` (``eps = (|a|^2 - 1) / 2``, ``kappa^2
= |a x b|^2 / |a|^6``) at all Gauss points (5 per element) with ``jax.jit(jax.vmap(...))``
of ``jax.grad`` and ``jax.hessian`` (x64, CPU), against the generated ``point_gh`` called
in a numba loop over the same points and the whole compiled kernel (force and tangent,
undamped).  JAX's time excludes the chain rule and the scatter, which would still need
compiled loops; its first call traces and compiles (again for every new number of points).

Run ``python benchmarks/laws.py [--base 93f5041] [--repeats 5] [--jax] [--quick]``
(``--quick``: sizes 60 and 1000, one repeat, 0.1 s per process, unless given).  Machines
are noisy: read the ratios, not the absolute times.
"""

import argparse
import importlib.util
import json
import math
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
import scipy.sparse as sps

ROOT = Path(__file__).resolve().parents[1]
SIZES = (60, 1000, 6000)

#: The last commit with the hand-written kernel (``kernels/cable.py`` compiled by itself).
BASE = "93f5041"

#: Shared head of the snippets run in subprocesses: the section, the perturbed state, the
#: user laws (only in a tree that has ``cable_law``) and the timer.
COMMON = r"""
import inspect, json, math, sys, time
import numpy as np
import skfem_cable as sc

LENGTH = 1000.0
SECTION = sc.Section(E=7e10, A=4.28e-9, I=1.47e-18, rho=7653.0,
                     gamma_axial=0.01, gamma_bending=0.01)
CK, CC = 1.0, 0.5


def perturbed(q0, n):
    rng = np.random.default_rng(n)
    return (q0 + 1e-3 * rng.standard_normal(q0.size), 1e-2 * rng.standard_normal(q0.size))


# the paper's formulation (every term on the Gauss rule of the basis), the base tree's only
# one and the one the scikit-fem forms give, where the tree has others
PAPER = {"formulation": "paper"} if "formulation" in inspect.signature(sc.Cable).parameters else {}


def evaluation(system, q, v, data):
    # a call of system.evaluate at (q, v) with the tangent into data, given the layout
    # where the tree's evaluate takes it (since 085fe95; the base tree's does not)
    lam = np.zeros(0)
    layout = ({"layout": system.layout}
              if "layout" in inspect.signature(system.evaluate).parameters else {})
    return lambda: system.evaluate(q, v, 0.0, lam, cK=CK, cC=CC, data=data, **layout)


def mean_time(fn, seconds):
    start = time.perf_counter()
    fn()
    one = time.perf_counter() - start
    calls = max(3, math.ceil(seconds / max(one, 1e-9)))
    start = time.perf_counter()
    for _ in range(calls):
        fn()
    return (time.perf_counter() - start) / calls, calls


if hasattr(sc, "cable_law"):
    from skfem_cable import laws

    @sc.cable_law
    def biot(a, b, EA, EI):
        e = laws.norm(a) - 1
        return EA * e**2 / 2 + EI * laws.kappa2(a, b) / 2

    def power_law(a, b, ad, bd, EA, c, n=2.0):
        e_dot = laws.dot(a, ad) / laws.norm(a)
        return c * EA * laws.Abs(e_dot) ** (n + 1) / (n + 1)

    LAWS = {"builtin": laws.green, "biot": biot,
            "biot_damped": biot.with_dissipation(power_law).with_parameters(c=1e-6)}
"""

#: Per-evaluation cost of one case: ``kernel`` (the tree's default law, so the same code
#: runs on the base tree), ``biot``, ``biot_damped``, ``forms`` or ``forms_damped``.
EVALUATE = COMMON + r"""
import scipy.sparse as sps
import skfem

case, n, seconds, save = sys.argv[1], int(sys.argv[2]), float(sys.argv[3]), sys.argv[4]
kwargs = {"law": LAWS[case]} if case.startswith("biot") else {}
cable = sc.Cable.straight([0, 0, 0], [LENGTH, 0, 0], n, SECTION, **kwargs, **PAPER)
system = sc.System([cable])
q, v = perturbed(system.q0, n)
nd = cable.n_dofs
if case.startswith("forms"):
    L, a = sc.forms.internal(cable)
    c = sc.forms.damping(cable)

    def evaluate():
        w = sc.forms.state(cable, q, v)
        out = [skfem.asm(L, cable.basis, **w), skfem.asm(a, cable.basis, **w)]
        if case == "forms_damped":
            out.append(skfem.asm(c, cable.basis, **w))
        return out

    out = evaluate()
    f = out[0]
    C = out[2] if len(out) > 2 else skfem.asm(c, cable.basis, **sc.forms.state(cable, q, v))
    K = CK * out[1] + CC * C
else:
    data = np.zeros(system.layout.nnz)
    evaluate = evaluation(system, q, v, data)

    f = evaluate()[0][:nd].copy()
    K = system.layout.matrix(data)[:nd, :nd]
if save:
    np.save(save + ".npy", f)
    sps.save_npz(save + ".npz", sps.csr_matrix(K))
mean, calls = mean_time(evaluate, seconds)
print(json.dumps({"ms": 1e3 * mean, "calls": calls, "file": sc.__file__}))
"""

#: One-off costs of a law (``builtin``, ``biot``, ``biot_damped``) or of the hand-written
#: kernel (``base``), with the caches given by the environment.
ONE_OFF = r"""
import time
start = time.perf_counter()
import skfem_cable
import_time = time.perf_counter() - start
""" + COMMON + r"""
name = sys.argv[1]
n = 60
sym = gen = None
if name == "base":  # the hand-written kernel, called by itself
    from skfem_cable.kernels import cable as module
    cable = sc.Cable.straight([0, 0, 0], [LENGTH, 0, 0], n, SECTION)
    params = (SECTION.EA, SECTION.EI, SECTION.gamma_axial, SECTION.gamma_bending)
    q, v = perturbed(cable.q0, n)
    elements = tuple(np.ascontiguousarray(t) for t in (
        cable.element_dofs.astype(np.int64), cable.Sx, cable.Sxx, cable.weights, cable.h))
    scatter = np.arange(n * 144, dtype=np.int64).reshape(n, 12, 12)
    out = (np.zeros(q.size), np.zeros(q.size), np.zeros(n * 144), scatter, np.zeros(2),
           np.zeros(2))

    def evaluate():
        module.force_tangent((q, v), elements, params, out, (CK, CC))
else:  # a law: its span, the one element loop and the system's terms module
    law = LAWS[name]
    start = time.perf_counter()
    law.symbolic
    sym = time.perf_counter() - start
    start = time.perf_counter()
    law.compiled()
    gen = time.perf_counter() - start
    system = sc.System([sc.Cable.straight([0, 0, 0], [LENGTH, 0, 0], n, SECTION, law=law)])
    q, v = perturbed(system.q0, n)
    evaluate = evaluation(system, q, v, np.zeros(system.layout.nnz))
times = []
for _ in range(2):
    start = time.perf_counter()
    evaluate()
    times.append(time.perf_counter() - start)
# (a first call that compiles nothing, its kernels cached, costs a second's: the difference
# is then the timer's noise, either sign)
print(json.dumps({"import": import_time, "sym": sym, "gen": gen,
                  "jit": max(times[0] - times[1], 0.0)}))
"""

#: G and H of the Green law at all Gauss points: JAX against the generated numba code.
JAX = COMMON + r"""
import jax
jax.config.update("jax_enable_x64", True)
import jax.numpy as jnp
import numba
from skfem_cable.laws import SLOPE_FLOOR

n, seconds = int(sys.argv[1]), float(sys.argv[2])
cable = sc.Cable.straight([0, 0, 0], [LENGTH, 0, 0], n, SECTION)
system = sc.System([cable])
q, _ = perturbed(system.q0, n)
law = laws.green
point_gh = law.compiled().point_gh
prm = np.array(law.parameter_values(SECTION))
qe = q[cable.element_dofs].reshape(n, 4, 3)
X = np.concatenate([np.einsum("egk,eki->egi", cable.Sx, qe),
                    np.einsum("egk,eki->egi", cable.Sxx, qe)], axis=-1).reshape(-1, 6)
hp = np.repeat(cable.h, cable.Sx.shape[1])
G, H = np.empty((len(X), 6)), np.empty((len(X), 6, 6))


@numba.njit
def all_points(X, prm, h, G, H):
    for k in range(X.shape[0]):
        point_gh(X[k], prm, h[k], G[k], H[k])


def energy(x, EA, EI):
    a, b = x[:3], x[3:]
    p = a @ a
    eps = (p - 1) / 2
    axb = jnp.cross(a, b)
    return EA * eps**2 / 2 + EI * (axb @ axb) / jnp.maximum(p, SLOPE_FLOOR) ** 3 / 2


gh = jax.jit(jax.vmap(lambda x, EA, EI: (jax.grad(energy)(x, EA, EI),
                                         jax.hessian(energy)(x, EA, EI)),
                      in_axes=(0, None, None)))
EA, EI = SECTION.EA, SECTION.EI
Xj = jax.device_put(X)
start = time.perf_counter()
Gj, Hj = jax.block_until_ready(gh(Xj, EA, EI))
first = time.perf_counter() - start
jax_device, _ = mean_time(lambda: jax.block_until_ready(gh(Xj, EA, EI)), seconds)
jax_numpy, _ = mean_time(lambda: [np.asarray(r) for r in gh(X, EA, EI)], seconds)
all_points(X, prm, hp, G, H)
numba_points, _ = mean_time(lambda: all_points(X, prm, hp, G, H), seconds)
data = np.zeros(system.layout.nnz)
lam = np.zeros(0)
system.evaluate(q, None, 0.0, lam, data=data)
kernel, _ = mean_time(lambda: system.evaluate(q, None, 0.0, lam, data=data,
                                              layout=system.layout), seconds)
diff = max(np.abs(np.asarray(Gj) - G).max() / np.abs(G).max(),
           np.abs(np.asarray(Hj) - H).max() / np.abs(H).max())
print(json.dumps({"points": len(X), "first": first, "jax": 1e3 * jax_device,
                  "jax_numpy": 1e3 * jax_numpy, "numba_points": 1e3 * numba_points,
                  "kernel": 1e3 * kernel, "diff": float(diff),
                  "backend": jax.default_backend()}))
"""

#: Rows of the per-evaluation table: (label, tree ("here"/"base"), snippet case).
ROWS = (
    ("(a) built-in law, generated (this tree)", "here", "kernel"),
    ("(b) hand-written kernel (base)", "base", "kernel"),
    ("(c) user law: Biot, undamped", "here", "biot"),
    ("(c) user law: Biot + power-law damping", "here", "biot_damped"),
    ("(d) scikit-fem forms: L + a", "here", "forms"),
    ("(d) scikit-fem forms: L + a + damping", "here", "forms_damped"),
)

#: Rows of the one-off table: (label, tree, law).
ONE_OFF_ROWS = (
    ("built-in law (Green + Kelvin-Voigt)", "here", "builtin"),
    ("user law: Biot, undamped", "here", "biot"),
    ("user law: Biot + power-law damping", "here", "biot_damped"),
    ("hand-written kernel (base)", "base", "base"),
)


def run(snippet, args, tree, env=None):
    """Run ``snippet`` with ``args`` in a fresh interpreter importing ``skfem_cable`` from
    ``tree``.

    Parameters
    ----------
    snippet : str
        Python source; its last printed line is a JSON object.
    args : sequence
        Command-line arguments of the snippet.
    tree : Path
        Root of the checkout to import (``PYTHONPATH`` and working directory).
    env : dict, optional
        Extra environment variables (cache folders).

    Returns
    -------
    dict
        The decoded JSON line.
    """
    environ = dict(os.environ, PYTHONPATH=str(tree), **(env or {}))
    proc = subprocess.run([sys.executable, "-c", snippet, *map(str, args)], env=environ,
                          cwd=tree, capture_output=True, text=True)
    if proc.returncode != 0:
        raise RuntimeError(f"benchmark process failed ({args}):\n{proc.stderr[-3000:]}")
    return json.loads(proc.stdout.strip().splitlines()[-1])


def relative_difference(path, reference):
    """Largest difference of the saved force and tangent at ``path`` from those at
    ``reference``, each relative to the largest entry of the reference.

    Returns
    -------
    tuple of float
        ``(force, tangent)``.
    """
    f, fa = np.load(f"{path}.npy"), np.load(f"{reference}.npy")
    K, Ka = sps.load_npz(f"{path}.npz"), sps.load_npz(f"{reference}.npz")
    return (float(np.abs(f - fa).max() / np.abs(fa).max()),
            float(abs(K - Ka).max() / abs(Ka).max()))


def evaluation_costs(trees, tmp, sizes, repeats, seconds, env):
    """Minimum over ``repeats`` fresh processes of the mean ms per evaluation of every row
    of ``ROWS`` at every size, and the differences of the results from row (a).

    Returns
    -------
    times : dict
        ``{(case label, n): ms}``.
    checks : dict
        ``{(case label, n): (force, tangent)}`` relative differences from (a) (``None``
        for another law).
    """
    times, checks = {}, {}
    for n in sizes:
        for rep in range(repeats):
            for label, tree, case in ROWS:
                save = str(tmp / f"{tree}-{case}-{n}") if rep == 0 else ""
                out = run(EVALUATE, (case, n, seconds, save), trees[tree], env)
                if not Path(out["file"]).resolve().is_relative_to(trees[tree].resolve()):
                    raise RuntimeError(f"{label}: imported {out['file']}, not {trees[tree]}")
                times[label, n] = min(times.get((label, n), math.inf), out["ms"])
        reference = tmp / f"here-kernel-{n}"
        for label, tree, case in ROWS:
            same_law = not case.startswith("biot")
            checks[label, n] = (relative_difference(tmp / f"{tree}-{case}-{n}", reference)
                                if same_law else None)
    return times, checks


def one_off_costs(trees, tmp):
    """Cold (empty caches) and cached one-off costs of every row of ``ONE_OFF_ROWS``.

    Returns
    -------
    dict
        ``{label: (cold, cached)}``, each the dict printed by ``ONE_OFF``.
    """
    rows = {}
    for label, tree, law in ONE_OFF_ROWS:
        env = {"SKFEM_CABLE_CACHE": str(tmp / f"cold-{law}" / "laws"),
               "NUMBA_CACHE_DIR": str(tmp / f"cold-{law}" / "numba")}
        rows[label] = tuple(run(ONE_OFF, (law,), trees[tree], env) for _ in range(2))
    return rows


def jax_costs(sizes, repeats, seconds, env):
    """JAX gradient and Hessian of the Green density at all Gauss points against the
    generated numba code: minimum over ``repeats`` fresh processes per size.

    Returns
    -------
    dict
        ``{n: dict printed by JAX}``.
    """
    rows = {}
    for n in sizes:
        runs = [run(JAX, (n, seconds), ROOT, env) for _ in range(repeats)]
        rows[n] = {k: (max if k == "diff" else min)(r[k] for r in runs)
                   if isinstance(runs[0][k], float) else runs[0][k] for k in runs[0]}
    return rows


def _seconds(value):
    return "-" if value is None else f"{value:.3f}"


def print_tables(sizes, times, checks, one_off, jax_rows):
    """Print the results as markdown tables."""
    print("### Cost of one evaluation (force + tangent), ms (ratio to (a))\n")
    print("| path | " + " | ".join(f"n = {n}" for n in sizes)
          + " | max rel. diff from (a), f / K |")
    print("|---|" + "---:|" * len(sizes) + "---|")
    first = ROWS[0][0]
    for label, _, _ in ROWS:
        cells = [f"{times[label, n]:.3f} ({times[label, n] / times[first, n]:.2f})"
                 for n in sizes]
        diffs = [checks[label, n] for n in sizes]
        check = ("other law" if diffs[0] is None else
                 f"{max(d[0] for d in diffs):.1e} / {max(d[1] for d in diffs):.1e}")
        print(f"| {label} | " + " | ".join(cells) + f" | {check} |")

    print("\n### One-off costs of a law, s (n = 60)\n")
    print("| law | import skfem_cable | sympy expressions | derive + generate + import "
          "| numba compile | total | cached: import | cached: expressions + load module "
          "| cached: numba load | cached: total |")
    print("|---|" + "---:|" * 9)
    for label, (cold, warm) in one_off.items():
        total = [sum(r[k] or 0.0 for k in ("sym", "gen", "jit")) for r in (cold, warm)]
        load = None if warm["gen"] is None else warm["sym"] + warm["gen"]
        print(f"| {label} | {cold['import']:.3f} | {_seconds(cold['sym'])} "
              f"| {_seconds(cold['gen'])} | {cold['jit']:.3f} | {total[0]:.3f} "
              f"| {warm['import']:.3f} | {_seconds(load)} | {warm['jit']:.3f} "
              f"| {total[1]:.3f} |")
    print("\n(Totals exclude the import.)")

    if jax_rows:
        backend = next(iter(jax_rows.values()))["backend"]
        print(f"\n### Green law: G and H at all Gauss points, JAX ({backend}, x64) against "
              "the generated numba code, ms per call\n")
        print("| n | points | JAX first call (trace + compile), s | JAX G+H | "
              "JAX G+H, numpy in/out | numba point_gh loop | numba full kernel f + K "
              "(undamped) | JAX / point loop | JAX / full kernel | max rel. diff |")
        print("|---:|" + "---:|" * 9)
        for n, r in jax_rows.items():
            print(f"| {n} | {r['points']} | {r['first']:.3f} | {r['jax']:.3f} "
                  f"| {r['jax_numpy']:.3f} | {r['numba_points']:.3f} | {r['kernel']:.3f} "
                  f"| {r['jax'] / r['numba_points']:.1f} | {r['jax'] / r['kernel']:.2f} "
                  f"| {r['diff']:.1e} |")


def records(times, checks, one_off, jax_rows):
    """The results as plain rows: ``evaluation`` (``path``, ``n``, ``ms``, ``ratio`` to
    (a), ``diff`` force / tangent or ``None``), ``one_off`` (``law``, ``cold``, ``cached``)
    and ``jax`` (``n`` and the figures)."""
    first = ROWS[0][0]
    return {"evaluation": [{"path": label, "n": n, "ms": ms, "ratio": ms / times[first, n],
                            "diff": checks[label, n]} for (label, n), ms in times.items()],
            "one_off": [{"law": label, "cold": cold, "cached": cached}
                        for label, (cold, cached) in one_off.items()],
            "jax": [{"n": n, **row} for n, row in jax_rows.items()]}


def main(argv=None):
    """Parse the arguments, run the measurements in a temporary folder, print them and
    return them (``records``)."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--base", default=BASE,
                        help="a commit with the hand-written kernel (no skfem_cable/laws)")
    parser.add_argument("--quick", action="store_true",
                        help="defaults --sizes 60 1000 --repeats 1 --seconds 0.1")
    parser.add_argument("--repeats", type=int, default=None, help="default 5")
    parser.add_argument("--sizes", type=int, nargs="+", default=None,
                        help=f"default {' '.join(map(str, SIZES))}")
    parser.add_argument("--seconds", type=float, default=None,
                        help="timed duration of each process (at least 3 calls; default 0.5)")
    parser.add_argument("--jax", action="store_true",
                        help="also time JAX's gradient and Hessian (if jax is installed)")
    args = parser.parse_args(argv)
    quick = {"repeats": 1, "sizes": [60, 1000], "seconds": 0.1}
    full = {"repeats": 5, "sizes": list(SIZES), "seconds": 0.5}
    for key, value in (quick if args.quick else full).items():
        if getattr(args, key) is None:
            setattr(args, key, value)
    use_jax = args.jax and importlib.util.find_spec("jax") is not None
    if args.jax and not use_jax:
        print("jax is not importable: skipping the JAX comparison", file=sys.stderr)
    with tempfile.TemporaryDirectory(prefix="skfem_cable-laws-") as name:
        tmp = Path(name)
        trees = {"here": ROOT, "base": tmp / "base"}
        subprocess.run(["git", "worktree", "add", "--detach", str(trees["base"]), args.base],
                       cwd=ROOT, check=True, capture_output=True)
        if (trees["base"] / "skfem_cable" / "laws").exists():
            subprocess.run(["git", "worktree", "remove", "--force", str(trees["base"])],
                           cwd=ROOT, check=False, capture_output=True)
            parser.error(f"--base {args.base} already has the element laws; give a commit "
                         f"with the hand-written kernel (e.g. {BASE})")
        env = {"SKFEM_CABLE_CACHE": str(tmp / "cache"), "NUMBA_CACHE_DIR": str(tmp / "numba")}
        try:
            one_off = one_off_costs(trees, tmp)
            times, checks = evaluation_costs(trees, tmp, args.sizes, args.repeats,
                                             args.seconds, env)
            jax_rows = (jax_costs(args.sizes, args.repeats, args.seconds, env)
                        if use_jax else {})
        finally:
            subprocess.run(["git", "worktree", "remove", "--force", str(trees["base"])],
                           cwd=ROOT, check=False, capture_output=True)
    print(f"base: {args.base}, repeats: {args.repeats}, CPUs: {os.cpu_count()}\n")
    print_tables(args.sizes, times, checks, one_off, jax_rows)
    return records(times, checks, one_off, jax_rows)


if __name__ == "__main__":
    main()
