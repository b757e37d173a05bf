"""A new cable element in a page: the ANCF cable with the engineering (Biot) strain.

The library's cable uses the Green strain ``eps = (|r_x|^2 - 1) / 2``, whose force
``N = EA eps |r_x|`` is not linear in the stretch.  With the engineering strain
``e = |r_x| - 1`` and the energy density ``W = EA e^2 / 2 + EI kappa^2 / 2`` the axial force
is ``N = EA e``: a bar pulled by a tip force ``P`` stretches by exactly ``P L / EA``, however
large.  The element needs only the density's gradient and Hessian with respect to
``(a, b) = (r_x, r_xx)``:

    W_a  = EA e a / |a|,
    W_aa = EA (a a^T / |a|^2 + e (I - a a^T / |a|^2) / |a|),

plus the bending part, reused from ``kernels.density.squared_curvature``.  One chain rule
through the Hermite derivative tables ``S_x``, ``S_xx`` gives the element forces and
tangents (``docs/custom_element.md`` explains the contract).

Run ``python demos/custom_element.py``: it pulls a bar with ``P = 0.1 EA`` and bends the
elastica with both strain measures.
"""

import numpy as np

import skfem_cable as sc
from skfem_cable.analytic import elastica_tip_load
from skfem_cable.kernels.density import squared_curvature


def biot_density(a, b, EA, EI):
    """Energy density, gradient (6,) and Hessian (6, 6) in ``(a, b)`` at every Gauss
    point (leading axes)."""
    p = np.einsum("...i,...i", a, a)
    n = np.sqrt(p)[..., None]
    e = n[..., 0] - 1.0
    t = a / n
    tt = t[..., :, None] * t[..., None, :]
    k2, grad, hess = squared_curvature(a, b)
    W = 0.5 * EA * e**2 + 0.5 * EI * k2
    G = 0.5 * EI * grad
    H = 0.5 * EI * hess
    G[..., :3] += EA * e[..., None] * t
    H[..., :3, :3] += EA * (tt + e[..., None, None] * (np.eye(3) - tt) / n[..., None])
    return W, G, H


# --8<-- [start:BiotCable]
class BiotCable(sc.Cable):
    """ANCF cable with the engineering strain (no internal damping)."""

    def bind(self, system):
        """The element's ``Term`` (see ``docs/extending.md``): its tangent pattern is the
        12 x 12 block of every element, its hook adds ``dU/dq`` and ``cK d2U/dq2``."""
        edofs = self.global_element_dofs(system)
        ne = len(edofs)
        S6 = np.stack([self.Sx, self.Sxx], axis=2)  # (ne, nq, 2, 4): d/dx, d2/dx2
        w = self.weights
        EA, EI = self.section.EA, self.EI_active

        def add(ev, index):
            x = np.einsum("eqUA,eAi->eqUi", S6, ev.q[edofs].reshape(ne, 4, 3))
            W, G, H = biot_density(x[..., 0, :], x[..., 1, :], EA, EI)
            fe = np.einsum("eq,eqUA,eqUi->eAi", w, S6, G.reshape(ne, -1, 2, 3))
            np.add.at(ev.f, edofs, fe.reshape(ne, 12))
            ev.energy[0] += np.sum(w * W)  # all of it booked as "axial" for brevity
            if ev.want_tangent:
                H = H.reshape(ne, -1, 2, 3, 2, 3)
                Ke = np.einsum("eq,eqUA,eqVB,eqUiVj->eAiBj", w, S6, S6, H)
                ev.add_tangent(index, Ke.reshape(ne, 12, 12))

        return sc.Term(add=add, rows=edofs[:, :, None], cols=edofs[:, None, :],
                       name=self.name)

    def strain(self, q, s):
        """Engineering strain ``|r_x| - 1``."""
        return np.linalg.norm(self.interpolate(q, s)[1], axis=-1) - 1.0

    def tension(self, q, s):
        """Axial force ``EA e`` (bending contribution left out)."""
        return self.section.EA * self.strain(q, s)
# --8<-- [end:BiotCable]


def pulled_bar(cls, load=0.1, n_elements=4):
    """Tip stretch ``u / L`` of a bar clamped at one end, pulled by ``P = load EA``."""
    section = sc.Section(E=1e9, A=1e-4, I=1e-10, rho=7850.0)
    bar = cls.straight([0, 0, 0], [1, 0, 0], n_elements, section)
    system = sc.System([bar]).clamp(bar.node(0))
    system.add_point_load(bar.node(-1), [load * section.EA, 0, 0])
    return sc.solve_static(system, load_steps=5).position(bar, 1.0)[0] - 1.0


def elastica(cls, k=5.0, n_elements=16):
    """Tip deflection ``w / L`` of the cantilever of ``demos/cantilever.py``."""
    section = sc.Section(E=1e9, A=1e-4, I=1e-11, rho=7850.0)
    cable = cls.straight([0, 0, 0], [1, 0, 0], n_elements, section)
    system = sc.System([cable]).clamp(cable.node(0))
    system.add_point_load(cable.node(-1), [0, -k * section.EI, 0])
    return -sc.solve_static(system, load_steps=20).position(cable, 1.0)[1]


def main(n_elements=16):
    """Tip stretch of the bar and elastica deflection for both strain measures."""
    return {"stretch_biot": pulled_bar(BiotCable), "stretch_green": pulled_bar(sc.Cable),
            "stretch_exact_biot": 0.1,
            "elastica_biot": elastica(BiotCable, n_elements=n_elements),
            "elastica_green": elastica(sc.Cable, n_elements=n_elements),
            "elastica_exact": elastica_tip_load(5.0)[1]}


if __name__ == "__main__":
    for key, value in main().items():
        print(f"{key:>20s}: {value:.10g}")
