"""The elastic term of a deploying cable (``deploy``): the kernels of its law on the mesh
stretched to the deployed length, and the coupling of a reel's length with the cable's
coordinates."""

from dataclasses import replace

import numpy as np

from ..core.contract import NO_INDEX, Term, static_evaluation


class Stretched:
    """The hooks of a deploying cable's term (``deploy``): its tables ``(Sx, Sxx, weights,
    h)`` rescaled to the material arc length of the mesh stretched by ``lam = l / L0``
    (``Sx / lam``, ``Sxx / lam^2``, ``lam weights``, ``lam h``).

    A prescribed length ``l(t)`` rescales them once per time (``Term.prepare``) and its
    elastic energy has the explicit time derivative ``energy_rate``.  A reel's length is a
    coordinate: the term evaluates the kernels at the stretch of the coordinates (a Python
    ``add``) and adds the derivatives of the elastic energy in the length, ``dU/dl`` to the
    reel's equation, ``d^2U/dq dl`` and ``d^2U/dl^2`` to the tangent (``derivatives``)."""

    #: Relative step in ``lam`` of the difference quotients in the length (fourth order).
    STEP = 1e-4

    def __init__(self, deployment, term, passes):
        self.deployment = deployment
        self.built = [tuple(np.array(t) for t in tables[:4]) for _, tables, *_ in passes]
        self.kernels = term.kernels
        self.dofs_per_element = term.rows.shape[1]
        #: no tangent entries, as the kernels take them (int, 3-D)
        self.no_index = NO_INDEX.reshape(0, self.dofs_per_element, self.dofs_per_element)

    def term(self, system, term):
        """The deploying cable's term, from the plain ``term`` of its kernels."""
        if self.deployment.reel is None:
            return replace(term, key=None, prepare=self.prepare,
                           energy_rate=self.energy_rate)
        dofs, reel = system.dofs(self.deployment.cable), self.deployment.reel
        rows, cols = np.broadcast_arrays(term.rows, term.cols)
        self.n_element_entries = rows.size
        self.dofs = dofs
        line = np.full(dofs.size, reel)
        return Term(add=self.add, rows=np.concatenate([rows.ravel(), dofs, line, [reel]]),
                    cols=np.concatenate([cols.ravel(), line, dofs, [reel]]), name=term.name)

    def scaled(self, lam, out=None):
        """The tables of every pass for the stretch ``lam`` (into ``out`` if given)."""
        out = out or [tuple(np.empty_like(t) for t in tables) for tables in self.built]
        for (Sx0, Sxx0, w0, h0), (Sx, Sxx, w, h) in zip(self.built, out):
            np.divide(Sx0, lam, out=Sx)
            np.divide(Sxx0, lam * lam, out=Sxx)
            np.multiply(w0, lam, out=w)
            np.multiply(h0, lam, out=h)
        return out

    def prepare(self, t):
        """``Term.prepare``: the term's own tables at time ``t``."""
        self.scaled(self.deployment.stretch(t), [pack[1:5] for _, pack in self.kernels])

    def add(self, ev, index):
        """``Term.add`` of a reel's cable: the kernels at the stretch of ``ev.q``, and the
        coupling with the length."""
        deployment = self.deployment
        L0 = deployment.L0
        lam = deployment.stretch(ev.t, ev.q)
        self.scaled(lam, [pack[1:5] for _, pack in self.kernels])
        m = self.dofs_per_element
        own = self.no_index if index is None else \
            index[:self.n_element_entries].reshape(-1, m, m)
        packed = ev.packed()
        for function, pack in self.kernels:
            function(pack, own, packed)
        dU, g, d2U = self.derivatives(ev.q, lam)
        ev.f[deployment.reel] += dU / L0
        if index is not None:
            ev.add_tangent(index[self.n_element_entries:],
                           np.concatenate([g, g, [d2U / L0]]) / L0)

    def derivatives(self, q, lam):
        """``(dU/dlam, d f/dlam on the cable's coordinates, d^2U/dlam^2)`` of the elastic
        energy ``U`` and force ``f`` at ``q`` (all the system's coordinates), by fourth-order
        central differences of step ``STEP lam`` (five kernel evaluations)."""
        d = self.STEP * lam
        values = [self.elastic(q, lam + k * d) for k in (-2, -1, 0, 1, 2)]
        (Em2, fm2), (Em1, fm1), (E0, _), (E1, f1), (E2, f2) = values
        dU = (8 * (E1 - Em1) - (E2 - Em2)) / (12 * d)
        g = (8 * (f1 - fm1) - (f2 - fm2))[self.dofs] / (12 * d)
        d2U = (16 * (E1 + Em1) - (E2 + Em2) - 30 * E0) / (12 * d * d)
        return dU, g, d2U

    def elastic(self, q, lam):
        """The elastic energy and force (all the system's coordinates) of the coordinates
        ``q`` on the mesh stretched by ``lam``, by the law's kernels."""
        return static_evaluation(
            [(function, (pack[0], *tables, *pack[5:]))
             for (function, pack), tables in zip(self.kernels, self.scaled(lam))],
            q, self.no_index)

    def energy(self, q, lam):
        """The elastic energy of the coordinates ``q`` (all the system's) on the mesh
        stretched by ``lam``."""
        return self.elastic(q, lam)[0]

    def energy_rate(self, q, t):
        """``Term.energy_rate``: ``dU/dt = (l' / L0) dU/dlam`` at fixed coordinates, the
        power the reel takes from the stored energy (``dU/dlam`` by central differences
        of relative step 1e-6)."""
        ell, rate, _ = self.deployment.state(t)
        lam = ell / self.deployment.L0
        d = 1e-6 * lam
        return rate / self.deployment.L0 * (self.energy(q, lam + d)
                                            - self.energy(q, lam - d)) / (2 * d)
