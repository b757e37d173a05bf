"""The node spring of ``docs/extending.md`` for the tests: a force ``-k (r - anchor)`` on a
cable node, as a Python ``add`` hook (``NodeSpring``) and as its compiled twin
(``CompiledNodeSpring``, the kernel ``spring_kernel``), the same load both ways."""

import numpy as np
from numba import njit

import skfem_cable as sc


class NodeSpring:
    """Force ``-k (r - anchor)`` on a cable node, a Python ``add`` hook; its term is named
    ``name``."""

    def __init__(self, node, k, anchor, name="node spring"):
        self.node, self.k, self.anchor = node, k, np.asarray(anchor, float)
        self.name = name

    def bind(self, system):
        d = system.dofs(self.node)[:3]
        K = -self.k * np.eye(3)

        def add(ev, index):
            ev.f_ext[d] += -self.k * (ev.q[d] - self.anchor)
            ev.add_tangent(index, K, sign=-1.0)

        return sc.Term(add=add, rows=d[:, None], cols=d[None, :], name=self.name)


@njit(cache=True)
def spring_kernel(pack, index, ev):
    """The node spring as a compiled hook (``contract.Term.kernels``)."""
    d, k, anchor = pack
    q, v, s, f, f_ext, f_damping, data, energy, power = ev
    for i in range(3):
        f_ext[d[i]] -= k * (q[d[i]] - anchor[i])
        if data.size:
            data[index[i, i]] += s[1] * k


class CompiledNodeSpring(NodeSpring):
    """Its compiled twin."""

    def bind(self, system):
        d = system.dofs(self.node)[:3]
        return sc.Term(kernels=((spring_kernel, (d, float(self.k), self.anchor)),),
                       rows=d[:, None], cols=d[None, :], name=self.name)
