"""What one Python term costs the compiled step (issue 46, must-show 2).

The E-sail rig of ``commit_compare`` (12 tethers x 5 elements, rigid hub, solar wind,
``dt = 0.1 s``) with the ``NodeSpring`` of ``docs/extending.md`` on the tip of its first
tether (a Python ``add`` hook, anchored at the tip's start, ``k = 1e-4 N/m``), against the
same rig with the spring's compiled twin; alternately, ``--repeats`` times, in one process
(numba caches warm: one untimed run of each first).  The cost per step is the difference
of a run of ``--steps`` steps and one of a sixth of them over the difference of their
steps (``commit_compare``), in CPU time of the process (one thread: on a shared machine
wall time also counts the other processes' turns); the table gives the minimum ms per
step of each, the Newton corrections per step and the ratio (Python term / compiled
twin).  It uses only the public API, so ``PYTHONPATH=<other tree> python
benchmarks/python_term_cost.py`` times another commit.
"""

import argparse
import time

import numpy as np
from numba import njit

import skfem_cable as sc
from skfem_cable.scenes import esail

K, DT, RHO = 1e-4, 0.1, 0.25


class NodeSpring:
    """Force -k (r - anchor) on a cable node (``docs/extending.md``)."""

    def __init__(self, node, k, anchor):
        self.node, self.k, self.anchor = node, k, np.asarray(anchor, float)

    def bind(self, system):
        d = system.dofs(self.node)[:3]
        K = -self.k * np.eye(3)                      # dF/dq

        def add(ev, index):
            ev.f_ext[d] += -self.k * (ev.q[d] - self.anchor)
            ev.add_tangent(index, K, sign=-1.0)      # external force: minus its derivative

        return sc.Term(add=add, rows=d[:, None], cols=d[None, :], name="node spring")


@njit(cache=True)
def spring_kernel(pack, index, ev):
    d, k, anchor = pack
    q, v, s, f, f_ext, f_damping, data, energy, power = ev
    for i in range(3):
        f_ext[d[i]] -= k * (q[d[i]] - anchor[i])
        if data.size:
            data[index[i, i]] += s[1] * k           # -(cK dF/dq), dF/dq = -k I


class CompiledNodeSpring(NodeSpring):
    def bind(self, system):
        d = system.dofs(self.node)[:3]
        return sc.Term(kernels=((spring_kernel, (d, float(self.k), self.anchor)),),
                       rows=d[:, None], cols=d[None, :], name="node spring")


def rig(spring):
    """The rig with ``spring`` (a class) on its first tether's tip."""
    scene = esail.build(esail.BaselineConfig(), alpha_deg=10.0, n_elements=5, kind="cable")
    tip = scene.tethers[0].node(-1)
    anchor = scene.initial.q[scene.system.dofs(tip)[:3]]
    scene.system.add_load(spring(tip, K, anchor))
    return scene


def run(scene, n):
    start = time.process_time()
    r = sc.simulate(scene.system, t_end=n * DT, dt=DT, rho_inf=RHO, initial=scene.initial,
                    every=n)
    return time.process_time() - start, r


def per_step(scene, steps):
    """ms per step (setup excluded) and the run of ``steps`` steps."""
    short = max(1, steps // 6)
    wall_short, _ = run(scene, short)
    wall, r = run(scene, steps)
    return 1e3 * (wall - wall_short) / (steps - short), r


def main(argv=None):
    """Time both rigs; returns ``{"python": ..., "compiled": ..., "ratio": ...}`` (ms per
    step, minimum over the repeats) and prints the table."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=10)
    parser.add_argument("--steps", type=int, default=1800)
    parser.add_argument("--quick", action="store_true",
                        help="two repeats of 300 steps (indicative)")
    args = parser.parse_args(argv)
    if args.quick:
        args.repeats, args.steps = 2, 300
    scenes = {"python": rig(NodeSpring), "compiled": rig(CompiledNodeSpring)}
    best, runs = {}, {}
    for scene in scenes.values():
        run(scene, 2)  # compile, layout
    for _ in range(args.repeats):
        for name, scene in scenes.items():
            ms, runs[name] = per_step(scene, args.steps)
            best[name] = min(best.get(name, np.inf), ms)
    for name in scenes:
        r = runs[name]
        print(f"{name:>9}: {best[name]:7.3f} ms/step, {r.stats['newton'] / r.stats['steps']:.2f}"
              f" Newton/step, path {r.stats['path']}")
    gap = np.abs(runs["python"].q[-1] - runs["compiled"].q[-1]).max()
    ratio = best["python"] / best["compiled"]
    print(f"ratio python/compiled: {ratio:.3f} (final states differ by {gap:.1e})")
    return {**best, "ratio": ratio}


if __name__ == "__main__":
    main()
