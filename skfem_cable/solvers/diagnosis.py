"""What a failed step of the generalized-alpha integrator says (``Diagnosis``, a part of
``GeneralizedAlpha``): the singular unknown of the iteration matrix, the residual's worst
coordinate, or the body whose kinetic energy grew: the diagnostics of ``SimulationError``
that name the time, the step, the residual or energy history and the body responsible.
It reads the integrator's ``system``, ``n``, ``res_weight``, ``con_weight``, ``lay``,
``v`` and ``guard``."""

import numpy as np

from ..constraints.dependence import dependence_message, dependent_constraints
from ..core.linalg import SingularMatrixError


class Diagnosis:
    """The messages of a failed step (module docstring)."""

    def _singular(self, t, h, index):
        """The message of a singular iteration matrix, naming the unknown ``index``
        (-1: not located)."""
        where = self.system.describe_dof(index) if index >= 0 else \
            "an unknown not located (system too large)"
        return f"t={t:.6g}, h={h:.3g}: singular iteration matrix at {where}"

    def _singular_start(self, t, index, jacobian):
        """The error of a singular matrix at the start (consistent accelerations): a
        ``ValueError`` naming the dependent constraints when the constraint ``jacobian``
        has dependent rows (``constraints.dependent_constraints``), else the
        ``SingularMatrixError`` naming the unknown ``index``."""
        names, rank = dependent_constraints(self.system, jacobian)
        if names:
            return ValueError(dependence_message(names, rank, f"the initial state (t={t:g})"))
        where = self.system.describe_dof(index) if index >= 0 else \
            "an unknown not located (system too large)"
        return SingularMatrixError(f"t={t:.6g}: singular matrix of the initial state at "
                                   f"{where}", index)

    def _diagnose_growth(self, t, h, v1, reason):
        """Where a rejected step put its energy: the body whose kinetic energy grew most,
        and its fastest coordinate."""
        system, mass = self.system, self.lay.mass.scipy
        gains = []
        for body in system.bodies:
            d = system.dofs(body)
            M = mass[d][:, d]
            gains.append((0.5 * (v1[d] @ (M @ v1[d]) - self.v[d] @ (M @ self.v[d])), body, d))
        gain, body, d = max(gains, key=lambda g: g[0])
        fastest = d[int(np.argmax(np.abs(v1[d] - self.v[d])))]
        return (f"t={t:.6g}, h={h:.3g}: {reason}; {body.name} gained {gain:.4g} J of kinetic "
                f"energy, fastest at {system.describe_dof(fastest)}; energy balance of the "
                f"last accepted steps: {self.guard.describe_history()}")

    def _diagnose(self, t, h, history, r, what):
        system, n = self.system, self.n
        res = np.abs(r[:n]) * self.res_weight
        res_c = np.abs(r[n:]) * self.con_weight
        parts = [f"t={t:.6g}, h={h:.3g}: {what}; scaled residual history "
                 f"{[float(f'{e:.3e}') for e in history]}"]
        for label, values, offset in (("dynamic", res, 0), ("constraint", res_c, n)):
            if not values.size:
                continue
            bad = ~np.isfinite(values)
            i = int(np.argmax(bad)) if bad.any() else int(np.argmax(values))
            kind = "non-finite" if bad.any() else "largest"
            parts.append(f"{kind} {label} residual at {system.describe_dof(offset + i)}")
        return "; ".join(parts)
